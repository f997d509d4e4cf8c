//! Stripe detection on an area-fraction profile (cells of equal width over a periodic axis).
//!
//! A stripe is a maximal run of cells whose area fraction exceeds `threshold`, at least
//! `min_width` wide; runs that touch at the periodic seam are one stripe. Defaults
//! ([`StripeParams::default_for`]): threshold `min(1.5 phi_mean, (phi_mean + PHI_JAM) / 2)`
//! and a minimum width of five mean grain diameters (3.75 mm in the thesis' layer).
//!
//! Why these values: in a homogeneous random layer at the thesis packing (0.23, 1 mm cells)
//! single cells exceed 1.5 x the mean often, but runs above it are short. Measured over 100
//! layers of 4000 grains (`analysis/tests/synthetic_layers.rs`): the longest run was 2 cells
//! for non-overlapping random layers and 3 cells for independent (overlapping) positions,
//! so a minimum of two diameters (1.5 mm) gave false stripes while five (4 cells) gives
//! none. Thesis stripes are centimetres wide.
//!
//! The cap `(phi_mean + PHI_JAM) / 2`, "closer to the jammed layer than to the mean one",
//! takes over above `phi_mean = 0.41`. A stripe cannot be denser than a jammed layer, so a
//! threshold proportional to the mean leaves no room at high packing: at `phi_mean = 0.46`
//! (the DEM's first stripes, 3 Hz, 10 mm), `1.5 phi_mean = 0.69` sits on the bands' plateau
//! (0.70-0.79 in 1 mm cells), and a run with three clear bands was counted as two. The cap
//! gives 0.64 there. Independent uniform positions at 0.46 have a cell standard deviation
//! of 0.094 (1 mm cells, measured), so 0.64 is the mean plus 1.9 of them, above the 1.7 of
//! the thesis packing's `1.5 phi_mean`: the cap is no easier on noise than the old rule.

/// Area fraction of a jammed (randomly close packed) layer of polydisperse disks, the
/// densest a stripe can be: 0.82 (random close packing of bidisperse disks is 0.82-0.84;
/// the cores of the DEM's bands reach 0.79 in 1 mm cells).
pub const PHI_JAM: f64 = 0.82;

/// Detection parameters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StripeParams {
    /// Area-fraction threshold.
    pub threshold: f64,
    /// Minimum width (m).
    pub min_width: f64,
}

impl StripeParams {
    /// Defaults for a layer of mean area fraction `mean_phi` and mean grain diameter `d` (m):
    /// threshold `min(1.5 mean_phi, (mean_phi + PHI_JAM) / 2)` (module docs).
    pub fn default_for(mean_phi: f64, d: f64) -> Self {
        Self {
            threshold: (1.5 * mean_phi).min(0.5 * (mean_phi + PHI_JAM)),
            min_width: 5.0 * d,
        }
    }
}

/// One stripe: centre and width (m), and mass as projected area per unit width (m), the
/// integral of the area fraction over the stripe. It covers `[start, start + width)`
/// (periodic; `start` in `[0, L)`), and its centre is the area-weighted mean position.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Stripe {
    pub start: f64,
    pub center: f64,
    pub width: f64,
    pub mass: f64,
}

/// Stripes of the profile `phi` (cells of width `length / phi.len()`) on a periodic axis.
pub fn detect(phi: &[f64], length: f64, p: &StripeParams) -> Vec<Stripe> {
    let n = phi.len();
    if n == 0 {
        return Vec::new();
    }
    let h = length / n as f64;
    let above: Vec<bool> = phi.iter().map(|&v| v > p.threshold).collect();
    if above.iter().all(|&a| a) {
        let mass = phi.iter().sum::<f64>() * h;
        return if length >= p.min_width {
            vec![Stripe {
                start: 0.0,
                center: 0.5 * length,
                width: length,
                mass,
            }]
        } else {
            Vec::new()
        };
    }
    // Start scanning just after a cell below threshold, so runs across the seam stay whole.
    let start = (0..n).find(|&k| !above[k]).expect("some cell is below") + 1;
    let mut out = Vec::new();
    let mut k = 0;
    while k < n {
        let c = (start + k) % n;
        if !above[c] {
            k += 1;
            continue;
        }
        let first = start + k;
        let (mut len, mut mass, mut moment) = (0usize, 0.0, 0.0);
        while k < n && above[(start + k) % n] {
            let v = phi[(start + k) % n];
            let x = (start + k) as f64 * h + 0.5 * h; // unwrapped
            mass += v * h;
            moment += v * h * x;
            len += 1;
            k += 1;
        }
        let width = len as f64 * h;
        if width >= p.min_width {
            let center = (moment / mass).rem_euclid(length);
            out.push(Stripe {
                start: (first as f64 * h).rem_euclid(length),
                center,
                width,
                mass,
            });
        }
    }
    out.sort_by(|a, b| a.center.total_cmp(&b.center));
    out
}

