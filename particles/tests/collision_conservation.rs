//! Conservation laws and symmetries of binary collisions (issue 2 acceptance).

use particles::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::experiment::collide::{Collision, CollisionResult, Impact, StepSize, Target};
use particles::integrate::Integrator;
use particles::{SimError, Vec3};
use proptest::prelude::*;

fn oblique(tangential: TangentialLaw, rolling: RollingLaw) -> Collision {
    Collision {
        law: ContactLaw {
            normal: NormalLaw::hertz(1e6 / 0.91, 8.5e-6),
            tangential,
            rolling,
        },
        r1: 4e-4,
        m1: 6e-7,
        omega1: Vec3::new(30.0, -200.0, 50.0),
        target: Target::Sphere {
            r: 2.5e-4,
            m: 1.7e-7,
            omega: Vec3::new(-80.0, 10.0, 400.0),
        },
        impact: Impact::Components { vn: 0.3, vt: 0.4 },
        step: StepSize::PerContact(500.0),
        integrator: Integrator::VelocityVerlet,
    }
}

#[test]
fn oblique_frictional_impacts_conserve_momentum_and_respect_coulomb() {
    for tangential in [
        TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 },
        TangentialLaw::CundallStrack { kt: 300.0, mu: 0.3 },
    ] {
        for rolling in [RollingLaw::None, RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 }] {
            let r = oblique(tangential, rolling).run().unwrap();
            println!(
                "{tangential:?} {rolling:?}: dP {:.1e} dL {:.1e} max |Ft|/(mu Fn) {:.15} min Fn {:e} eps_t {:?}",
                r.momentum_error.unwrap(),
                r.angular_momentum_error.unwrap(),
                r.max_friction_ratio,
                r.min_normal_force,
                r.eps_t
            );
            assert!(r.momentum_error.unwrap() < 1e-13, "momentum {:e}", r.momentum_error.unwrap());
            assert!(
                r.angular_momentum_error.unwrap() < 1e-12,
                "angular momentum {:e}",
                r.angular_momentum_error.unwrap()
            );
            assert!(
                r.max_friction_ratio <= 1.0 + 1e-12,
                "|F_t| / mu |F_n| reached {}",
                r.max_friction_ratio
            );
            assert!(r.min_normal_force >= 0.0);
            assert!(r.energy_after < r.energy_before);
        }
    }
}

#[test]
fn central_impact_without_tangential_speed_gives_no_nan() {
    let mut c = oblique(
        TangentialLaw::CundallStrack { kt: 300.0, mu: 0.3 },
        RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 },
    );
    c.omega1 = Vec3::zeros();
    c.target = Target::Sphere {
        r: 2.5e-4,
        m: 1.7e-7,
        omega: Vec3::zeros(),
    };
    c.impact = Impact::Components { vn: 0.3, vt: 0.0 };
    let r = c.run().unwrap();
    assert!(r.eps_n.is_finite() && r.eps_t.is_none() && r.phi == 0.0, "{r:?}");
}

fn law_strategy() -> impl Strategy<Value = (ContactLaw, f64)> {
    // Returns the law and the damping parameter used (for the energy property).
    let normal = prop_oneof![
        (0.02f64..0.8).prop_map(|ratio| (0, ratio)),
        (0.02f64..0.3).prop_map(|frac| (1, frac)),
    ];
    let tangential = prop_oneof![
        Just(TangentialLaw::None),
        (1e-4f64..1e-1, 0.05f64..1.0).prop_map(|(gamma_t, mu)| TangentialLaw::HaffWerner { gamma_t, mu }),
        (10f64..1e3, 0.05f64..1.0).prop_map(|(kt, mu)| TangentialLaw::CundallStrack { kt, mu }),
    ];
    let rolling = prop_oneof![
        Just(RollingLaw::None),
        (1e-6f64..1e-4).prop_map(|mu_r| RollingLaw::BrilliantovPoschel { mu_r })
    ];
    (normal, tangential, rolling).prop_map(|((kind, damping), tangential, rolling)| {
        let normal = if kind == 0 {
            // Linear: damping ratio mapped to gamma later (needs masses); store ratio.
            NormalLaw::Linear {
                kn: 500.0,
                gamma_n: damping,
            }
        } else {
            NormalLaw::hertz(1e6, damping)
        };
        (
            ContactLaw {
                normal,
                tangential,
                rolling,
            },
            damping,
        )
    })
}

prop_compose! {
    fn collision()(
        (law, damping) in law_strategy(),
        r1 in 1e-4f64..1e-3, r2 in 1e-4f64..1e-3,
        m1 in 1e-8f64..1e-5, m2 in 1e-8f64..1e-5,
        vn in 0.01f64..1.0, vt in -1.0f64..1.0,
        w1 in prop::array::uniform3(-500.0f64..500.0), w2 in prop::array::uniform3(-500.0f64..500.0),
    ) -> Collision {
        let mut c = Collision {
            law, r1, m1, omega1: Vec3::from(w1),
            target: Target::Sphere { r: r2, m: m2, omega: Vec3::from(w2) },
            impact: Impact::Components { vn, vt },
            step: StepSize::PerContact(300.0),
            integrator: Integrator::VelocityVerlet,
        };
        // Turn the drawn damping into law parameters scaled to this impact.
        let (m_eff, _) = c.effective();
        c.law.normal = match c.law.normal {
            NormalLaw::Linear { kn, .. } => NormalLaw::Linear { kn, gamma_n: 2.0 * damping * (kn * m_eff).sqrt() },
            NormalLaw::Hertz { reduced_modulus, .. } => {
                let t = NormalLaw::hertz(reduced_modulus, 0.0).undamped_contact_time(m_eff, r1 * r2 / (r1 + r2), vn);
                NormalLaw::hertz(reduced_modulus, damping * t)
            }
        };
        c
    }
}

