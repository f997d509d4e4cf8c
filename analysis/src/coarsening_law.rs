//! The coarsening law of the stripe count `S(t)`, fitted two ways: a power law
//! `S = a t^-alpha` and the logarithmic decay `S = a - b ln t` that the thesis cites (eq 1.3,
//! after Oyama's drum: `S(t) = S0 (1 - s log(omega t / 2 pi))`), each by least squares on `S`
//! itself, with 95 % confidence intervals; then which one fits better.
//!
//! - Power law: Gauss-Newton on `S`, started from the straight line through `(ln t, ln S)`.
//! - Logarithm: ordinary least squares of `S` on `ln t`.
//! - Intervals: `+- t_{0.975, n-2} sqrt(diag(s^2 (J^T J)^-1))`, `s^2 = RSS / (n - 2)`. They
//!   assume independent residuals; a count read every period stays the same for many frames,
//!   so the true intervals are wider: read them as a lower bound on the uncertainty.
//! - Which fits ([`Verdict`]): both models have two parameters, so their Akaike criteria
//!   (`n ln(RSS / n) + 2 k`) differ by `n ln(RSS_power / RSS_log)`. A difference beyond 2
//!   (Burnham and Anderson's "substantially less support") names the better law; otherwise,
//!   or with fewer than [`MIN_POINTS`] points or fewer than [`MIN_LEVELS`] distinct counts,
//!   the law is `undetermined`.

use serde::Serialize;

/// Fewer points than this leave the law undetermined.
pub const MIN_POINTS: usize = 6;
/// Fewer distinct values of `S` than this leave the law undetermined (a count that steps
/// once is fitted equally well by any decreasing curve).
pub const MIN_LEVELS: usize = 3;
/// The Akaike difference that names the better law.
pub const AIC_MARGIN: f64 = 2.0;

/// One fitted law: `S = a t^-rate` (power) or `S = a - rate ln t` (logarithmic), with 95 %
/// confidence intervals, the residual sum of squares on `S` and the Akaike criterion.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Fit {
    pub a: f64,
    pub a_ci95: (f64, f64),
    /// `alpha` of the power law, `b` of the logarithm.
    pub rate: f64,
    pub rate_ci95: (f64, f64),
    pub rss: f64,
    pub aic: f64,
    pub points: usize,
}

impl Fit {
    /// The fitted `S` at `t` for the power law (`power = true`) or the logarithm.
    pub fn eval(&self, t: f64, power: bool) -> f64 {
        if power {
            self.a * t.powf(-self.rate)
        } else {
            self.a - self.rate * t.ln()
        }
    }
}

/// Which law fits the count better.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    Power,
    Logarithmic,
    Undetermined,
}

/// Both fits and the verdict, with the reason in words.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawComparison {
    pub power: Option<Fit>,
    pub logarithmic: Option<Fit>,
    /// `AIC_power - AIC_log`: negative favours the power law.
    pub delta_aic: Option<f64>,
    pub better: Verdict,
    pub note: String,
}

/// The 97.5 % quantile of Student's t with `dof` degrees of freedom (the table's values for 1
/// to 4, the Cornish-Fisher expansion to third order above: within 0.2 % of the table at 5,
/// 1e-4 from 10 on).
pub fn t975(dof: usize) -> f64 {
    match dof {
        0 => f64::INFINITY,
        1 => 12.706204736,
        2 => 4.302652730,
        3 => 3.182446305,
        4 => 2.776445105,
        _ => {
            let z: f64 = 1.959963985;
            let n = dof as f64;
            let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
            z + (z3 + z) / (4.0 * n)
                + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * n * n)
                + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * n * n * n)
        }
    }
}

fn aic(rss: f64, n: usize) -> f64 {
    let n = n as f64;
    n * (rss.max(1e-300) / n).ln() + 2.0 * 3.0
}

/// Intervals and summary of a two-parameter least-squares fit with Jacobian rows `j` at the
/// optimum `(a, rate)`.
fn finish(a: f64, rate: f64, j: &[[f64; 2]], rss: f64) -> Fit {
    let n = j.len();
    let (mut s00, mut s01, mut s11) = (0.0, 0.0, 0.0);
    for r in j {
        s00 += r[0] * r[0];
        s01 += r[0] * r[1];
        s11 += r[1] * r[1];
    }
    let det = s00 * s11 - s01 * s01;
    let s2 = if n > 2 { rss / (n - 2) as f64 } else { f64::NAN };
    let q = t975(n.saturating_sub(2));
    let (ea, er) = if det > 0.0 {
        (q * (s2 * s11 / det).sqrt(), q * (s2 * s00 / det).sqrt())
    } else {
        (f64::NAN, f64::NAN)
    };
    Fit {
        a,
        a_ci95: (a - ea, a + ea),
        rate,
        rate_ci95: (rate - er, rate + er),
        rss,
        aic: aic(rss, n),
        points: n,
    }
}

