//! Material constants of the viscoelastic (Hertz) contact law and their mixing rules.

use serde::{Deserialize, Serialize};

/// Constants of one material. SI units throughout. The default is the thesis' glass beads
/// (Table 3.3), and every missing key of a scene's `[material]` takes its value from it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Mass density rho, kg/m^3.
    pub density: f64,
    /// Young's modulus Y, Pa.
    pub young: f64,
    /// Poisson ratio nu (dimensionless). The thesis does not state it; 0.3 is used for glass-like beads.
    pub poisson: f64,
    /// Dissipative constant A of the viscoelastic law (eq 3.8), s.
    pub dissipation: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            density: 2500.0,
            young: 1e6,
            poisson: 0.3,
            dissipation: 8.5e-6,
        }
    }
}

impl Material {
    /// Reduced modulus of one material, `Y / (1 - nu^2)`, Pa.
    pub fn reduced_modulus(&self) -> f64 {
        self.young / (1.0 - self.poisson * self.poisson)
    }

    /// Mass of a sphere of radius `r` (m): `m = rho 4/3 pi r^3`, kg.
    pub fn sphere_mass(&self, r: f64) -> f64 {
        self.density * 4.0 / 3.0 * std::f64::consts::PI * r * r * r
    }
}

/// Effective Hertz constants of a contact between materials `a` and `b`.
///
/// - eq 3.9: the dissipative constant is the arithmetic mean, `A = (A_i + A_j) / 2`.
/// - eq 3.10: `Y / (1 - nu^2)` is replaced by a mean of the two reduced moduli. Taken
///   literally (`[(1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j]^-1`) it would halve the force of two
///   identical spheres relative to eq 3.8, so it is read as the *harmonic mean*
///   `2 [(1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j]^-1`, which reduces to `Y/(1-nu^2)` for like
///   materials (eq 3.8) and equals Hertz' `4/3 E*` convention for unlike ones.
///
/// Returns `(reduced_modulus, dissipation)`.
pub fn mix(a: &Material, b: &Material) -> (f64, f64) {
    let reduced = 2.0 / (1.0 / a.reduced_modulus() + 1.0 / b.reduced_modulus());
    (reduced, 0.5 * (a.dissipation + b.dissipation))
}

/// Effective radius `R_eff = R_i R_j / (R_i + R_j)` (m); a wall (`None`) gives `R_i` (eq 3.17).
pub fn effective_radius(ri: f64, rj: Option<f64>) -> f64 {
    match rj {
        Some(rj) => ri * rj / (ri + rj),
        None => ri,
    }
}

/// Effective mass `m_eff = m_i m_j / (m_i + m_j)` from inverse masses (kg); a wall has
/// inverse mass 0 and gives `m_i`.
pub fn effective_mass(inv_mi: f64, inv_mj: f64) -> f64 {
    1.0 / (inv_mi + inv_mj)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLASS: Material = Material {
        density: 2500.0,
        young: 1e6,
        poisson: 0.3,
        dissipation: 8.5e-6,
    };

    #[test]
    fn mixing_like_materials_is_identity() {
        let (y, a) = mix(&GLASS, &GLASS);
        assert!((y - GLASS.reduced_modulus()).abs() < 1e-9 * y);
        assert_eq!(a, GLASS.dissipation);
    }

    #[test]
    fn mixing_unlike_materials_is_harmonic_and_arithmetic() {
        let soft = Material {
            young: 2e6,
            poisson: 0.5,
            dissipation: 1.5e-6,
            ..GLASS
        };
        let (y, a) = mix(&GLASS, &soft);
        let expect = 2.0 / ((1.0 - 0.09) / 1e6 + (1.0 - 0.25) / 2e6);
        assert!((y - expect).abs() < 1e-9 * expect);
        assert!((a - 5e-6).abs() < 1e-18);
        // symmetric
        assert_eq!(mix(&soft, &GLASS), (y, a));
    }

    #[test]
    fn wall_partner_gives_particle_values() {
        assert_eq!(effective_radius(0.3, None), 0.3);
        assert_eq!(effective_mass(2.0, 0.0), 0.5);
        assert!((effective_radius(1.0, Some(1.0)) - 0.5).abs() < 1e-15);
    }
}
