//! The choice of a law for each slot, as the scene file and the command line name it, and
//! the one place where a choice and its parameters become a [`ContactLaw`].
//!
//! One choice, one type: `contact.normal = "linear"` in a scene and `--normal linear` in
//! `stripes collide` parse into the same [`NormalKind`]; both build their laws with
//! [`LawChoice::build`], which refuses a choice whose parameter is missing instead of
//! building a law with a placeholder.

use serde::{Deserialize, Serialize};

use super::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};

/// Defines a kind enum with its kebab-case names (serde and `FromStr` alike).
macro_rules! kind {
    ($(#[$m:meta])* $name:ident { $($(#[$vm:meta])* $variant:ident = $text:literal),+ $(,)? }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
        pub enum $name {
            $($(#[$vm])* #[serde(rename = $text)] $variant),+
        }

        impl $name {
            /// Every name, in declaration order (for help texts and parsers).
            pub const NAMES: &'static [&'static str] = &[$($text),+];

            /// The name in scene files and on the command line.
            pub fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text),+
                }
            }
        }

        impl std::str::FromStr for $name {
            type Err = crate::error::UnknownName;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                match s {
                    $($text => Ok($name::$variant),)+
                    _ => Err(crate::error::UnknownName {
                        what: "variant",
                        given: s.into(),
                        expected: Self::NAMES,
                    }),
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

kind!(
    /// Normal-law slot.
    NormalKind {
        /// Viscoelastic Hertz, eq 3.8 (material: Y, nu, A).
        Hertz = "hertz",
        /// Linear spring-dashpot, eq 4.21 (k_n, gamma_n).
        Linear = "linear",
    }
);

kind!(
    /// Tangential-law slot.
    TangentialKind {
        /// Frictionless.
        None = "none",
        /// Haff-Werner, eq 3.12 (gamma_t, mu).
        HaffWerner = "haff-werner",
        /// Cundall-Strack, eq 4.32-4.34 (k_t, mu).
        CundallStrack = "cundall-strack",
    }
);

kind!(
    /// Rolling-law slot.
    RollingKind {
        /// No rolling resistance.
        None = "none",
        /// Brilliantov-Pöschel, eq 3.15 (mu_r in s).
        BrilliantovPoschel = "brilliantov-poschel",
        /// Spring-dashpot-slider, Ai et al. 2011 model C; LAMMPS `rolling sds` (mu_r
        /// dimensionless, k_roll, gamma_roll).
        SpringDashpotSlider = "sds",
    }
);

/// A kind per slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LawChoice {
    pub normal: NormalKind,
    pub tangential: TangentialKind,
    pub rolling: RollingKind,
}

/// Every parameter a choice may draw on (SI units). The ones a choice does not use are
/// ignored; an `Option` that the choice needs must be `Some`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawParameters {
    /// Hertz: reduced modulus `Y / (1 - nu^2)` (Pa), mixed (eq 3.10).
    pub reduced_modulus: f64,
    /// Hertz: dissipative constant A (s), mixed (eq 3.9).
    pub dissipation: f64,
    /// Linear: stiffness k_n (N/m).
    pub kn: Option<f64>,
    /// Linear: damping gamma_n (kg/s).
    pub gamma_n: f64,
    /// Coulomb coefficient; `inf` for no cap.
    pub mu: f64,
    /// Haff-Werner: damping gamma_t (N s/m).
    pub gamma_t: f64,
    /// Cundall-Strack: stiffness k_t (N/m).
    pub kt: Option<f64>,
    /// Brilliantov-Pöschel: mu_r (s).
    pub mu_r: f64,
    /// Spring-dashpot-slider: rolling resistance mu_r (dimensionless).
    pub rolling_resistance: Option<f64>,
    /// Spring-dashpot-slider: k_roll (N/m); `None`: `2.25 mu_r^2 k_n`.
    pub k_roll: Option<f64>,
    /// Spring-dashpot-slider: gamma_roll (N s/m).
    pub gamma_roll: f64,
}

/// A parameter the chosen law needs and was not given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Missing {
    /// k_n, needed by [`NormalKind::Linear`].
    Kn,
    /// k_t, needed by [`TangentialKind::CundallStrack`].
    Kt,
    /// The dimensionless mu_r, needed by [`RollingKind::SpringDashpotSlider`].
    RollingResistance,
}

impl LawChoice {
    /// The law of this choice with these parameters, built whole.
    pub fn build(&self, p: &LawParameters) -> Result<ContactLaw, Missing> {
        let normal = match self.normal {
            NormalKind::Hertz => NormalLaw::hertz(p.reduced_modulus, p.dissipation),
            NormalKind::Linear => NormalLaw::Linear {
                kn: p.kn.ok_or(Missing::Kn)?,
                gamma_n: p.gamma_n,
            },
        };
        let tangential = match self.tangential {
            TangentialKind::None => TangentialLaw::None,
            TangentialKind::HaffWerner => TangentialLaw::HaffWerner {
                gamma_t: p.gamma_t,
                mu: p.mu,
            },
            TangentialKind::CundallStrack => TangentialLaw::CundallStrack {
                kt: p.kt.ok_or(Missing::Kt)?,
                mu: p.mu,
            },
        };
        let rolling = match self.rolling {
            RollingKind::None => RollingLaw::None,
            RollingKind::BrilliantovPoschel => RollingLaw::BrilliantovPoschel { mu_r: p.mu_r },
            RollingKind::SpringDashpotSlider => RollingLaw::SpringDashpotSlider {
                mu_r: p.rolling_resistance.ok_or(Missing::RollingResistance)?,
                k_roll: p.k_roll,
                gamma_roll: p.gamma_roll,
            },
        };
        Ok(ContactLaw {
            normal,
            tangential,
            rolling,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> LawParameters {
        LawParameters {
            reduced_modulus: 1e6,
            dissipation: 8.5e-6,
            kn: None,
            gamma_n: 0.0,
            mu: f64::INFINITY,
            gamma_t: 0.007,
            kt: None,
            mu_r: 8.5e-6,
            rolling_resistance: None,
            k_roll: None,
            gamma_roll: 0.0,
        }
    }

    #[test]
    fn names_parse_back_and_missing_parameters_are_refused() {
        for name in TangentialKind::NAMES {
            assert_eq!(name.parse::<TangentialKind>().unwrap().name(), *name);
        }
        assert!("hooke".parse::<NormalKind>().unwrap_err().to_string().contains("hertz, linear"));
        let cs = LawChoice {
            normal: NormalKind::Linear,
            tangential: TangentialKind::CundallStrack,
            rolling: RollingKind::None,
        };
        assert_eq!(cs.build(&params()), Err(Missing::Kn));
        let p = LawParameters { kn: Some(1e3), ..params() };
        assert_eq!(cs.build(&p), Err(Missing::Kt));
        let law = cs.build(&LawParameters { kt: Some(5e2), ..p }).unwrap();
        assert_eq!(
            law.tangential,
            TangentialLaw::CundallStrack {
                kt: 5e2,
                mu: f64::INFINITY
            }
        );
    }
}
