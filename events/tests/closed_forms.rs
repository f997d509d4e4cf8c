//! The event-driven engine against closed forms: time reversal, equipartition and the
//! barometric law of an elastic gas, Haff's law of a cooling gas, the bouncing ball's
//! period-1 orbit, and the collapse guards.

use events::collision::{Restitution, Rule};
use events::config::{Config, Guard, Rules, SideWalls, Species};
use events::observe::{ledger_error, Observer};
use events::wall::Motion;
use events::{EventsError, Simulation, Vec2};

fn species(count: usize, r: f64, m: f64) -> Species {
    Species {
        count,
        radius_min: r,
        radius_max: r,
        mass: events::Mass::Each(m),
    }
}

fn fixed_box(width: f64, height: f64, gravity: f64, sp: Vec<Species>, pair: Rule, wall: Rule) -> Config {
    let n = sp.len();
    Config {
        width,
        height,
        side_walls: SideWalls::Fixed,
        gravity,
        q: 0.5,
        species: sp,
        floor: Some(Motion::FIXED),
        base: None,
        lid: Some(Motion::FIXED),
        waveform: events::Waveform::Sine,
        rules: Rules::uniform(pair, wall, n),
        guard: Guard::default(),
        initial_speed: 1.0,
        seed: 7,
    }
}

/// An elastic column of disks (head-on collisions, walls and gravity), run forward over
/// 1e4 collisions and back: every disk returns to its start to round-off.
#[test]
fn elastic_runs_are_time_reversible_over_ten_thousand_collisions() {
    let cfg = fixed_box(0.03, 1.0, 9.81, vec![species(8, 0.01, 1e-3)], Rule::smooth(1.0), Rule::smooth(1.0));
    let mut sim = Simulation::new(cfg).unwrap();
    let n = sim.len();
    // A vertical column at x = 0.015, 5 cm apart, moving only vertically.
    let r0: Vec<Vec2> = (0..n).map(|k| Vec2::new(0.015, 0.05 + 0.05 * k as f64)).collect();
    let v0: Vec<Vec2> = (0..n).map(|k| Vec2::new(0.0, 1.0 - 0.3 * k as f64)).collect();
    sim.set_state(&r0, &v0, &vec![0.0; n]).unwrap();
    let mut t = 0.0;
    while sim.collisions() < 10_000 {
        t += 0.05;
        sim.run_until(t).unwrap();
    }
    let forward = sim.collisions();
    let (r1, v1): (Vec<Vec2>, Vec<Vec2>) = (0..n).map(|i| sim.state(i)).unzip();
    let back: Vec<Vec2> = v1.iter().map(|v| -v).collect();
    sim.set_state(&r1, &back, &vec![0.0; n]).unwrap();
    sim.run_until(2.0 * t).unwrap();
    let worst = (0..n).map(|i| (sim.state(i).0 - r0[i]).norm()).fold(0.0, f64::max);
    println!(
        "{forward} collisions forward, {} in all; largest return error {worst:e} m",
        sim.collisions()
    );
    assert!(worst < 1e-9, "returned within {worst:e} m");
    for (i, v) in v0.iter().enumerate() {
        assert!((sim.state(i).1 + v).norm() < 1e-8);
    }
}

