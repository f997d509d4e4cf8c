//! Probability densities from samples, binned on a fixed range: what the velocity and
//! free-time distributions of the event-driven model are drawn with.

/// The probability density of `values` on `bins` equal bins over `[lo, hi)`: per bin, its
/// centre and `count / (total * width)`, with `total` counting every finite value (those
/// outside the range too, so the densities integrate to the fraction inside it). Empty or
/// degenerate input gives no bins.
pub fn density(values: &[f64], lo: f64, hi: f64, bins: usize) -> Vec<(f64, f64)> {
    let finite: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if finite.is_empty() || bins == 0 || hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Vec::new();
    }
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0u64; bins];
    for x in &finite {
        if *x >= lo && *x < hi {
            counts[(((x - lo) / width) as usize).min(bins - 1)] += 1;
        }
    }
    let total = finite.len() as f64;
    counts
        .iter()
        .enumerate()
        .map(|(k, &c)| (lo + (k as f64 + 0.5) * width, c as f64 / (total * width)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densities_integrate_to_the_fraction_inside_the_range() {
        // Values between bin edges (a value on an edge falls on either side by round-off).
        let v: Vec<f64> = (0..1000).map(|k| (k as f64 + 0.5) / 1000.0).collect();
        let d = density(&v, 0.0, 0.5, 10);
        let integral: f64 = d.iter().map(|(_, p)| p * 0.05).sum();
        assert!((integral - 0.5).abs() < 1e-12, "{integral}");
        assert!(d.iter().all(|(_, p)| (p - 1.0).abs() < 1e-12));
        assert_eq!(d[0].0, 0.025);
        assert!(density(&[], 0.0, 1.0, 4).is_empty());
        assert!(density(&[f64::NAN], 0.0, 1.0, 4).is_empty());
    }
}
