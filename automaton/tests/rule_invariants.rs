//! Invariants of the automaton's rules (issue 5 acceptance tests).

use automaton::{
    Activation, Automaton, Direction, FlightCap, Frustration, Knock, Lateral, Lattice, Params, Physical, RuleSet, Sideways, Threshold,
    YBoundary,
};
use proptest::prelude::*;

fn all_on(cap: usize, y: YBoundary) -> Params {
    Params {
        rule: RuleSet::Physical,
        physical: Physical {
            threshold: Threshold::Coulomb {
                tray_acceleration: 400.0,
                friction_acceleration: 7.0,
            },
            cap: FlightCap::Cells { cells: cap },
            activation: Activation::Bernoulli { p: 0.6 },
            knock: Knock::Bernoulli { p: 0.5 },
            lateral: Lateral::Neighbours,
            sideways: Sideways::Bernoulli { p: 0.2 },
            frustration: Frustration::Bernoulli { p: 0.3 },
            trains: false,
            transport: automaton::Transport::Uniform,
        },
        y,
        x_walls: false,
        seed: 11,
        measured: None,
    }
}

fn strict(y: YBoundary) -> Params {
    Params {
        rule: RuleSet::Strict,
        physical: Physical::off(),
        y,
        x_walls: false,
        seed: 1,
        measured: None,
    }
}

/// Deterministic pseudo-random heights in 0..=max with about `fill` of the cells occupied.
fn random_heights(nx: usize, ny: usize, fill: f64, max: u8, seed: u64) -> Vec<u8> {
    let mut s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    (0..nx * ny)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            if u < fill {
                1 + ((s % max as u64) as u8)
            } else {
                0
            }
        })
        .collect()
}

#[test]
fn mass_is_conserved_exactly_and_heights_stay_non_negative() {
    for (nx, ny, max) in [(533, 27, 1u8), (100, 7, 1), (64, 5, 4), (37, 3, 6)] {
        for y in [YBoundary::Walls, YBoundary::Periodic] {
            let h = random_heights(nx, ny, 0.3, max, nx as u64);
            let lattice = Lattice::from_heights(nx, ny, &h).unwrap();
            let mass = lattice.mass();
            let mut a = Automaton::new(lattice, all_on(nx / 8 + 1, y), Direction::Plus).unwrap();
            for _ in 0..60 {
                a.half_step();
                // u8 heights cannot go negative; an underflow would wrap to 255 and change
                // the mass, so a conserved mass with bounded heights proves both.
                assert_eq!(a.lattice().mass(), mass, "{nx}x{ny} {y:?} after {} half steps", a.half_steps());
                let top = *a.lattice().heights().iter().max().unwrap() as u64;
                assert!(top <= mass.min(200), "height {top}");
            }
        }
    }
}

#[test]
fn bit_parallel_step_equals_the_byte_reference_on_submonolayers() {
    // Rows of 1 to 16 words (up to 1024 cells) take the fixed-width step.
    for (k, (nx, ny)) in [(533usize, 27usize), (64, 4), (65, 3), (200, 1), (129, 2), (1024, 3)]
        .into_iter()
        .enumerate()
    {
        for y in [YBoundary::Walls, YBoundary::Periodic] {
            let mut clusters = all_on(nx / 5 + 2, y);
            clusters.physical.lateral = Lateral::Clusters;
            for params in [all_on(nx / 7 + 1, y), strict(y), all_on(3, y), all_on(10 * nx, y), clusters] {
                let h = random_heights(nx, ny, 0.25 + 0.1 * k as f64, 1, 3 + k as u64);
                let bits = Lattice::from_heights(nx, ny, &h).unwrap();
                assert!(bits.is_bit_packed());
                let bytes = bits.clone().into_byte_storage();
                let mut a = Automaton::new(bits, params, Direction::Minus).unwrap();
                let mut b = Automaton::new(bytes, params, Direction::Minus).unwrap();
                for _ in 0..40 {
                    a.half_step();
                    b.half_step();
                    assert_eq!(
                        a.lattice().heights(),
                        b.lattice().heights(),
                        "{nx}x{ny} {y:?} {:?} half step {}",
                        params.rule,
                        a.half_steps()
                    );
                }
            }
        }
    }
}