/// An elastic binary gas of rough disks (beta = +1) between fixed walls under gravity:
/// equipartition between the species and between translation and rotation, and barometric
/// density profiles `n_i ~ exp(-m_i g z / T)`.
#[test]
fn an_elastic_gas_shares_its_energy_equally_and_thins_out_barometrically() {
    let rough = Rule::Walton {
        e: Restitution::Constant(1.0),
        mu: f64::INFINITY,
        beta0: 1.0,
    };
    let mut cfg = fixed_box(
        4.0,
        30.0,
        1.0,
        vec![species(150, 0.02, 1.0), species(150, 0.02, 2.0)],
        rough,
        Rule::smooth(1.0),
    );
    cfg.initial_speed = 2.5;
    cfg.seed = 3;
    let mut sim = Simulation::new(cfg).unwrap();
    let e0 = sim.energy();
    sim.run_until(150.0).unwrap();
    let mut obs = Observer::new(2, 0.5, 30.0, sim.config.width);
    for k in 1..=600 {
        sim.run_until(150.0 + 0.5 * k as f64).unwrap();
        obs.sample(&sim);
    }
    let (tx1, tz1, tr1) = obs.temperatures(0);
    let (tx2, tz2, tr2) = obs.temperatures(1);
    let t = (tx1 + tz1 + tx2 + tz2) / 4.0;
    println!(
        "T: {tx1:.3} {tz1:.3} {tx2:.3} {tz2:.3}, rot {tr1:.3} {tr2:.3}; {} collisions",
        sim.collisions()
    );
    for (name, x) in [
        ("T_x,1", tx1),
        ("T_z,1", tz1),
        ("T_x,2", tx2),
        ("T_z,2", tz2),
        ("T_rot,1", tr1),
        ("T_rot,2", tr2),
    ] {
        assert!((x / t - 1.0).abs() < 0.06, "{name} = {x} against {t}");
    }
    // Barometric slopes: a least-squares fit of ln n against z over the bins with counts.
    for (k, m) in [(0usize, 1.0), (1, 2.0)] {
        let pts: Vec<(f64, f64)> = obs
            .profile(k)
            .iter()
            .filter(|p| p[1] * 600.0 * 0.5 > 200.0 && p[0] > 0.5)
            .map(|p| (p[0], p[1].ln()))
            .collect();
        let nn = pts.len() as f64;
        let (sx, sy) = (pts.iter().map(|p| p.0).sum::<f64>(), pts.iter().map(|p| p.1).sum::<f64>());
        let sxx = pts.iter().map(|p| p.0 * p.0).sum::<f64>();
        let sxy = pts.iter().map(|p| p.0 * p.1).sum::<f64>();
        let slope = (nn * sxy - sx * sy) / (nn * sxx - sx * sx);
        let expected = -m * 1.0 / t;
        println!("species {k}: slope {slope:.3}, expected {expected:.3} over {} bins", pts.len());
        assert!(
            (slope / expected - 1.0).abs() < 0.1,
            "species {k}: slope {slope} against {expected}"
        );
    }
    // Equipartition holds at every height, so in any layer (here the dense bottom one).
    let ratio = obs.temperature_ratio(0.0, 2.0);
    assert!((ratio - 1.0).abs() < 0.06, "T2/T1 = {ratio} in the bottom layer");
    assert!(obs.temperature_ratio(40.0, 50.0).is_nan(), "no grain above the box");
    // Across the box nothing acts: each species fills the width evenly, with the same
    // temperature in every column, and counts the same grains as against height.
    for k in 0..2 {
        let across = obs.profile_across(k, 4.0);
        assert_eq!(across.len(), 8);
        let total: f64 = across.iter().map(|p| p[1] * 0.5).sum();
        assert!((total - 150.0).abs() < 1e-9, "species {k}: {total} grains across");
        for p in &across {
            assert!((p[1] * 0.5 / (150.0 / 8.0) - 1.0).abs() < 0.08, "species {k}: {p:?}");
            assert!((p[2] / t - 1.0).abs() < 0.1, "species {k}: T_x {p:?} against {t}");
        }
    }
    // Elastic: nothing dissipated, and the energy kept to round-off.
    assert!(sim.ledger.dissipated.abs() < 1e-12 * e0);
    assert!(ledger_error(&sim, e0) < 1e-9, "{}", ledger_error(&sim, e0));
}

