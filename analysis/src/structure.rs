//! Observables of a pattern's structure, beyond its label: the structure factor of the grain
//! positions along x, the widths of the bands and the gaps between them, the fraction of
//! grains in bands, and one distance between two runs' patterns.
//!
//! - **Structure factor** (binning-free): `S(k) = |sum_j exp(i k x_j)|^2 / N` at the modes of
//!   the periodic tray, `k_m = 2 pi m / L`, `m = 1 .. M`. For grains placed independently
//!   `S = 1` at every mode; bands of spacing `lambda` raise a peak at `k = 2 pi / lambda`.
//!   The peak ([`Peak`]) is the mode of largest `S`, refined by a parabola through it and
//!   its neighbours; its width is the full width at half maximum above the independent
//!   level 1, read off linearly between modes.
//! - **Bands** come from the area-fraction profile ([`crate::stripes::detect`]): their
//!   widths, and the gaps from the end of one band to the start of the next (periodic).
//! - **Pattern distance** between two runs: the mean of (a) the L1 distance between their
//!   late-time structure factors, each normalised to unit sum over `k`, on a common grid
//!   of `k`, and (b) the 1D earth mover's distance between their band-width distributions,
//!   divided by the mean band width of both. Both terms are 0 for identical patterns;
//!   (a) is at most 2 and (b) is dimensionless. The number means little alone: divide it by
//!   the distance between two seeds of one scene ([`scaled`]), which is what run-to-run
//!   scatter alone gives; a scaled distance above 1 says the patterns differ by more than
//!   seeds do.

use crate::stripes::Stripe;

/// `S(k)` at the modes `m = 1 ..= modes` of a periodic axis of length `length` (m):
/// `(k, S)` pairs, `k` in rad/m.
pub fn structure_factor(x: &[f64], length: f64, modes: usize) -> Vec<(f64, f64)> {
    let n = x.len().max(1) as f64;
    (1..=modes)
        .map(|m| {
            let k = 2.0 * std::f64::consts::PI * m as f64 / length;
            let (mut c, mut s) = (0.0, 0.0);
            for &xi in x {
                let (sn, cs) = (k * xi).sin_cos();
                c += cs;
                s += sn;
            }
            (k, (c * c + s * s) / n)
        })
        .collect()
}

/// The peak of a structure factor.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Peak {
    /// Wavenumber (rad/m) and the spacing `2 pi / k` (m).
    pub k: f64,
    pub spacing: f64,
    /// Height `S(k)` at the peak mode.
    pub height: f64,
    /// Full width at half maximum above the independent level 1 (rad/m).
    pub width: f64,
}

/// The peak of `s` (from [`structure_factor`]), or `None` when no mode rises above the
/// independent level 1.
pub fn peak(s: &[(f64, f64)]) -> Option<Peak> {
    let (i, &(k0, h)) = s.iter().enumerate().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))?;
    if h <= 1.0 {
        return None;
    }
    // Parabolic refinement of the position between the neighbouring modes.
    let k = if i > 0 && i + 1 < s.len() {
        let (a, c) = (s[i - 1].1, s[i + 1].1);
        let denom = a - 2.0 * h + c;
        let dk = s[i + 1].0 - k0;
        if denom < 0.0 {
            k0 + 0.5 * (a - c) / denom * dk
        } else {
            k0
        }
    } else {
        k0
    };
    let half = 1.0 + 0.5 * (h - 1.0);
    let cross = |range: &mut dyn Iterator<Item = usize>| -> Option<f64> {
        let mut prev = i;
        for j in range {
            if s[j].1 < half {
                let (k1, s1, k2, s2) = (s[prev].0, s[prev].1, s[j].0, s[j].1);
                return Some(k1 + (s1 - half) / (s1 - s2) * (k2 - k1));
            }
            prev = j;
        }
        None
    };
    let left = cross(&mut (0..i).rev()).unwrap_or(s[0].0);
    let right = cross(&mut (i + 1..s.len())).unwrap_or(s[s.len() - 1].0);
    Some(Peak {
        k,
        spacing: 2.0 * std::f64::consts::PI / k,
        height: h,
        width: right - left,
    })
}

