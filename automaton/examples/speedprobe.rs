//! Speed probe of the `physical` half step alone: a random 0/1 layer (4000 grains on the
//! thesis bench's 533 x 27 cells, or 1000 on the quick scene's 133 x 27) with the thesis
//! scene's mapped parameters, `steps` half steps, wall-clock cell updates per second and a
//! checksum of the final lattice (equal checksums: the same random stream).
//!
//! `cargo run --release -p automaton --example speedprobe -- [thesis|quick] [steps]`
use ::automaton::{
    Activation, Automaton, Direction, FlightCap, Frustration, Knock, Lateral, Lattice, Params, Physical, RuleSet, Sideways, Threshold,
    YBoundary,
};
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (nx, ny, grains) = if args.get(1).map(|s| s.as_str()) == Some("quick") {
        (133, 27, 1000)
    } else {
        (533, 27, 4000)
    };
    let steps: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let mut h = vec![0u8; nx * ny];
    let mut s = 1u64;
    let mut placed = 0;
    while placed < grains {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        let c = ((z ^ (z >> 31)) % (nx * ny) as u64) as usize;
        if h[c] == 0 {
            h[c] = 1;
            placed += 1;
        }
    }
    let params = Params {
        rule: RuleSet::Physical,
        physical: Physical {
            threshold: Threshold::Coulomb {
                tray_acceleration: 394.78,
                friction_acceleration: 7.0,
            },
            cap: FlightCap::Cells { cells: 66 },
            activation: Activation::Bernoulli { p: 0.8 },
            knock: Knock::Bernoulli { p: 0.18218049708252038 },
            lateral: Lateral::Clusters,
            sideways: Sideways::Bernoulli { p: 0.1 },
            frustration: Frustration::None,
            trains: false,
            transport: automaton::Transport::Uniform,
        },
        y: YBoundary::Walls,
        x_walls: false,
        seed: 1,
        measured: None,
    };
    let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), params, Direction::Plus).unwrap();
    let t = Instant::now();
    for _ in 0..steps {
        a.half_step();
    }
    let dt = t.elapsed().as_secs_f64();
    let hsum: u64 = a
        .lattice()
        .heights()
        .iter()
        .enumerate()
        .map(|(i, &x)| (i as u64 + 1) * x as u64)
        .sum();
    println!(
        "{:.3} e9 cells/s (wall) checksum {hsum}",
        (nx * ny) as f64 * steps as f64 / dt / 1e9
    );
}
