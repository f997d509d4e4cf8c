//! A run continued from its exported state matches the uninterrupted run bit for bit, on a
//! sawtooth base and in the mixture's box (lazy clocks, predicted events and cell orders
//! are all part of the state).

use events::collision::Rule;
use events::config::{Config, Guard, Rules, SideWalls, Species};
use events::{Motion, Sawtooth, Simulation};

fn config(sawtooth: bool) -> Config {
    let rule = Rule::Walton {
        e: events::Restitution::Constant(0.8),
        mu: 0.1,
        beta0: 0.0,
    };
    Config {
        width: 0.036,
        height: 0.04,
        side_walls: if sawtooth { SideWalls::Periodic } else { SideWalls::Fixed },
        gravity: 9.81,
        q: 0.5,
        species: vec![
            Species {
                count: 20,
                radius_min: 1.0e-3,
                radius_max: 1.1e-3,
                mass: events::Mass::Each(1e-5),
            },
            Species {
                count: 10,
                radius_min: 1.0e-3,
                radius_max: 1.0e-3,
                mass: events::Mass::Each(3e-6),
            },
        ],
        floor: Some(Motion {
            amplitude: 2e-3,
            frequency: 25.0,
            phase: 0.0,
        }),
        base: sawtooth.then_some(Sawtooth {
            width: 6e-3,
            height: 3e-3,
            asymmetry: 0.1,
            tip_radius: 5e-4,
        }),
        lid: Some(Motion::FIXED),
        waveform: events::Waveform::Sine,
        rules: Rules {
            pair: vec![rule.clone(); 3],
            floor: vec![rule.clone(); 2],
            side: vec![rule.clone(); 2],
            lid: vec![rule; 2],
        },
        guard: Guard {
            min_rebound_speed: Some(5e-3),
            ..Guard::default()
        },
        initial_speed: 0.1,
        seed: 3,
    }
}

#[test]
fn a_run_continued_from_its_exported_state_matches_the_uninterrupted_run_bit_for_bit() {
    for sawtooth in [true, false] {
        let mut whole = Simulation::new(config(sawtooth)).unwrap();
        whole.run_until(1.0).unwrap();
        let mut first = Simulation::new(config(sawtooth)).unwrap();
        first.run_until(0.4).unwrap();
        let mut second = Simulation::import_state(config(sawtooth), first.export_state()).unwrap();
        second.run_until(1.0).unwrap();
        assert!(whole.collisions() > 1000);
        assert_eq!(whole.export_state(), second.export_state(), "sawtooth: {sawtooth}");
        // A state from another configuration is refused.
        let mut other = config(sawtooth);
        other.species[0].count = 21;
        assert!(Simulation::import_state(other, first.export_state()).is_err());
    }
}
