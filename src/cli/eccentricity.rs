//! `stripes eccentricity`: the chapter 4 study.

use std::path::PathBuf;

use analysis::plot::{LinePlot, Mark};
use particles::experiment::eccentricity::{thesis_studies, EccentricPoint};
use serde::Serialize;

use crate::rundir::output::{RunDir, Written};
use crate::rundir::report::{report, Headline, Reported, Summary};

/// Options of `stripes eccentricity`. The four configurations are the thesis' (Fig 4.4, 4.7,
/// 4.10): linear dashpot and viscoelastic spheres, smooth and with Cundall-Strack friction.
#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Number of eccentricities, evenly spaced in [0, --max-e].
    #[arg(long, default_value_t = 50)]
    pub points: usize,
    /// Largest eccentricity.
    #[arg(long, default_value_t = 0.98)]
    pub max_e: f64,
    /// Steps per estimated contact time.
    #[arg(long, default_value_t = 1000.0)]
    pub steps_per_contact: f64,
    /// Output directory.
    #[arg(long, default_value = "out/eccentricity")]
    pub out: PathBuf,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
}

/// What the study found: `summary.json`, field for field.
#[derive(Serialize)]
struct EccentricitySummary {
    studies: Vec<Study>,
    #[serde(flatten)]
    written: Written,
}

/// One configuration's curves in a few numbers.
#[derive(Serialize)]
struct Study {
    study: &'static str,
    eps_n_hs_zero_crossing_e: Option<f64>,
    eps_n_hs_min: f64,
    eps_n_max_deviation_from_1: f64,
    phi_max: f64,
}

impl Summary for EccentricitySummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

/// Eccentricity at which eps_n^HS changes sign (linear interpolation), if it does.
fn zero_crossing(points: &[EccentricPoint]) -> Option<f64> {
    points.windows(2).find(|w| w[0].eps_n_hs > 0.0 && w[1].eps_n_hs <= 0.0).map(|w| {
        let (a, b) = (&w[0], &w[1]);
        a.e + (b.e - a.e) * a.eps_n_hs / (a.eps_n_hs - b.eps_n_hs)
    })
}

pub fn run(args: Args) -> Reported {
    if args.points < 2 || !(0.0..1.0).contains(&args.max_e) {
        return Err("--points must be >= 2 and --max-e in [0, 1)".into());
    }
    let es: Vec<f64> = (0..args.points).map(|k| args.max_e * k as f64 / (args.points - 1) as f64).collect();
    crate::rundir::output::claim(&args.out, args.writing.force)?;
    let mut dir = RunDir::create(&args.out, &args)?;
    let (mut hs, mut en, mut phi) = (
        LinePlot::new(
            "Hard-sphere coefficient of normal restitution (eq 4.1)",
            "impact eccentricity e",
            "eps_n^HS",
        ),
        LinePlot::new("Coefficient of normal restitution (eq 4.2)", "impact eccentricity e", "eps_n"),
        LinePlot::new("Reorientation of the normal (eq 4.3)", "impact eccentricity e", "phi (rad)"),
    );
    let mut summary = Vec::new();
    let mut header = vec!["e".to_string()];
    let mut columns: Vec<Vec<f64>> = vec![es.clone()];
    for study in thesis_studies() {
        let pts = study.sweep(&es, args.steps_per_contact)?;
        let slug = study.name.replace(", ", "_");
        for (name, f) in [
            ("eps_n_hs", (|p: &EccentricPoint| p.eps_n_hs) as fn(&EccentricPoint) -> f64),
            ("eps_n", |p| p.eps_n),
            ("phi", |p| p.phi),
            ("t_c", |p| p.t_c),
        ] {
            header.push(format!("{slug}_{name}"));
            columns.push(pts.iter().map(f).collect());
        }
        let mark = if study.name.ends_with("friction") {
            Mark::Dashed
        } else {
            Mark::Line
        };
        hs = hs.series(study.name, pts.iter().map(|p| (p.e, p.eps_n_hs)).collect(), mark);
        en = en.series(study.name, pts.iter().map(|p| (p.e, p.eps_n)).collect(), mark);
        phi = phi.series(study.name, pts.iter().map(|p| (p.e, p.phi)).collect(), mark);
        summary.push(Study {
            study: study.name,
            eps_n_hs_zero_crossing_e: zero_crossing(&pts),
            eps_n_hs_min: pts.iter().map(|p| p.eps_n_hs).fold(f64::INFINITY, f64::min),
            eps_n_max_deviation_from_1: pts.iter().map(|p| (p.eps_n - 1.0).abs()).fold(0.0, f64::max),
            phi_max: pts.iter().map(|p| p.phi).fold(0.0, f64::max),
        });
    }
    let rows: Vec<Vec<f64>> = (0..es.len()).map(|k| columns.iter().map(|c| c[k]).collect()).collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    dir.csv("eccentricity.csv", &header, &rows)?;
    dir.plot("eps_n_hs", &hs)?;
    dir.plot("eps_n", &en)?;
    dir.plot("phi", &phi)?;
    let summary = EccentricitySummary {
        studies: summary,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    report(summary)
}
