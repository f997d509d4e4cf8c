//! `stripes analyze RUN_DIR`: density map and stripes of a run's snapshots.

use std::path::PathBuf;

use analysis::density::area_fraction_cells;
use analysis::plot::{Heatmap, LinePlot, Mark};
use analysis::snapshot::read_snapshots;
use analysis::stripes::{detect, onset, StripeParams};
use serde::Serialize;
use serde_json::json;

use crate::output::{CliError, RunDir};

#[derive(clap::Args, Debug, Serialize)]
pub struct Args {
    /// A run directory (holding snapshots.bin) or a snapshots.bin file.
    pub input: PathBuf,
    /// Output directory (default: <RUN_DIR>/analysis).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Cell width of the density map (m); the area fraction is averaged exactly per cell.
    #[arg(long, default_value_t = 1e-3)]
    pub cell: f64,
    /// Stripe threshold on the area fraction (default: 1.5 x the layer's mean).
    #[arg(long)]
    pub threshold: Option<f64>,
    /// Minimum stripe width (m; default: two mean grain diameters).
    #[arg(long)]
    pub min_width: Option<f64>,
}

pub fn run(args: Args) -> Result<String, CliError> {
    let file = if args.input.is_dir() {
        args.input.join("snapshots.bin")
    } else {
        args.input.clone()
    };
    let (header, frames) = read_snapshots(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    if frames.is_empty() {
        return Err(format!("{} holds no complete frame", file.display()).into());
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| file.parent().unwrap_or(std::path::Path::new(".")).join("analysis"));
    let mut dir = RunDir::create(&out, &args)?;
    let cells = ((header.length / args.cell).round() as usize).max(1);
    let n = header.radii.len() as f64;
    let mean_phi = header.radii.iter().map(|r| std::f64::consts::PI * r * r).sum::<f64>() / (header.length * header.width);
    let mean_d = 2.0 * header.radii.iter().sum::<f64>() / n;
    let mut params = StripeParams::default_for(mean_phi, mean_d);
    if let Some(t) = args.threshold {
        params.threshold = t;
    }
    if let Some(w) = args.min_width {
        params.min_width = w;
    }

    let mut map = Vec::with_capacity(frames.len());
    let (mut times, mut counts) = (Vec::new(), Vec::new());
    let mut stripe_rows = Vec::new();
    for f in &frames {
        let x: Vec<f64> = f.pos.iter().map(|p| p[0]).collect();
        let phi = area_fraction_cells(&x, &header.radii, header.length, header.width, cells);
        let stripes = detect(&phi, header.length, &params);
        for s in &stripes {
            stripe_rows.push(vec![f.time, s.center, s.width, s.mass]);
        }
        times.push(f.time);
        counts.push(stripes.len());
        map.push(phi);
    }
    let onset_s = onset(&times, &counts);
    let final_count = *counts.last().expect("at least one frame");

    let mut header_row = vec!["t".to_string()];
    header_row.extend((0..cells).map(|c| format!("x{:.5}", (c as f64 + 0.5) * header.length / cells as f64)));
    let rows: Vec<Vec<f64>> = times
        .iter()
        .zip(&map)
        .map(|(t, phi)| std::iter::once(*t).chain(phi.iter().copied()).collect())
        .collect();
    let hr: Vec<&str> = header_row.iter().map(String::as_str).collect();
    dir.csv("density_map.csv", &hr, &rows)?;
    let count_rows: Vec<Vec<f64>> = times.iter().zip(&counts).map(|(t, c)| vec![*t, *c as f64]).collect();
    dir.csv("stripe_count.csv", &["t", "count"], &count_rows)?;
    dir.csv("stripes.csv", &["t", "center", "width", "mass"], &stripe_rows)?;

    let t_end = *times.last().expect("frames");
    let heat = Heatmap {
        title: "Projected area fraction phi(x, t)".into(),
        x_label: "x (m)".into(),
        y_label: "t (s)".into(),
        x_range: (0.0, header.length),
        y_range: (times[0], t_end.max(times[0] + 1e-9)),
        values: map,
        colorbar_label: "area fraction".into(),
    };
    let files = heat.save(&out.join("density_map")).map_err(|e| format!("density map: {e}"))?;
    dir.note_files(files);
    let count_plot = LinePlot::new("Stripes over time", "t (s)", "stripe count").series(
        "stripes",
        times.iter().zip(&counts).map(|(t, c)| (*t, *c as f64)).collect(),
        Mark::LinePoints,
    );
    dir.plot("stripe_count", &count_plot)?;
    dir.finish(json!({
        "input": file.display().to_string(),
        "frames": frames.len(),
        "particles": header.radii.len(),
        "mean_area_fraction": mean_phi,
        "stripe_params": params,
        "stripe_count_final": final_count,
        "stripe_onset_s": onset_s,
    }))
}
