//! Normal force laws. The returned force is the *unclamped* value; [`super::evaluate`] clamps
//! it at zero (no attraction), and the contact ends when it vanishes.

use super::lane::Lane;

/// Normal force law of one kind of contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalLaw {
    /// Viscoelastic Hertz law (eq 3.8, 3.20):
    /// `F_n = (2/3) Y* sqrt(R_eff) (xi^{3/2} + A sqrt(xi) dxi/dt)`, `Y* = Y/(1-nu^2)` (Pa),
    /// already mixed for unlike materials (see [`crate::material::mix`]); `A` in s.
    Hertz { reduced_modulus: f64, dissipation: f64 },
    /// Linear spring-dashpot (eq 4.21): `F_n = k_n xi + gamma_n dxi/dt`; `k_n` in N/m,
    /// `gamma_n` in kg/s.
    Linear { kn: f64, gamma_n: f64 },
}

impl NormalLaw {
    /// The same law without its dissipative part (`A = 0`, or `gamma_n = 0`): pure Hertz
    /// (eq 3.29) or an undamped spring.
    pub fn elastic(&self) -> Self {
        match *self {
            NormalLaw::Hertz { reduced_modulus, .. } => NormalLaw::hertz(reduced_modulus, 0.0),
            NormalLaw::Linear { kn, .. } => NormalLaw::Linear { kn, gamma_n: 0.0 },
        }
    }

    /// Hertz law from the reduced modulus `Y/(1-nu^2)` (Pa) and the dissipative constant `A` (s).
    pub fn hertz(reduced_modulus: f64, dissipation: f64) -> Self {
        NormalLaw::Hertz {
            reduced_modulus,
            dissipation,
        }
    }

    /// Hertz prefactor `k = 2 Y sqrt(R_eff) / (3 (1 - nu^2))` (eq 3.8), N/m^{3/2}; this is
    /// `zeta` of eq 3.19.
    #[inline]
    fn hertz_stiffness(reduced_modulus: f64, r_eff: f64) -> f64 {
        2.0 / 3.0 * reduced_modulus * r_eff.sqrt()
    }

    /// Everything a contact needs from the normal law in one evaluation (a single square
    /// root, `k sqrt(xi) = (2/3) Y* sqrt(R_eff xi)`): unclamped force, its elastic part, and
    /// the stored energy. Over lanes: one contact (`f64`) or several side by side.
    #[inline(always)]
    pub fn evaluate<L: Lane>(&self, xi: L, xi_dot: L, r_eff: L) -> NormalForce<L> {
        match *self {
            NormalLaw::Hertz {
                reduced_modulus,
                dissipation,
            } => {
                let k_sqrt_xi = L::splat(2.0 / 3.0 * reduced_modulus) * (r_eff * xi).sqrt();
                let elastic = k_sqrt_xi * xi;
                NormalForce {
                    raw: elastic + k_sqrt_xi * L::splat(dissipation) * xi_dot,
                    elastic,
                    energy: L::splat(0.4) * elastic * xi,
                }
            }
            NormalLaw::Linear { kn, gamma_n } => NormalForce {
                raw: L::splat(kn) * xi + L::splat(gamma_n) * xi_dot,
                elastic: L::splat(kn) * xi,
                energy: L::splat(0.5 * kn) * xi * xi,
            },
        }
    }

    /// The normal stiffness `k_n` (N/m) a spring-dashpot-slider derives its default rolling
    /// stiffness from, and its rate of change `dk_n/dt` (N/m/s), at overlap `xi` closing at
    /// `xi_dot`: the tangent stiffness `dF_el/dxi`. Hertz: `(3/2) k sqrt(xi)`, changing at
    /// `k_n xi_dot / (2 xi)` (0 at `xi = 0`); linear: `k_n`, constant.
    #[inline(always)]
    pub fn stiffness<L: Lane>(&self, xi: L, xi_dot: L, r_eff: L) -> (L, L) {
        match *self {
            NormalLaw::Hertz { reduced_modulus, .. } => {
                let kn = L::splat(reduced_modulus) * (r_eff * xi).sqrt();
                let zero = L::splat(0.0);
                let rate = L::select(L::le(xi, zero), zero, L::splat(0.5) * kn * xi_dot / xi);
                (kn, rate)
            }
            NormalLaw::Linear { kn, .. } => (L::splat(kn), L::splat(0.0)),
        }
    }

    /// [`Self::stiffness`] of a contact that carries the static load `f` (N) without an
    /// overlap of its own (a pinned grain on the floor): the tangent stiffness at the overlap
    /// [`Self::static_overlap`] that would carry it, `(3/2) k^{2/3} f^{1/3}` (Hertz).
    pub fn stiffness_under(&self, f: f64, r_eff: f64) -> f64 {
        let xi = self.static_overlap(f.max(0.0), r_eff);
        self.stiffness(xi, 0.0, r_eff).0
    }

    /// Release margin (m): a quantity with the sign of the unclamped force for `xi > 0` that
    /// stays smooth through the release, so the end of a contact can be interpolated between
    /// steps: `xi + A dxi/dt` (Hertz, since `F = k sqrt(xi) (xi + A dxi/dt)`),
    /// `xi + (gamma_n / k_n) dxi/dt` (linear).
    #[inline]
    pub fn release_margin(&self, xi: f64, xi_dot: f64) -> f64 {
        match *self {
            NormalLaw::Hertz { dissipation, .. } => xi + dissipation * xi_dot,
            NormalLaw::Linear { kn, gamma_n } => xi + gamma_n / kn * xi_dot,
        }
    }

