//! The files of an analysis directory: its CSV tables and its plots, all from one
//! [`Report`].

use analysis::camera::Camera;
use analysis::density::CountProfile;
use analysis::input::Geometry;
use analysis::plot::{Heatmap, LinePlot, Mark, TopView};
use analysis::report::Report;

use crate::rundir::output::CliError as Error;
use crate::rundir::output::RunDir;

pub(super) fn write_tables(dir: &mut RunDir, r: &Report, run: &analysis::input::Run) -> Result<(), Error> {
    let mut names = vec!["t".to_string()];
    names.extend((0..r.cells).map(|c| format!("x{:.6}", (c as f64 + 0.5) * r.cell)));
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let rows: Vec<Vec<f64>> = r
        .times
        .iter()
        .zip(&r.density_map)
        .map(|(t, phi)| std::iter::once(*t).chain(phi.iter().copied()).collect())
        .collect();
    dir.csv("density_map.csv", &names, &rows)?;
    let rows: Vec<Vec<f64>> = r
        .coarsening
        .iter()
        .zip(&r.contrast_series)
        .map(|(c, k)| vec![c.time, c.count as f64, c.mean_width, c.mean_mass, c.mass_fraction, *k])
        .collect();
    dir.csv(
        "coarsening.csv",
        &["t", "count", "mean_width", "mean_mass", "mass_fraction", "contrast"],
        &rows,
    )?;
    let rows: Vec<Vec<f64>> = r
        .times
        .iter()
        .zip(&r.stripes)
        .flat_map(|(t, s)| s.iter().map(move |s| vec![*t, s.start, s.center, s.width, s.mass]))
        .collect();
    dir.csv("stripes.csv", &["t", "start", "center", "width", "mass"], &rows)?;
    // Structure: the S(k) peak and the fraction in bands per frame, the late S(k), the late
    // band widths and gaps.
    let nan = f64::NAN;
    let rows: Vec<Vec<f64>> = r
        .structure
        .iter()
        .map(|p| {
            let (k, spacing, height, width) = p.peak.map_or((nan, nan, nan, nan), |q| (q.k, q.spacing, q.height, q.width));
            vec![p.time, k, spacing, height, width, p.in_band_fraction]
        })
        .collect();
    dir.csv(
        "structure.csv",
        &[
            "t",
            "peak_k_per_m",
            "spacing_m",
            "peak_height",
            "peak_fwhm_per_m",
            "in_band_fraction",
        ],
        &rows,
    )?;
    let rows: Vec<Vec<f64>> = r.late.s.iter().map(|&(k, s)| vec![k, 2.0 * std::f64::consts::PI / k, s]).collect();
    dir.csv("structure_factor_late.csv", &["k_per_m", "wavelength_m", "S"], &rows)?;
    let n = r.late.band_widths.len().max(r.late_gaps.len());
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|j| {
            vec![
                r.late.band_widths.get(j).copied().unwrap_or(nan),
                r.late_gaps.get(j).copied().unwrap_or(nan),
            ]
        })
        .collect();
    dir.csv("bands_late.csv", &["band_width_m", "gap_m"], &rows)?;
    // The classifier's thresholds varied around the given ones: which phase each set gives.
    let mut text = String::from("mobility_min,contrast_min,persistence_periods,stationary_stripe_count,phase\n");
    for v in &r.sensitivity.variants {
        let p = v.params;
        text.push_str(&format!(
            "{},{},{},{},{}\n",
            p.mobility_min,
            p.contrast_min,
            p.persistence_periods,
            v.stationary_stripe_count,
            v.phase.name()
        ));
    }
    dir.text("phase_sensitivity.csv", &text)?;
    let sk = LinePlot::new("Structure factor of the late frames", "wavelength 2 pi / k (m)", "S(k)")
        .series(
            "S(k)",
            r.late.s.iter().map(|&(k, s)| (2.0 * std::f64::consts::PI / k, s)).collect(),
            Mark::LinePoints,
        )
        .series(
            "independent grains",
            r.late.s.iter().map(|&(k, _)| (2.0 * std::f64::consts::PI / k, 1.0)).collect(),
            Mark::Dashed,
        )
        .log_x()
        .legend(analysis::plot::LegendCorner::UpperLeft)
        .include_y(0.0)
        .include_y(1.25 * r.late.s.iter().map(|p| p.1).fold(1.0, f64::max));
    dir.plot("structure_factor", &sk)?;
    let rows: Vec<Vec<f64>> = r.msd.iter().map(|p| vec![p.time, p.d]).collect();
    dir.csv("msd.csv", &["t", "D"], &rows)?;
    let rows: Vec<Vec<f64>> = r
        .autocorrelation
        .iter()
        .map(|a| vec![a.lag as f64, a.lag_s, a.raw, a.normalised])
        .collect();
    dir.csv("autocorrelation.csv", &["lag", "lag_s", "C_raw", "C_normalised"], &rows)?;
    let rows: Vec<Vec<f64>> = r
        .tracer
        .points
        .iter()
        .map(|p| vec![p.time, p.x, p.y, p.z, p.x_unwrapped, p.vx])
        .collect();
    dir.csv("tracer.csv", &["t", "x", "y", "z", "x_unwrapped", "vx"], &rows)?;
    let d = &r.radii;
    let rows: Vec<Vec<f64>> = (0..d.whole.len())
        .map(|k| vec![d.edges[k], d.edges[k + 1], d.whole[k], d.stripes[k]])
        .collect();
    dir.csv("radii.csv", &["r_from", "r_to", "pdf_whole", "pdf_stripes"], &rows)?;
    // The exact binning-free count density (Appendix A) of the last frame.
    let last = run.frames.last().expect("analyze refuses empty runs");
    let x: Vec<f64> = last.pos.iter().map(|p| p[0]).collect();
    let p = CountProfile::new(&x, &run.header.radii, run.header.length);
    let rows: Vec<Vec<f64>> = (0..p.breaks.len())
        .map(|k| vec![p.breaks[k], p.breaks.get(k + 1).copied().unwrap_or(p.length), p.values[k] as f64])
        .collect();
    dir.csv("count_density_final.csv", &["x_from", "x_to", "grains"], &rows)
}