fn swapped(c: &Collision) -> Collision {
    let Target::Sphere { r, m, omega } = c.target else { unreachable!() };
    Collision {
        r1: r,
        m1: m,
        omega1: omega,
        target: Target::Sphere {
            r: c.r1,
            m: c.m1,
            omega: c.omega1,
        },
        ..*c
    }
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * scale
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn random_collisions_conserve_momenta_and_never_gain_energy(c in collision()) {
        let r: CollisionResult = match c.run() {
            Ok(r) => r,
            // Refusing an impact too hard for the soft-sphere picture is a correct outcome.
            Err(SimError::ExcessiveOverlap { overlap, radius, limit, .. }) => {
                prop_assert!(overlap > limit * radius);
                return Ok(());
            }
            // So is refusing one the step cannot resolve: an overdamped slow impact whose contact
            // lasts half a step (the saved case of `vn = 0.01` m/s) has no numbers to check.
            Err(SimError::CollisionUnresolved { .. }) => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        // Round-off: every step rounds both bodies' velocities (a few operations per
        // component), so the total momentum drifts by up to tens of ulps of m_1 v per step; the
        // bound is 64 ulps per step. (1e-12 flat was exceeded by a legitimate impact of 268
        // steps at mass ratio 1:454, 1.005e-12, kept in the regressions file.)
        let bound = 64.0 * f64::EPSILON * r.steps as f64;
        prop_assert!(r.momentum_error.unwrap() < bound, "momentum error {:e} in {} steps (bound {:e})", r.momentum_error.unwrap(), r.steps, bound);
        prop_assert!(r.angular_momentum_error.unwrap() < 1e-11, "angular momentum error {:e}", r.angular_momentum_error.unwrap());
        prop_assert!(r.energy_after <= r.energy_before * (1.0 + 1e-9), "energy gained: {} -> {}", r.energy_before, r.energy_after);
        prop_assert!(r.max_friction_ratio <= 1.0 + 1e-12, "|F_t| / mu |F_n| = {}", r.max_friction_ratio);
    }

    #[test]
    fn swapping_the_particles_mirrors_the_result(c in collision()) {
        // The swapped run is the original seen under the point reflection x -> r_0 - x and the
        // boost v -> g_0 - v (spins, axial vectors, are unchanged).
        let (a, b) = match (c.run(), swapped(&c).run()) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(SimError::ExcessiveOverlap { .. }), Err(SimError::ExcessiveOverlap { .. })) => return Ok(()),
            // Regression: an overdamped slow impact that both runs refuse alike (the contact
            // lasts half a step) was reported as a difference; the same refusal mirrors too,
            // its measured contact time equal to round-off (5.479890165068301e-6 s against
            // 5.47989016506801e-6 s in one drawn case).
            (Err(SimError::CollisionUnresolved { .. }), Err(SimError::CollisionUnresolved { .. })) => return Ok(()),
            (a, b) => return Err(TestCaseError::fail(format!("the swapped run differs in outcome: {a:?} / {b:?}"))),
        };
        let (vn, v) = c.speeds();
        prop_assert!(close(a.eps_n, b.eps_n, 1.0) && close(a.eps_n_hs, b.eps_n_hs, 1.0), "{} {}", a.eps_n, b.eps_n);
        prop_assert!(close(a.t_c, b.t_c, a.t_c) && close(a.phi, b.phi, 1.0));
        let g0 = Vec3::new(-vn, match c.impact { Impact::Components { vt, .. } => vt, _ => unreachable!() }, 0.0);
        let (a1, a2) = (Vec3::from(a.v1), Vec3::from(a.v2.unwrap()));
        let (b1, b2) = (Vec3::from(b.v1), Vec3::from(b.v2.unwrap()));
        // (see the note on tolerances below)
        prop_assert!((b1 - (g0 - a2)).norm() <= 1e-6 * v, "{b1} vs {}", g0 - a2);
        prop_assert!((b2 - (g0 - a1)).norm() <= 1e-6 * v, "{b2} vs {}", g0 - a1);
        // Velocities and spins to 1e-6 of their scales: the mirrored run differs by round-off,
        // which the Haff-Werner switch between its viscous and Coulomb branches amplifies (a
        // real asymmetry would show at the step's order, 1e-3). Regression: a head-on Hertz
        // impact of spinning grains (the last saved case) mirrored its velocities to 3.8e-8 and
        // its spins to 3.8e-9 of their scales, on this code and on the code before the house
        // rewrite alike, against the 1e-9 asked before.
        let wscale = 1.0 + Vec3::from(a.omega1).norm() + Vec3::from(a.omega2.unwrap()).norm();
        prop_assert!((Vec3::from(b.omega1) - Vec3::from(a.omega2.unwrap())).norm() <= 1e-6 * wscale);
        prop_assert!((Vec3::from(b.omega2.unwrap()) - Vec3::from(a.omega1)).norm() <= 1e-6 * wscale);
    }
}
