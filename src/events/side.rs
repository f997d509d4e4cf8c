//! The side cluster of an event-driven run on disk: the left-right imbalance of the grains
//! over time (`side_imbalance.csv` and its plot) and its statistics for the summary
//! (`events::side`: spread against independent grains, how long a side is held, the
//! correlation time). The mixture paper's cluster at a side wall (seed 001, section 3.3).

use analysis::plot::{LinePlot, Mark};
use events::observe::Observer;
use events::side::{self, SideStats};
use serde::Serialize;

use crate::rundir::output::{CliError, RunDir};

/// The summary's `side_cluster` entry.
#[derive(Clone, Debug, Serialize)]
pub struct SideSummary {
    /// Values in the record, and the time between them (s).
    pub samples: usize,
    pub interval_s: f64,
    /// RMS of `(N_left - N_right) / N`, and its value for independent grains, `1 / sqrt(N)`.
    pub imbalance_rms: f64,
    pub imbalance_rms_independent: f64,
    /// A side counts as held once `|s|` passes this, `max(2 / sqrt(N), RMS / 2)`.
    pub threshold: f64,
    /// Complete times a side was held: how many, their mean and standard error (s; null
    /// when fewer than two).
    pub residences: usize,
    pub residence_mean_s: Option<f64>,
    pub residence_stderr_s: Option<f64>,
    /// Integrated autocorrelation time of the imbalance (s).
    pub correlation_time_s: f64,
}

impl SideSummary {
    fn new(st: &SideStats, interval_s: f64) -> Self {
        let n = st.residences.len();
        let (mean, stderr) = analysis::stats::mean_stderr(&st.residences);
        SideSummary {
            samples: st.samples,
            interval_s,
            imbalance_rms: st.rms,
            imbalance_rms_independent: st.rms_independent,
            threshold: st.threshold,
            residences: n,
            residence_mean_s: (n >= 1).then_some(mean),
            residence_stderr_s: (n >= 2).then_some(stderr),
            correlation_time_s: st.correlation_time,
        }
    }
}

/// Writes the imbalance record of a run sampled every `dt_sample` seconds with `grains`
/// grains, and returns its statistics; nothing for a run without a record (a periodic box).
pub fn write(dir: &mut RunDir, obs: &Observer, dt_sample: f64, grains: usize) -> Result<Option<SideSummary>, CliError> {
    let s = &obs.side.kept;
    if s.is_empty() {
        return Ok(None);
    }
    let dt = dt_sample * obs.side.stride as f64;
    let st = side::stats(s, dt, grains);
    let rows: Vec<Vec<f64>> = s.iter().enumerate().map(|(k, x)| vec![k as f64 * dt, *x]).collect();
    dir.csv("side_imbalance.csv", &["t_s", "imbalance"], &rows)?;
    let line = |y: f64| vec![(0.0, y), ((s.len() - 1) as f64 * dt, y)];
    let plot = LinePlot::new(
        "Left-right imbalance (N_left - N_right) / N, from the first sample",
        "t (s)",
        "imbalance",
    )
    .series("imbalance", rows.iter().map(|r| (r[0], r[1])).collect(), Mark::Line)
    .series("left side held beyond", line(st.threshold), Mark::Dashed)
    .series("right side held beyond", line(-st.threshold), Mark::Dashed);
    dir.plot("side_imbalance", &plot)?;
    Ok(Some(SideSummary::new(&st, dt)))
}
