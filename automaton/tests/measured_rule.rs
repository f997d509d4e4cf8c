//! The `measured` rule ([`automaton::measured_rule`]) on lattices built for it: a band's
//! leading edge escapes at the measured rate, grains are conserved, and the same seed gives
//! the same lattice.

use automaton::measured::{Bands, Cell, ClassMoves, Excursions, MeasuredFile, Source, Spread};
use automaton::measured_rule::{BandDetection, MeasuredRule};
use automaton::{Automaton, Direction, Lattice, Params, Physical, RuleSet, YBoundary};

const CELL: f64 = 1e-3;

/// Every quantile `x` metres.
fn flat(x: f64) -> Spread {
    Spread {
        samples: 100,
        mean: x,
        q10: x,
        q25: x,
        median: x,
        q75: x,
        q90: x,
    }
}

/// A file whose every grain jumps `jump` cells and never steps sideways, with the given
/// edge escape per period.
fn file(jump: f64, sideways: f64, escape: f64) -> MeasuredFile {
    let class = |n: f64| ClassMoves {
        low: n,
        high: n,
        excursion: flat(jump * CELL),
        sideways: flat(sideways * CELL),
    };
    MeasuredFile {
        source: Source {
            run: "test".into(),
            grains: 0,
            mean_diameter_m: CELL,
            length_m: 1.0,
            width_m: 1.0,
            periodic: true,
            drive: vec![[0.0, 3.0, 0.01]],
        },
        cell: Cell { size_m: Some(CELL) },
        excursion: Excursions {
            all: class(0.0),
            by_contacts: (0..5).map(|n| class(n as f64)).collect(),
        },
        bands: Bands {
            core_packing: Some(0.77),
            edge_escape_per_period: Some(escape),
        },
    }
}

fn params(f: &MeasuredFile, seed: u64) -> Params {
    Params {
        rule: RuleSet::Measured,
        physical: Physical::off(),
        y: YBoundary::Walls,
        seed,
        measured: Some(MeasuredRule::new(f, CELL, CELL, BandDetection { fill: 0.5, min_cells: 3 }).unwrap()),
    }
}

/// One band: columns `a..=b` full, nothing else.
fn one_band(nx: usize, ny: usize, a: usize, b: usize) -> Lattice {
    let mut h = vec![0u8; nx * ny];
    for j in 0..ny {
        for i in a..=b {
            h[j * nx + i] = 1;
        }
    }
    Lattice::from_heights(nx, ny, &h).unwrap()
}

/// Grains of the columns `a..=b`.
fn within(l: &Lattice, a: usize, b: usize) -> usize {
    (0..l.ny).map(|j| (a..=b).filter(|&i| l.height(i, j) > 0).count()).sum()
}

/// Each grain of a band's leading edge escapes with the measured probability in the half
/// step its edge leads, and each edge leads in one half step of a period: over many seeds
/// the fraction of the +x edge's grains that leave the band in the first half step (towards
/// +x) is the parameter, and so is the -x edge's in the second, while the edges that trail
/// lose none.
#[test]
fn a_band_loses_its_leading_edge_at_the_measured_rate_and_nothing_else() {
    let (nx, ny, a, b) = (120, 20, 50, 69);
    let p = 0.41420118343195267;
    let f = file(10.0, 0.0, p);
    let (mut left_plus, mut left_minus, mut trials) = (0usize, 0usize, 0usize);
    for seed in 0..300 {
        let mut auto = Automaton::new(one_band(nx, ny, a, b), params(&f, seed), Direction::Plus).unwrap();
        auto.half_step();
        let l = auto.lattice();
        // Towards +x: only the last column's grains leave, ten cells on.
        assert_eq!(within(l, a, b - 1), (b - a) * ny, "the band's interior and trailing edge are held");
        let gone = ny - within(l, b, b);
        assert_eq!(within(l, b + 10, b + 10), gone, "escaped grains jump their measured 10 cells");
        left_plus += gone;
        auto.half_step();
        let l = auto.lattice();
        // Towards -x: the first column leads; the +x escapees fly back to their cells.
        left_minus += ny - within(l, a, a);
        trials += ny;
        assert_eq!(within(l, a + 1, b), (b - a) * ny, "the +x escapees are back, the rest held");
        assert_eq!(l.mass(), ((b - a + 1) * ny) as u64);
    }
    // Binomial: sd sqrt(p (1 - p) / 6000) = 0.0064; allow 4 sd.
    for (edge, left) in [("+x", left_plus), ("-x", left_minus)] {
        let rate = left as f64 / trials as f64;
        assert!((rate - p).abs() < 0.026, "{edge} edge: {rate} against {p}");
    }
}

/// The rule conserves grains, leaves no cell with two grains of a submonolayer, and gives
/// the same lattice for the same seed (and another for another seed).
#[test]
fn grains_are_conserved_and_a_seed_gives_one_lattice() {
    let (nx, ny) = (97, 13);
    let mut s = 12345u64;
    let h: Vec<u8> = (0..nx * ny)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % 100 < 55) as u8
        })
        .collect();
    let grains = h.iter().map(|&x| x as u64).sum::<u64>();
    // Spread jumps and sideways steps: the stripe scene's overall excursion, in 0.76 mm cells.
    let mut f = file(0.0, 0.0, 0.41);
    let all = ClassMoves {
        low: 0.0,
        high: f64::INFINITY,
        excursion: Spread {
            samples: 16000,
            mean: 0.01325,
            q10: 0.01013,
            q25: 0.01284,
            median: 0.01426,
            q75: 0.01429,
            q90: 0.0143,
        },
        sideways: Spread {
            samples: 16000,
            mean: 0.00025,
            q10: 0.0,
            q25: 0.0,
            median: 7.8e-6,
            q75: 0.00033,
            q90: 0.00087,
        },
    };
    f.excursion.all = all;
    f.excursion.by_contacts.clear();
    let run = |seed: u64| {
        let mut m = params(&f, seed);
        m.measured.as_mut().unwrap().cell_m = 0.76e-3;
        m.measured.as_mut().unwrap().cell_y_m = 0.76e-3;
        let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), m, Direction::Plus).unwrap();
        for _ in 0..40 {
            a.half_step();
            assert_eq!(a.lattice().mass(), grains);
            assert!(a.lattice().heights().iter().all(|&x| x <= 1));
        }
        a.lattice().heights()
    };
    let once = run(5);
    assert_eq!(once, run(5));
    assert_ne!(once, run(6));
    assert_ne!(once, h, "grains move");
}

#[test]
fn the_measured_rule_needs_its_numbers() {
    let mut p = params(&file(1.0, 0.0, 0.5), 1);
    p.measured = None;
    let e = Automaton::new(one_band(10, 2, 2, 5), p, Direction::Plus).err().unwrap();
    assert!(e.to_string().contains("automaton.parameters"), "{e}");
}
