//! `stripes contact-time`: Fig 3.5.

use std::path::PathBuf;

use analysis::plot::{LinePlot, Mark};
use particles::experiment::contact_time::{study, ContactTimeCase};
use serde::Serialize;
use serde_json::json;

use crate::rundir::output::{RunDir, Written};
use crate::rundir::report::{report, Headline, Reported, Summary};

/// Options of `stripes contact-time`; the base point is Fig 3.5's (R = 0.5 mm, Y = 1e6 Pa,
/// A = 8.5e-6 s, v = 2 mm/s, rho = 2500 kg/m^3, nu = 0.3).
#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// Values per sweep.
    #[arg(long, default_value_t = 13, value_parser = crate::cli::values::at_least_two)]
    pub points: usize,
    /// Steps per estimated contact time.
    #[arg(long, default_value_t = 1000.0)]
    pub steps_per_contact: f64,
    /// Output directory.
    #[arg(long, default_value = "out/contact-time")]
    pub out: PathBuf,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
}

/// What the sweeps found: `summary.json`, field for field.
#[derive(Serialize)]
struct ContactTimeSummary {
    /// Each swept parameter's range of `t_c / t_c(eq 3.19)`.
    sweeps: std::collections::BTreeMap<&'static str, Ratios>,
    base_t_c: f64,
    #[serde(flatten)]
    written: Written,
}

#[derive(Serialize)]
struct Ratios {
    min_ratio_to_eq_3_19: f64,
    max_ratio_to_eq_3_19: f64,
}

impl Summary for ContactTimeSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

pub fn run(args: Args) -> Reported {
    let base = ContactTimeCase::default();
    let rows = study(base, args.points, args.steps_per_contact)?;
    crate::rundir::output::claim(&args.out, args.writing.force)?;
    let mut dir = RunDir::create(&args.out, &json!({ "args": &args, "base": base }))?;
    let mut sweeps = std::collections::BTreeMap::new();
    for (param, label, unit, log_x) in [
        ("dissipation", "dissipation A", "s", false),
        ("radius", "radius R", "m", true),
        ("young", "Young's modulus Y", "Pa", true),
        ("speed", "impact speed v", "m/s", true),
    ] {
        let sel: Vec<_> = rows.iter().filter(|r| r.parameter == param).collect();
        let table: Vec<Vec<f64>> = sel
            .iter()
            .map(|r| vec![r.value, r.t_c, r.t_c_eq_3_19, r.t_c / r.t_c_eq_3_19, r.eps_n])
            .collect();
        dir.csv(
            &format!("contact_time_{param}.csv"),
            &[param, "t_c", "t_c_eq_3_19", "ratio", "eps_n"],
            &table,
        )?;
        let mut plot = LinePlot::new(
            &format!("Contact time against {label}"),
            &format!("{label} ({unit})"),
            "contact time t_c (s)",
        )
        .series(
            "DEM (viscoelastic)",
            sel.iter().map(|r| (r.value, r.t_c)).collect(),
            Mark::LinePoints,
        )
        .series(
            "eq 3.19 (undamped)",
            sel.iter().map(|r| (r.value, r.t_c_eq_3_19)).collect(),
            Mark::Dashed,
        );
        if log_x {
            plot = plot.log_x().log_y();
        }
        dir.plot(&format!("contact_time_{param}"), &plot)?;
        let ratios: Vec<f64> = sel.iter().map(|r| r.t_c / r.t_c_eq_3_19).collect();
        sweeps.insert(
            param,
            Ratios {
                min_ratio_to_eq_3_19: ratios.iter().cloned().fold(f64::INFINITY, f64::min),
                max_ratio_to_eq_3_19: ratios.iter().cloned().fold(0.0, f64::max),
            },
        );
    }
    let summary = ContactTimeSummary {
        sweeps,
        base_t_c: rows[0].t_c_eq_3_19,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    report(summary)
}
