//! Stripe detection on an area-fraction profile (cells of equal width over a periodic axis).
//!
//! A stripe is a maximal run of cells whose area fraction exceeds `threshold`, at least
//! `min_width` wide; runs that touch at the periodic seam are one stripe. Defaults
//! ([`StripeParams::default_for`]): threshold `1.5` times the mean area fraction of the layer
//! (a homogeneous layer at the thesis packing, 0.23, fluctuates well below 0.34 when cells
//! are 1 mm wide) and a minimum width of two mean grain diameters.

/// Detection parameters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StripeParams {
    /// Area-fraction threshold.
    pub threshold: f64,
    /// Minimum width (m).
    pub min_width: f64,
}

impl StripeParams {
    /// Defaults for a layer of mean area fraction `mean_phi` and mean grain diameter `d` (m).
    pub fn default_for(mean_phi: f64, d: f64) -> Self {
        Self {
            threshold: 1.5 * mean_phi,
            min_width: 2.0 * d,
        }
    }
}

/// One stripe: centre and width (m), and mass as projected area per unit width (m), the
/// integral of the area fraction over the stripe.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Stripe {
    pub center: f64,
    pub width: f64,
    pub mass: f64,
}

/// Stripe onset: the first time from which a stripe is present in every later frame
/// (`None` if the last frame has none). `times` and `counts` are per frame, in time order.
pub fn onset(times: &[f64], counts: &[usize]) -> Option<f64> {
    let last_empty = counts.iter().rposition(|&c| c == 0);
    match last_empty {
        None => times.first().copied(),
        Some(k) if k + 1 < counts.len() => Some(times[k + 1]),
        Some(_) => None,
    }
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
            out.push(Stripe { center, width, mass });
        }
    }
    out.sort_by(|a, b| a.center.total_cmp(&b.center));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn onset_is_the_start_of_the_final_run_of_stripes() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(onset(&t, &[0, 1, 0, 2, 3]), Some(3.0));
        assert_eq!(onset(&t, &[1, 1, 1, 1, 1]), Some(0.0));
        assert_eq!(onset(&t, &[1, 1, 1, 1, 0]), None);
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