impl Stripe {
    /// Whether position `x` (any real, periodic with `length`) lies inside the stripe.
    pub fn contains(&self, x: f64, length: f64) -> bool {
        (x - self.start).rem_euclid(length) < self.width
    }
}

/// The spacing of a periodic profile `phi` over `length` (m): `length / k` for the Fourier
/// mode `1 <= k <= max_modes` (and up to the Nyquist mode) of largest power of the
/// mean-subtracted profile. Robust where counting stripes is not: a weak band between two
/// strong ones changes the count by one but hardly the dominant mode. The bound keeps a single
/// narrow band (whose spectrum is flat) from being read as a fine pattern: callers pass twice
/// the number of bands found. `None` for a flat profile.
pub fn dominant_spacing(phi: &[f64], length: f64, max_modes: usize) -> Option<f64> {
    let n = phi.len();
    if n < 2 {
        return None;
    }
    let mean = phi.iter().sum::<f64>() / n as f64;
    let mut best = (0, 0.0);
    for k in 1..=(n / 2).min(max_modes) {
        let w = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        let (mut re, mut im) = (0.0, 0.0);
        for (i, p) in phi.iter().enumerate() {
            let (s, c) = (w * i as f64).sin_cos();
            re += (p - mean) * c;
            im += (p - mean) * s;
        }
        let power = re * re + im * im;
        if power > best.1 * (1.0 + 1e-12) {
            best = (k, power);
        }
    }
    (best.0 > 0 && best.1 > 1e-24).then(|| length / best.0 as f64)
}

/// Stripe onset time: the first frame time from which every later frame holds at least
/// one stripe (`None` when the last frame holds none). `times` and `counts` are per frame.
pub fn onset(times: &[f64], counts: &[usize]) -> Option<f64> {
    assert_eq!(times.len(), counts.len(), "one count per frame");
    match counts.iter().rposition(|&c| c == 0) {
        None => times.first().copied(),
        Some(k) if k + 1 < counts.len() => Some(times[k + 1]),
        Some(_) => None,
    }
}

/// One point of the coarsening curve: the stripes of one frame in summary.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Coarsening {
    /// Frame time (s).
    pub time: f64,
    /// Number of stripes.
    pub count: usize,
    /// Mean stripe width (m; NaN without stripes).
    pub mean_width: f64,
    /// Mean stripe mass, projected area per unit tray width (m; NaN without stripes).
    pub mean_mass: f64,
    /// Fraction of all grains' projected area held in stripes (0..1).
    pub mass_fraction: f64,
}