/// The titles and axis labels of the plots that mean something else for each geometry: a
/// tray seen from above has an area fraction and stripes; an event-driven box seen from the
/// side has grains stacked in z, so its "area fraction" is a column load (grains' projected
/// area over the cell's, many layers deep) and its bands are dense columns.
pub(super) struct Labels {
    pub map_title: &'static str,
    pub map_scale: &'static str,
    pub count_title: &'static str,
    pub count_axis: &'static str,
}

pub(super) fn labels(geometry: Geometry) -> Labels {
    match geometry {
        Geometry::Tray => Labels {
            map_title: "Projected area fraction phi(x, t)",
            map_scale: "area fraction",
            count_title: "Stripes over time",
            count_axis: "stripe count",
        },
        Geometry::VerticalBox => Labels {
            map_title: "Vertical box: column load phi(x, t), grains stacked in z (not a packing)",
            map_scale: "column load (projected grain area / cell area)",
            count_title: "Dense columns over time (bands of the column load)",
            count_axis: "dense columns",
        },
    }
}

/// The plots of the report, titled for `geometry`; `density_map.png` draws `camera`'s
/// stroboscopic tray-frame profiles when given, else every frame as stored.
pub(super) fn draw(dir: &mut RunDir, r: &Report, geometry: Geometry, camera: Option<&Camera>) -> Result<(), Error> {
    let labels = labels(geometry);
    let (frames, times, values) = match camera.filter(|c| !c.profiles.is_empty()) {
        Some(c) => (
            "in the tray frame, at the turning points",
            c.frames.iter().map(|f| f.time).collect::<Vec<_>>(),
            c.profiles.clone(),
        ),
        None => ("every frame, positions as stored", r.times.clone(), r.density_map.clone()),
    };
    let t0 = times[0];
    let t1 = times.last().copied().unwrap_or(t0).max(t0 + 1e-9);
    let heat = Heatmap {
        title: format!("{}, {frames}", labels.map_title),
        x_label: "x (m)".into(),
        y_label: "t (s)".into(),
        x_range: (0.0, r.length),
        y_range: (t0, t1),
        values,
        colorbar_label: labels.map_scale.into(),
        scale: None,
        cell_names: None,
    };
    let files = heat
        .save(&dir.path.join("density_map"))
        .map_err(|e| format!("cannot draw density_map: {e}"))?;
    dir.note_files(files);

    let mut count = LinePlot::new(labels.count_title, "t (s)", labels.count_axis).integer_y().series(
        if geometry == Geometry::Tray { "stripes" } else { "dense columns" },
        r.coarsening.iter().map(|c| (c.time, c.count as f64)).collect(),
        Mark::Line,
    );
    if let Some(on) = r.onset {
        let max = r.coarsening.iter().map(|c| c.count).max().unwrap_or(0) as f64;
        count = count.series(&format!("onset {on:.3} s"), vec![(on, 0.0), (on, max.max(1.0))], Mark::Dashed);
    }
    dir.plot("stripe_count", &count)?;

    let mut msd = LinePlot::new("Mean square displacement per period (eq 3.30)", "t (s)", "D (m^2)").series(
        "D",
        r.msd.iter().map(|p| (p.time, p.d)).collect(),
        Mark::Line,
    );
    // A log axis only when D spans more than a decade and a half (with less, plotters
    // draws no tick labels on it).
    let positive = r.msd.iter().map(|p| p.d).filter(|d| *d > 0.0);
    let (lo, hi) = positive.fold((f64::INFINITY, 0.0f64), |(a, b), d| (a.min(d), b.max(d)));
    if hi > 30.0 * lo {
        msd = msd.log_y();
    }
    for (name, p) in [("a1", r.plateau_before), ("a2", r.plateau_after)] {
        if let Some(p) = p {
            let label = format!("{name} = {:.3e} m^2 on [{:.2}, {:.2}] s", p.value, p.from, p.to);
            msd = msd.series(&label, vec![(p.from, p.value), (p.to, p.value)], Mark::Dashed);
        }
    }
    dir.plot("msd", &msd)?;

    let tr = &r.tracer;
    let path: Vec<(f64, f64)> = tr.points.iter().map(|p| (p.x_unwrapped, p.y)).collect();
    let mut traj = LinePlot::new(
        &format!("Tracer {} (R = {:.3} mm): trajectory", tr.index, tr.radius * 1e3),
        "x, followed across the periodic seam (m)",
        "y (m)",
    )
    .series("path", path.clone(), Mark::Line);
    if let (Some(a), Some(b)) = (path.first(), path.last()) {
        traj = traj.series("start", vec![*a], Mark::Points).series("end", vec![*b], Mark::Points);
    }
    dir.plot("tracer_trajectory", &traj)?;
    // Without velocities (an automaton run, a dump without `vx`) the phase space would be a
    // line at v_x = 0: not drawn.
    if tr.points.iter().any(|p| p.vx != 0.0) {
        let phase = LinePlot::new(
            &format!("Tracer {}: phase space", tr.index),
            "x, followed across the periodic seam (m)",
            "v_x (m/s)",
        )
        .series("snapshots", tr.points.iter().map(|p| (p.x_unwrapped, p.vx)).collect(), Mark::Points);
        dir.plot("tracer_phase_space", &phase)?;
    }

    let d = &r.radii;
    let steps = |v: &[f64]| -> Vec<(f64, f64)> {
        (0..v.len())
            .flat_map(|k| [(d.edges[k] * 1e3, v[k] * 1e-3), (d.edges[k + 1] * 1e3, v[k] * 1e-3)])
            .collect()
    };
    let mut radii = LinePlot::new("Radii: stripes against the whole layer", "R (mm)", "probability density (1/mm)").series(
        &format!("whole layer, mean {:.4} mm", d.mean_whole * 1e3),
        steps(&d.whole),
        Mark::Line,
    );
    if d.in_stripes > 0 {
        radii = radii.series(
            &format!(
                "in stripes ({} over the last {} frames), mean {:.4} mm",
                d.in_stripes,
                d.frames,
                d.mean_stripes * 1e3
            ),
            steps(&d.stripes),
            Mark::Dashed,
        );
    } else {
        // An empty series: the legend says why there is no second curve.
        radii = radii.series(
            &format!("in stripes: no grain in a stripe over the last {} frames", d.frames),
            Vec::new(),
            Mark::Dashed,
        );
    }
    dir.plot("radii", &radii)?;

    let ac = LinePlot::new("Autocorrelation of D (eq 3.32)", "lag (s)", "normalised C").series(
        "C",
        r.autocorrelation.iter().map(|a| (a.lag_s, a.normalised)).collect(),
        Mark::Line,
    );
    dir.plot("autocorrelation", &ac)
}

