//! The restitution table against its closed forms (equal spheres, `alpha = (2/7) m_eff`,
//! `omega_n = sqrt(k_n / m_eff)`, a linear spring without normal damping where a limit
//! needs it; stiff enough, 1e5 N/m, that the normal barely turns and the overlap stays below
//! 0.05 % of the radius, the hard-sphere limit the closed forms assume): Walton's Coulomb branch for any law, Haff-Werner's and Cundall-Strack's
//! limits as `g_t -> 0`. A wrong law or a wrong sign of beta fails here.

use particles::contact::choice::{LawChoice, LawParameters, NormalKind, RollingKind, TangentialKind};
use particles::experiment::collide::{Collision, Impact, Target};
use particles::experiment::restitution::{coulomb_branch, table};

const R: f64 = 5e-4;
const RHO: f64 = 2500.0;
const KN: f64 = 1e5;

fn collision(tangential: TangentialKind, gamma_n: f64, mu: f64, gamma_t: f64, kt: f64, wall: bool) -> Collision {
    let law = LawChoice {
        normal: NormalKind::Linear,
        tangential,
        rolling: RollingKind::None,
    }
    .build(&LawParameters {
        reduced_modulus: 1e6,
        dissipation: 0.0,
        kn: Some(KN),
        gamma_n,
        mu,
        gamma_t,
        kt: Some(kt),
        mu_r: 0.0,
        rolling_resistance: None,
        k_roll: None,
        gamma_roll: 0.0,
    })
    .unwrap();
    let mut c = Collision::equal_spheres(law, R, RHO, Impact::Components { vn: 0.1, vt: 0.0 }, 2000.0);
    if wall {
        c.target = Target::Wall;
    }
    c
}

fn m_eff(wall: bool) -> f64 {
    let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
    if wall {
        m
    } else {
        m / 2.0
    }
}

#[test]
fn sliding_impacts_follow_the_coulomb_branch_for_both_tangential_laws_pairs_and_floor() {
    for wall in [false, true] {
        for (law, gamma_t, kt) in [(TangentialKind::HaffWerner, 10.0, KN), (TangentialKind::CundallStrack, 0.0, KN)] {
            let c = collision(law, 2e-3, 0.1, gamma_t, kt, wall);
            let rows = table(&c, &[0.05, 0.2], &[3.0, 6.0]).unwrap();
            for row in rows {
                let want = coulomb_branch(0.1, row.eps_n, row.g_t_over_g_n);
                assert!(
                    (row.beta - want).abs() < 5e-3,
                    "{law:?} wall {wall}: beta {} vs Coulomb {want} at g_t/g_n {}",
                    row.beta,
                    row.g_t_over_g_n
                );
                assert!(row.eps_n > 0.5 && row.eps_n < 1.0);
            }
        }
    }
}

#[test]
fn haff_werner_without_sliding_gives_the_exponential_limit() {
    for wall in [false, true] {
        let m = m_eff(wall);
        let (alpha, omega_n) = (2.0 / 7.0 * m, (KN / m).sqrt());
        // gamma_t chosen so that the exponent is about 1.
        let gamma_t = alpha * omega_n / std::f64::consts::PI;
        let c = collision(TangentialKind::HaffWerner, 0.0, 1e6, gamma_t, KN, wall);
        let want = -(-std::f64::consts::PI * gamma_t / (alpha * omega_n)).exp();
        for row in table(&c, &[0.1], &[0.01, 0.1]).unwrap() {
            assert!((row.eps_n - 1.0).abs() < 1e-3, "elastic normal spring: {}", row.eps_n);
            assert!((row.beta - want).abs() < 5e-3, "wall {wall}: beta {} vs {want}", row.beta);
        }
    }
}

#[test]
fn cundall_strack_without_sliding_gives_the_cosine_limit() {
    for (kt, wall) in [(KN, false), (KN, true), (0.5 * KN, false)] {
        let c = collision(TangentialKind::CundallStrack, 0.0, 1e6, 0.0, kt, wall);
        let want = -(std::f64::consts::PI * (kt / KN * 3.5).sqrt()).cos();
        if kt == KN {
            assert!((want - -0.919).abs() < 1e-3);
        }
        for row in table(&c, &[0.1], &[0.01, 0.1]).unwrap() {
            assert!(
                (row.beta - want).abs() < 5e-3,
                "k_t/k_n {} wall {wall}: beta {} vs {want}",
                kt / KN,
                row.beta
            );
        }
    }
}

#[test]
fn a_ratio_of_zero_is_refused_naming_it() {
    let c = collision(TangentialKind::HaffWerner, 0.0, 0.5, 1e-3, KN, false);
    let e = table(&c, &[0.1], &[0.0]).unwrap_err().to_string();
    assert!(e.contains("g_t / g_n = 0"), "{e}");
}
