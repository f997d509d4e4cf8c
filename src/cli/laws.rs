//! The contact-law options of `stripes collide`: the three laws and their parameters, mapped
//! onto the study's [`Laws`].

use serde::Serialize;

use particles::contact::choice::{NormalKind, RollingKind, TangentialKind};

use crate::cli::values::kind;
use crate::studies::collide::Laws;

#[derive(clap::Args, Clone, Debug, Serialize)]
pub struct LawArgs {
    /// Normal law: hertz (eq 3.8; --young, --poisson, --dissipation) or linear (eq 4.21;
    /// --kn, --gamma-n).
    #[arg(long, value_parser = kind::<NormalKind>(NormalKind::NAMES), default_value = "hertz")]
    pub normal: NormalKind,
    /// Tangential law: none, haff-werner (eq 3.12; --gamma-t, --mu) or cundall-strack
    /// (eq 4.32-4.34; --kt, --mu).
    #[arg(long, value_parser = kind::<TangentialKind>(TangentialKind::NAMES), default_value = "none")]
    pub tangential: TangentialKind,
    /// Rolling law: none, brilliantov-poschel (eq 3.15; --mu-r) or sds (spring-dashpot-slider;
    /// --mu-roll, --k-roll, --gamma-roll).
    #[arg(long, value_parser = kind::<RollingKind>(RollingKind::NAMES), default_value = "none")]
    pub rolling: RollingKind,
    /// Young's modulus Y (Pa), Hertz only.
    #[arg(long, default_value = "1e6", value_parser = crate::cli::values::not_nan)]
    pub young: f64,
    /// Poisson ratio, Hertz only.
    #[arg(long, default_value_t = 0.3, value_parser = crate::cli::values::not_nan)]
    pub poisson: f64,
    /// Dissipative constant A (s), Hertz only (eq 3.8).
    #[arg(long, default_value = "8.5e-6", value_parser = crate::cli::values::not_nan)]
    pub dissipation: f64,
    /// Normal stiffness k_n (N/m), linear only.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub kn: Option<f64>,
    /// Normal damping gamma_n (kg/s), linear only.
    #[arg(long, default_value_t = 0.0, value_parser = crate::cli::values::not_nan)]
    pub gamma_n: f64,
    /// Tangential spring stiffness k_t (N/m), Cundall-Strack only.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub kt: Option<f64>,
    /// Coulomb friction coefficient.
    #[arg(long, default_value_t = 0.7, value_parser = crate::cli::values::not_nan)]
    pub mu: f64,
    /// Tangential damping gamma_t (N s/m), Haff-Werner only.
    #[arg(long, default_value_t = 0.007, value_parser = crate::cli::values::not_nan)]
    pub gamma_t: f64,
    /// Rolling friction mu_r (s), Brilliantov-Pöschel only.
    #[arg(long, default_value = "8.5e-6", value_parser = crate::cli::values::not_nan)]
    pub mu_r: f64,
    /// Rolling resistance mu_r (dimensionless), spring-dashpot-slider only.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub mu_roll: Option<f64>,
    /// Rolling stiffness k_roll (N/m; spring torque k_roll R_eff^2 per radian),
    /// spring-dashpot-slider only; default 2.25 mu_r^2 k_n.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub k_roll: Option<f64>,
    /// Rolling damping gamma_roll (N s/m), spring-dashpot-slider only.
    #[arg(long, default_value_t = 0.0, value_parser = crate::cli::values::not_nan)]
    pub gamma_roll: f64,
}

impl LawArgs {
    pub fn laws(&self) -> Laws {
        Laws {
            normal: self.normal,
            tangential: self.tangential,
            rolling: self.rolling,
            young: self.young,
            poisson: self.poisson,
            dissipation: self.dissipation,
            kn: self.kn,
            gamma_n: self.gamma_n,
            kt: self.kt,
            mu: self.mu,
            gamma_t: self.gamma_t,
            mu_r: self.mu_r,
            mu_roll: self.mu_roll,
            k_roll: self.k_roll,
            gamma_roll: self.gamma_roll,
        }
    }
}