/// Top views (x-y) of a tray in the tray's frame at `times` (each the stroboscopic frame
/// nearest it), or at the first, middle and last stroboscopic frames: `top_view.png`, grains
/// drawn dark on white as the thesis' inverted camera pictures (Figs 2.11-2.12).
pub(super) fn top_view(dir: &mut RunDir, run: &analysis::input::Run, camera: &Camera, times: &[f64]) -> Result<(), Error> {
    let strobe = &camera.frames;
    if strobe.is_empty() {
        return Ok(());
    }
    let mut picked: Vec<usize> = if times.is_empty() {
        vec![0, strobe.len() / 2, strobe.len() - 1]
    } else {
        times
            .iter()
            .map(|&t| {
                (0..strobe.len())
                    .min_by(|&a, &b| (strobe[a].time - t).abs().total_cmp(&(strobe[b].time - t).abs()))
                    .expect("strobe frames are not empty")
            })
            .collect()
    };
    picked.dedup();
    let h = &run.header;
    let panels = picked
        .iter()
        .map(|&k| {
            let s = strobe[k];
            let f = &run.frames[s.frame];
            let grains = f
                .pos
                .iter()
                .zip(&h.radii)
                .map(|(p, r)| ((p[0] - s.tray_x).rem_euclid(h.length), p[1], *r))
                .collect();
            let n = camera.stripes[k].len();
            (format!("t = {:.3} s, tray frame: {n} stripe(s) counted", f.time), grains)
        })
        .collect();
    let view = TopView {
        title: format!("Top view of the tray ({} grains), at the turning point", h.radii.len()),
        length: h.length,
        width: h.width,
        panels,
    };
    let files = view
        .save(&dir.path.join("top_view"))
        .map_err(|e| format!("cannot draw top_view: {e}"))?;
    dir.note_files(files);
    Ok(())
}

