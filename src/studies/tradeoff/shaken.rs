//! The shaken-tray half of the study, and the dense-packing hard case.

use analysis::density::area_fraction_cells;
use analysis::stripes::{detect, onset, StripeParams};

use super::lab::matched_linear;
use super::setting::{base_scene, failed, setting_dt, with, Config, Row, Setting, Study, THESIS_DT};
use crate::host::clock::Stopwatch;
use crate::scene::edit::{DemEdit, DemToggle};
use particles::advance::{advance, ObserverError, Stop};
use particles::experiment::step_control::{self, REFERENCE_STEPS};
use particles::integrate::Integrator;
use particles::neighbor::NeighborSearch;
use particles::prepare::initial_state;
use particles::scene::Scene;
use particles::sim::Simulation;
use particles::state::State;
use particles::time_step;
use particles::timescale;
use particles::tray;
use particles::SimError;

/// What one tray run produced.
pub(super) struct TrayRun {
    pub(super) wall_s: f64,
    dt: f64,
    profiles: Vec<Vec<f64>>,
    times: Vec<f64>,
    ledger_error: f64,
    pub(super) builds: u64,
    mean_phi: f64,
    mean_d: f64,
}

pub(super) fn run_tray(
    scene: &Scene,
    s: &Setting,
    base_state: &State,
    steps_override: Option<f64>,
    cpu_time: bool,
) -> Result<TrayRun, SimError> {
    let mut setup = tray::setup(scene, tray::drive(scene), time_step::for_scene(scene)?)?;
    setup.dt = setting_dt(scene, steps_override.or(s.steps))?;
    setup.integrator = s.integrator;
    if let Some(k) = s.skin {
        setup.neighbors = NeighborSearch::verlet(k * scene.particles.radius_max);
    }
    let n = base_state.len();
    let order: Vec<usize> = (0..n).collect();
    let mut state = State::default();
    for &i in &order {
        let nudge = if s.perturbed && i == 0 { 1e-9 } else { 0.0 };
        state.push(
            base_state.pos[i] + particles::Vec3::new(nudge, 0.0, 0.0),
            base_state.vel[i],
            base_state.omega[i],
            base_state.radius[i],
            base_state.mass(i),
        );
    }
    let mut sim = Simulation::new(setup, state)?;
    let e0 = sim.total_energy();
    let (l, w) = (scene.tray.length, scene.tray.width);
    let cells = ((l / 1e-3).round() as usize).max(1);
    // Radii in the original order, for the profiles.
    let radius: Vec<f64> = base_state.radius.clone();
    let sample_every = 0.25 / scene.drive.frequency;
    let total = (scene.run.duration / sim.setup.dt).round() as u64;
    let (mut profiles, mut times) = (Vec::new(), Vec::new());
    let mut next = sample_every;
    let clock = Stopwatch::start(cpu_time);
    let mut sample = |sim: &Simulation| -> Result<(), ObserverError> {
        if sim.time >= next - 0.5 * sim.setup.dt {
            let mut x = vec![0.0; n];
            let state = sim.state();
            for (k, &i) in order.iter().enumerate() {
                x[i] = state.pos[k].x;
            }
            profiles.push(area_fraction_cells(&x, &radius, l, w, cells));
            times.push(sim.time);
            next += sample_every;
        }
        Ok(())
    };
    advance(&mut sim, total, &mut [&mut sample]).map_err(physics)?;
    let wall = clock.seconds();
    let de = sim.total_energy() - e0;
    let ledger = sim.ledger.injected - sim.ledger.dissipated;
    let mean_phi = radius.iter().map(|r| std::f64::consts::PI * r * r).sum::<f64>() / (l * w);
    Ok(TrayRun {
        wall_s: wall,
        dt: sim.setup.dt,
        profiles,
        times,
        ledger_error: (de - ledger).abs() / sim.ledger.injected.abs().max(f64::MIN_POSITIVE),
        builds: sim.neighbor_builds(),
        mean_phi,
        mean_d: 2.0 * radius.iter().sum::<f64>() / n as f64,
    })
}

/// Mean over common sample times of `mean_x |phi - phi_ref| / <phi>`.
pub fn density_distance(a: &[Vec<f64>], b: &[Vec<f64>], mean_phi: f64) -> f64 {
    let k = a.len().min(b.len());
    if k == 0 {
        return f64::NAN;
    }
    let per_frame = |p: &Vec<f64>, q: &Vec<f64>| p.iter().zip(q).map(|(x, y)| (x - y).abs()).sum::<f64>() / p.len() as f64;
    (0..k).map(|f| per_frame(&a[f], &b[f])).sum::<f64>() / k as f64 / mean_phi
}

