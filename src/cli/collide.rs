//! `stripes collide`: one binary impact of two spheres or of a sphere on a wall, or the restitution table over the normal speed and g_t/g_n (the study: [`crate::studies::collide`]).

use std::path::PathBuf;

use serde::Serialize;

use particles::contact::choice::{NormalKind, RollingKind, TangentialKind};
use particles::integrate::Integrator;

use crate::cli::values::{kind, parse_vec3};
use crate::rundir::report::{report, Reported};
use crate::studies::collide::{collide, restitution_table, Options};

#[derive(clap::Args, Clone, Debug, Serialize)]
pub struct Args {
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
    /// Radius of sphere 1 (m).
    #[arg(long, default_value_t = 5e-4, value_parser = crate::cli::values::not_nan)]
    pub r1: f64,
    /// Radius of sphere 2 (m); defaults to --r1.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub r2: Option<f64>,
    /// Density (kg/m^3), used for masses not given by --m1/--m2.
    #[arg(long, default_value_t = 2500.0, value_parser = crate::cli::values::not_nan)]
    pub rho: f64,
    /// Mass of sphere 1 (kg); defaults to rho 4/3 pi r1^3.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub m1: Option<f64>,
    /// Mass of sphere 2 (kg); defaults to rho 4/3 pi r2^3.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub m2: Option<f64>,
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
    /// Normal approach speed (m/s); with --eccentricity, the relative speed.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true, value_parser = crate::cli::values::not_nan)]
    pub v: f64,
    /// Tangential speed at impact (m/s).
    #[arg(long, default_value_t = 0.0, conflicts_with = "eccentricity", allow_negative_numbers = true, value_parser = crate::cli::values::not_nan)]
    pub vt: f64,
    /// Impact eccentricity e = d / (R1 + R2) in [0, 1) (Fig 4.2).
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub eccentricity: Option<f64>,
    /// Initial spin of sphere 1, "x,y,z" (rad/s).
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0")]
    pub omega1: [f64; 3],
    /// Initial spin of sphere 2, "x,y,z" (rad/s).
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0")]
    pub omega2: [f64; 3],
    /// Sphere 1 hits a fixed flat wall instead of sphere 2.
    #[arg(long)]
    pub wall: bool,
    /// Time step (s); otherwise --steps-per-contact.
    #[arg(long, conflicts_with = "steps_per_contact", value_parser = crate::cli::values::not_nan)]
    pub dt: Option<f64>,
    /// Steps per estimated (undamped) contact time.
    #[arg(long, default_value_t = 1000.0, value_parser = crate::cli::values::not_nan)]
    pub steps_per_contact: f64,
    /// Time integrator: velocity-verlet or thesis (sec 3.5.1).
    #[arg(long, value_parser = kind::<Integrator>(Integrator::NAMES), default_value = "velocity-verlet")]
    pub integrator: Integrator,
    /// Sweep the impact over --g-n and --ratios, for pairs and for the floor, and write the
    /// restitution tables (restitution.csv, restitution_floor.csv) with plots.
    #[arg(long)]
    pub table: bool,
    /// With --table: the normal impact speeds g_n (m/s).
    #[arg(long, value_delimiter = ',', default_value = "0.01,0.02,0.05,0.1,0.2,0.5,1", requires = "table")]
    pub g_n: Vec<f64>,
    /// With --table: the ratios g_t / g_n of tangential to normal contact-point speed (> 0).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.05,0.1,0.2,0.3,0.5,0.75,1,1.5,2,3,5,10",
        requires = "table"
    )]
    pub ratios: Vec<f64>,
    /// With --table: take the pair and wall laws, the mean radius and the density from this
    /// tray scene (with its toggles) instead of the law options.
    #[arg(long, requires = "table")]
    pub scene: Option<PathBuf>,
    /// Output directory (default: none for one impact, which is then printed and nothing is
    /// written, as a calculator; out/collide for --table).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            normal: self.normal,
            tangential: self.tangential,
            rolling: self.rolling,
            r1: self.r1,
            r2: self.r2,
            rho: self.rho,
            m1: self.m1,
            m2: self.m2,
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
            v: self.v,
            vt: self.vt,
            eccentricity: self.eccentricity,
            omega1: self.omega1,
            omega2: self.omega2,
            wall: self.wall,
            dt: self.dt,
            steps_per_contact: self.steps_per_contact,
            integrator: self.integrator,
            table: self.table,
            g_n: self.g_n.clone(),
            ratios: self.ratios.clone(),
            scene: self.scene.clone(),
            out: self.out.clone(),
            force: self.writing.force,
            quiet: self.writing.quiet,
        }
    }
}

pub fn run(args: Args) -> Reported {
    let options = args.options();
    if options.table {
        return report(restitution_table(&options)?);
    }
    report(collide(&options)?)
}