/// Smooth inelastic disks cooling without gravity: per collision `T = T0 exp(-(1 - e^2) C / 2)`
/// with `C` the collisions per particle, and in time Haff's `T0 / (1 + t / t0)^2` with `t0`
/// from the Enskog collision rate, until clusters form.
#[test]
fn a_cooling_gas_follows_haffs_law() {
    for e in [0.9, 0.97, 0.99] {
        let (n, r, width, height) = (400usize, 0.005, 1.0, 1.0);
        let mut cfg = fixed_box(width, height, 0.0, vec![species(n, r, 1.0)], Rule::smooth(e), Rule::smooth(1.0));
        cfg.floor = Some(Motion::FIXED);
        cfg.seed = 11;
        let mut sim = Simulation::new(cfg).unwrap();
        // Spread evenly: let the elastic walls and a short elastic period mix the lattice.
        let t_of = |sim: &Simulation| {
            (0..sim.len())
                .map(|i| 0.5 * sim.mass[i] * sim.state(i).1.norm_squared())
                .sum::<f64>()
                / sim.len() as f64
        };
        // Two collisions per particle first, so that the velocities are Maxwellian and the
        // lattice forgotten; the laws start from there.
        let mut t = 0.0;
        while sim.counts.pair < n as u64 {
            t += 1e-3;
            sim.run_until(t).unwrap();
        }
        let (t0_temp, c0, start) = (t_of(&sim), sim.counts.pair, sim.time);
        // Enskog: omega = 2 n sigma chi sqrt(pi T / m), chi = (1 - 7 phi / 16) / (1 - phi)^2.
        let area = width * height;
        let phi = n as f64 * std::f64::consts::PI * r * r / area;
        let chi = (1.0 - 7.0 * phi / 16.0) / (1.0 - phi).powi(2);
        let omega0 = 2.0 * (n as f64 / area) * (2.0 * r) * chi * (std::f64::consts::PI * t0_temp).sqrt();
        let tau0 = 4.0 / ((1.0 - e * e) * omega0);
        let (mut worst_c, mut worst_t) = (0.0f64, 0.0f64);
        // Until T has fallen to a quarter (before clusters in this dilute gas).
        let mut k = 0;
        loop {
            k += 1;
            let t = start + 0.02 * tau0 * k as f64;
            sim.run_until(t).unwrap();
            let temp = t_of(&sim);
            if temp < 0.25 * t0_temp {
                break;
            }
            let c = 2.0 * (sim.counts.pair - c0) as f64 / n as f64;
            let per_collision = t0_temp * (-(1.0 - e * e) * c / 2.0).exp();
            let haff = t0_temp / (1.0 + (t - start) / tau0).powi(2);
            worst_c = worst_c.max((temp / per_collision - 1.0).abs());
            worst_t = worst_t.max((temp / haff - 1.0).abs());
        }
        println!(
            "e = {e}: {} collisions, worst per-collision {worst_c:.3}, worst Haff {worst_t:.3}",
            sim.counts.pair
        );
        assert!(worst_c < 0.05, "e = {e}: per collision off by {worst_c}");
        assert!(worst_t < 0.05, "e = {e}: Haff's law off by {worst_t}");
    }
}

fn ball_on_plate(e: f64, gamma: f64, frequency: f64) -> Config {
    let omega = 2.0 * std::f64::consts::PI * frequency;
    let g = 9.81;
    Config {
        width: 0.01,
        height: 1.0,
        side_walls: SideWalls::Periodic,
        gravity: g,
        q: 0.4,
        species: vec![species(1, 1e-3, 1e-5)],
        floor: Some(Motion {
            amplitude: gamma * g / (omega * omega),
            frequency,
            phase: 0.0,
        }),
        base: None,
        lid: None,
        waveform: events::Waveform::Sine,
        rules: Rules::uniform(Rule::smooth(1.0), Rule::smooth(e), 1),
        // While the plate pushes harder than gravity the ball sticks to it; the guard lets it
        // hop with 0.1 mm/s instead of colliding without end.
        guard: Guard {
            min_rebound_speed: Some(1e-4),
            ..Guard::default()
        },
        initial_speed: 0.0,
        seed: 1,
    }
}

