//! Autocorrelation of a time series sampled once per period, such as the mean square
//! displacement `D` (thesis eq 3.32, Fig 3.47).
//!
//! The thesis writes `C(t) = sum_{t0=0}^{N-1} D(t) D(t + t0)`. For a finite series of
//! `M` samples this is read as the sum over all available pairs at lag `k`,
//! `C_k = sum_{j=0}^{M-1-k} D_j D_{j+k}` ([`raw`]). Because `D` never changes sign, `C_k`
//! is dominated by the number of pairs and the mean; [`normalised`] is the usual estimator
//! of the autocorrelation coefficient, `rho_k = sum_j (D_j - m)(D_{j+k} - m) / ((M - k) s^2)`
//! with mean `m` and variance `s^2`, which is 1 at lag 0 and shows the memory of the series
//! (e.g. a stripe lifetime as a peak, as the thesis suggests near 100 s).

/// Eq 3.32 as a sum over the `M - k` pairs at each lag `k = 0..max_lag` (inclusive, capped
/// at `M - 1`).
pub fn raw(series: &[f64], max_lag: usize) -> Vec<f64> {
    let m = series.len();
    (0..=max_lag.min(m.saturating_sub(1)))
        .take(m)
        .map(|k| (0..m - k).map(|j| series[j] * series[j + k]).sum())
        .collect()
}

/// Autocorrelation coefficient `rho_k` for `k = 0..max_lag` (inclusive, capped at `M - 1`);
/// all NaN after lag 0 if the series is constant (it has no variance to correlate), and
/// empty for an empty series.
pub fn normalised(series: &[f64], max_lag: usize) -> Vec<f64> {
    let m = series.len();
    if m == 0 {
        return Vec::new();
    }
    let mean = series.iter().sum::<f64>() / m as f64;
    let var = series.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / m as f64;
    (0..=max_lag.min(m - 1))
        .map(|k| {
            if var == 0.0 {
                return if k == 0 { 1.0 } else { f64::NAN };
            }
            let c: f64 = (0..m - k).map(|j| (series[j] - mean) * (series[j + k] - mean)).sum();
            c / ((m - k) as f64 * var)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_periodic_series_correlates_at_its_period() {
        let s: Vec<f64> = (0..400)
            .map(|k| 1.0 + (2.0 * std::f64::consts::PI * k as f64 / 50.0).sin())
            .collect();
        let rho = normalised(&s, 100);
        assert!((rho[0] - 1.0).abs() < 1e-12);
        assert!((rho[25] + 1.0).abs() < 0.02, "anti-correlated at half the period: {}", rho[25]);
        assert!((rho[50] - 1.0).abs() < 0.02, "{}", rho[50]);
        let c = raw(&[1.0, 2.0, 3.0], 5);
        assert_eq!(c, vec![14.0, 8.0, 3.0]);
        assert!(normalised(&[2.0; 4], 2)[1].is_nan());
    }
}
