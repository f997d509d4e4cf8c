//! `stripes single`: one sphere on the shaken plate with the tray's own laws, beside the closed forms of rolling and sliding, and the rolling-friction stopping test (the study: [`crate::studies::single`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::rundir::report::{report, Reported};
use crate::studies::single::{single_sphere, Options};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Scene whose particle-wall law (after its toggles), grain density, drive, time step and
    /// integrator the sphere uses.
    /// (default: the thesis' reference scene, `scenes/thesis-reference.toml`, built into the
    /// program so that `stripes single` works from any directory).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub set: crate::cli::args::Overrides,
    /// Shaking frequency (Hz), or a sweep `LO:HI:N` (N frequencies evenly spaced from LO to
    /// HI). Default: the scene's drive.frequency.
    #[arg(long)]
    pub frequency: Option<String>,
    /// Shaking amplitude (m). Default: the scene's drive.amplitude.
    #[arg(long)]
    pub amplitude: Option<f64>,
    /// Sphere radius (m). Default: the scene's particles.radius_max (thesis 3.3: 0.5 mm).
    #[arg(long)]
    pub radius: Option<f64>,
    /// Duration of each shaking run (s); the amplitudes are measured over its last half.
    #[arg(long, default_value_t = 5.0)]
    pub duration: f64,
    /// Rolling friction mu_r of the runs "with rolling friction" (s). Default: the scene's
    /// contact.rolling_friction; with 0 only the runs without rolling friction are made.
    #[arg(long)]
    pub mu_r: Option<f64>,
    /// Rolling friction coefficients of the stopping test (s), comma separated.
    #[arg(long, value_delimiter = ',', default_value = "0,2e-6,8.5e-6,2e-5,5e-5")]
    pub stop_mu_r: Vec<f64>,
    /// Launch speed of the stopping test (m/s).
    #[arg(long, default_value_t = 0.05)]
    pub stop_speed: f64,
    /// Duration of the stopping test (s); 0 skips it.
    #[arg(long, default_value_t = 10.0)]
    pub stop_duration: f64,
    /// Time step (s). Default: the scene's run.dt (for "auto", the step the scene's tray
    /// would take at each frequency).
    #[arg(long)]
    pub dt: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out/single")]
    pub out: PathBuf,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            scene: self.scene.clone(),
            overrides: self.set.overrides.clone(),
            frequency: self.frequency.clone(),
            amplitude: self.amplitude,
            radius: self.radius,
            duration: self.duration,
            mu_r: self.mu_r,
            stop_mu_r: self.stop_mu_r.clone(),
            stop_speed: self.stop_speed,
            stop_duration: self.stop_duration,
            dt: self.dt,
            out: self.out.clone(),
            force: self.writing.force,
            quiet: self.writing.quiet,
        }
    }
}

pub fn run(args: Args) -> Reported {
    report(single_sphere(&args.options())?)
}