/// Ordinary least squares of `y` on `x`: (intercept, slope); None when `x` is constant.
fn line(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|v| (v - mx) * (v - mx)).sum();
    if sxx.is_nan() || sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    Some((my - slope * mx, slope))
}

/// `S = a - b ln t` by least squares (points with `t > 0`); None with fewer than 3 such points
/// or a single time.
pub fn fit_log(t: &[f64], s: &[f64]) -> Option<Fit> {
    let (lt, s): (Vec<f64>, Vec<f64>) = t.iter().zip(s).filter(|(t, _)| **t > 0.0).map(|(t, s)| (t.ln(), *s)).unzip();
    if lt.len() < 3 {
        return None;
    }
    let (a, slope) = line(&lt, &s)?;
    let b = -slope;
    let rss = lt.iter().zip(&s).map(|(l, v)| (v - (a - b * l)).powi(2)).sum();
    let j: Vec<[f64; 2]> = lt.iter().map(|l| [1.0, -l]).collect();
    Some(finish(a, b, &j, rss))
}

/// The points with `t > 0` and `S > 0`, the only ones both laws are defined on.
fn positive_points(t: &[f64], s: &[f64]) -> (Vec<f64>, Vec<f64>) {
    t.iter()
        .zip(s)
        .filter(|(t, s)| **t > 0.0 && **s > 0.0)
        .map(|(t, s)| (*t, *s))
        .unzip()
}

/// `S = a t^-alpha` by least squares on `S` (points with `t > 0` and `S > 0`); None with
/// fewer than 3 such points or a single time.
pub fn fit_power(t: &[f64], s: &[f64]) -> Option<Fit> {
    let (t, s) = positive_points(t, s);
    if t.len() < 3 {
        return None;
    }
    let lt: Vec<f64> = t.iter().map(|v| v.ln()).collect();
    let ls: Vec<f64> = s.iter().map(|v| v.ln()).collect();
    let (la, slope) = line(&lt, &ls)?;
    let (mut a, mut alpha) = (la.exp(), -slope);
    let rss_of = |a: f64, alpha: f64| -> f64 { lt.iter().zip(&s).map(|(l, v)| (v - a * (-alpha * l).exp()).powi(2)).sum() };
    let mut rss = rss_of(a, alpha);
    for _ in 0..100 {
        // Gauss-Newton step on (a, alpha), halved until the residual falls.
        let (mut g0, mut g1, mut h00, mut h01, mut h11) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (l, v) in lt.iter().zip(&s) {
            let p = (-alpha * l).exp();
            let (j0, j1) = (p, -a * p * l);
            let r = v - a * p;
            g0 += j0 * r;
            g1 += j1 * r;
            h00 += j0 * j0;
            h01 += j0 * j1;
            h11 += j1 * j1;
        }
        let det = h00 * h11 - h01 * h01;
        if det.is_nan() || det <= 0.0 {
            break;
        }
        let (mut da, mut dal) = ((h11 * g0 - h01 * g1) / det, (h00 * g1 - h01 * g0) / det);
        let mut improved = false;
        for _ in 0..30 {
            let r = rss_of(a + da, alpha + dal);
            if r <= rss {
                improved = r < rss * (1.0 - 1e-15);
                a += da;
                alpha += dal;
                rss = r;
                break;
            }
            da *= 0.5;
            dal *= 0.5;
        }
        if !improved {
            break;
        }
    }
    let j: Vec<[f64; 2]> = lt
        .iter()
        .map(|l| {
            let p = (-alpha * l).exp();
            [p, -a * p * l]
        })
        .collect();
    Some(finish(a, alpha, &j, rss))
}

