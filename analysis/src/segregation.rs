//! Size segregation: the distribution of radii of the grains inside stripes against the
//! whole layer (thesis Fig 3.26: "the average radius in the stripes ... a change of about
//! 2.5 per cent, suggesting that size segregation plays no role").
//!
//! A grain is inside a stripe when its centre lies in the stripe's interval
//! [`Stripe::contains`]. Histograms have equal bins between the smallest and the largest
//! radius of the layer ([`RadiusBins`]) and are normalised to probability densities (1/m).
//! Over several frames (the report uses the final-state frames, like the thesis' "last
//! phase of the simulation") the grains inside stripes are counted once per frame
//! ([`RadiusTally`]).

use crate::stripes::Stripe;

/// Equal bins over the radius range of a layer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusBins {
    pub lo: f64,
    pub step: f64,
    pub bins: usize,
}

impl RadiusBins {
    /// `bins` (at least 1) equal bins from the smallest to the largest radius (widened a
    /// little when all radii are equal).
    pub fn of(radii: &[f64], bins: usize) -> Self {
        let bins = bins.max(1);
        let (lo, hi) = radii
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        let (lo, hi) = if radii.is_empty() {
            (0.0, 1.0)
        } else if hi > lo {
            (lo, hi)
        } else {
            (lo * 0.99, lo * 1.01 + f64::MIN_POSITIVE)
        };
        Self {
            lo,
            step: (hi - lo) / bins as f64,
            bins,
        }
    }

    /// Bin of radius `r` (clamped to the range).
    pub fn bin(&self, r: f64) -> usize {
        (((r - self.lo) / self.step).max(0.0) as usize).min(self.bins - 1)
    }

    /// The `bins + 1` bin edges (m).
    pub fn edges(&self) -> Vec<f64> {
        (0..=self.bins).map(|k| self.lo + k as f64 * self.step).collect()
    }
}

/// Grains inside stripes, counted per radius bin (summable over frames).
#[derive(Clone, Debug, PartialEq)]
pub struct RadiusTally {
    /// Number of grains per bin.
    pub counts: Vec<f64>,
    /// Total number of grains counted.
    pub n: usize,
    /// Sum of their radii (m).
    pub sum: f64,
}

impl RadiusTally {
    /// An empty tally over `bins`.
    pub fn new(bins: &RadiusBins) -> Self {
        Self {
            counts: vec![0.0; bins.bins],
            n: 0,
            sum: 0.0,
        }
    }

    /// Counts the grains at `x` (radii `r`) inside `stripes` (non-overlapping intervals);
    /// O(N log S).
    pub fn add_frame(&mut self, x: &[f64], r: &[f64], stripes: &[Stripe], length: f64, bins: &RadiusBins) {
        assert_eq!(x.len(), r.len(), "one radius per grain");
        if stripes.is_empty() {
            return;
        }
        let mut by_start = stripes.to_vec();
        by_start.sort_by(|a, b| a.start.total_cmp(&b.start));
        let last = by_start[by_start.len() - 1];
        for (&xi, &ri) in x.iter().zip(r) {
            let xw = xi.rem_euclid(length);
            let k = by_start.partition_point(|s| s.start <= xw);
            // The stripe starting at or before x, or the last one wrapping across the seam.
            let inside = (k > 0 && by_start[k - 1].contains(xw, length)) || last.contains(xw, length);
            if inside {
                self.counts[bins.bin(ri)] += 1.0;
                self.n += 1;
                self.sum += ri;
            }
        }
    }

    /// [`RadiusTally::add_frame`] for stripes found on `cells` equal cells of `[0, length)`
    /// (their edges are cell edges): a grain is inside when its centre's cell is; O(N + cells).
    pub fn add_frame_on_cells(&mut self, x: &[f64], r: &[f64], stripes: &[Stripe], length: f64, cells: usize, bins: &RadiusBins) {
        assert_eq!(x.len(), r.len(), "one radius per grain");
        if stripes.is_empty() || cells == 0 {
            return;
        }
        let h = length / cells as f64;
        let mut inside = vec![false; cells];
        for s in stripes {
            let (first, n) = ((s.start / h).round() as usize, (s.width / h).round() as usize);
            for k in 0..n.min(cells) {
                inside[(first + k) % cells] = true;
            }
        }
        for (&xi, &ri) in x.iter().zip(r) {
            let c = ((crate::density::wrap(xi, length) / h) as usize).min(cells - 1);
            if inside[c] {
                self.counts[bins.bin(ri)] += 1.0;
                self.n += 1;
                self.sum += ri;
            }
        }
    }

    /// Adds another tally (of the same bins).
    pub fn merge(&mut self, other: &RadiusTally) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        self.n += other.n;
        self.sum += other.sum;
    }
}

/// Radii inside stripes against the whole layer.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RadiusDistribution {
    /// Bin edges (m), `bins + 1` of them.
    pub edges: Vec<f64>,
    /// Probability density of the whole layer per bin (1/m).
    pub whole: Vec<f64>,
    /// Probability density of the grains inside stripes per bin (1/m; zeros when none).
    pub stripes: Vec<f64>,
    /// Number of grains inside stripes (summed over the frames tallied).
    pub in_stripes: usize,
    /// Number of frames tallied.
    pub frames: usize,
    /// Mean radius of the layer (m).
    pub mean_whole: f64,
    /// Mean radius inside stripes (m; NaN when no grain is inside one).
    pub mean_stripes: f64,
    /// `mean_stripes / mean_whole - 1`.
    pub relative_change: f64,
}