/// The bouncing ball's period-1 orbit: the ball leaves the plate at phase `phi` with speed
/// `g T / 2` and lands one period later at the same phase, which the restitution law allows
/// when `cos(phi) = pi (1 - e) / (Gamma (1 + e))`: the orbit exists for `Gamma` above
/// `pi (1 - e) / (1 + e)`. Started on it, slightly off, the ball keeps one bounce per period
/// and returns to it (the orbit is stable where the plate decelerates at impact, below
/// `sqrt((pi (1 - e) / (1 + e))^2 + 4 (1 + e^2)^2 / (1 + e)^2)`).
#[test]
fn a_bouncing_ball_holds_the_period_one_orbit_above_its_threshold() {
    let (e, f, g) = (0.5, 20.0, 9.81);
    let low = std::f64::consts::PI * (1.0 - e) / (1.0 + e);
    let high = (low * low + 4.0 * (1.0 + e * e).powi(2) / (1.0 + e).powi(2)).sqrt();
    let period = 1.0 / f;
    for gamma in [low * 1.05, 0.5 * (low + high)] {
        let phi = (low / gamma).acos();
        let mut cfg = ball_on_plate(e, gamma, f);
        cfg.guard = Guard::default();
        cfg.floor = cfg.floor.map(|m| Motion { phase: phi, ..m });
        let mut sim = Simulation::new(cfg).unwrap();
        let a = sim.config.floor.unwrap().amplitude;
        // Launched from the plate at phase phi, 0.1 % faster than the orbit.
        let u = 0.5 * g * period * 1.001;
        sim.set_state(&[Vec2::new(0.005, a * phi.sin() + 1e-3)], &[Vec2::new(0.0, u)], &[0.0])
            .unwrap();
        let mut heights = Vec::new();
        for k in 1..=200 {
            let before = sim.counts.wall;
            // The k-th landing (and launch) comes at k T; the top of the next flight half a
            // period later, where the height is sampled.
            sim.run_until((k as f64 + 0.5) * period).unwrap();
            assert_eq!(sim.counts.wall - before, 1, "Gamma {gamma:.3}: one bounce in period {k}");
            heights.push(sim.state(0).0.y);
        }
        let tail = &heights[150..];
        let spread = tail.iter().cloned().fold(f64::MIN, f64::max) - tail.iter().cloned().fold(f64::MAX, f64::min);
        println!("Gamma {gamma:.3} in ({low:.3}, {high:.3}): period-1 orbit, stroboscopic spread {spread:e} m");
        assert!(spread < 1e-9, "Gamma {gamma}: the orbit wanders by {spread:e} m");
    }
}

/// With `e = 0` a ball rides the plate while the plate accelerates upwards faster than
/// `-g`, and lifts off where the plate's acceleration falls through `-g`:
/// `sin(omega t + phi) = 1 / Gamma`. Hard collisions hold no lasting contact, so the ball
/// rides by hops of the guard's minimum rebound speed `v` (1e-7 m/s, hops of 20 ns); the
/// first long flight starts at the lift-off phase. The hops let it leave early, by about
/// `sqrt(v / (A omega^3))` (a hop that starts there never comes back): 6 microseconds here.
#[test]
fn with_no_restitution_the_ball_lifts_off_where_the_plate_falls_faster_than_gravity() {
    let (f, gamma) = (20.0, 2.5);
    let mut cfg = ball_on_plate(0.0, gamma, f);
    cfg.guard = Guard {
        min_rebound_speed: Some(1e-7),
        ..Guard::default()
    };
    let mut sim = Simulation::new(cfg).unwrap();
    let a = sim.config.floor.unwrap().amplitude;
    // On the plate at t = 0 (plate at its mean position, moving up), at rest relative to it.
    let omega = 2.0 * std::f64::consts::PI * f;
    sim.set_state(&[Vec2::new(0.005, 1e-3)], &[Vec2::new(0.0, a * omega)], &[0.0])
        .unwrap();
    let period = 1.0 / f;
    let step = period / 20_000.0;
    let (mut t, mut last_count, mut last_hit) = (0.0, 0, 0.0);
    let lift = loop {
        t += step;
        sim.run_until(t).unwrap();
        if sim.counts.wall > last_count {
            last_count = sim.counts.wall;
            last_hit = t;
        } else if t - last_hit > 0.01 * period && last_count > 100 {
            break last_hit;
        }
        assert!(t < 2.0 * period, "no lift-off within two periods");
    };
    let expected = (1.0 / gamma).asin() / omega;
    println!(
        "lift-off at {lift:.6} s, sin(omega t) = {:.4}, 1/Gamma = {:.4}",
        (omega * lift).sin(),
        1.0 / gamma
    );
    assert!((lift - expected).abs() < 1e-5, "lift-off at {lift} s, expected {expected} s");
}

/// Without a guard, a ball bouncing inelastically on a fixed floor collapses (infinitely
/// many bounces in finite time): the run stops with an error naming it, never hangs. With a
/// guard it keeps hopping, never sinks, and the run finishes.
#[test]
fn a_resting_grain_collapses_without_a_guard_and_rests_with_one() {
    let mut cfg = ball_on_plate(0.5, 0.0, 1.0);
    cfg.floor = Some(Motion::FIXED);
    cfg.guard = Guard::default();
    let mut sim = Simulation::new(cfg.clone()).unwrap();
    match sim.run_until(10.0) {
        Err(EventsError::Collapse {
            particles, time, events, ..
        }) => {
            assert_eq!(particles, vec![0]);
            assert!(time > 0.0 && time < 1.0 && events >= 1000, "t = {time}, {events} events");
        }
        other => panic!("expected a collapse, got {other:?}"),
    }
    for guard in [
        Guard {
            min_rebound_speed: Some(1e-3),
            ..Guard::default()
        },
        Guard {
            tc: Some(1e-4),
            ..Guard::default()
        },
    ] {
        let mut g = cfg.clone();
        g.guard = guard;
        let mut sim = Simulation::new(g).unwrap();
        for k in 1..=100 {
            sim.run_until(0.1 * k as f64).unwrap();
            let z = sim.state(0).0.y;
            assert!(z >= 1e-3 * (1.0 - 1e-9), "sank to {z} with {guard:?}");
        }
        assert!(sim.collisions() > 10);
    }
}

