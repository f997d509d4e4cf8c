//! `stripes collide`: one binary impact of two spheres or of a sphere on a wall, or the restitution table over the normal speed and g_t/g_n (the study: [`crate::studies::collide`]).

use std::path::PathBuf;

use serde::Serialize;

use particles::integrate::Integrator;

use crate::cli::laws::LawArgs;
use crate::cli::values::{kind, parse_vec3};
use crate::rundir::report::{report, Reported};
use crate::studies::collide::{collide, restitution_table, Options};

#[derive(clap::Args, Clone, Debug, Serialize)]
pub struct Args {
    #[command(flatten)]
    #[serde(flatten)]
    pub laws: LawArgs,
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
            laws: self.laws.laws(),
            r1: self.r1,
            r2: self.r2,
            rho: self.rho,
            m1: self.m1,
            m2: self.m2,
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