/// Rows wider than the bit-parallel step's 1024 cells are stored as bytes, where the byte
/// step applies the same rules; a narrower submonolayer keeps bits.
#[test]
fn rows_wider_than_1024_cells_run_on_bytes() {
    let h = random_heights(1025, 3, 0.3, 1, 5);
    let wide = Lattice::from_heights(1025, 3, &h).unwrap();
    assert!(!wide.is_bit_packed());
    assert!(!Lattice::empty(1025, 3).is_bit_packed());
    assert!(Lattice::from_heights(1024, 3, &h[..1024 * 3]).unwrap().is_bit_packed());
    let mass = wide.mass();
    let mut a = Automaton::new(wide, all_on(100, YBoundary::Walls), Direction::Plus).unwrap();
    for _ in 0..20 {
        a.half_step();
    }
    assert_eq!(a.lattice().mass(), mass);
    assert!(!a.lattice().is_bit_packed());
}

/// Stripes leave free runs longer than a word in every row: the flight-cap mask must see
/// runs that cover whole 64-cell words (a bit path once missed them; the byte path did not).
#[test]
fn bit_parallel_step_equals_the_byte_reference_on_a_striped_layer() {
    let (nx, ny) = (533usize, 27usize);
    let mut h = random_heights(nx, ny, 0.9, 1, 17);
    for j in 0..ny {
        for i in 0..nx {
            if !(100..260).contains(&i) {
                h[j * nx + i] = 0;
            }
        }
    }
    let mut params = all_on(66, YBoundary::Walls);
    params.physical.lateral = Lateral::Clusters;
    params.physical.activation = Activation::Bernoulli { p: 0.8 };
    let bits = Lattice::from_heights(nx, ny, &h).unwrap();
    let mut a = Automaton::new(bits.clone(), params, Direction::Plus).unwrap();
    let mut b = Automaton::new(bits.into_byte_storage(), params, Direction::Plus).unwrap();
    for _ in 0..30 {
        a.half_step();
        b.half_step();
        assert_eq!(a.lattice().heights(), b.lattice().heights(), "half step {}", a.half_steps());
    }
}

#[test]
fn mirror_image_with_reversed_drive_phase_gives_the_mirrored_pattern() {
    for (nx, ny, max) in [(533, 27, 1u8), (90, 6, 3)] {
        let h = random_heights(nx, ny, 0.3, max, 5);
        let lattice = Lattice::from_heights(nx, ny, &h).unwrap();
        let mirror = lattice.mirrored();
        let params = all_on(17, YBoundary::Walls);
        let mut a = Automaton::new(lattice, params, Direction::Plus).unwrap();
        let mut b = Automaton::new(mirror, params, Direction::Minus).unwrap();
        for _ in 0..50 {
            a.half_step();
            b.half_step();
        }
        assert_ne!(a.lattice().heights(), h, "something moved");
        assert_eq!(a.lattice().mirrored(), *b.lattice());
    }
}

#[test]
fn below_the_sliding_threshold_nothing_moves() {
    let h = random_heights(200, 10, 0.3, 1, 9);
    let lattice = Lattice::from_heights(200, 10, &h).unwrap();
    let mut params = all_on(20, YBoundary::Walls);
    params.physical.threshold = Threshold::Coulomb {
        tray_acceleration: 4.93, // 5 Hz, 5 mm: A (2 pi nu)^2
        friction_acceleration: 7.0,
    };
    let mut a = Automaton::new(lattice.clone(), params, Direction::Plus).unwrap();
    assert!(a.frozen());
    for _ in 0..20 {
        a.period();
    }
    assert_eq!(*a.lattice(), lattice);
}

#[test]
fn multilayer_slopes_relax_to_at_most_one() {
    for seed in 0..5 {
        let (nx, ny) = (80, 4);
        let h = random_heights(nx, ny, 0.5, 9, seed);
        let lattice = Lattice::from_heights(nx, ny, &h).unwrap();
        assert!(lattice.max_x_slope() >= 2, "the start must be steep");
        let mass = lattice.mass();
        for params in [strict(YBoundary::Walls), all_on(10, YBoundary::Periodic)] {
            let mut a = Automaton::new(lattice.clone(), params, Direction::Plus).unwrap();
            for _ in 0..10 {
                a.half_step();
                assert!(a.lattice().max_x_slope() <= 1, "slope {}", a.lattice().max_x_slope());
                assert_eq!(a.lattice().mass(), mass);
            }
        }
    }
}