/// The tray study.
pub(super) fn tray_study(config: &Config, progress: &mut impl FnMut(&str)) -> Result<Vec<Row>, SimError> {
    let base = base_scene(config.tray_count, config.tray_duration);
    let state = initial_state(&base)?;
    let thesis_steps = timescale::shortest_contact_time(&base)? / THESIS_DT;
    let auto = with(&base, &[DemEdit::AutoStep])?;
    let default_dt = time_step::for_scene(&auto)?;
    let default_steps = timescale::shortest_contact_time(&base)? / default_dt;
    // Linear law matched as in the lab.
    let reference_lab = step_control::run_all(&step_control::scene_probes(&base, REFERENCE_STEPS, Integrator::VelocityVerlet)?)?;
    let r = base.particles.radius_min;
    let (kn, gamma_n) = matched_linear(
        0.5 * base.material().sphere_mass(r),
        reference_lab[0].eps_n,
        reference_lab[0].t_c,
        timescale::max_impact_speed(&base),
    );

    let converged = run_tray(
        &base,
        &Setting::new("converged", "reference"),
        &state,
        Some(config.reference_steps),
        config.cpu_time,
    )?;
    progress(&format!("converged tray reference ({} steps/contact)", config.reference_steps));

    let mut settings = vec![Setting::reference(thesis_steps)];
    let mut floor = Setting::new("noise floor: reference with one grain moved by 1 nm", "noise floor").steps(thesis_steps);
    floor.perturbed = true;
    settings.push(floor);
    for s in [8.0, 20.0, 30.0] {
        settings.push(Setting::new(format!("{s} steps/contact"), "time step").steps(s));
    }
    settings.push(
        Setting::new(format!("thesis integrator, {thesis_steps:.1} steps/contact"), "integrator")
            .steps(thesis_steps)
            .integrator(Integrator::Thesis),
    );
    settings.extend(Setting::softer(thesis_steps));
    settings.push(
        Setting::new("pinned 2D (jumping off)", "dimension")
            .edit(DemEdit::Off(DemToggle::Jumping))
            .steps(thesis_steps),
    );
    settings.push(Setting::matched_linear(kn, gamma_n, thesis_steps));
    // Fixed skins against the reference's adaptive one (0.2 R_max at rest, growing in a gas).
    for k in [0.0, 0.1, 0.2, 0.4, 1.0, 2.0] {
        let name = if k == 0.0 {
            "skin 0: rebuild every step".to_string()
        } else {
            format!("fixed skin {k} R_max (rebuild at skin/2)")
        };
        settings.push(Setting::new(name, "neighbour list").steps(thesis_steps).skin(k));
    }
    settings.push(Setting::default_step(default_steps));

    let mut rows = Vec::new();
    let reference = (settings[0].clone(), run_tray(&base, &settings[0], &state, None, config.cpu_time)?);
    for s in &settings {
        let row = tray_row(&base, s, config, &state, &converged, &reference).unwrap_or_else(|e| failed(s, Study::Tray, e));
        rows.push(row);
        progress(&s.name);
    }
    Ok(rows)
}

