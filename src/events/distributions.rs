//! The velocity distributions of an event-driven run and the free times between
//! collisions, the mixture paper's (seed 001) Figs 8, 9 and 12:
//! - `velocity_distribution.csv`: v_x rescaled by its root mean square, per species, beside
//!   the paper's fit and the unit Gaussian (Fig. 8, translational);
//! - `angular_distribution.csv`: the spin w rescaled likewise (Fig. 8, rotational);
//! - `velocity_by_height.csv`: both, per species, in the bottom, middle and top thirds of the
//!   box's height (Fig. 12, on the tall box);
//! - `free_times.csv`: the free times per species beside an elastic gas (Fig. 9).
//!
//! Each comes with a plot of the same name (log scale), drawn from the observer's evenly
//! thinned record of velocities (`events::observe::Observer`).

use analysis::plot::{LinePlot, Mark};
use events::observe::Observer;
use events::Simulation;

use crate::rundir::output::{CliError, RunDir};

/// Writes every distribution that has data.
pub fn write(dir: &mut RunDir, obs: &Observer, sim: &Simulation) -> Result<(), CliError> {
    translational(dir, obs)?;
    angular(dir, obs)?;
    by_height(dir, obs, sim.config.height)?;
    free_times(dir, sim, obs.vx.len())
}

/// Fewest values a distribution is drawn from.
const MIN_VALUES: usize = 100;

