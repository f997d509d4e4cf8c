//! Summary statistics of repeated measurements (seeds, runs, residence times).

/// Mean and standard error of the mean, `s / sqrt(n)` with the sample standard deviation
/// `s`; the error is NaN (undefined) for one value, and both are NaN for none.
pub fn mean_stderr(xs: &[f64]) -> (f64, f64) {
    if xs.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    // One value has no spread: its error is undefined (NaN), not 0 (issue 43, finding 10:
    // one seed gave a standard error of 0).
    if xs.len() < 2 {
        return (mean, f64::NAN);
    }
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_standard_error_of_small_samples() {
        let (m, se) = mean_stderr(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(m, 2.5);
        // s^2 = 5/3, se = sqrt(5/12).
        assert!((se - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
        let (m, se) = mean_stderr(&[7.0]);
        assert!(m == 7.0 && se.is_nan(), "one value: {m} +- {se}");
        let (m, se) = mean_stderr(&[]);
        assert!(m.is_nan() && se.is_nan());
    }
}