/// Widths of the bands and the gaps between neighbouring bands (m), periodic over `length`.
pub fn widths_and_gaps(bands: &[Stripe], length: f64) -> (Vec<f64>, Vec<f64>) {
    let widths: Vec<f64> = bands.iter().map(|b| b.width).collect();
    let mut starts: Vec<(f64, f64)> = bands.iter().map(|b| (b.start, b.width)).collect();
    starts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let gaps = (0..starts.len())
        .filter(|_| starts.len() > 1)
        .map(|j| {
            let (s, w) = starts[j];
            let next = starts[(j + 1) % starts.len()].0;
            (next - (s + w)).rem_euclid(length)
        })
        .collect();
    (widths, gaps)
}

/// Fraction of the grains at `x` whose centre lies in one of the bands.
pub fn in_band_fraction(x: &[f64], bands: &[Stripe], length: f64) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    x.iter().filter(|&&xi| bands.iter().any(|b| b.contains(xi, length))).count() as f64 / x.len() as f64
}

/// A run's late-time structure, the input of [`distance`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Structure {
    /// Time-averaged `S(k)` of the late frames, `(k, S)`.
    pub s: Vec<(f64, f64)>,
    /// Widths of the bands of the late frames (m), pooled.
    pub band_widths: Vec<f64>,
}

/// The 1D earth mover's (Wasserstein-1) distance between two samples (m): the mean absolute
/// difference of their quantile functions, read at 200 quantiles.
fn earth_movers(a: &[f64], b: &[f64]) -> f64 {
    let sorted = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v
    };
    let (a, b) = (sorted(a), sorted(b));
    let q = |v: &[f64], u: f64| v[((u * v.len() as f64) as usize).min(v.len() - 1)];
    (0..200)
        .map(|k| (k as f64 + 0.5) / 200.0)
        .map(|u| (q(&a, u) - q(&b, u)).abs())
        .sum::<f64>()
        / 200.0
}

/// `S(k)` read linearly at `k` (0 outside the computed range), for curves on other grids.
fn s_at(s: &[(f64, f64)], k: f64) -> f64 {
    match s.iter().position(|p| p.0 >= k) {
        Some(0) if s[0].0 > k => 0.0,
        Some(0) => s[0].1,
        Some(j) => {
            let (k1, s1, k2, s2) = (s[j - 1].0, s[j - 1].1, s[j].0, s[j].1);
            s1 + (s2 - s1) * (k - k1) / (k2 - k1)
        }
        None => 0.0,
    }
}

/// The pattern distance (module docs) between two structures; `None` if either has no
/// structure factor.
pub fn distance(a: &Structure, b: &Structure) -> Option<f64> {
    if a.s.is_empty() || b.s.is_empty() {
        return None;
    }
    // A common grid: the finer of the two mode spacings, up to the smaller top mode.
    let dk = (a.s[0].0).min(b.s[0].0);
    let top = a.s[a.s.len() - 1].0.min(b.s[b.s.len() - 1].0);
    let grid: Vec<f64> = (1..).map(|m| m as f64 * dk).take_while(|&k| k <= top * (1.0 + 1e-12)).collect();
    let norm = |s: &[(f64, f64)]| {
        let v: Vec<f64> = grid.iter().map(|&k| s_at(s, k)).collect();
        let sum: f64 = v.iter().sum();
        v.into_iter().map(|x| x / sum.max(1e-300)).collect::<Vec<f64>>()
    };
    let (na, nb) = (norm(&a.s), norm(&b.s));
    let d_s: f64 = na.iter().zip(&nb).map(|(x, y)| (x - y).abs()).sum();
    let d_w = match (a.band_widths.is_empty(), b.band_widths.is_empty()) {
        (true, true) => 0.0,
        // Bands in one run only: as far apart as band widths go.
        (true, false) | (false, true) => 1.0,
        (false, false) => {
            let mean = (a.band_widths.iter().sum::<f64>() / a.band_widths.len() as f64
                + b.band_widths.iter().sum::<f64>() / b.band_widths.len() as f64)
                / 2.0;
            earth_movers(&a.band_widths, &b.band_widths) / mean
        }
    };
    Some(0.5 * (d_s + d_w))
}