/// The camera's tables: the stroboscopic count, profiles, stripes, tracks and the profile's
/// autocorrelation.
pub(super) fn write_camera(dir: &mut RunDir, c: &Camera, r: &Report) -> Result<(), Error> {
    let nan = f64::NAN;
    let (power, log) = (c.law.power, c.law.logarithmic);
    let fitted = |t: f64| c.law_from.is_some_and(|from| t >= from);
    let rows: Vec<Vec<f64>> = c
        .frames
        .iter()
        .zip(&c.stripes)
        .zip(&c.contrast)
        .map(|((f, s), k)| {
            vec![
                f.time,
                f.tray_x,
                f.offset.unwrap_or(nan),
                s.len() as f64,
                *k,
                power.filter(|_| fitted(f.time)).map_or(nan, |p| p.eval(f.time, true)),
                log.filter(|_| fitted(f.time)).map_or(nan, |p| p.eval(f.time, false)),
            ]
        })
        .collect();
    dir.csv(
        "camera_count.csv",
        &["t", "tray_x", "offset_periods", "count", "contrast", "power_fit", "log_fit"],
        &rows,
    )?;
    let mut names = vec!["t".to_string(), "tray_x".to_string()];
    names.extend((0..r.cells).map(|k| format!("x{:.6}", (k as f64 + 0.5) * r.cell)));
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let rows: Vec<Vec<f64>> = c
        .frames
        .iter()
        .zip(&c.profiles)
        .map(|(f, p)| [f.time, f.tray_x].into_iter().chain(p.iter().copied()).collect())
        .collect();
    dir.csv("camera_profiles.csv", &names, &rows)?;
    let rows: Vec<Vec<f64>> = c
        .frames
        .iter()
        .zip(&c.stripes)
        .flat_map(|(f, s)| s.iter().map(move |s| vec![f.time, s.start, s.center, s.width, s.mass]))
        .collect();
    dir.csv("camera_stripes.csv", &["t", "start", "center", "width", "mass"], &rows)?;
    let rows: Vec<Vec<f64>> = c
        .tracks
        .iter()
        .map(|t| {
            vec![
                t.born,
                t.ended.unwrap_or(nan),
                f64::from(u8::from(t.from_start)),
                t.center,
                t.lifetime().unwrap_or(nan),
            ]
        })
        .collect();
    dir.csv(
        "stripe_tracks.csv",
        &["born", "ended", "from_start", "center_last", "lifetime"],
        &rows,
    )?;
    let rows: Vec<Vec<f64>> = c.correlation.iter().map(|p| vec![p.lag as f64, p.lag_s, p.c]).collect();
    dir.csv("profile_correlation.csv", &["lag", "lag_s", "C"], &rows)
}

