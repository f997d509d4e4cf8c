//! Mean square displacement per drive period (thesis eq 3.30-3.31) and its plateau fits
//! (thesis Table 3.5).
//!
//! `D = (1/2) <r_i^2>` (eq 3.30), with `r_i = |r_i(t) - r_i(t - T)|` the displacement of
//! grain i between two snapshots one period `T` apart (eq 3.31), averaged over all grains
//! (m^2). Snapshots are taken once per period at a fixed phase of the tray, so `r_i` is the
//! drift relative to the tray. Only x and y enter (the layer's plane); x is periodic, and its
//! displacement is taken as the minimum image, i.e. a grain is assumed to move less than
//! `L / 2` per period; y is the plain difference unless the layer is periodic in y too.
//!
//! The plateau fits follow the thesis: the best constant `D(t) = a` on a time window is the
//! mean of `D` there, reported with its standard error `s / sqrt(n)`. A constant describes
//! `D` only where `D` is flat: [`flat_plateau`] reports one only when the means of the first
//! and the last third of the window differ by at most [`PLATEAU_FLATNESS`], and otherwise
//! says why there is none.

/// Half the mean square in-plane displacement between two frames' positions (m^2), eq 3.30.
/// `length` is the periodic box length along x; `width` is used as the y period when
/// `periodic_y` is set.
pub fn half_msd(a: &[[f64; 3]], b: &[[f64; 3]], length: f64, width: f64, periodic_y: bool) -> f64 {
    assert_eq!(a.len(), b.len(), "the same grains in both frames");
    if a.is_empty() {
        return 0.0;
    }
    let min_image = |d: f64, p: f64| d - p * (d / p).round();
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| {
            let dx = min_image(q[0] - p[0], length);
            let dy = if periodic_y { min_image(q[1] - p[1], width) } else { q[1] - p[1] };
            dx * dx + dy * dy
        })
        .sum();
    0.5 * sum / a.len() as f64
}

/// For each frame (times increasing), the index of an earlier frame one `period` before it,
/// within `tolerance * period`; `None` when there is none (the first period, or irregular
/// snapshots such as the t = 0 frame of `stripes run`, which lies a quarter period before
/// the first turning point).
pub fn period_partners(times: &[f64], period: f64, tolerance: f64) -> Vec<Option<usize>> {
    times
        .iter()
        .map(|&t| {
            let target = t - period;
            let k = times.partition_point(|&s| s < target);
            [k.checked_sub(1), Some(k)]
                .into_iter()
                .flatten()
                .filter(|&j| j < times.len() && times[j] < t)
                .min_by(|&i, &j| (times[i] - target).abs().total_cmp(&(times[j] - target).abs()))
                .filter(|&j| (times[j] - target).abs() <= tolerance * period)
        })
        .collect()
}

/// The drive period of a run from its snapshot times: the median spacing of successive
/// frames (robust to an irregular first frame); `None` with fewer than two frames.
pub fn median_spacing(times: &[f64]) -> Option<f64> {
    let mut d: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    Some(d[d.len() / 2])
}

/// One value of `D` (eq 3.30) at the later frame's time.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MsdPoint {
    /// Time of the later frame (s).
    pub time: f64,
    /// `D` (m^2).
    pub d: f64,
}

/// A constant fitted to `D` on a time window (thesis Table 3.5).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Plateau {
    /// Window `[from, to]` (s).
    pub from: f64,
    pub to: f64,
    /// Best constant, the mean of `D` on the window (m^2).
    pub value: f64,
    /// Standard error of the mean (m^2; 0 for a single point).
    pub stderr: f64,
    /// Number of points fitted.
    pub points: usize,
}

/// Least-squares constant on the points with `from <= time <= to`; `None` if none lies there.
pub fn fit_plateau(points: &[MsdPoint], from: f64, to: f64) -> Option<Plateau> {
    let v: Vec<f64> = points.iter().filter(|p| p.time >= from && p.time <= to).map(|p| p.d).collect();
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let stderr = if v.len() > 1 {
        (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() / n.sqrt()
    } else {
        0.0
    };
    Some(Plateau {
        from,
        to,
        value: mean,
        stderr,
        points: v.len(),
    })
}

/// Largest ratio between the means of `D` over the first and the last third of a plateau
/// window for the window to count as flat. The thesis' two plateaus differ 5.6-fold (a1 = 1.6e-4,
/// a2 = 8.9e-4 m^2); a window whose ends differ by more than 2 straddles a change of the size
/// the plateaus are meant to measure, while the scatter of a stationary `D` (a mean over all
/// grains, averaged again over a third of the window) stays far below a factor 2.
pub const PLATEAU_FLATNESS: f64 = 2.0;

/// [`fit_plateau`], kept only when `D` is flat on the window: at least three points, and the
/// means of its first and last thirds within a factor `tolerance` of each other. The error
/// says why there is no plateau.
pub fn flat_plateau(points: &[MsdPoint], from: f64, to: f64, tolerance: f64) -> Result<Plateau, NoPlateau> {
    let v: Vec<f64> = points.iter().filter(|p| p.time >= from && p.time <= to).map(|p| p.d).collect();
    if v.len() < 3 {
        return Err(NoPlateau::TooFewPoints { points: v.len(), from, to });
    }
    let k = v.len() / 3;
    let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len() as f64;
    let (head, tail) = (mean(&v[..k]), mean(&v[v.len() - k..]));
    let (lo, hi) = (head.min(tail), head.max(tail));
    if !(hi <= tolerance * lo || hi == 0.0) {
        return Err(NoPlateau::NotFlat {
            from,
            to,
            head,
            tail,
            tolerance,
        });
    }
    Ok(fit_plateau(points, from, to).expect("points in the window"))
}

/// Why [`flat_plateau`] finds no plateau on the window `[from, to]` (s).
#[derive(Clone, Debug, PartialEq)]
pub enum NoPlateau {
    /// Fewer than three values of `D` on the window.
    TooFewPoints { points: usize, from: f64, to: f64 },
    /// The means of the window's first and last thirds (`head`, `tail`, m^2) differ by more
    /// than the factor `tolerance`.
    NotFlat {
        from: f64,
        to: f64,
        head: f64,
        tail: f64,
        tolerance: f64,
    },
}

impl std::fmt::Display for NoPlateau {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            NoPlateau::TooFewPoints { points, from, to } => write!(
                f,
                "{points} value(s) of D on [{from:.3}, {to:.3}] s; at least 3 are needed to tell a plateau from a trend"
            ),
            NoPlateau::NotFlat {
                from,
                to,
                head,
                tail,
                tolerance,
            } => write!(
                f,
                "D is not flat on [{from:.3}, {to:.3}] s: it goes from {head:.3e} to {tail:.3e} m^2 (first and last third), \
                 more than the factor {tolerance} a plateau may change by"
            ),
        }
    }
}