fn rotated(h: &[u8], nx: usize, ny: usize, shift: isize) -> Vec<u8> {
    let mut out = vec![0; h.len()];
    for j in 0..ny {
        for i in 0..nx {
            let to = (i as isize + shift).rem_euclid(nx as isize) as usize;
            out[j * nx + to] = h[j * nx + i];
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Thesis rule 1 read literally: each grain stops just before where the next grain
    /// started, so a submonolayer moves rigidly by one cell against the flight.
    #[test]
    fn strict_moves_any_submonolayer_rigidly_by_one_cell_per_half_step(
        nx in 1usize..150,
        ny in 1usize..5,
        cells in prop::collection::vec(any::<bool>(), 600),
        periodic in any::<bool>(),
        bytes in any::<bool>(),
    ) {
        let h: Vec<u8> = cells.iter().take(nx * ny).map(|&c| c as u8).chain(std::iter::repeat(0)).take(nx * ny).collect();
        let mut lattice = Lattice::from_heights(nx, ny, &h).unwrap();
        if bytes {
            lattice = lattice.into_byte_storage();
        }
        let y = if periodic { YBoundary::Periodic } else { YBoundary::Walls };
        let mut a = Automaton::new(lattice, strict(y), Direction::Plus).unwrap();
        a.half_step(); // flight towards +x: pattern moves by -1
        prop_assert_eq!(a.lattice().heights(), rotated(&h, nx, ny, -1));
        a.half_step(); // back
        prop_assert_eq!(a.lattice().heights(), h);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Conservation-law suite (issue 7): any lattice (submonolayer or piles), any combination
    /// of ingredients, any seed and boundary conserves the number of grains exactly.
    #[test]
    fn any_rules_on_any_lattice_conserve_mass(
        nx in 2usize..120,
        ny in 1usize..9,
        fill in 0.0f64..0.9,
        max in 1u8..5,
        seed in any::<u64>(),
        cap in 1usize..40,
        switches in prop::collection::vec(any::<bool>(), 5),
        periodic in any::<bool>(),
        half_steps in 1usize..40,
    ) {
        let h = random_heights(nx, ny, fill, max, seed);
        let lattice = Lattice::from_heights(nx, ny, &h).unwrap();
        let mass = lattice.mass();
        let y = if periodic { YBoundary::Periodic } else { YBoundary::Walls };
        let mut p = all_on(cap, y);
        p.seed = seed;
        if !switches[0] { p.physical.activation = Activation::None; }
        if !switches[1] { p.physical.knock = Knock::None; }
        if !switches[2] { p.physical.lateral = Lateral::None; }
        if !switches[3] { p.physical.sideways = Sideways::None; }
        if !switches[4] { p.physical.cap = FlightCap::None; }
        let mut a = Automaton::new(lattice, p, Direction::Plus).unwrap();
        for _ in 0..half_steps {
            a.half_step();
        }
        prop_assert_eq!(a.lattice().mass(), mass);
    }
}

/// Grains of row 0 (of `ny` rows) at every 4th cell fly at most one cell in one half step;
/// returns the fraction of them that moved over `runs` seeds, and the number of trials.
fn moved_fraction(nx: usize, ny: usize, h: &[u8], params: Params, runs: u64) -> (f64, f64) {
    let (mut moved, mut trials) = (0usize, 0usize);
    for seed in 0..runs {
        let lattice = Lattice::from_heights(nx, ny, h).unwrap();
        assert!(lattice.is_bit_packed());
        let mut a = Automaton::new(lattice, Params { seed, ..params }, Direction::Plus).unwrap();
        a.half_step();
        let after = a.lattice().heights();
        for i in (0..nx).step_by(4) {
            trials += 1;
            moved += (after[i] == 0) as usize;
        }
    }
    (moved as f64 / trials as f64, trials as f64)
}

fn assert_binomial(frac: f64, n: f64, p: f64, what: &str) {
    let sigma = (p * (1.0 - p) / n).sqrt();
    assert!(
        (frac - p).abs() < 5.0 * sigma,
        "{what}: {frac} against {p} (n = {n}, sigma = {sigma})"
    );
}

/// Every ingredient on, then knock-through, lateral contacts and sideways moves off: flights
/// whose outcome depends only on activation, frustration and trains.
fn bare(cap: usize, activation: Activation, frustration: Frustration) -> Params {
    let mut params = all_on(cap, YBoundary::Walls);
    params.physical.knock = Knock::None;
    params.physical.lateral = Lateral::None;
    params.physical.sideways = Sideways::None;
    params.physical.activation = activation;
    params.physical.frustration = frustration;
    params
}

/// The flight and holding draws (which share one set of random digit words, on disjoint
/// cells) give their nominal (quantised) probabilities, and independently so.
#[test]
fn flight_and_holding_probabilities_match_their_nominal_values() {
    let nx = 1000; // the bit-parallel step's widest rows are 1024 cells
                   // Isolated grains with a cap of one cell: a grain moves exactly when it flies.
    let mut params = bare(1, Activation::Bernoulli { p: 0.6 }, Frustration::None);
    let h: Vec<u8> = (0..nx).map(|i| (i % 4 == 0) as u8).collect();
    let (frac, n) = moved_fraction(nx, 1, &h, params, 80);
    assert_binomial(frac, n, 38.0 / 64.0, "activation 0.6 (38/64)");

    // Row 1 holds a grain right ahead of each grain of row 0: a lateral contact that holds
    // with probability 1 - p_knock. Row 0's grains move when they fly and the contact gives.
    let mut h = vec![0u8; 2 * nx];
    for i in (0..nx).step_by(4) {
        h[i] = 1;
        h[nx + i + 1] = 1;
    }
    params.physical.lateral = Lateral::Neighbours;
    params.physical.knock = Knock::Bernoulli { p: 0.3 };
    params.physical.activation = Activation::None;
    let (frac, n) = moved_fraction(nx, 2, &h, params, 80);
    assert_binomial(frac, n, 19.0 / 64.0, "contact gives, p_knock 0.3 (19/64)");
    params.physical.activation = Activation::Bernoulli { p: 0.6 };
    let (frac, n) = moved_fraction(nx, 2, &h, params, 80);
    assert_binomial(frac, n, 38.0 / 64.0 * 19.0 / 64.0, "flies and contact gives");
}

/// Frustration: each occupied neighbouring cell holds a grain with probability h, so a grain
/// with n neighbours flies with probability (1 - h)^n, independently of its activation.
#[test]
fn crowded_grains_fly_with_probability_one_minus_h_to_the_n() {
    let nx = 1000; // the bit-parallel step's widest rows are 1024 cells
    let mut params = bare(1, Activation::None, Frustration::Bernoulli { p: 0.3 }); // 19/64
    let free: f64 = 45.0 / 64.0;
    // Row 0: a grain every 4th cell; row 1: n = 1 (the cell beside it) or n = 2 (that one
    // and the one behind it), never ahead of it, so nothing blocks its one-cell flight.
    for (n, offsets) in [(1, vec![0usize]), (2, vec![0, nx - 1])] {
        let mut h = vec![0u8; 2 * nx];
        for i in (0..nx).step_by(4) {
            h[i] = 1;
            for &o in &offsets {
                h[nx + (i + o) % nx] = 1;
            }
        }
        let (frac, trials) = moved_fraction(nx, 2, &h, params, 80);
        assert_binomial(frac, trials, free.powi(n), &format!("{n} neighbour(s)"));
        params.physical.activation = Activation::Bernoulli { p: 0.6 };
        let (frac, trials) = moved_fraction(nx, 2, &h, params, 80);
        assert_binomial(
            frac,
            trials,
            38.0 / 64.0 * free.powi(n),
            &format!("{n} neighbour(s), activation 0.6"),
        );
        params.physical.activation = Activation::None;
    }
}

/// One half step towards +x of a single row with `trains`, every grain flying unless held.
fn one_row_step(nx: usize, grains: &[usize], cap: usize, hold: Option<f64>, trains: bool) -> Vec<usize> {
    let mut h = vec![0u8; nx];
    for &i in grains {
        h[i] = 1;
    }
    let mut params = bare(
        cap,
        Activation::None,
        hold.map_or(Frustration::None, |p| Frustration::Bernoulli { p }),
    );
    params.physical.trains = trains;
    let mut a = Automaton::new(Lattice::from_heights(nx, 1, &h).unwrap(), params, Direction::Plus).unwrap();
    a.half_step();
    let after = a.lattice().heights();
    (0..nx).filter(|&i| after[i] == 1).collect()
}

/// Trains: rolling grains do not stop one another. A touching line of free grains moves as
/// a whole by the cap, where the thesis' rule moves only its front grain; grains queue up
/// behind a resting (held) pair instead of stopping at the first grain of the copy L.
#[test]
fn trains_move_together_and_queue_behind_resting_grains() {
    assert_eq!(one_row_step(40, &[3, 4, 5], 5, None, true), vec![8, 9, 10]);
    assert_eq!(one_row_step(40, &[3, 4, 5], 5, None, false), vec![3, 4, 10]);
    // The pair at 20, 21 is held (every neighbour holds, p = 1); 5 and 7 are free.
    assert_eq!(one_row_step(40, &[5, 7, 20, 21], 30, Some(1.0), true), vec![18, 19, 20, 21]);
    assert_eq!(one_row_step(40, &[5, 7, 20, 21], 30, Some(1.0), false), vec![6, 19, 20, 21]);
    // With trains the whole ring of free grains turns rigidly.
    assert_eq!(one_row_step(10, &[0, 1, 2, 5], 4, None, true), vec![4, 5, 6, 9]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Trains and frustration conserve mass exactly, on any layer.
    #[test]
    fn trains_conserve_mass(seed in 0u64..1000, fill in 0.1f64..0.9, cap in 1usize..40, periodic in any::<bool>()) {
        let (nx, ny) = (97, 7);
        let h = random_heights(nx, ny, fill, 1, seed);
        let lattice = Lattice::from_heights(nx, ny, &h).unwrap();
        let mass = lattice.mass();
        let mut p = all_on(cap, if periodic { YBoundary::Periodic } else { YBoundary::Walls });
        p.seed = seed;
        p.physical.trains = true;
        let mut a = Automaton::new(lattice, p, Direction::Plus).unwrap();
        for _ in 0..20 {
            a.half_step();
            prop_assert!(a.lattice().heights().iter().all(|&x| x <= 1));
        }
        prop_assert_eq!(a.lattice().mass(), mass);
    }
}

/// Graded transport from the DEM's measured slope ([`automaton::transport`]) with the given
/// share of the hold left by agitation.
fn graded(cap: usize, hold: f64, trains: bool, sideways: f64) -> Params {
    use automaton::transport::{Graded, SlopeTable};
    Params {
        rule: RuleSet::Physical,
        physical: Physical {
            cap: FlightCap::Cells { cells: cap },
            activation: Activation::None,
            sideways: Sideways::Bernoulli { p: sideways },
            trains,
            transport: automaton::Transport::Graded(Graded {
                slope: SlopeTable::InBands,
                hold,
                grain_fraction: 0.05,
                window_cells: 1.67,
            }),
            ..Physical::off()
        },
        y: YBoundary::Walls,
        x_walls: false,
        seed: 5,
        measured: None,
    }
}

#[test]
fn graded_transport_conserves_mass_and_keeps_a_submonolayer() {
    for (nx, ny, fill) in [(167, 33, 0.36), (83, 33, 0.6), (40, 4, 0.9), (50, 1, 0.3)] {
        for (trains, hold) in [(true, 1.0), (false, 1.0), (true, 0.3), (true, 0.0)] {
            let h = random_heights(nx, ny, fill, 1, nx as u64);
            let lattice = Lattice::from_heights(nx, ny, &h).unwrap();
            let m0 = lattice.mass();
            let mut a = Automaton::new(lattice, graded(24, hold, trains, 0.1), Direction::Plus).unwrap();
            for _ in 0..60 {
                a.half_step();
                assert_eq!(a.lattice().mass(), m0, "{nx} x {ny}, trains {trains}, hold {hold}");
                assert!(a.lattice().heights().iter().all(|&x| x <= 1), "grains never share a cell");
            }
        }
    }
}

/// The melt rule's limit: with no hold left every grain jumps a free grain's cap, so a lone
/// grain and a sparse layer go the cap forth and back; with the full hold a jammed strip
/// (every cell of its columns taken) moves by its jammed slope's share of the cap only.
#[test]
fn without_hold_grains_jump_the_cap_and_jammed_strips_creep_with_it() {
    let (nx, ny, cap) = (100, 3, 24);
    let mut h = vec![0u8; nx * ny];
    h[10] = 1;
    let mut a = Automaton::new(
        Lattice::from_heights(nx, ny, &h).unwrap(),
        graded(cap, 0.0, true, 0.0),
        Direction::Plus,
    )
    .unwrap();
    a.half_step();
    assert_eq!(a.lattice().height(10 + cap, 0), 1);
    a.half_step();
    assert_eq!(a.lattice().height(10, 0), 1, "back after a period");
    // A jammed block of 10 columns across all 3 rows: its own packing sets its jump.
    let mut h = vec![0u8; nx * ny];
    for j in 0..ny {
        for i in 40..50 {
            h[j * nx + i] = 1;
        }
    }
    let params = |hold| {
        let mut p = graded(cap, hold, true, 0.0);
        if let automaton::Transport::Graded(g) = &mut p.physical.transport {
            g.grain_fraction = 0.9 / (3.0 * 1.67); // a full window of 3 rows: phi = 0.9
        }
        p
    };
    for (hold, expect) in [(1.0, 5), (0.0, cap)] {
        let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), params(hold), Direction::Plus).unwrap();
        a.half_step();
        // Inside the block (column 45) the window is full, phi = 0.9, and the jammed slope
        // 0.15 gives round(24 * 0.1536 / (5/7)) = 5 cells; its edges are less packed.
        let moved: Vec<usize> = (0..nx).filter(|&i| a.lattice().height(i, 1) == 1).collect();
        assert_eq!(moved.len(), 10);
        assert!(moved.contains(&(45 + expect)), "hold {hold}: {moved:?}");
    }
}
