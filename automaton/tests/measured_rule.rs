//! The `measured` and `swing` rules ([`automaton::measured_rule`], [`automaton::swing`]) on
//! lattices built for them: a band's leading edge escapes at the measured rate, grains are
//! conserved, the same seed gives the same lattice, and the swing follows the local packing.

use automaton::measured::{Bands, Cell, ClassMoves, Excursions, MeasuredFile, Source, Spread, SwingClassFile, SwingFieldFile};
use automaton::measured_rule::{BandDetection, MeasuredRule};
use automaton::{Automaton, Direction, Lattice, Params, Physical, RuleSet, Tracks, YBoundary};

const CELL: f64 = 1e-3;

/// Every quantile `x` metres.
fn flat(x: f64) -> Spread {
    Spread {
        samples: 100,
        mean: x,
        sd: 0.0,
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
            drift_signed: Some(flat(0.0)),
        },
        swing_field: None,
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
        x_walls: false,
        seed,
        measured: Some(MeasuredRule::new(f, CELL, CELL, BandDetection { fill: 0.5, min_cells: 3 }, 0.77).unwrap()),
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
            sd: 0.0,
            q10: 0.01013,
            q25: 0.01284,
            median: 0.01426,
            q75: 0.01429,
            q90: 0.0143,
        },
        sideways: Spread {
            samples: 16000,
            mean: 0.00025,
            sd: 0.0,
            q10: 0.0,
            q25: 0.0,
            median: 7.8e-6,
            q75: 0.00033,
            q90: 0.00087,
        },
    };
    f.excursion.all = all;
    f.excursion.by_contacts.clear();
    // The stripe scene's signed drift per period (seed 1).
    f.excursion.drift_signed = Some(Spread {
        samples: 14000,
        mean: -0.000149,
        sd: 0.0,
        q10: -0.00204,
        q25: -0.00015,
        median: -2.9e-5,
        q75: 2.1e-5,
        q90: 0.00135,
    });
    let run = |seed: u64| {
        let mut m = params(&f, seed);
        m.measured.as_mut().unwrap().cell_m = 0.76e-3;
        m.measured.as_mut().unwrap().cell_y_m = 0.76e-3;
        let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), m, Direction::Plus).unwrap();
        let mut tracks = Tracks::new(a.lattice()).unwrap();
        for _ in 0..40 {
            a.half_step();
            assert_eq!(a.lattice().mass(), grains);
            assert!(a.lattice().heights().iter().all(|&x| x <= 1));
            tracks.apply(a.measured_moves().expect("a submonolayer's grains are followed"));
            assert!(tracks.matches(a.lattice()), "the followed grains are the lattice's");
        }
        a.lattice().heights()
    };
    let once = run(5);
    assert_eq!(once, run(5));
    assert_ne!(once, run(6));
    assert_ne!(once, h, "grains move");
}

/// A lone grain swings out by its drawn excursion and back by the same less the period's
/// drift: over many seeds its net move per period has the measured signed drift's mean (in
/// cells, the stochastic rounding keeps it) and quantiles (within the rounding's cell), while
/// its moves per half period keep the excursion's mean.
#[test]
fn a_lone_grain_drifts_per_period_by_the_measured_drift() {
    let (nx, ny) = (200, 3);
    let mut f = file(0.0, 0.0, 0.5);
    // Excursions 12-16 cells, drifts -4 to +3 cells: the way back never clamps at 0.
    let spread = |mean: f64, q: [f64; 5]| Spread {
        samples: 1000,
        mean: mean * CELL,
        sd: 0.0,
        q10: q[0] * CELL,
        q25: q[1] * CELL,
        median: q[2] * CELL,
        q75: q[3] * CELL,
        q90: q[4] * CELL,
    };
    f.excursion.all.excursion = spread(14.0, [12.5, 13.0, 14.0, 15.0, 15.5]);
    f.excursion.by_contacts.clear();
    let drift = spread(-0.5, [-2.5, -1.5, -0.5, 0.5, 1.5]);
    f.excursion.drift_signed = Some(drift);
    let (mut nets, mut half_abs, mut halves) = (Vec::new(), 0.0, 0usize);
    for seed in 0..400 {
        let mut h = vec![0u8; nx * ny];
        h[nx + 100] = 1;
        let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), params(&f, seed), Direction::Plus).unwrap();
        let mut tracks = Tracks::new(a.lattice()).unwrap();
        for _ in 0..5 {
            let x0 = tracks.unwrapped_x()[0];
            for _ in 0..2 {
                let before = tracks.unwrapped_x()[0];
                a.half_step();
                tracks.apply(a.measured_moves().unwrap());
                half_abs += (tracks.unwrapped_x()[0] - before).abs() as f64;
                halves += 1;
            }
            nets.push((tracks.unwrapped_x()[0] - x0) as f64);
        }
    }
    let n = nets.len() as f64;
    let mean = nets.iter().sum::<f64>() / n;
    // sd of a drift about 1.6 cells over sqrt(2000): 0.04; allow 0.15.
    assert!(
        (mean - drift.mean / CELL).abs() < 0.15,
        "drift {mean} cells against {}",
        drift.mean / CELL
    );
    nets.sort_by(f64::total_cmp);
    let at = |p: f64| nets[(p * (n - 1.0)).round() as usize];
    for (p, v) in [(0.1, drift.q10), (0.5, drift.median), (0.9, drift.q90)] {
        assert!((at(p) - v / CELL).abs() <= 1.0, "q{p}: {} cells against {}", at(p), v / CELL);
    }
    // Out at the excursion's mean, back at it less the mean drift's share (small).
    let half = half_abs / halves as f64;
    assert!((half - 14.0).abs() < 0.5, "|dx| per half period {half} cells");
}