impl std::error::Error for NoPlateau {}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn displacement_across_the_seam_is_the_short_way() {
        let a = [[0.399, 0.01, 0.0], [0.1, 0.01, 0.0]];
        let b = [[0.001, 0.01, 0.0], [0.1, 0.013, 0.0]];
        // grain 0 moved +2 mm across the seam, grain 1 moved 3 mm in y.
        let d = half_msd(&a, &b, 0.4, 0.02, false);
        assert!((d - 0.5 * (4e-6 + 9e-6) / 2.0).abs() < 1e-15, "{d}");
        let c = [[0.1, 0.019, 0.0]];
        let e = [[0.1, 0.001, 0.0]];
        assert!((half_msd(&c, &e, 0.4, 0.02, true) - 0.5 * 4e-6).abs() < 1e-15);
        assert!((half_msd(&c, &e, 0.4, 0.02, false) - 0.5 * 3.24e-4).abs() < 1e-15);
    }

    #[test]
    fn partners_skip_the_quarter_period_first_frame() {
        let t = [0.0, 0.0125, 0.0625, 0.1125, 0.1625];
        assert_eq!(median_spacing(&t), Some(0.05));
        assert_eq!(period_partners(&t, 0.05, 0.1), vec![None, None, Some(1), Some(2), Some(3)]);
        // Two snapshots per period: partners are two frames back.
        let t: Vec<f64> = (0..6).map(|k| k as f64 * 0.025).collect();
        assert_eq!(period_partners(&t, 0.05, 0.1), vec![None, None, Some(0), Some(1), Some(2), Some(3)]);
    }

    #[test]
    fn plateau_is_the_mean_with_its_standard_error() {
        let pts: Vec<MsdPoint> = [1.0, 3.0, 1.0, 3.0, 100.0]
            .iter()
            .enumerate()
            .map(|(k, &d)| MsdPoint { time: k as f64, d })
            .collect();
        let p = fit_plateau(&pts, 0.0, 3.0).unwrap();
        assert_eq!((p.value, p.points), (2.0, 4));
        assert!((p.stderr - (4.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-15);
        assert!(fit_plateau(&pts, 10.0, 20.0).is_none());
    }

    /// Issue 19, point 5: a decaying transient is no plateau.
    #[test]
    fn a_decaying_transient_is_no_plateau() {
        let decay: Vec<MsdPoint> = (0..30)
            .map(|k| MsdPoint {
                time: k as f64,
                d: 8e-4 * (-(k as f64) / 6.8).exp(), // falls 80-fold over the window
            })
            .collect();
        let e = flat_plateau(&decay, 0.0, 29.0, PLATEAU_FLATNESS).unwrap_err();
        assert!(matches!(e, NoPlateau::NotFlat { .. }) && e.to_string().contains("not flat"), "{e}");
        let noisy: Vec<MsdPoint> = (0..30)
            .map(|k| MsdPoint {
                time: k as f64,
                d: 1e-4 * (1.0 + 0.3 * ((k * 7 % 5) as f64 - 2.0) / 2.0),
            })
            .collect();
        let p = flat_plateau(&noisy, 0.0, 29.0, PLATEAU_FLATNESS).unwrap();
        assert!((p.value / 1e-4 - 1.0).abs() < 0.05, "{p:?}");
        assert!(flat_plateau(&noisy, 0.0, 1.0, PLATEAU_FLATNESS)
            .unwrap_err()
            .to_string()
            .contains("at least 3"));
    }

    proptest! {
        #[test]
        fn a_rigid_translation_gives_half_its_square(
            pos in prop::collection::vec((0.0f64..0.4, 0.0f64..0.02), 1..50),
            dx in -0.19f64..0.19, dy in -0.005f64..0.005,
        ) {
            let a: Vec<[f64; 3]> = pos.iter().map(|p| [p.0, p.1, 0.0]).collect();
            let b: Vec<[f64; 3]> = a.iter().map(|p| [(p[0] + dx).rem_euclid(0.4), p[1] + dy, 0.0]).collect();
            let d = half_msd(&a, &b, 0.4, 0.02, false);
            prop_assert!((d - 0.5 * (dx * dx + dy * dy)).abs() < 1e-12);
        }
    }
}