/// The collapse detector at Gamma 240-320 tells a collapse from fast, dense dynamics. A grain
/// rattling elastically between a side wall and a much heavier grain, 0.5 nm from each, at
/// 5 m/s (about the peak speed of the Gamma 320 floor), collides every 0.1-1 ns at metres
/// per second: the old detector (every collision counted, `collapse_speed = inf`) stopped
/// such a run; the detector that counts only slow collisions lets it run. A grain that meets the same floor at its lowest point,
/// where it pushes up at 240-320 g, with e = 0.5, does collapse: its approach speeds fall to
/// zero, and the run stops with the error naming it.
#[test]
fn the_collapse_detector_tells_a_collapse_from_fast_dynamics_at_gamma_240_to_320() {
    for gamma in [240.0, 320.0] {
        let r = 1e-3;
        let mut cfg = ball_on_plate(1.0, gamma, 100.0);
        cfg.side_walls = SideWalls::Fixed;
        cfg.species = vec![species(1, r, 1e-5), species(1, r, 1e3)];
        cfg.rules = Rules::uniform(Rule::smooth(1.0), Rule::smooth(1.0), 2);
        cfg.guard = Guard::default();
        let a = cfg.floor.unwrap().amplitude;
        // Grain 0 between the left wall and a grain 1e8 times heavier, 0.5 nm from each.
        let rattle = |cfg: &Config| {
            let mut sim = Simulation::new(cfg.clone()).unwrap();
            let light = (0..2).position(|i| sim.mass[i] < 1.0).unwrap();
            let mut r0 = [Vec2::new(r + 0.5e-9, a + 0.01); 2];
            let mut v0 = [Vec2::zeros(); 2];
            r0[1 - light].x = 3.0 * r + 1e-9;
            v0[light].x = 5.0;
            sim.set_state(&r0, &v0, &[0.0; 2]).unwrap();
            let run = sim.run_until(5e-6);
            (run, sim.collisions())
        };
        let (run, collisions) = rattle(&cfg);
        assert!(run.is_ok(), "Gamma {gamma}: {run:?}");
        assert!(collisions > 2_000, "{collisions}");
        let mut every = cfg.clone();
        every.guard.collapse_speed = Some(f64::INFINITY);
        assert!(
            matches!(rattle(&every).0, Err(EventsError::Collapse { .. })),
            "the old detector, every collision counted, stops the rattle"
        );
        // The floor at its lowest point (phase 3/4), the grain resting 1 nm above it.
        let mut push = ball_on_plate(0.5, gamma, 100.0);
        push.guard = Guard::default();
        let motion = push.floor.as_mut().unwrap();
        motion.phase = 1.5 * std::f64::consts::PI;
        let mut sim = Simulation::new(push.clone()).unwrap();
        let low = -push.floor.unwrap().amplitude;
        sim.set_state(&[Vec2::new(0.005, low + r + 1e-9)], &[Vec2::zeros()], &[0.0])
            .unwrap();
        match sim.run_until(2e-3) {
            Err(EventsError::Collapse {
                particles, time, message, ..
            }) => {
                assert_eq!(particles, vec![0]);
                assert!(time < 2e-3 && message.contains("approach speed"), "{time} {message}");
            }
            other => panic!("Gamma {gamma}: expected a collapse, got {other:?}"),
        }
    }
}