#[test]
fn the_measured_rule_needs_its_numbers() {
    let mut p = params(&file(1.0, 0.0, 0.5), 1);
    p.measured = None;
    let e = Automaton::new(one_band(10, 2, 2, 5), p, Direction::Plus).err().unwrap();
    assert!(e.to_string().contains("automaton.parameters"), "{e}");
}

/// A file whose swing field is `(packing, swing in cells, spread in cells)` per class.
fn swing_file(points: &[(f64, f64, f64)]) -> MeasuredFile {
    let mut f = file(0.0, 0.0, 0.5);
    f.swing_field = Some(SwingFieldFile {
        local_radius_diameters: 2.5,
        across_m: 2.5 * CELL,
        classes: points
            .iter()
            .map(|&(packing, swing, spread)| SwingClassFile {
                low: 0.0,
                high: 1.0,
                packing,
                swing: Spread {
                    samples: 1000,
                    ..flat(swing * CELL)
                },
                relative: Spread {
                    sd: spread * CELL,
                    ..flat(0.0)
                },
            })
            .collect(),
    });
    f
}

fn swing_params(f: &MeasuredFile, seed: u64) -> Params {
    Params {
        rule: RuleSet::Swing,
        ..params(f, seed)
    }
}

/// A random submonolayer of `nx` x `ny` cells, a fraction `fill` occupied.
fn random_layer(nx: usize, ny: usize, fill: u64, mut s: u64) -> Vec<u8> {
    (0..nx * ny)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % 100 < fill) as u8
        })
        .collect()
}

/// With one swing at every packing and no spread, the whole layer moves out and back by it
/// as one sheet: no queue shortens a flight, no grain is held, and the lattice returns.
#[test]
fn a_flat_swing_moves_the_layer_out_and_back_as_one_sheet() {
    let (nx, ny) = (120, 10);
    let h = random_layer(nx, ny, 40, 99);
    let f = swing_file(&[(0.5, 7.0, 0.0)]);
    let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), swing_params(&f, 3), Direction::Plus).unwrap();
    let mut tracks = Tracks::new(a.lattice()).unwrap();
    let x0 = tracks.unwrapped_x().to_vec();
    a.half_step();
    tracks.apply(a.measured_moves().unwrap());
    assert!(
        tracks.unwrapped_x().iter().zip(&x0).all(|(x, x0)| x - x0 == 7),
        "every grain flies 7 cells"
    );
    a.half_step();
    tracks.apply(a.measured_moves().unwrap());
    assert_eq!(tracks.unwrapped_x(), &x0[..]);
    assert_eq!(a.lattice().heights(), h);
}

/// A dense block swings by the dense class's swing and a lone grain by the sparse one's; a
/// grain behind the block queues behind its landing, and grains are conserved.
#[test]
fn the_swing_follows_the_local_packing() {
    let (nx, ny) = (200, 12);
    let mut h = vec![0u8; nx * ny];
    for j in 0..ny {
        for i in 60..80 {
            h[j * nx + i] = 1;
        }
    }
    h[6 * nx + 150] = 1; // a lone grain far from the block
    h[6 * nx + 57] = 1; // a grain just behind the block
                        // Packing 0.77 in the block's interior, 0.77 / 55 for the lone grain (one grain in a
                        // window of 11 columns by 5 rows: 5 cells either way along x, 2 rows either way across).
    let f = swing_file(&[(0.02, 12.0, 0.0), (0.77, 4.0, 0.0)]);
    let mut p = swing_params(&f, 1);
    p.measured.as_mut().unwrap().swing.as_mut().unwrap().reach_m = 5.0 * CELL;
    let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), p, Direction::Plus).unwrap();
    a.half_step();
    let l = a.lattice();
    assert_eq!(l.mass(), (20 * ny + 2) as u64);
    let moved = |from: (usize, usize)| a.measured_moves().unwrap().iter().find(|m| m.from == from).map(|m| m.dx);
    assert_eq!(moved((6, 150)), Some(12), "the lone grain swings the sparse swing");
    // Mid-block (packing 0.77): 4 cells; its front column runs ahead of the interior only
    // by its sparser disk, and every grain of a row lands behind the grain ahead.
    assert_eq!(moved((6, 70)), Some(4));
    let (behind, last) = (moved((6, 57)).unwrap(), moved((6, 60)).unwrap());
    assert!(57 + behind < 60 + last, "the grain behind the block does not fly through it");
    assert!((1..12).contains(&behind), "it queues behind the block's last grain: {behind}");
}