/// One tray row; `reference` (wall time and profiles) is set by the first (reference)
/// setting. The noise-floor row is compared with the reference run, every other row with
/// the converged run.
fn tray_row(
    base: &Scene,
    s: &Setting,
    config: &Config,
    state: &State,
    converged: &TrayRun,
    reference: &(Setting, TrayRun),
) -> Result<Row, SimError> {
    {
        let scene = with(base, &s.edits)?;
        let (ref_setting, ref_run) = reference;
        let ref_scene = with(base, &ref_setting.edits)?;
        // Timing in pairs (reference, setting), run back to back so that both see the same
        // load; the median of the pair ratios counts.
        let mut run = run_tray(&scene, s, state, None, config.cpu_time)?;
        let mut ratios = Vec::new();
        for k in 0..config.tray_repeats.max(1) {
            let r = run_tray(&ref_scene, ref_setting, state, None, config.cpu_time)?;
            if k > 0 {
                let again = run_tray(&scene, s, state, None, config.cpu_time)?;
                run.wall_s = again.wall_s;
            }
            ratios.push(r.wall_s / run.wall_s);
        }
        ratios.sort_by(f64::total_cmp);
        let speed_ratio = if ratios.len() % 2 == 1 {
            ratios[ratios.len() / 2]
        } else {
            0.5 * (ratios[ratios.len() / 2 - 1] + ratios[ratios.len() / 2])
        };
        let ref_profiles = &ref_run.profiles;
        let params = StripeParams::default_for(run.mean_phi, run.mean_d);
        let counts: Vec<usize> = run.profiles.iter().map(|p| detect(p, scene.tray.length, &params).len()).collect();
        let against = if s.axis == "noise floor" {
            ref_profiles
        } else {
            &converged.profiles
        };
        let distance = density_distance(&run.profiles, against, run.mean_phi);
        let stripes = counts.last().copied();
        let onset_s = onset(&run.times, &counts);
        Ok(Row {
            name: s.name.clone(),
            study: Study::Tray,
            axis: s.axis.into(),
            // The reference is 1 by definition; its timed self-ratio (the timing noise) is
            // in the outcome.
            speed_ratio: if s.axis == "reference" { 1.0 } else { speed_ratio },
            error: distance,
            wall_s: run.wall_s,
            dt: run.dt,
            steps_per_contact: timescale::shortest_contact_time(&scene)? / run.dt,
            eps_error: None,
            energy_error: Some(run.ledger_error),
            density_distance: Some(distance),
            stripes,
            onset_s,
            neighbor_builds: Some(run.builds),
            on_front: false,
            outcome: format!(
                "{} samples; stripes at the end {} (converged run: {}); timed reference/setting ratio {:.2}; {} neighbour builds",
                run.times.len(),
                stripes.unwrap_or(0),
                converged
                    .profiles
                    .last()
                    .map(|p| detect(p, base.tray.length, &params).len())
                    .unwrap_or(0),
                speed_ratio,
                run.builds
            ),
        })
    }
}

/// Dense packing (hard case): 8000 grains at area fraction 0.46 in the thesis tray (0.4 m x
/// 0.02 m), started on the lattice (two layers), shaken for `steps` steps at the thesis dt.
/// `speed_ratio` is its throughput (particle-steps per second) relative to 4000 grains at
/// the thesis packing measured in the same call; `error` is the energy-ledger error.
pub fn dense_packing(steps: u64, cpu_time: bool) -> Result<Row, SimError> {
    let throughput = |count: usize| -> Result<(f64, Simulation), SimError> {
        let scene = with(&base_scene(4000, 1.0), &[DemEdit::Count(count)])?;
        let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene)?)?;
        let mut sim = Simulation::new(setup, initial_state(&scene)?)?;
        let t0 = Stopwatch::start(cpu_time);
        advance(&mut sim, steps, &mut []).map_err(physics)?;
        Ok((steps as f64 * count as f64 / t0.seconds(), sim))
    };
    let (base_rate, _) = throughput(4000)?;
    let e_start = {
        let scene = with(&base_scene(4000, 1.0), &[DemEdit::Count(8000)])?;
        let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene)?)?;
        Simulation::new(setup, initial_state(&scene)?)?.total_energy()
    };
    let (rate, sim) = throughput(8000)?;
    let packing = with(&base_scene(4000, 1.0), &[DemEdit::Count(8000)])?.packing();
    let ledger = sim.ledger.injected - sim.ledger.dissipated;
    let error = ((sim.total_energy() - e_start) - ledger).abs() / sim.ledger.injected.abs().max(f64::MIN_POSITIVE);
    Ok(Row {
        name: format!("dense packing: 8000 grains, area fraction {packing:.2}, {steps} steps"),
        study: Study::HardCase,
        axis: "hard case".into(),
        speed_ratio: rate / base_rate,
        error,
        wall_s: steps as f64 * 8000.0 / rate,
        dt: sim.setup.dt,
        steps_per_contact: f64::NAN,
        eps_error: None,
        energy_error: Some(error),
        density_distance: None,
        stripes: None,
        onset_s: None,
        neighbor_builds: Some(sim.neighbor_builds()),
        on_front: false,
        outcome: format!(
            "ran without error: {:.2e} particle-steps/s (4000 grains: {:.2e}); {} pair and {} wall contacts at the end; speed_ratio is the throughput ratio, error the energy-ledger error",
            rate, base_rate, sim.contact_counts.0, sim.contact_counts.1
        ),
    })
}

/// The physics' refusal that stopped [`advance`]; the observers of this file never fail.
fn physics(stop: Stop) -> SimError {
    match stop {
        Stop::Sim(e) => e,
        Stop::Observer(e) => unreachable!("a sampler of this file failed: {e}"),
    }
}