impl Coarsening {
    /// Summary of `stripes` at `time` in a layer of mean area fraction `mean_phi` and
    /// length `length` (the layer's total mass is `mean_phi * length`).
    pub fn of(time: f64, stripes: &[Stripe], mean_phi: f64, length: f64) -> Self {
        let n = stripes.len();
        let (w, m) = stripes.iter().fold((0.0, 0.0), |(w, m), s| (w + s.width, m + s.mass));
        let mean = |v: f64| if n == 0 { f64::NAN } else { v / n as f64 };
        Self {
            time,
            count: n,
            mean_width: mean(w),
            mean_mass: mean(m),
            mass_fraction: if mean_phi > 0.0 { m / (mean_phi * length) } else { 0.0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominant_spacing_finds_the_band_period() {
        let n = 200;
        let l = 0.2;
        // Four bands, plus a weak fifth one and a slope: still 50 mm.
        let phi: Vec<f64> = (0..n)
            .map(|i| {
                let x = i as f64 / n as f64;
                0.4 + 0.3 * (((x * 4.0).fract() - 0.5).abs() < 0.05) as u8 as f64
                    + 0.05 * (((x - 0.125) * 1.0).abs() < 0.01) as u8 as f64
                    + 0.01 * x
            })
            .collect();
        let s = dominant_spacing(&phi, l, 10).unwrap();
        assert!((s - 0.05).abs() < 1e-12, "{s}");
        assert_eq!(dominant_spacing(&vec![0.3; n], l, 10), None);
        // One narrow band: its spectrum is flat; bounded to two modes, one band per tray.
        let one: Vec<f64> = (0..n).map(|i| if (90..96).contains(&i) { 0.8 } else { 0.4 }).collect();
        assert!((dominant_spacing(&one, l, 2).unwrap() - l).abs() < 1e-12);
        // A pure cosine of 7 periods.
        let phi: Vec<f64> = (0..n)
            .map(|i| (2.0 * std::f64::consts::PI * 7.0 * i as f64 / n as f64).cos())
            .collect();
        assert!((dominant_spacing(&phi, l, 100).unwrap() - l / 7.0).abs() < 1e-12);
    }

    #[test]
    fn onset_is_the_start_of_the_final_run_of_stripes() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(onset(&t, &[0, 1, 0, 2, 3]), Some(3.0));
        assert_eq!(onset(&t, &[1, 1, 1, 1, 1]), Some(0.0));
        assert_eq!(onset(&t, &[1, 1, 1, 1, 0]), None);
    }

    #[test]
    fn membership_wraps_across_the_seam() {
        let s = Stripe {
            start: 0.95,
            center: 0.0,
            width: 0.1,
            mass: 0.05,
        };
        assert!(s.contains(0.97, 1.0) && s.contains(0.02, 1.0) && s.contains(1.02, 1.0));
        assert!(!s.contains(0.06, 1.0) && !s.contains(0.5, 1.0));
    }

    fn bands(k: usize, offset: f64, n: usize) -> Vec<f64> {
        // k dense bands of width 0.04 on a background of 0.1, on [0, 1).
        (0..n)
            .map(|c| {
                let x = (c as f64 + 0.5) / n as f64;
                let in_band = (0..k).any(|b| {
                    let center = (offset + b as f64 / k as f64).rem_euclid(1.0);
                    let d = (x - center).abs();
                    d.min(1.0 - d) < 0.02
                });
                if in_band {
                    0.6
                } else {
                    0.1
                }
            })
            .collect()
    }

    #[test]
    fn k_separated_bands_give_k_stripes_at_any_offset() {
        let p = StripeParams {
            threshold: 0.3,
            min_width: 0.01,
        };
        for k in 1..=8 {
            for offset in [0.0, 0.003, 0.5, 0.99] {
                let s = detect(&bands(k, offset, 1000), 1.0, &p);
                assert_eq!(s.len(), k, "k = {k}, offset {offset}: {s:?}");
                assert!(s.iter().all(|s| (s.width - 0.04).abs() < 0.003));
                for (b, st) in s.iter().enumerate() {
                    let want = (offset + b as f64 / k as f64).rem_euclid(1.0);
                    let near = s
                        .iter()
                        .any(|s| ((s.center - want).rem_euclid(1.0)).min((want - s.center).rem_euclid(1.0)) < 1e-3);
                    assert!(near, "k = {k}, offset {offset}: no stripe at {want} ({st:?})");
                }
            }
        }
    }

    #[test]
    fn narrow_runs_are_not_stripes() {
        let mut phi = vec![0.1; 100];
        phi[10] = 0.9;
        assert!(detect(
            &phi,
            1.0,
            &StripeParams {
                threshold: 0.3,
                min_width: 0.02
            }
        )
        .is_empty());
    }
}