/// The spread about the swing is the measured one: over many seeds a lone grain's flights
/// have the swing's mean and the spread's standard deviation (in cells, the stochastic
/// rounding adding at most 1/12 to the variance).
#[test]
fn a_lone_grain_flies_the_swing_with_the_measured_spread() {
    let (nx, ny) = (100, 3);
    let f = swing_file(&[(0.5, 9.3, 1.5)]);
    let mut flights = Vec::new();
    for seed in 0..2000 {
        let mut h = vec![0u8; nx * ny];
        h[nx + 20] = 1;
        let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), swing_params(&f, seed), Direction::Plus).unwrap();
        a.half_step();
        flights.push(a.measured_moves().unwrap().first().map_or(0, |m| m.dx) as f64);
    }
    let n = flights.len() as f64;
    let mean = flights.iter().sum::<f64>() / n;
    let var = flights.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    // sd of the mean 1.5 / sqrt(2000) = 0.034: allow 4 sd.
    assert!((mean - 9.3).abs() < 0.14, "mean flight {mean} cells");
    assert!(
        var > 1.5f64.powi(2) * 0.85 && var < 1.5f64.powi(2) * 1.15 + 1.0 / 12.0,
        "variance {var}"
    );
}

/// Grains are conserved, followed one by one, and a seed gives one lattice under the swing rule.
#[test]
fn the_swing_rule_conserves_grains_and_a_seed_gives_one_lattice() {
    let (nx, ny) = (97, 13);
    let h = random_layer(nx, ny, 45, 777);
    let grains = h.iter().map(|&x| x as u64).sum::<u64>();
    let f = swing_file(&[(0.15, 15.7, 1.0), (0.45, 13.0, 1.2), (0.85, 10.4, 1.3)]);
    let run = |seed: u64| {
        let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), swing_params(&f, seed), Direction::Plus).unwrap();
        let mut tracks = Tracks::new(a.lattice()).unwrap();
        for _ in 0..40 {
            a.half_step();
            assert_eq!(a.lattice().mass(), grains);
            assert!(a.lattice().heights().iter().all(|&x| x <= 1));
            tracks.apply(a.measured_moves().unwrap());
            assert!(tracks.matches(a.lattice()));
        }
        a.lattice().heights()
    };
    let once = run(5);
    assert_eq!(once, run(5));
    assert_ne!(once, run(6));
}

#[test]
fn the_swing_rule_needs_a_swing_field() {
    let e = Automaton::new(one_band(10, 2, 2, 5), swing_params(&file(1.0, 0.0, 0.5), 1), Direction::Plus)
        .err()
        .unwrap();
    assert!(e.to_string().contains("[swing_field]"), "{e}");
}

/// Between end walls no grain crosses the ends: a row's front grain stops at the last cell
/// and the grains behind it queue, grains are conserved and followed, and the rules whose
/// rows wrap round refuse end walls.
#[test]
fn end_walls_stop_the_swing_and_the_other_rules_refuse_them() {
    let (nx, ny) = (30, 4);
    let mut h = vec![0u8; nx * ny];
    for i in [20, 24, 27] {
        h[nx + i] = 1;
    }
    let f = swing_file(&[(0.5, 7.0, 0.0)]);
    let mut p = swing_params(&f, 1);
    p.x_walls = true;
    let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), p, Direction::Plus).unwrap();
    let mut tracks = Tracks::new(a.lattice()).unwrap();
    a.half_step();
    tracks.apply(a.measured_moves().unwrap());
    let row: Vec<usize> = (0..nx).filter(|&i| a.lattice().height(i, 1) > 0).collect();
    assert_eq!(row, [27, 28, 29], "the front grain at the wall, the others queued behind it");
    assert!(tracks.matches(a.lattice()));
    // Back towards -x: 7 cells each, nothing reaches the wall at 0.
    a.half_step();
    let row: Vec<usize> = (0..nx).filter(|&i| a.lattice().height(i, 1) > 0).collect();
    assert_eq!(row, [20, 21, 22]);
    // Many half steps towards a crowded wall: conserved, one grain a cell.
    let h = random_layer(nx, ny, 60, 4242);
    let mut p = swing_params(&swing_file(&[(0.2, 12.0, 1.0), (0.7, 6.0, 1.0)]), 2);
    p.x_walls = true;
    let mut a = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), p, Direction::Plus).unwrap();
    for _ in 0..20 {
        a.half_step();
        assert_eq!(a.lattice().mass(), h.iter().map(|&x| x as u64).sum::<u64>());
        assert!(a.lattice().heights().iter().all(|&x| x <= 1));
    }
    let strict = Params {
        rule: RuleSet::Strict,
        x_walls: true,
        ..params(&f, 1)
    };
    let e = Automaton::new(Lattice::from_heights(nx, ny, &h).unwrap(), strict, Direction::Plus)
        .err()
        .unwrap();
    assert!(e.to_string().contains("box.x_walls"), "{e}");
}