/// Bad input is refused, naming the field.
#[test]
fn bad_parameters_are_refused_by_name() {
    let base = fixed_box(0.1, 0.1, 9.81, vec![species(10, 1e-3, 1e-5)], Rule::smooth(0.9), Rule::smooth(0.9));
    let field = |c: Config| match Simulation::new(c) {
        Err(EventsError::Invalid { field, .. }) => field,
        Err(e) => format!("{e}"),
        Ok(_) => "accepted".into(),
    };
    let mut c = base.clone();
    c.rules.pair[0] = Rule::smooth(1.5);
    assert_eq!(field(c), "rules.pair[0].e");
    let mut c = base.clone();
    c.rules.floor[0] = Rule::Walton {
        e: Restitution::Constant(0.9),
        mu: 0.1,
        beta0: 2.0,
    };
    assert_eq!(field(c), "rules.floor[0].beta0");
    let mut c = base.clone();
    c.rules.lid[0] = Rule::Walton {
        e: Restitution::Constant(0.9),
        mu: -0.1,
        beta0: 0.0,
    };
    assert_eq!(field(c), "rules.lid[0].mu");
    let mut c = base.clone();
    c.floor = Some(Motion {
        amplitude: 0.06,
        frequency: 50.0,
        phase: 0.0,
    });
    assert_eq!(field(c), "drive.amplitude");
    let mut c = base.clone();
    c.species[0].count = 100_000;
    assert!(matches!(Simulation::new(c), Err(EventsError::DoNotFit { .. })));
}

/// A run's kept velocities stay within the cap however long it samples, as whole samples
/// evenly spaced in time; the free times likewise.
#[test]
fn the_kept_velocities_and_free_times_stay_bounded_and_even() {
    let mut sim = Simulation::new(fixed_box(
        4.0,
        30.0,
        1.0,
        vec![species(30, 0.02, 1.0), species(20, 0.02, 2.0)],
        Rule::smooth(1.0),
        Rule::smooth(1.0),
    ))
    .unwrap();
    sim.run_until(1.0).unwrap();
    let mut obs = Observer::new(2, 0.5, 30.0, sim.config.width);
    let samples = 3 * Observer::VELOCITY_CAP / 30 + 7;
    for _ in 0..samples {
        obs.sample(&sim);
    }
    assert_eq!(obs.samples as usize, samples);
    assert!(obs.vx[0].len() < Observer::VELOCITY_CAP, "{}", obs.vx[0].len());
    assert_eq!(obs.velocity_stride, 4);
    // Whole samples: 30 and 20 grains each, and every grain's value where it should be.
    let kept = obs.velocity_samples as usize;
    assert_eq!(obs.vx[0].len(), 30 * kept);
    assert_eq!(obs.w[1].len(), 20 * kept);
    let first: Vec<f64> = (0..sim.len()).filter(|&i| sim.species[i] == 0).map(|i| sim.state(i).1.x).collect();
    assert_eq!(&obs.vx[0][30 * (kept - 1)..], &first[..]);
    // The profiles still count every sample.
    let counted: f64 = obs.profile(0).iter().map(|p| p[1] * 0.5).sum::<f64>();
    assert!((counted - 30.0).abs() < 1e-9, "{counted}");
    // Free times: a long elastic run keeps at most the cap of them.
    sim.run_until(50.0).unwrap();
    let seen = sim.collisions();
    assert!(sim.free_times[0].kept.len() <= events::thinned::Thinned::CAP);
    assert!(sim.free_times[0].kept.len() as u64 <= 2 * seen);
}