/// Both laws fitted to the same points (those with `t > 0` and `S > 0`, so the two compare on
/// one set) and the verdict (module docs).
pub fn compare(t: &[f64], s: &[f64]) -> LawComparison {
    let (t, s) = positive_points(t, s);
    let power = fit_power(&t, &s);
    let logarithmic = fit_log(&t, &s);
    let mut levels: Vec<f64> = s.clone();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    let delta_aic = match (power, logarithmic) {
        (Some(p), Some(l)) => Some(p.aic - l.aic),
        _ => None,
    };
    let (better, note) = if t.len() < MIN_POINTS {
        (
            Verdict::Undetermined,
            format!("{} points with S > 0 (at least {MIN_POINTS} needed)", t.len()),
        )
    } else if levels.len() < MIN_LEVELS {
        (
            Verdict::Undetermined,
            format!(
                "the count takes {} distinct value(s) (at least {MIN_LEVELS} needed to tell two decreasing laws apart)",
                levels.len()
            ),
        )
    } else {
        match delta_aic {
            Some(d) if d < -AIC_MARGIN => (Verdict::Power, format!("AIC_power - AIC_log = {d:.2} < -{AIC_MARGIN}")),
            Some(d) if d > AIC_MARGIN => (Verdict::Logarithmic, format!("AIC_power - AIC_log = {d:.2} > {AIC_MARGIN}")),
            Some(d) => (
                Verdict::Undetermined,
                format!(
                    "|AIC_power - AIC_log| = {:.2} <= {AIC_MARGIN}: the data do not tell the laws apart",
                    d.abs()
                ),
            ),
            None => (Verdict::Undetermined, "a fit failed (a single time)".to_string()),
        }
    };
    LawComparison {
        power,
        logarithmic,
        delta_aic,
        better,
        note,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic relative noise of about +-1 %.
    fn noise(k: usize) -> f64 {
        0.01 * ((k as f64 * 12.9898).sin() * 43758.5453).fract()
    }

    fn times() -> Vec<f64> {
        (0..40).map(|k| 10f64.powf(k as f64 * 3.5 / 39.0)).collect()
    }

    #[test]
    fn t_quantile_matches_the_table() {
        for (dof, want) in [(3, 3.182446), (5, 2.570582), (10, 2.228139), (30, 2.042272), (1000, 1.962339)] {
            assert!((t975(dof) - want).abs() < 2e-3 * want, "dof {dof}: {} vs {want}", t975(dof));
        }
    }

    #[test]
    fn a_power_law_count_gives_its_exponent_back_and_is_told_from_a_logarithm() {
        let t = times();
        let s: Vec<f64> = t.iter().enumerate().map(|(k, t)| 12.0 * t.powf(-0.3) * (1.0 + noise(k))).collect();
        let c = compare(&t, &s);
        let p = c.power.unwrap();
        assert!(p.rate_ci95.0 < 0.3 && 0.3 < p.rate_ci95.1, "{p:?}");
        assert!((p.rate - 0.3).abs() < 0.01 && p.rate_ci95.1 - p.rate_ci95.0 < 0.02, "{p:?}");
        assert!((p.a - 12.0).abs() < 0.01 * 12.0 && p.a_ci95.0 < p.a && p.a < p.a_ci95.1, "{p:?}");
        assert_eq!(c.better, Verdict::Power, "{c:?}");
    }

    #[test]
    fn a_logarithmic_count_gives_its_slope_back_and_is_told_from_a_power_law() {
        let t = times();
        let s: Vec<f64> = t
            .iter()
            .enumerate()
            .map(|(k, t)| (12.0 - 1.2 * t.ln()) * (1.0 + noise(k)))
            .collect();
        let c = compare(&t, &s);
        let l = c.logarithmic.unwrap();
        assert!(l.rate_ci95.0 < 1.2 && 1.2 < l.rate_ci95.1, "{l:?}");
        assert!(l.a_ci95.0 < 12.0 && 12.0 < l.a_ci95.1, "{l:?}");
        assert_eq!(c.better, Verdict::Logarithmic, "{c:?}");
        assert!(c.delta_aic.unwrap() > AIC_MARGIN);
    }

    #[test]
    fn few_points_or_levels_leave_the_law_undetermined() {
        let c = compare(&[1.0, 2.0, 4.0, 8.0], &[5.0, 4.0, 3.0, 2.0]);
        assert_eq!(c.better, Verdict::Undetermined);
        assert!(c.note.contains("4 points"), "{}", c.note);
        let t = times();
        let s: Vec<f64> = t.iter().map(|t| if *t < 100.0 { 3.0 } else { 2.0 }).collect();
        let c = compare(&t, &s);
        assert_eq!(c.better, Verdict::Undetermined, "{c:?}");
        assert!(c.note.contains("2 distinct"), "{}", c.note);
    }
}
