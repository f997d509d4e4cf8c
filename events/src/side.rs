//! Which side of the box the grains crowd to, and for how long: the mixture paper's cluster
//! at a side wall (its section 3.3: a "denser cloud of grains in the vicinity of one of the
//! side walls ... maintained over an interval much longer than the vibration period", which
//! "evaporates to form again close to a randomly selected side wall").
//!
//! The record is the imbalance `s = (N_left - N_right) / N` at each sample. Grains placed
//! independently and evenly would give `s` a spread of `1 / sqrt(N)`; a cluster shows as a
//! larger spread, and its life as the time `s` keeps its sign. A side is held from the
//! sample where `s` passes `+threshold` (or `-threshold`) until it passes the opposite one,
//! so that noise around zero does not count as a change of side. The threshold is the larger
//! of two independent spreads, `2 / sqrt(N)`, and half the record's own RMS: a strongly
//! clustered box swings by more than independent grains would, and its swings about one side
//! are not changes of side.

/// The imbalance's statistics over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct SideStats {
    /// Samples in the record.
    pub samples: usize,
    /// Root mean square of `s`, and the same for independent grains, `1 / sqrt(N)`.
    pub rms: f64,
    pub rms_independent: f64,
    /// The side-holding threshold used.
    pub threshold: f64,
    /// Times a side was held from one change to the next (s); the first and the last stay
    /// out, since the record cuts them.
    pub residences: Vec<f64>,
    /// Integrated autocorrelation time of `s` (s), summed until the autocorrelation first
    /// drops below zero.
    pub correlation_time: f64,
}

impl SideStats {
    /// The mean of the complete residence times (NaN when there are none).
    pub fn mean_residence(&self) -> f64 {
        if self.residences.is_empty() {
            f64::NAN
        } else {
            self.residences.iter().sum::<f64>() / self.residences.len() as f64
        }
    }
}

/// The imbalance of one configuration: `x` the centres' positions along the floor, in a box
/// from 0 to `width`.
pub fn imbalance(x: impl Iterator<Item = f64>, width: f64) -> f64 {
    let (mut left, mut n) = (0i64, 0i64);
    for x in x {
        n += 1;
        if x.rem_euclid(width) < 0.5 * width {
            left += 1;
        }
    }
    if n == 0 {
        return 0.0;
    }
    (2 * left - n) as f64 / n as f64
}

/// Statistics of a record `s` taken every `dt` seconds of a box of `n` grains, with the
/// side-holding threshold `max(2 / sqrt(N), RMS / 2)`.
pub fn stats(s: &[f64], dt: f64, n: usize) -> SideStats {
    let rms_independent = 1.0 / (n.max(1) as f64).sqrt();
    let rms = (s.iter().map(|x| x * x).sum::<f64>() / s.len().max(1) as f64).sqrt();
    let threshold = (2.0 * rms_independent).max(0.5 * rms);
    // Side changes with hysteresis.
    let mut side = 0i8;
    let mut changes = Vec::new();
    for (k, &x) in s.iter().enumerate() {
        let now = if x > threshold {
            1
        } else if x < -threshold {
            -1
        } else {
            side
        };
        if now != side {
            if side != 0 {
                changes.push(k);
            }
            side = now;
        }
    }
    let residences = changes.windows(2).map(|w| (w[1] - w[0]) as f64 * dt).collect();
    SideStats {
        samples: s.len(),
        rms,
        rms_independent,
        threshold,
        residences,
        correlation_time: correlation_time(s, dt),
    }
}

/// `dt (1/2 + sum_k C(k) / C(0))` over lags until `C` first turns negative, with `C` the
/// autocovariance about the mean (0 for a record shorter than 2 or with no variance).
fn correlation_time(s: &[f64], dt: f64) -> f64 {
    let n = s.len();
    if n < 2 {
        return 0.0;
    }
    let mean = s.iter().sum::<f64>() / n as f64;
    let d: Vec<f64> = s.iter().map(|x| x - mean).collect();
    let c0 = d.iter().map(|x| x * x).sum::<f64>() / n as f64;
    if c0 <= 0.0 {
        return 0.0;
    }
    let mut sum = 0.5;
    for lag in 1..n / 2 {
        let c = d[..n - lag].iter().zip(&d[lag..]).map(|(a, b)| a * b).sum::<f64>() / n as f64;
        if c <= 0.0 {
            break;
        }
        sum += c / c0;
    }
    sum * dt
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imbalance_counts_the_halves_of_the_box() {
        assert_eq!(imbalance([0.1, 0.2, 0.3, 0.8].into_iter(), 1.0), 0.5);
        assert_eq!(imbalance([0.9, 0.6].into_iter(), 1.0), -1.0);
        // Positions outside [0, width) are wrapped, as on a periodic box.
        assert_eq!(imbalance([1.1, -0.1].into_iter(), 1.0), 0.0);
        assert_eq!(imbalance(std::iter::empty(), 1.0), 0.0);
    }

    #[test]
    fn a_square_wave_gives_its_half_period_as_residence() {
        // 100 grains; the cluster sits 30 samples left, then 30 right, ...: the threshold is
        // half the RMS, above the independent grains' 2 / sqrt(100).
        let s: Vec<f64> = (0..300).map(|k| if (k / 30) % 2 == 0 { 0.5 } else { -0.5 }).collect();
        let st = stats(&s, 0.1, 100);
        assert_eq!(st.threshold, 0.25);
        assert_eq!(st.residences.len(), 8, "{:?}", st.residences);
        assert!(st.residences.iter().all(|r| (r - 3.0).abs() < 1e-12));
        assert!((st.mean_residence() - 3.0).abs() < 1e-12);
        assert!((st.rms - 0.5).abs() < 1e-12);
        // Noise around zero between the sides does not count as a change.
        let mut noisy = s.clone();
        for (k, x) in noisy.iter_mut().enumerate() {
            if k % 30 == 29 {
                *x = 0.1 * if k % 2 == 0 { 1.0 } else { -1.0 };
            }
        }
        assert_eq!(stats(&noisy, 0.1, 100).residences.len(), 8);
    }

    #[test]
    fn uncorrelated_noise_has_a_short_correlation_time_and_no_cluster() {
        // A deterministic pseudo-random sequence of +-0.05 around zero: below the threshold
        // of independent grains, 0.2.
        let mut x = 12345u64;
        let s: Vec<f64> = (0..2000)
            .map(|_| {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                if x >> 63 == 1 {
                    0.05
                } else {
                    -0.05
                }
            })
            .collect();
        let st = stats(&s, 0.01, 100);
        assert_eq!(st.threshold, 0.2);
        assert!(st.residences.is_empty());
        assert!(st.mean_residence().is_nan());
        assert!(st.correlation_time < 0.02, "{}", st.correlation_time);
        // A slow square wave's correlation time is of the order of its half period.
        let slow: Vec<f64> = (0..2000).map(|k| if (k / 100) % 2 == 0 { 0.5 } else { -0.5 }).collect();
        let t = stats(&slow, 0.01, 100).correlation_time;
        // (a triangle from 1 at lag 0 to 0 at half its half period: about 0.25 s).
        assert!(t > 0.2 && t < 0.35, "{t}");
    }
}