/// A sawtooth floor (Barrat and Trizac's, of negligible excursion) stands at `z = 0` and
/// meets every grain moving up at `V = A 2 pi f`, whatever the time of the impact: a grain
/// that strikes it at speed `u` leaves at `w = (1 + e) V + e u`, and the wall's frame loses
/// `m (1 - e^2) (u + V)^2 / 2`. Dropped from rest at `z0`, the grain's k-th impact comes at
/// the speed it left the (k-1)-th with, so the impact times and speeds follow in closed form
/// and converge to the fixed point `(1 + e) V / (1 - e)`.
#[test]
fn a_sawtooth_floor_sends_every_grain_off_at_the_same_wall_speed() {
    let (e, f, gamma, g, z0) = (0.8, 50.0, 56.0, 9.81, 0.05);
    let mut cfg = ball_on_plate(e, gamma, f);
    cfg.waveform = events::Waveform::Sawtooth;
    cfg.guard = Guard::default();
    let (a, radius, m) = (cfg.floor.unwrap().amplitude, 1e-3, 1e-5);
    let push = a * 2.0 * std::f64::consts::PI * f;
    let mut sim = Simulation::new(cfg).unwrap();
    sim.set_state(&[Vec2::new(0.005, z0)], &[Vec2::zeros()], &[0.0]).unwrap();
    let e0 = sim.energy();
    let mut t = (2.0 * (z0 - radius) / g).sqrt();
    let mut u = g * t;
    let mut lost = 0.0;
    for k in 1..=40 {
        let w = (1.0 + e) * push + e * u;
        lost += 0.5 * m * (1.0 - e * e) * (u + push).powi(2);
        // Halfway up the next flight: one more impact, rising at w / 2, at w t - g t^2 / 2.
        let s = 0.5 * w / g;
        sim.run_until(t + s).unwrap();
        assert_eq!(sim.counts.wall, k, "impact {k}");
        let (r, v) = sim.state(0);
        assert!(
            (v.y - 0.5 * w).abs() < 1e-10 * w,
            "impact {k}: rising at {} against {}",
            v.y,
            0.5 * w
        );
        let z = radius + w * s - 0.5 * g * s * s;
        assert!((r.y - z).abs() < 1e-10 * z, "impact {k}: at {} m against {z} m", r.y);
        assert!((sim.ledger.dissipated - lost).abs() < 1e-10 * lost, "impact {k}: dissipated");
        (t, u) = (t + 2.0 * w / g, w);
    }
    let fixed = (1.0 + e) * push / (1.0 - e);
    assert!(
        (u - fixed).abs() < 1e-3 * fixed,
        "after 40 impacts {u} against the fixed point {fixed}"
    );
    assert!(ledger_error(&sim, e0) < 1e-12, "ledger {}", ledger_error(&sim, e0));
    println!("sawtooth floor: V = {push:.4} m/s, 40 impacts, speed {u:.5} -> fixed point {fixed:.5} m/s");

    // A sawtooth lid pushes down: without gravity an elastic grain between floor and lid
    // gains 2 V at every impact, and crosses the gap h - 2 R at its current speed.
    let mut cfg = ball_on_plate(1.0, gamma, f);
    cfg.waveform = events::Waveform::Sawtooth;
    cfg.gravity = 0.0;
    cfg.height = 0.05;
    cfg.lid = cfg.floor;
    cfg.guard = Guard::default();
    let mut sim = Simulation::new(cfg).unwrap();
    let (u0, gap) = (0.3, 0.05 - 2.0 * radius);
    sim.set_state(&[Vec2::new(0.005, 0.01)], &[Vec2::new(0.0, u0)], &[0.0]).unwrap();
    let mut t = (0.05 - radius - 0.01) / u0;
    for k in 1..=20u64 {
        let speed = u0 + 2.0 * k as f64 * push;
        sim.run_until(t + 0.5 * gap / speed).unwrap();
        assert_eq!(sim.counts.wall, k, "impact {k}");
        let (_, v) = sim.state(0);
        let sign = if k % 2 == 1 { -1.0 } else { 1.0 };
        assert!(
            (v.y - sign * speed).abs() < 1e-12 * speed,
            "impact {k}: {} against {}",
            v.y,
            sign * speed
        );
        t += gap / speed;
    }
}

/// A sawtooth drive stands the floor still: a sawtooth base cannot follow it, and side walls
/// that move with the floor have no velocity to lend; both are errors naming the waveform.
#[test]
fn a_sawtooth_drive_refuses_a_base_and_sides_that_move_with_the_floor() {
    let mut cfg = ball_on_plate(0.8, 56.0, 50.0);
    cfg.waveform = events::Waveform::Sawtooth;
    cfg.side_walls = SideWalls::WithFloor;
    match Simulation::new(cfg.clone()) {
        Err(EventsError::Invalid { field, .. }) => assert_eq!(field, "drive.waveform"),
        other => panic!("{:?}", other.map(|_| ())),
    }
    cfg.side_walls = SideWalls::Periodic;
    cfg.base = Some(events::Sawtooth {
        width: 0.01,
        height: 1e-3,
        asymmetry: 0.5,
        tip_radius: 1e-4,
    });
    match Simulation::new(cfg) {
        Err(EventsError::Invalid { field, .. }) => assert_eq!(field, "drive.waveform"),
        other => panic!("{:?}", other.map(|_| ())),
    }
}
