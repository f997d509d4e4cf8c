//! `stripes events-collide`: single impacts of the event-driven rule on a wall or a grain, and sweeps over the impact angle beside the rule's closed form (the study: [`crate::events::impacts`]).

use std::path::PathBuf;

use serde::Serialize;

use crate::events::impacts::{impacts, Options};
use crate::rundir::report::Reported;

#[derive(clap::Args, Clone, Debug, Serialize)]
pub struct Args {
    /// What grain 1 hits: "wall" (a floor at rest) or "pair" (an equal grain at rest below).
    #[arg(long, default_value = "wall")]
    pub target: String,
    /// Grain 1's speed before the impact (m/s, > 0).
    #[arg(long, default_value_t = 1.0, value_parser = crate::cli::values::not_nan)]
    pub speed: f64,
    /// Grain 1's impact angle from the normal (degrees, [0, 90)), one impact.
    #[arg(long, default_value_t = 30.0, value_parser = crate::cli::values::not_nan)]
    pub angle: f64,
    /// Grain 1's spin before the impact (rad/s, counter-clockwise in the x-z plane).
    #[arg(long, default_value_t = 0.0, value_parser = crate::cli::values::not_nan)]
    pub spin: f64,
    /// Grain 1's centre above the wall, or above grain 2's centre (m); default: in contact
    /// (R, or 2 R). Any other value is refused: the grains must touch.
    #[arg(long, value_parser = crate::cli::values::not_nan)]
    pub z1: Option<f64>,
    /// Normal restitution e in [0, 1].
    #[arg(long, default_value_t = 0.9, value_parser = crate::cli::values::not_nan)]
    pub e: f64,
    /// Coulomb friction mu (>= 0); several, comma-separated, for a sweep.
    #[arg(long, value_delimiter = ',', default_value = "0.5", value_parser = crate::cli::values::not_nan)]
    pub mu: Vec<f64>,
    /// Tangential restitution of sticking contacts beta0 in [-1, 1] (-1 smooth, +1 perfectly
    /// rough); several, comma-separated, for a sweep.
    #[arg(long, value_delimiter = ',', default_value = "0.5", value_parser = crate::cli::values::not_nan)]
    pub beta0: Vec<f64>,
    /// Inertia factor q = I / (m R^2) in (0, 1] (sphere 0.4, disk 0.5, hollow sphere 2/3).
    #[arg(long, default_value_t = 0.4, value_parser = crate::cli::values::not_nan)]
    pub q: f64,
    /// Radius of each grain (m).
    #[arg(long, default_value = "1e-3", value_parser = crate::cli::values::not_nan)]
    pub radius: f64,
    /// Mass of each grain (kg).
    #[arg(long, default_value = "1e-6", value_parser = crate::cli::values::not_nan)]
    pub mass: f64,
    /// Sweep the impact angle over this many angles from 0 to --max-angle.
    #[arg(long)]
    pub sweep: Option<usize>,
    /// The largest impact angle of a sweep (degrees, < 90).
    #[arg(long, default_value_t = 89.0, value_parser = crate::cli::values::not_nan)]
    pub max_angle: f64,
    /// Output directory of a sweep (one impact is printed and nothing is written).
    #[arg(long, default_value = "out/events-collide")]
    pub out: PathBuf,
    #[command(flatten)]
    pub replace: crate::cli::args::Force,
    #[command(flatten)]
    #[serde(flatten)]
    pub quiet: crate::cli::args::Quiet,
}

impl Args {
    fn options(&self) -> Options {
        Options {
            target: self.target.clone(),
            speed: self.speed,
            angle: self.angle,
            spin: self.spin,
            z1: self.z1,
            e: self.e,
            mu: self.mu.clone(),
            beta0: self.beta0.clone(),
            q: self.q,
            radius: self.radius,
            mass: self.mass,
            sweep: self.sweep,
            max_angle: self.max_angle,
            out: self.out.clone(),
            force: self.replace.force,
            quiet: self.quiet.quiet,
        }
    }
}

pub fn run(args: Args) -> Reported {
    impacts(&args.options())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: Args,
    }

    fn error(options: &[&str]) -> String {
        let cli = Cli::try_parse_from(std::iter::once("events-collide").chain(options.iter().copied())).unwrap();
        match run(cli.args) {
            Err(e) => e.to_string(),
            Ok(r) => panic!("{options:?} accepted: {}", r.json_line().unwrap()),
        }
    }

    /// The bad impacts, each refused with the option it came from: a speed that is
    /// not positive, grains apart or overlapping (wall and pair), q outside (0, 1].
    #[test]
    fn bad_impacts_name_their_option() {
        for speed in ["--speed=0", "--speed=-1"] {
            let e = error(&[speed]);
            assert!(e.starts_with("--speed:"), "{e}");
        }
        // R = 1 mm: in contact with the wall at z1 = R, with a grain below at z1 = 2 R.
        for (target, z1) in [
            ("wall", "1.001e-3"),
            ("wall", "0.999e-3"),
            ("pair", "2.002e-3"),
            ("pair", "1.998e-3"),
        ] {
            let e = error(&["--target", target, "--z1", z1]);
            assert!(e.starts_with("--z1:"), "{target} at {z1}: {e}");
        }
        for q in ["0", "1.2"] {
            let e = error(&["--q", q]);
            assert!(e.starts_with("--q:"), "{e}");
        }
        // In contact, the default impact is accepted.
        let cli = Cli::try_parse_from(["events-collide", "--target", "pair", "--z1", "2e-3"]).unwrap();
        assert!(run(cli.args).unwrap().json_line().unwrap().contains("\"branch\""));
    }
}