/// The density of `v / <v^2>^(1/2)` on 60 bins over [-6, 6]; empty with fewer than
/// [`MIN_VALUES`] values or none moving.
fn rescaled(v: &[f64]) -> Vec<(f64, f64)> {
    let rms = (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    if v.len() < MIN_VALUES || rms <= 0.0 || !rms.is_finite() {
        return Vec::new();
    }
    let c: Vec<f64> = v.iter().map(|x| x / rms).collect();
    analysis::histogram::density(&c, -6.0, 6.0, 60)
}

/// The unit Gaussian, the reference of every rescaled distribution.
fn gauss(c: f64) -> f64 {
    (-0.5 * c * c).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// Points on [-6, 6] for the reference curves.
fn grid() -> impl Iterator<Item = f64> {
    (0..=120).map(|k| -6.0 + 0.1 * k as f64)
}

/// `plot` with the unit Gaussian drawn where a log axis can show it.
fn gaussian(plot: LinePlot) -> LinePlot {
    plot.series(
        "Gaussian",
        grid().map(|c| (c, gauss(c))).filter(|(_, p)| *p > 1e-7).collect(),
        Mark::Line,
    )
}

/// A reference curve drawn beside the data: its column name and its density.
type Reference = (&'static str, fn(f64) -> f64);

/// One measured distribution: its column in the table, its label in the plot, its density.
struct Named {
    column: String,
    label: String,
    density: Vec<(f64, f64)>,
}

/// Per species `k` (from 1): column `{prefix}{k}`, label `{label}species {k}`.
fn per_species(lists: &[Vec<f64>], prefix: &str, label: &str) -> Vec<Named> {
    lists
        .iter()
        .enumerate()
        .map(|(k, v)| Named {
            column: format!("{prefix}{}", k + 1),
            label: format!("{label}species {}", k + 1),
            density: rescaled(v),
        })
        .collect()
}

/// Named rescaled distributions (all on the same bins) as one table, `c` first, then the
/// optional `reference` and the Gaussian, and as one plot.
fn table(dir: &mut RunDir, stem: &str, title: &str, x_label: &str, named: &[Named], reference: Option<Reference>) -> Result<(), CliError> {
    let named: Vec<&Named> = named.iter().filter(|n| !n.density.is_empty()).collect();
    let Some(first) = named.first().map(|n| &n.density) else {
        return Ok(());
    };
    let mut header = vec!["c"];
    header.extend(named.iter().map(|n| n.column.as_str()));
    header.extend(reference.map(|(n, _)| n));
    header.push("gaussian");
    let rows: Vec<Vec<f64>> = (0..first.len())
        .map(|b| {
            let c = first[b].0;
            let mut row = vec![c];
            row.extend(named.iter().map(|n| n.density[b].1));
            row.extend(reference.map(|(_, f)| f(c)));
            row.push(gauss(c));
            row
        })
        .collect();
    dir.csv(&format!("{stem}.csv"), &header, &rows)?;
    let mut plot = LinePlot::new(title, x_label, "P(c)").log_y();
    for n in &named {
        plot = plot.series(
            &n.label,
            n.density.iter().copied().filter(|(_, p)| *p > 0.0).collect(),
            Mark::Points,
        );
    }
    if let Some((name, f)) = reference {
        plot = plot.series(name, grid().map(|c| (c, f(c))).collect(), Mark::Dashed);
    }
    dir.plot(stem, &gaussian(plot))
}

/// The spin of each species rescaled by its rms (Fig. 8's rotational half).
fn angular(dir: &mut RunDir, obs: &Observer) -> Result<(), CliError> {
    let named = per_species(&obs.w, "p_", "");
    table(
        dir,
        "angular_distribution",
        "Spin, rescaled by its rms",
        "c = w / <w^2>^(1/2)",
        &named,
        None,
    )
}

/// The thirds of a box of `height` (from the floor's mean position), by name.
const REGIONS: [&str; 3] = ["bottom", "middle", "top"];

/// v_x and w of each species in each third of the box's height, each rescaled by its own rms
/// (Fig. 12); a third with fewer than [`MIN_VALUES`] samples is left out.
fn by_height(dir: &mut RunDir, obs: &Observer, height: f64) -> Result<(), CliError> {
    let third = |z: f64| ((3.0 * z / height).floor().max(0.0) as usize).min(2);
    for (stem, lists, title, label) in [
        (
            "velocity_by_height",
            &obs.vx,
            "Horizontal velocity by height, rescaled",
            "c = v_x / <v_x^2>^(1/2)",
        ),
        ("angular_by_height", &obs.w, "Spin by height, rescaled", "c = w / <w^2>^(1/2)"),
    ] {
        let mut named = Vec::new();
        for (r, region) in REGIONS.iter().enumerate() {
            let within: Vec<Vec<f64>> = lists
                .iter()
                .zip(&obs.z)
                .map(|(v, z)| v.iter().zip(z).filter(|(_, z)| third(**z) == r).map(|(v, _)| *v).collect())
                .collect();
            named.extend(per_species(&within, &format!("{region}_"), &format!("{region}, ")));
        }
        table(dir, stem, title, label, &named, None)?;
    }
    Ok(())
}

/// The mixture paper's distributions: v_x rescaled by its root mean square, per species,
/// beside the paper's fit `f(c) = A / (exp(beta |c|^alpha) + exp(-beta |c|^alpha))` (A =
/// 1.068, beta = 1.74, alpha = 0.918, its Fig. 8) and the unit Gaussian
/// (`velocity_distribution.csv`); and the free times between a grain's collisions, per
/// species, beside the exponential of an elastic gas with the same mean free time
/// (`free_times.csv`, its Fig. 9; counted from t = 0).
/// v_x of each species beside the paper's fit `f(c) = A / (exp(beta |c|^alpha) +
/// exp(-beta |c|^alpha))` with A = 1.068, beta = 1.74, alpha = 0.918 (Fig. 8).
fn translational(dir: &mut RunDir, obs: &Observer) -> Result<(), CliError> {
    let named = per_species(&obs.vx, "p_", "");
    let title = "Horizontal velocity, rescaled by its rms";
    table(
        dir,
        "velocity_distribution",
        title,
        "c = v_x / <v_x^2>^(1/2)",
        &named,
        Some(("paper_fit", paper_fit)),
    )
}

/// The mixture paper's fit to its rescaled v_x distribution (Fig. 8).
fn paper_fit(c: f64) -> f64 {
    let x = 1.74 * c.abs().powf(0.918);
    1.068 / (x.exp() + (-x).exp())
}

fn free_times(dir: &mut RunDir, sim: &Simulation, species: usize) -> Result<(), CliError> {
    let times: Vec<&Vec<f64>> = sim.free_times.iter().take(species).map(|t| &t.kept).collect();
    if times.iter().all(|t| !t.is_empty()) {
        let means: Vec<f64> = times.iter().map(|t| t.iter().sum::<f64>() / t.len() as f64).collect();
        let top = 5.0 * means.iter().copied().fold(0.0, f64::max);
        let hists: Vec<Vec<(f64, f64)>> = times.iter().map(|t| analysis::histogram::density(t, 0.0, top, 50)).collect();
        let mut header = vec!["t_s".to_string()];
        for k in 1..=species {
            header.push(format!("p_{k}_per_s"));
            header.push(format!("elastic_{k}_per_s"));
        }
        let rows: Vec<Vec<f64>> = (0..hists[0].len())
            .map(|b| {
                let t = hists[0][b].0;
                let mut row = vec![t];
                for (h, m) in hists.iter().zip(&means) {
                    row.push(h[b].1);
                    row.push((-t / m).exp() / m);
                }
                row
            })
            .collect();
        let refs: Vec<&str> = header.iter().map(String::as_str).collect();
        dir.csv("free_times.csv", &refs, &rows)?;
        let mut plot = LinePlot::new("Free times between collisions", "t (s)", "P(t) (1/s)").log_y();
        for (k, (h, m)) in hists.iter().zip(&means).enumerate() {
            plot = plot
                .series(
                    &format!("species {}", k + 1),
                    h.iter().copied().filter(|(_, p)| *p > 0.0).collect(),
                    Mark::Points,
                )
                .series(
                    &format!("elastic gas, same mean, species {}", k + 1),
                    h.iter().map(|(t, _)| (*t, (-t / m).exp() / m)).collect(),
                    Mark::Dashed,
                );
        }
        dir.plot("free_times", &plot)?;
    }
    Ok(())
}
