//! The collision lab against closed forms (issue 2 acceptance).

use particles::contact::{ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::experiment::closed_form::{gamma_for_damping_ratio, linear_dashpot};
use particles::experiment::collide::{Collision, Impact, StepSize, Target};
use particles::integrate::Integrator;
use particles::Vec3;

fn smooth(normal: NormalLaw) -> ContactLaw {
    ContactLaw {
        normal,
        tangential: TangentialLaw::None,
        rolling: RollingLaw::None,
    }
}

fn head_on(law: ContactLaw, r: f64, m: f64, v: f64, steps: f64) -> Collision {
    Collision {
        law,
        r1: r,
        m1: m,
        omega1: Vec3::zeros(),
        target: Target::Sphere {
            r,
            m,
            omega: Vec3::zeros(),
        },
        impact: Impact::Components { vn: v, vt: 0.0 },
        step: StepSize::PerContact(steps),
        integrator: Integrator::VelocityVerlet,
    }
}

#[test]
fn linear_dashpot_matches_damped_oscillator_for_damping_ratios_0_05_to_2() {
    let (r, m, k, v) = (1e-3, 1e-5, 1e3, 0.5);
    let m_eff = m / 2.0;
    for ratio in [0.05, 0.2, 0.5, 0.9, 1.0, 1.3, 2.0] {
        let gamma = gamma_for_damping_ratio(m_eff, k, ratio);
        let law = smooth(NormalLaw::Linear { kn: k, gamma_n: gamma });
        let got = head_on(law, r, m, v, 4000.0).run().unwrap();
        let (tc, eps) = linear_dashpot(m_eff, k, gamma, v);
        let (et, ee) = ((got.t_c - tc).abs() / tc, (got.eps_n - eps).abs() / eps);
        println!(
            "ratio {ratio}: t_c {:.6e} vs {tc:.6e} ({et:.1e}), eps {:.6} vs {eps:.6} ({ee:.1e})",
            got.t_c, got.eps_n
        );
        assert!(et < 1e-3 && ee < 1e-3, "ratio {ratio}: t_c err {et:e}, eps err {ee:e}");
    }
}

fn glass_hertz(dissipation: f64) -> ContactLaw {
    smooth(NormalLaw::hertz(1e6 / (1.0 - 0.3 * 0.3), dissipation))
}

fn sphere_mass(r: f64) -> f64 {
    2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
}

#[test]
fn hertz_undamped_contact_time_matches_eq_3_19() {
    for (r, v) in [(5e-4, 0.002), (2.5e-4, 0.1), (5e-4, 1.0)] {
        let c = head_on(glass_hertz(0.0), r, sphere_mass(r), v, 2000.0);
        let got = c.run().unwrap();
        let rel = (got.t_c - got.contact_time_estimate).abs() / got.contact_time_estimate;
        println!(
            "R {r} v {v}: t_c {:.6e} eq 3.19 {:.6e} rel {rel:.1e}",
            got.t_c, got.contact_time_estimate
        );
        assert!(rel < 1e-2, "{rel}");
        assert!((got.eps_n - 1.0).abs() < 1e-6, "eps_n {}", got.eps_n);
    }
}

#[test]
fn hertz_elastic_head_on_equal_spheres_exchange_momentum() {
    let r = 5e-4;
    let m = sphere_mass(r);
    let v = 0.05;
    let got = head_on(glass_hertz(0.0), r, m, v, 20000.0).run().unwrap();
    // Particle j (the projectile) stops, particle i (the target) takes its momentum.
    let v2 = got.v2.unwrap();
    println!("projectile {:?} target {:?} eps {}", v2, got.v1, got.eps_n);
    assert!(
        Vec3::from(v2).norm() / v < 1e-9,
        "projectile keeps {:e} of its speed",
        Vec3::from(v2).norm() / v
    );
    assert!((got.v1[0] + v).abs() / v < 1e-9, "target {:?}", got.v1);
    assert!(got.momentum_error.unwrap() < 1e-12);
    let de = (got.energy_after - got.energy_before).abs() / got.energy_before;
    assert!(de < 1e-6, "energy error {de:e}");
}

/// eps_n of the viscoelastic law at `steps` per contact.
fn viscoelastic_eps(v: f64, steps: f64) -> f64 {
    let r = 5e-4;
    head_on(glass_hertz(8.5e-6 * 20.0), r, sphere_mass(r), v, steps)
        .run()
        .unwrap()
        .eps_n
}

#[test]
fn viscoelastic_restitution_falls_with_speed_and_converges_at_order_one_and_a_half() {
    let speeds = [0.01, 0.1, 0.5, 2.0];
    let eps: Vec<f64> = speeds.iter().map(|&v| viscoelastic_eps(v, 400.0)).collect();
    println!("eps_n(v) = {eps:?}");
    for w in eps.windows(2) {
        assert!(w[1] < w[0], "eps_n must fall with impact speed: {eps:?}");
    }
    // Observed order from three step sizes halving each time (Richardson). The damping
    // force k A sqrt(xi) dxi/dt grows like sqrt(t) at the onset of contact, so any
    // fixed-step scheme converges at order 3/2 here (smooth forces give 2).
    let e: Vec<f64> = [800.0, 1600.0, 3200.0].iter().map(|&n| viscoelastic_eps(0.5, n)).collect();
    let order = ((e[0] - e[1]) / (e[1] - e[2])).abs().log2();
    println!("eps at 800/1600/3200 steps: {e:?}; observed order {order:.2}");
    assert!(order > 1.3 && order < 1.8, "observed order {order}");
}

#[test]
fn thesis_integrator_is_first_order_and_converges_to_the_same_value() {
    let r = 5e-4;
    let law = ContactLaw {
        normal: NormalLaw::Linear { kn: 300.0, gamma_n: 1e-3 },
        tangential: TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 },
        rolling: RollingLaw::None,
    };
    let run = |steps: f64, integrator| {
        let mut c = head_on(law, r, sphere_mass(r), 0.5, steps);
        c.impact = Impact::Components { vn: 0.5, vt: 0.3 };
        c.integrator = integrator;
        c.run().unwrap().eps_n
    };
    let reference = run(1600.0, Integrator::VelocityVerlet);
    let errors: Vec<f64> = [200.0, 400.0, 800.0]
        .iter()
        .map(|&n| (run(n, Integrator::Thesis) - reference).abs())
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("thesis scheme errors {errors:?}, orders {orders:?}");
    for p in orders {
        assert!(p > 0.8 && p < 1.4, "order {p}");
    }
}
