//! Closed-form references for head-on collisions.

/// Head-on collision under the linear spring-dashpot law `F = k xi + gamma dxi/dt` with the
/// no-attraction clamp: `m xi'' + gamma xi' + k xi = 0`, `xi(0) = 0`, `xi'(0) = v`, ending at
/// the first `t > 0` where the force `k xi + gamma xi' = -m xi''` vanishes (eq 4.8; Schwager &
/// Pöschel 2007). With `beta = gamma / (2m)`, `w0^2 = k/m`:
/// - underdamped (`beta < w0`, `w = sqrt(w0^2 - beta^2)`):
///   `xi = (v/w) e^{-beta t} sin(w t)`, `t_c = atan2(2 beta w, beta^2 - w^2) / w`;
/// - critically damped: `xi = v t e^{-beta t}`, `t_c = 2 / beta`;
/// - overdamped (`W = sqrt(beta^2 - w0^2)`): `t_c = ln((beta + W)/(beta - W)) / W`.
///
/// Returns `(t_c, eps_n)` with `eps_n = -xi'(t_c) / v` (independent of `v`).
pub fn linear_dashpot(m_eff: f64, k: f64, gamma: f64, v: f64) -> (f64, f64) {
    let beta = gamma / (2.0 * m_eff);
    let w0 = (k / m_eff).sqrt();
    if beta < w0 * (1.0 - 1e-12) {
        let w = (w0 * w0 - beta * beta).sqrt();
        let tc = (2.0 * beta * w).atan2(beta * beta - w * w) / w;
        let xi_dot = v * (-beta * tc).exp() * ((w * tc).cos() - beta / w * (w * tc).sin());
        (tc, -xi_dot / v)
    } else if beta > w0 * (1.0 + 1e-12) {
        let big_w = (beta * beta - w0 * w0).sqrt();
        let (l1, l2) = (-beta + big_w, -beta - big_w);
        let tc = ((beta + big_w) / (beta - big_w)).ln() / big_w;
        let xi_dot = v / (2.0 * big_w) * (l1 * (l1 * tc).exp() - l2 * (l2 * tc).exp());
        (tc, -xi_dot / v)
    } else {
        let tc = 2.0 / beta;
        let xi_dot = v * (-beta * tc).exp() * (1.0 - beta * tc);
        (tc, -xi_dot / v)
    }
}

/// Damping coefficient `gamma` (kg/s) of the linear dashpot for a damping ratio
/// `zeta = gamma / (2 sqrt(k m))`.
pub fn gamma_for_damping_ratio(m_eff: f64, k: f64, ratio: f64) -> f64 {
    2.0 * ratio * (k * m_eff).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastic_limit_is_half_period() {
        let (tc, eps) = linear_dashpot(2.0, 8.0, 0.0, 1.0);
        assert!((tc - std::f64::consts::PI / 2.0).abs() < 1e-12);
        assert!((eps - 1.0).abs() < 1e-12);
    }

    #[test]
    fn regimes_join_continuously_at_critical_damping() {
        let (m, k) = (1.0, 1.0);
        let crit = linear_dashpot(m, k, 2.0, 1.0);
        for g in [2.0 * (1.0 - 1e-7), 2.0 * (1.0 + 1e-7)] {
            let near = linear_dashpot(m, k, g, 1.0);
            assert!((near.0 - crit.0).abs() < 1e-5, "{near:?} {crit:?}");
            assert!((near.1 - crit.1).abs() < 1e-5, "{near:?} {crit:?}");
        }
        // The force vanishes at t_c: xi'' = 0 there. Check with the critical solution.
        assert!((crit.0 - 2.0).abs() < 1e-12);
        assert!((crit.1 - (-2.0f64).exp()).abs() < 1e-12);
    }
}
