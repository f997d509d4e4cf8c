//! `stripes analyze RUN_DIR|SNAPSHOTS|DUMP`: the shared analysis of a DEM run, an automaton
//! run or a LAMMPS dump (see `analysis::input`), written as CSV tables, PNG + SVG plots and
//! `summary.json` by the pipeline ([`crate::analyze::analyze`]); this module turns the
//! command line into its options.

use std::path::PathBuf;

use analysis::report::Options;
use serde::Serialize;

use crate::analyze::{analyze, AnalysisOptions, MapFrame};
use crate::rundir::output::CliError;
use crate::rundir::report::{report, Reported};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// A run directory (holding snapshots.bin), a snapshots.bin file (DEM or automaton) or a
    /// LAMMPS text dump (`ITEM: ATOMS id radius x y z [vx vy vz]`).
    pub input: PathBuf,
    /// Output directory (default: <RUN_DIR>/analysis, or <DUMP>.analysis beside a dump).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    #[serde(flatten)]
    pub writing: crate::cli::args::Writing,
    /// Cell width of the density map (m); the area fraction is averaged exactly per cell.
    #[arg(long, default_value_t = 1e-3, value_parser = crate::cli::values::positive, allow_negative_numbers = true)]
    pub cell: f64,
    /// Stripe threshold on the area fraction (default: 1.5 x the layer's mean, at most halfway from the mean to the jammed 0.82)
    #[arg(long, value_parser = crate::cli::values::positive)]
    pub threshold: Option<f64>,
    /// Minimum stripe width (m; default: five mean grain diameters).
    #[arg(long)]
    pub min_width: Option<f64>,
    /// Time step of a LAMMPS dump (s): time = timestep x dt. Ignored for snapshots.
    #[arg(long, default_value = "8e-6")]
    pub dt: f64,
    /// Drive period for the MSD per period (s; default: 1 / drive.frequency from the run's
    /// config.json, else the median snapshot spacing).
    #[arg(long)]
    pub period: Option<f64>,
    /// Index of the tracer grain (0-based; LAMMPS: in order of atom id).
    #[arg(long, default_value_t = 0)]
    pub tracer: usize,
    /// Fraction of the frames, at the end, taken as the final state for the phase.
    #[arg(long, default_value_t = 0.1)]
    pub tail: f64,
    /// The layer is periodic in y too (walls off): y displacements use the minimum image.
    #[arg(long)]
    pub periodic_y: bool,
    /// Window FROM,TO (s) of the MSD plateau a1 before stripes (default: the first three
    /// quarters of the time before the onset; without onset, the first half of the run).
    #[arg(long, value_parser = crate::cli::values::window, value_name = "FROM,TO")]
    pub plateau_before: Option<(f64, f64)>,
    /// Window FROM,TO (s) of the MSD plateau a2 after stripes (default: from the onset plus a
    /// quarter of the remaining time; without onset, the second half of the run).
    #[arg(long, value_parser = crate::cli::values::window, value_name = "FROM,TO")]
    pub plateau_after: Option<(f64, f64)>,
    /// Classifier: below this mobility (mean diameters per period) the phase is `nothing`.
    #[arg(long, default_value_t = 0.1, value_parser = crate::cli::values::non_negative)]
    pub mobility_min: f64,
    /// Classifier: at or above this contrast (x random layer), with stripes, the phase is `stripes`.
    #[arg(long, default_value_t = 2.0, value_parser = crate::cli::values::non_negative)]
    pub contrast_min: f64,
    /// Classifier: drive periods over which a band must hold its place (in the time-averaged
    /// profile) to count as a stationary stripe, whatever the contrast.
    #[arg(long, default_value_t = 10.0, value_parser = crate::cli::values::positive)]
    pub persistence_periods: f64,
    /// Times (s) of the top views (x-y, in the tray's frame) drawn in top_view.png, e.g.
    /// 1,10,100; each is the stroboscopic frame (at the drive's turning point) nearest it
    /// (default: the first, middle and last stroboscopic frames).
    #[arg(long, value_delimiter = ',', value_name = "T,...", allow_negative_numbers = true)]
    pub top_view: Vec<f64>,
    /// The frame of density_map.png: `tray` (one frame per drive period at its turning point,
    /// positions relative to the tray, as the experiment's camera) or `lab` (every frame,
    /// positions as stored).
    #[arg(long, default_value = "tray", value_name = "tray|lab")]
    pub map_frame: MapFrame,
}

impl Args {
    /// The library options these arguments select.
    pub fn options(&self) -> Options {
        let mut o = Options {
            cell: self.cell,
            threshold: self.threshold,
            min_width: self.min_width,
            period: self.period,
            periodic_y: self.periodic_y,
            tracer: self.tracer,
            tail_fraction: self.tail,
            plateau_before: self.plateau_before,
            plateau_after: self.plateau_after,
            ..Options::default()
        };
        o.classify.mobility_min = self.mobility_min;
        o.classify.contrast_min = self.contrast_min;
        o.classify.persistence_periods = self.persistence_periods;
        o
    }

    /// The pipeline's options these arguments select.
    pub fn analysis_options(&self) -> Result<AnalysisOptions, CliError> {
        if let Some(t) = self.top_view.iter().find(|t| !t.is_finite()) {
            return Err(format!("--top-view: times must be finite numbers of seconds, got {t}").into());
        }
        Ok(AnalysisOptions {
            out: self.out.clone(),
            force: self.writing.force,
            dt: self.dt,
            options: self.options(),
            top_view: self.top_view.clone(),
            description: None,
            map_frame: self.map_frame,
        })
    }
}

pub fn run(args: Args) -> Reported {
    report(analyze(&args.input, &args.analysis_options()?)?)
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

    /// The analysis other commands make of their runs
    /// ([`AnalysisOptions::into_dir`]) is the command line's default one.
    #[test]
    fn default_matches_the_command_line_defaults() {
        let parsed = Cli::parse_from(["analyze", "run", "--force", "--out", "x"]).args;
        assert_eq!(parsed.options(), Options::default());
        let into_dir = AnalysisOptions::into_dir("x".into());
        assert_eq!(
            serde_json::to_value(parsed.analysis_options().unwrap()).unwrap(),
            serde_json::to_value(into_dir).unwrap()
        );
    }
}