    /// Duration of an undamped head-on contact at impact speed `v` (m/s) between bodies of
    /// effective mass `m_eff` (kg) and radius `r_eff` (m), in s:
    /// - Hertz, eq 3.19: `t_c = tau_c0 (m_eff / zeta)^{2/5} v^{-1/5}` with
    ///   `tau_c0 = 2 * 1.60903 = 3.21807` (twice the reduced time of maximal compression);
    /// - linear: half an oscillation period, `pi sqrt(m_eff / k_n)` (eq 4.22 prints `2 pi`,
    ///   the full period).
    pub fn undamped_contact_time(&self, m_eff: f64, r_eff: f64, v: f64) -> f64 {
        match *self {
            NormalLaw::Hertz { reduced_modulus, .. } => {
                let zeta = Self::hertz_stiffness(reduced_modulus, r_eff);
                HERTZ_TAU_C0 * (m_eff / zeta).powf(0.4) * v.abs().powf(-0.2)
            }
            NormalLaw::Linear { kn, .. } => std::f64::consts::PI * (m_eff / kn).sqrt(),
        }
    }

    /// Equilibrium overlap (m) under a static load `f` (N), e.g. a grain's weight on the floor.
    pub fn static_overlap(&self, f: f64, r_eff: f64) -> f64 {
        match *self {
            NormalLaw::Hertz { reduced_modulus, .. } => (f / Self::hertz_stiffness(reduced_modulus, r_eff)).powf(2.0 / 3.0),
            NormalLaw::Linear { kn, .. } => f / kn,
        }
    }
}

/// One evaluation of a normal law (N, N, J), per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalForce<L = f64> {
    /// Force before the no-attraction clamp.
    pub raw: L,
    /// Conservative part.
    pub elastic: L,
    /// Elastic energy stored.
    pub energy: L,
}

/// Reduced undamped Hertz contact duration `tau_c0 = 2 tau'_max`:
/// `tau_c0 = 2 (5/4)^{2/5} * integral_0^1 dx / sqrt(1 - x^{5/2})
///        = 2 (5/4)^{2/5} sqrt(pi) Gamma(7/5) / Gamma(9/10) = 3.218...` (thesis 3.2.5 quotes
/// `tau'_max ~ 1.609`).
pub const HERTZ_TAU_C0: f64 = 3.218_065_459_719_043_5;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tau_c0_matches_quadrature() {
        // 2 (5/4)^{2/5} int_0^1 dx / sqrt(1 - x^{5/2}); substitute x = 1 - s^2 to remove the
        // endpoint singularity, then Simpson.
        let n = 200_000;
        let f = |s: f64| {
            let x: f64 = 1.0 - s * s;
            let denom = (1.0 - x.powf(2.5)) / (s * s);
            if s == 0.0 {
                2.0 / 2.5f64.sqrt()
            } else {
                2.0 / denom.sqrt()
            }
        };
        let h = 1.0 / n as f64;
        let mut sum = f(0.0) + f(1.0);
        for k in 1..n {
            sum += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        let integral = sum * h / 3.0;
        let tau = 2.0 * 1.25f64.powf(0.4) * integral;
        assert!((tau - HERTZ_TAU_C0).abs() < 1e-9, "{tau}");
    }

    #[test]
    fn hertz_values_and_energy_derivative() {
        let law = NormalLaw::hertz(1e6 / 0.91, 8.5e-6);
        let (xi, r) = (1e-6, 2.5e-4);
        let k = NormalLaw::hertz_stiffness(1e6 / 0.91, r);
        // Eq 3.8 at rest, and eq 3.20 with its dissipative part at dxi/dt = 0.1 m/s.
        assert!((law.evaluate(xi, 0.0, r).raw - k * 1e-9).abs() < 1e-24);
        let expect = k * (1e-9 + 8.5e-6 * 1e-3 * 0.1);
        assert!((law.evaluate(xi, 0.1, r).raw - expect).abs() < 1e-14 * expect);
        for law in [law, NormalLaw::Linear { kn: 300.0, gamma_n: 0.1 }] {
            // The stored energy is the integral of the elastic force, and the elastic part
            // is the force at dxi/dt = 0.
            let h = 1e-10;
            let de = (law.evaluate(xi + h, 0.0, r).energy - law.evaluate(xi - h, 0.0, r).energy) / (2.0 * h);
            let e = law.evaluate(xi, 0.1, r);
            assert!((de - e.elastic).abs() < 1e-6 * de);
            assert_eq!(e.elastic, law.evaluate(xi, 0.0, r).raw);
        }
    }

    #[test]
    fn static_overlap_balances_load() {
        for law in [NormalLaw::hertz(1.1e6, 0.0), NormalLaw::Linear { kn: 100.0, gamma_n: 1.0 }] {
            let xi = law.static_overlap(1.3e-5, 5e-4);
            assert!((law.evaluate(xi, 0.0, 5e-4).elastic - 1.3e-5).abs() < 1e-15);
        }
    }
}
