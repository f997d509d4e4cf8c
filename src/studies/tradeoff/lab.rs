//! The collision-lab half of the study: the probe impacts of [`particles::experiment::step_control`]
//! under every setting, against the converged reference.

use super::setting::{base_scene, failed, setting_dt, with, Config, Row, Setting, Study, THESIS_DT};
use crate::host::clock::Stopwatch;
use particles::contact::TangentialLaw;
use particles::experiment::closed_form::{gamma_for_damping_ratio, linear_dashpot};
use particles::experiment::step_control::{self, REFERENCE_STEPS};
use particles::integrate::Integrator;
use particles::scene::{Scene, DEFAULT_RESTITUTION_TOLERANCE};
use particles::timescale;
use particles::SimError;

/// A linear spring-dashpot with the same head-on restitution `eps` and contact duration
/// `t_c` (s) as the given impact of effective mass `m_eff` (kg) at `v` (m/s): the damping
/// ratio from `eps` by bisection on [`linear_dashpot`], then `k_n` from `t_c ~ k^{-1/2}`.
/// Returns `(k_n, gamma_n)` in N/m and kg/s.
pub fn matched_linear(m_eff: f64, eps: f64, t_c: f64, v: f64) -> (f64, f64) {
    let eps_of = |ratio: f64| linear_dashpot(m_eff, 1.0, gamma_for_damping_ratio(m_eff, 1.0, ratio), v).1;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if eps_of(mid) > eps {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let ratio = 0.5 * (lo + hi);
    let t1 = linear_dashpot(m_eff, 1.0, gamma_for_damping_ratio(m_eff, 1.0, ratio), v).0;
    let k = (t1 / t_c).powi(2);
    (k, gamma_for_damping_ratio(m_eff, k, ratio))
}

/// Probe impacts of a setting, with the Hertz law replaced by `linear` if given.
fn lab_probes(scene: &Scene, s: &Setting, dt: f64, elastic: bool) -> Result<Vec<particles::experiment::collide::Collision>, SimError> {
    let (mut pair, mut wall) = scene.laws()?;
    if elastic {
        for law in [&mut pair, &mut wall] {
            law.normal = law.normal.elastic();
            law.tangential = TangentialLaw::None;
            law.rolling = particles::contact::RollingLaw::None;
        }
    }
    let r = scene.particles.radius_min;
    Ok(step_control::probes(
        pair,
        wall,
        r,
        scene.material().sphere_mass(r),
        timescale::max_impact_speed(scene),
        dt,
        s.integrator,
    ))
}

/// The collision-lab study.
pub(super) fn collision_study(config: &Config, progress: &mut impl FnMut(&str)) -> Result<Vec<Row>, SimError> {
    let base = base_scene(config.tray_count, config.tray_duration);
    let t_c = timescale::shortest_contact_time(&base)?;
    let reference = step_control::run_all(&step_control::scene_probes(&base, REFERENCE_STEPS, Integrator::VelocityVerlet)?)?;
    // The linear law matched to the reference's head-on pair impact.
    let r = base.particles.radius_min;
    let m_eff = 0.5 * base.material().sphere_mass(r);
    let (kn, gamma_n) = matched_linear(m_eff, reference[0].eps_n, reference[0].t_c, timescale::max_impact_speed(&base));
    let thesis_steps = t_c / THESIS_DT;
    let default_steps = step_control::choose(&base, DEFAULT_RESTITUTION_TOLERANCE, base.run.steps_per_contact)?.steps_per_contact;

    let mut settings = vec![Setting::reference(thesis_steps)];
    for s in [5.0, 8.0, 10.0, 20.0, 30.0, 50.0, 100.0, 300.0] {
        settings.push(Setting::new(format!("{s} steps/contact"), "time step").steps(s));
    }
    for s in [thesis_steps, 30.0, 100.0] {
        settings.push(
            Setting::new(format!("thesis integrator, {s:.1} steps/contact"), "integrator")
                .steps(s)
                .integrator(Integrator::Thesis),
        );
    }
    settings.extend(Setting::softer(thesis_steps));
    settings.push(Setting::matched_linear(kn, gamma_n, thesis_steps));
    settings.push(Setting::default_step(default_steps));

    let ref_probes = lab_probes(&base, &settings[0], setting_dt(&base, settings[0].steps)?, false)?;
    let mut rows = Vec::new();
    for s in &settings {
        let row = lab_row(&base, s, config, &reference, &ref_probes).unwrap_or_else(|e| failed(s, Study::Collision, e));
        rows.push(row);
        progress(&s.name);
    }
    Ok(rows)
}

/// One collision-lab row; `ref_cost` is set by the first (reference) setting.
fn lab_row(
    base: &Scene,
    s: &Setting,
    config: &Config,
    reference: &[particles::experiment::collide::CollisionResult],
    ref_probes: &[particles::experiment::collide::Collision],
) -> Result<Row, SimError> {
    {
        let scene = with(base, &s.edits)?;
        let dt = setting_dt(&scene, s.steps)?;
        let probes = lab_probes(&scene, s, dt, false)?;
        // The lab's impacts last microseconds and their time is dominated by setting each
        // one up, so the speed ratio counts steps per simulated second (the wall-time ratio
        // of a long run at equal cost per step; the cost per step of each integrator and law
        // is timed in the tray rows). The lab's own time is reported as `wall_s`.
        let ref_results = step_control::run_all(ref_probes)?;
        let rate = |r: &[particles::experiment::collide::CollisionResult]| {
            r.iter().map(|x| x.steps as f64).sum::<f64>() / r.iter().map(|x| x.t_c).sum::<f64>()
        };
        let clock = Stopwatch::start(config.cpu_time);
        let mut results = step_control::run_all(&probes)?;
        let mut reps = 1;
        while clock.seconds() < config.lab_min_wall {
            results = step_control::run_all(&probes)?;
            reps += 1;
        }
        let wall = clock.seconds();
        let speed_ratio = rate(&ref_results) / rate(&results);
        let eps_error = step_control::restitution_error(&results, reference);
        let elastic = step_control::run_all(&lab_probes(&scene, s, dt, true)?)?;
        let energy_error = elastic
            .iter()
            .map(|r| (r.energy_after - r.energy_before).abs() / r.energy_before)
            .fold(0.0, f64::max);
        let max_overlap = results.iter().map(|r| r.max_overlap / r1_of(&scene)).fold(0.0, f64::max);
        Ok(Row {
            name: s.name.clone(),
            study: Study::Collision,
            axis: s.axis.into(),
            speed_ratio,
            error: eps_error,
            wall_s: wall / reps as f64,
            dt,
            steps_per_contact: timescale::shortest_contact_time(&scene)? / dt,
            eps_error: Some(eps_error),
            energy_error: Some(energy_error),
            density_distance: None,
            stripes: None,
            onset_s: None,
            neighbor_builds: None,
            on_front: false,
            outcome: format!(
                "eps_n head-on {:.4} (ref {:.4}); max overlap {:.1}% of R",
                results[0].eps_n,
                reference[0].eps_n,
                100.0 * max_overlap
            ),
        })
    }
}

fn r1_of(scene: &Scene) -> f64 {
    scene.particles.radius_min
}