impl RadiusDistribution {
    /// The layer's radii `r` against the grains inside stripes in `tally`, taken over `frames` frames.
    pub fn from_tally(r: &[f64], bins: &RadiusBins, tally: &RadiusTally, frames: usize) -> Self {
        let mut whole = vec![0.0; bins.bins];
        for &ri in r {
            whole[bins.bin(ri)] += 1.0;
        }
        let density =
            |h: &[f64], n: usize| -> Vec<f64> { h.iter().map(|v| if n > 0 { v / (n as f64 * bins.step) } else { 0.0 }).collect() };
        let mean_whole = r.iter().sum::<f64>() / r.len().max(1) as f64;
        let mean_stripes = if tally.n > 0 { tally.sum / tally.n as f64 } else { f64::NAN };
        Self {
            edges: bins.edges(),
            whole: density(&whole, r.len()),
            stripes: density(&tally.counts, tally.n),
            in_stripes: tally.n,
            frames,
            mean_whole,
            mean_stripes,
            relative_change: mean_stripes / mean_whole - 1.0,
        }
    }
}

/// Radius distribution of one frame: the grains at `x` (radii `r`) inside `stripes`
/// against all, in `bins` bins.
pub fn radius_distribution(x: &[f64], r: &[f64], stripes: &[Stripe], length: f64, bins: usize) -> RadiusDistribution {
    let b = RadiusBins::of(r, bins);
    let mut t = RadiusTally::new(&b);
    t.add_frame(x, r, stripes, length, &b);
    RadiusDistribution::from_tally(r, &b, &t, 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stripe(start: f64, width: f64) -> Stripe {
        Stripe {
            start,
            center: start + 0.5 * width,
            width,
            mass: 0.01,
        }
    }

    #[test]
    fn big_grains_in_the_stripe_show_up() {
        // Small grains spread out, the big ones all in one stripe over [0.9, 0.1) (seam).
        let x = [0.3, 0.5, 0.7, 0.95, 0.05];
        let r = [1e-3, 1e-3, 1e-3, 2e-3, 2e-3];
        let d = radius_distribution(&x, &r, &[stripe(0.9, 0.2)], 1.0, 4);
        assert_eq!(d.in_stripes, 2);
        assert!((d.mean_stripes - 2e-3).abs() < 1e-15);
        assert!((d.mean_whole - 1.4e-3).abs() < 1e-15);
        assert!((d.relative_change - (2.0 / 1.4 - 1.0)).abs() < 1e-12);
        let integral = |h: &[f64]| h.iter().sum::<f64>() * (d.edges[1] - d.edges[0]);
        assert!((integral(&d.whole) - 1.0).abs() < 1e-12 && (integral(&d.stripes) - 1.0).abs() < 1e-12);
        assert_eq!(d.stripes[3] * (d.edges[1] - d.edges[0]), 1.0);
    }

    #[test]
    fn the_cell_mask_agrees_with_the_intervals() {
        // Stripes from a detected profile; grain centres at cell middles.
        let cells = 200;
        let phi: Vec<f64> = (0..cells)
            .map(|c| if (c / 13) % 3 == 0 || !(4..=190).contains(&c) { 0.8 } else { 0.1 })
            .collect();
        let stripes = crate::stripes::detect(
            &phi,
            1.0,
            &crate::stripes::StripeParams {
                threshold: 0.3,
                min_width: 0.0,
            },
        );
        let x: Vec<f64> = (0..1000).map(|k| (k as f64 + 0.5) / 1000.0).collect();
        let r: Vec<f64> = (0..1000).map(|k| 1e-3 + 1e-6 * (k % 7) as f64).collect();
        let b = RadiusBins::of(&r, 5);
        let (mut a, mut c) = (RadiusTally::new(&b), RadiusTally::new(&b));
        a.add_frame(&x, &r, &stripes, 1.0, &b);
        c.add_frame_on_cells(&x, &r, &stripes, 1.0, cells, &b);
        assert!(a.n > 100);
        assert_eq!(a, c);
    }

    #[test]
    fn binary_search_membership_matches_a_linear_scan() {
        let stripes = [stripe(0.95, 0.1), stripe(0.2, 0.05), stripe(0.5, 0.1), stripe(0.7, 0.01)];
        let x: Vec<f64> = (0..1000).map(|k| k as f64 / 1000.0 + 0.0003).collect();
        let r = vec![1e-3; x.len()];
        let b = RadiusBins::of(&r, 3);
        let mut t = RadiusTally::new(&b);
        t.add_frame(&x, &r, &stripes, 1.0, &b);
        let linear = x.iter().filter(|&&x| stripes.iter().any(|s| s.contains(x, 1.0))).count();
        assert_eq!(t.n, linear);
        assert_eq!(linear, 100 + 50 + 100 + 10);
        let mut twice = t.clone();
        twice.merge(&t);
        assert_eq!(twice.n, 2 * t.n);
    }
}