/// The distance in units of the seed-to-seed distance `scale` (`None` without one).
pub fn scaled(distance: f64, scale: Option<f64>) -> Option<f64> {
    scale.filter(|s| *s > 0.0).map(|s| distance / s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stripes::{detect, StripeParams};

    /// Grains in `bands` bands of width `w` (m) on a tray of length `l`, evenly spaced,
    /// `per` grains per band spread evenly across it.
    fn banded(l: f64, bands: usize, w: f64, per: usize) -> Vec<f64> {
        (0..bands)
            .flat_map(|b| {
                let c = (b as f64 + 0.5) * l / bands as f64;
                (0..per).map(move |j| c - 0.5 * w + w * (j as f64 + 0.5) / per as f64)
            })
            .collect()
    }

    #[test]
    fn the_peak_sits_at_the_band_spacing_and_independent_grains_have_none() {
        let l = 0.4;
        for bands in [3usize, 5, 12] {
            let x = banded(l, bands, 0.01, 200);
            let s = structure_factor(&x, l, 60);
            let p = peak(&s).unwrap();
            assert!((p.spacing - l / bands as f64).abs() < 1e-9 * l, "{bands} bands: {}", p.spacing);
            assert!(p.height > 100.0);
        }
        // A lattice finer than the highest mode reads as independent (S ~ 0 < 1): no peak.
        let even: Vec<f64> = (0..4000).map(|j| (j as f64 + 0.5) * l / 4000.0).collect();
        assert!(peak(&structure_factor(&even, l, 60)).is_none());
    }

    #[test]
    fn band_widths_gaps_and_in_band_fraction_are_exact_on_a_synthetic_profile() {
        // An area-fraction profile of 4 bands, 20 cells of 1 mm each, every 100 cells.
        let (l, n) = (0.4, 400);
        let phi: Vec<f64> = (0..n).map(|c| if c % 100 < 20 { 0.7 } else { 0.1 }).collect();
        let bands = detect(
            &phi,
            l,
            &StripeParams {
                threshold: 0.4,
                min_width: 0.005,
            },
        );
        let (w, g) = widths_and_gaps(&bands, l);
        assert_eq!(w.len(), 4);
        for x in w {
            assert!((x - 0.02).abs() < 1e-12);
        }
        for x in g {
            assert!((x - 0.08).abs() < 1e-12, "{x}");
        }
        let grains: Vec<f64> = (0..400).map(|j| (j as f64 + 0.5) * 1e-3).collect();
        assert!((in_band_fraction(&grains, &bands, l) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn the_distance_is_zero_for_one_pattern_and_grows_with_the_difference() {
        let l = 0.2;
        let st = |bands: usize, w: f64| Structure {
            s: structure_factor(&banded(l, bands, w, 300), l, 80),
            band_widths: vec![w; bands],
        };
        let two_broad = st(2, 0.014);
        let many_thin = st(8, 0.0045);
        assert_eq!(distance(&two_broad, &two_broad), Some(0.0));
        let near = distance(&two_broad, &st(2, 0.012)).unwrap();
        let far = distance(&two_broad, &many_thin).unwrap();
        assert!(near < 0.2 && far > 0.8, "near {near}, far {far}");
        assert!(scaled(far, Some(near)).unwrap() > 4.0);
        assert_eq!(scaled(far, None), None);
    }
}
