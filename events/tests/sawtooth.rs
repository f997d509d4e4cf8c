//! The sawtooth base in whole runs: no grain is ever found inside a tooth, the energy ledger
//! closes, and the ratchet paper's two reference shapes drive currents of opposite signs
//! (its Figs. 13 and 14: +3.9 and -3.2 cm/s).

use events::collision::Rule;
use events::config::{Config, Guard, Rules, SideWalls, Species};
use events::observe::{ledger_error, Observer};
use events::sawtooth::Piece;
use events::{Motion, Sawtooth, Simulation};

/// The ratchet paper's cell: 24 teeth 6 mm wide, A = 2 mm, disks of 1.05-1.155 mm with
/// e = 0.8, mu = 0.1 and sticking contacts (beta0 = 0) everywhere, v_min = 5 mm/s.
fn ratchet(height: f64, asymmetry: f64, frequency: f64, count: usize, seed: u64) -> Config {
    let rule = Rule::Walton {
        e: events::Restitution::Constant(0.8),
        mu: 0.1,
        beta0: 0.0,
    };
    Config {
        width: 0.144,
        height: 0.06,
        side_walls: SideWalls::Periodic,
        gravity: 9.81,
        q: 0.5,
        species: vec![Species {
            count,
            radius_min: 1.05e-3,
            radius_max: 1.155e-3,
            mass: events::Mass::Each(1e-5),
        }],
        floor: Some(Motion {
            amplitude: 2e-3,
            frequency,
            phase: 0.0,
        }),
        base: Some(Sawtooth {
            width: 6e-3,
            height,
            asymmetry,
            tip_radius: 5e-4,
        }),
        lid: Some(Motion::FIXED),
        waveform: events::Waveform::Sine,
        rules: Rules::uniform(rule.clone(), rule, 1),
        guard: Guard {
            min_rebound_speed: Some(5e-3),
            ..Guard::default()
        },
        initial_speed: 0.1,
        seed,
    }
}

/// The smallest gap between any grain and any piece of the moving base at the current time.
fn smallest_gap(sim: &Simulation) -> f64 {
    let base = sim.config.base.unwrap();
    let motion = sim.config.floor.unwrap();
    let mut smallest = f64::INFINITY;
    for i in 0..sim.len() {
        let (r, v) = sim.state(i);
        for tooth in base.teeth(r.x, r.x, sim.radius[i]) {
            for piece in 0..3 {
                let shape: Piece = base.piece(tooth, piece);
                let (gap, _, _) = Sawtooth::gap(&shape, &motion, r, v, sim.radius[i], sim.time);
                smallest = smallest.min(gap);
            }
        }
    }
    smallest
}

#[test]
fn no_grain_is_ever_inside_a_tooth_and_the_ledger_closes() {
    let mut sim = Simulation::new(ratchet(3e-3, 0.1, 25.0, 49, 7)).unwrap();
    let e0 = sim.energy();
    let mut worst = f64::INFINITY;
    // 5 s at 200 samples per period, at phases that do not repeat.
    for k in 1..=20_000 {
        sim.run_until(k as f64 * 2.5e-4).unwrap();
        worst = worst.min(smallest_gap(&sim));
    }
    assert!(worst > -1e-12, "a grain was found {worst:e} m inside a tooth");
    assert!(sim.counts.wall > 1000, "the base was hit {} times", sim.counts.wall);
    let ledger = ledger_error(&sim, e0);
    assert!(ledger < 1e-9, "ledger misses by {ledger:e}");
}

fn current(height: f64, asymmetry: f64, frequency: f64, count: usize) -> f64 {
    let mut sim = Simulation::new(ratchet(height, asymmetry, frequency, count, 1)).unwrap();
    let mut obs = Observer::new(1, 1e-3, 0.06, sim.config.width);
    sim.run_until(3.0).unwrap();
    for k in 1..=20 * 6 * 25 {
        sim.run_until(3.0 + k as f64 / (6.0 * frequency)).unwrap();
        obs.sample(&sim);
    }
    obs.mean_vx()
}

#[test]
fn the_papers_two_reference_teeth_drive_currents_of_opposite_signs() {
    // Fig. 13: h = 3 mm, a = 0.1, 25 Hz, n = 0.7 layers: +3.9 +- 0.3 cm/s.
    let forward = current(3e-3, 0.1, 25.0, 49);
    // Fig. 14: h = 6 mm, a = 0.25, 30 Hz, n = 0.35 layers: -3.2 +- 0.3 cm/s.
    let backward = current(6e-3, 0.25, 30.0, 25);
    assert!(forward > 0.02 && backward < -0.015, "currents {forward} and {backward} m/s");
}

/// The phase-resolved field over one tooth (the paper's Figs 13-14) accounts for every grain
/// between the valleys and its top: its mass densities, times the boxes' areas and the
/// teeth, give back the mass of the grains counted, frame by frame; a drive sampled six times
/// per period fills the six frames evenly.
#[test]
fn the_phase_field_holds_the_grains_mass_in_every_frame() {
    let config = ratchet(3e-3, 0.1, 25.0, 20, 3);
    let mut sim = Simulation::new(config).unwrap();
    let base = sim.config.base.unwrap();
    let mut obs = Observer::new(1, 1e-3, 0.06, 0.144).with_phase_field(&base, 0.144, 0.06);
    let per_period = 6;
    let mut expected = [0.0f64; 6];
    for k in 1..=(10 * per_period) {
        sim.run_until(k as f64 / (25.0 * per_period as f64)).unwrap();
        let lift = sim.config.floor.unwrap().displacement(sim.time);
        let counted = (0..sim.len())
            .filter(|&i| {
                let z = sim.state(i).0.y - lift;
                (0.0..0.06).contains(&z)
            })
            .map(|i| sim.mass[i])
            .sum::<f64>();
        expected[k % per_period] += counted;
        obs.sample(&sim);
    }
    let f = obs.field.as_ref().unwrap();
    assert_eq!(f.samples, vec![10; 6], "frames {:?}", f.samples);
    for (frame, expected) in expected.iter().enumerate() {
        let area = f.side() * f.side() * f.teeth;
        let mass: f64 = f.rows(frame).iter().map(|r| r[2] * area).sum::<f64>() * 10.0;
        assert!(
            (mass - expected).abs() <= 1e-12 * expected.max(1e-300),
            "frame {frame}: {mass} vs {expected}"
        );
        assert!(mass > 0.0);
    }
}
