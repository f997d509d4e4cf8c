//! Size segregation: the distribution of radii of the grains inside stripes against the
//! whole layer (thesis Fig 3.26: "the average radius in the stripes ... a change of about
//! 2.5 per cent, suggesting that size segregation plays no role").
//!
//! A grain is inside a stripe when its centre lies in the stripe's interval
//! [`Stripe::contains`]. The histogram has `bins` equal bins between the smallest and the
//! largest radius of the layer and is normalised to a probability density (1/m).

use crate::stripes::Stripe;

/// Radii inside stripes against the whole layer.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RadiusDistribution {
    /// Bin edges (m), `bins + 1` of them.
    pub edges: Vec<f64>,
    /// Probability density of the whole layer per bin (1/m).
    pub whole: Vec<f64>,
    /// Probability density of the grains inside stripes per bin (1/m; zeros when none).
    pub stripes: Vec<f64>,
    /// Number of grains inside stripes.
    pub in_stripes: usize,
    /// Mean radius of the layer (m).
    pub mean_whole: f64,
    /// Mean radius inside stripes (m; NaN when no grain is inside one).
    pub mean_stripes: f64,
    /// `mean_stripes / mean_whole - 1`.
    pub relative_change: f64,
}

/// Radius distribution of the grains at `x` (with radii `r`) inside `stripes` against all.
pub fn radius_distribution(x: &[f64], r: &[f64], stripes: &[Stripe], length: f64, bins: usize) -> RadiusDistribution {
    assert_eq!(x.len(), r.len(), "one radius per grain");
    let bins = bins.max(1);
    let (lo, hi) = r.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let (lo, hi) = if r.is_empty() {
        (0.0, 1.0)
    } else if hi > lo {
        (lo, hi)
    } else {
        (lo * 0.99, lo * 1.01 + f64::MIN_POSITIVE)
    };
    let step = (hi - lo) / bins as f64;
    let bin = |v: f64| (((v - lo) / step) as usize).min(bins - 1);
    let (mut whole, mut inside) = (vec![0.0; bins], vec![0.0; bins]);
    let (mut sum_in, mut n_in) = (0.0, 0usize);
    for (&xi, &ri) in x.iter().zip(r) {
        whole[bin(ri)] += 1.0;
        if stripes.iter().any(|s| s.contains(xi, length)) {
            inside[bin(ri)] += 1.0;
            sum_in += ri;
            n_in += 1;
        }
    }
    let normalise = |h: &mut Vec<f64>, n: usize| {
        if n > 0 {
            h.iter_mut().for_each(|v| *v /= n as f64 * step);
        }
    };
    normalise(&mut whole, r.len());
    normalise(&mut inside, n_in);
    let mean_whole = r.iter().sum::<f64>() / r.len().max(1) as f64;
    let mean_stripes = if n_in > 0 { sum_in / n_in as f64 } else { f64::NAN };
    RadiusDistribution {
        edges: (0..=bins).map(|k| lo + k as f64 * step).collect(),
        whole,
        stripes: inside,
        in_stripes: n_in,
        mean_whole,
        mean_stripes,
        relative_change: mean_stripes / mean_whole - 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn big_grains_in_the_stripe_show_up() {
        // Small grains spread out, the big ones all in one stripe over [0.9, 0.1) (seam).
        let x = [0.3, 0.5, 0.7, 0.95, 0.05];
        let r = [1e-3, 1e-3, 1e-3, 2e-3, 2e-3];
        let s = [Stripe {
            start: 0.9,
            center: 0.0,
            width: 0.2,
            mass: 0.01,
        }];
        let d = radius_distribution(&x, &r, &s, 1.0, 4);
        assert_eq!(d.in_stripes, 2);
        assert!((d.mean_stripes - 2e-3).abs() < 1e-15);
        assert!((d.mean_whole - 1.4e-3).abs() < 1e-15);
        assert!((d.relative_change - (2.0 / 1.4 - 1.0)).abs() < 1e-12);
        let integral = |h: &[f64]| h.iter().sum::<f64>() * (d.edges[1] - d.edges[0]);
        assert!((integral(&d.whole) - 1.0).abs() < 1e-12 && (integral(&d.stripes) - 1.0).abs() < 1e-12);
        assert_eq!(d.stripes[3] * (d.edges[1] - d.edges[0]), 1.0);
    }
}