/// The camera's plots: the count over time on a log time axis with both coarsening laws, and
/// the last stroboscopic profile with the counting threshold.
pub(super) fn draw_camera(dir: &mut RunDir, c: &Camera, r: &Report) -> Result<(), Error> {
    let pts: Vec<(f64, f64)> = c
        .frames
        .iter()
        .zip(&c.stripes)
        .filter(|(f, _)| f.time > 0.0)
        .map(|(f, s)| (f.time, s.len() as f64))
        .collect();
    let mut plot = LinePlot::new("Stripes counted at the turning points (tray frame)", "t (s)", "stripe count S")
        .integer_y()
        .include_y(0.0)
        .log_x()
        .legend(analysis::plot::LegendCorner::UpperRight)
        .series("S", pts.clone(), Mark::LinePoints);
    let fit_times: Vec<f64> = pts
        .iter()
        .map(|p| p.0)
        .filter(|t| c.law_from.is_some_and(|from| *t >= from))
        .collect();
    for (name, fit, power) in [("S = a t^-alpha", c.law.power, true), ("S = a - b ln t", c.law.logarithmic, false)] {
        if let Some(f) = fit {
            let label = format!(
                "{name}: a = {:.3}, {} = {:.3} [{:.3}, {:.3}]",
                f.a,
                if power { "alpha" } else { "b" },
                f.rate,
                f.rate_ci95.0,
                f.rate_ci95.1
            );
            plot = plot.series(&label, fit_times.iter().map(|&t| (t, f.eval(t, power))).collect(), Mark::Dashed);
        }
    }
    for (name, at) in [("clusters", c.cluster_onset), ("stripes", c.stripe_onset)] {
        if let Some(t) = at.filter(|t| *t > 0.0) {
            let top = pts.iter().map(|p| p.1).fold(1.0, f64::max);
            plot = plot.series(&format!("onset of {name} {t:.3} s"), vec![(t, 0.0), (t, top)], Mark::Dashed);
        }
    }
    dir.plot("stripe_count_log", &plot)?;
    if let (Some(f), Some(p)) = (c.frames.last(), c.profiles.last()) {
        let xs = |k: usize| (k as f64 + 0.5) * r.cell;
        let prof = LinePlot::new(
            &format!(
                "Tray-frame profile at t = {:.3} s (turning point): {} stripe(s)",
                f.time,
                c.stripes.last().map_or(0, Vec::len)
            ),
            "x relative to the tray (m)",
            "area fraction",
        )
        .include_y(0.0)
        .series("phi(x)", p.iter().enumerate().map(|(k, v)| (xs(k), *v)).collect(), Mark::Line)
        .series(
            &format!(
                "threshold {:.3} = {:.2} x mean; min width {:.1} mm",
                c.rule.threshold,
                c.rule.threshold_over_mean,
                c.rule.min_width_m * 1e3
            ),
            vec![(0.0, c.rule.threshold), (r.length, c.rule.threshold)],
            Mark::Dashed,
        )
        .series(
            &format!("mean {:.3}", r.mean_area_fraction),
            vec![(0.0, r.mean_area_fraction), (r.length, r.mean_area_fraction)],
            Mark::Dashed,
        );
        dir.plot("camera_profile_last", &prof)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 43: an event-driven box is not titled as a tray's projected area fraction, nor
    /// its dense columns as stripes; a tray keeps its titles.
    #[test]
    fn a_vertical_box_is_titled_as_one() {
        let tray = labels(Geometry::Tray);
        assert!(tray.map_title.starts_with("Projected area fraction") && tray.count_axis == "stripe count");
        let boxed = labels(Geometry::VerticalBox);
        for text in [boxed.map_title, boxed.map_scale, boxed.count_title, boxed.count_axis] {
            assert!(!text.contains("area fraction") && !text.to_lowercase().contains("stripe"), "{text}");
        }
        assert!(boxed.map_title.contains("Vertical box") && boxed.map_scale.contains("column load"));
    }
}
