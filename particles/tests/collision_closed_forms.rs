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
        let law = smooth(NormalLaw::Linear {
            kn: k,
            gamma_n: gamma,
        });
        let got = head_on(law, r, m, v, 4000.0).run().unwrap();
        let (tc, eps) = linear_dashpot(m_eff, k, gamma, v);
        let (et, ee) = ((got.t_c - tc).abs() / tc, (got.eps_n - eps).abs() / eps);
        println!(
            "ratio {ratio}: t_c {:.6e} vs {tc:.6e} ({et:.1e}), eps {:.6} vs {eps:.6} ({ee:.1e})",
            got.t_c, got.eps_n
        );
        assert!(
            et < 1e-3 && ee < 1e-3,
            "ratio {ratio}: t_c err {et:e}, eps err {ee:e}"
        );
    }
}
