//! The general half step on byte heights: any pile height, both rule sets, and the
//! multilayer resting rule. It states the rules cell by cell; on a submonolayer it gives
//! exactly what the bit-parallel [`crate::step`] gives (tested), which makes it the
//! reference of the fast path as well.
//!
//! In the flight frame (rows mirrored when grains fly towards -x), with `L` the unchanged
//! copy and `z = L[i] - 1` the level of the top grain of column `i`:
//! 1. *Flight.* Each flying top grain (all of them, or those drawn active, and with
//!    frustration not held by any of its occupied neighbouring cells) moves to the
//!    first column `c > i` whose `L` height exceeds `z` (in its row, or also the neighbouring
//!    rows with lateral contacts), minus one, or `cap` columns, whichever is nearer
//!    (thesis 3.1 rule 1, with the flight cap). A flight that ends on a grain of its own
//!    row after moving at least one cell without reaching the cap is an impact.
//!    With trains (the rolling regime), the flying grains of the own row are no obstacles:
//!    they move together, and a grain with `m` flying grains between it and the first
//!    obstacle lands `m` cells short of it (a train queues up behind a resting grain).
//! 2. *Knock-through.* For an impact drawn to transmit, the momentum runs through the line
//!    of touching grains that was hit (in the hit grain's row, own row first, in the new
//!    state, from the hit grain on), and the far grain of the line flies on, up to the cap,
//!    until it touches a grain of its row.
//! 3. *Sideways.* A top grain moves to the +y neighbour column if that is lower, with the
//!    drawn probability; all at once; then the same towards -y.
//!
//! The `measured` and `swing` rules replace steps 1-3 by their own ([`crate::measured_rule`]).
//! 4. *Resting (rule 2).* A top grain is at rest when both x-neighbours are at most one
//!    grain lower; otherwise it moves to the lower side (the flight direction on a tie).
//!    Applied in sweeps of increasing `i` until every slope is at most 1; each move lowers
//!    `sum h^2` by at least 2, so this ends.

use crate::measured_rule::{self, MeasuredScratch};
use crate::neighbours::{neighbour_row, offset_row, NEIGHBOURS};
use crate::params::{Lateral, Resolved, Tick};
use crate::rng::{self, Stream};
use crate::transport::{landings, Graded};

/// Buffers of the byte step.
pub(crate) struct ScalarScratch {
    lf: Vec<u8>,
    new: Vec<u8>,
    snap: Vec<u8>,
    flies: Vec<bool>,
    impacts: Vec<(usize, usize, u8)>,
    graded: GradedScratch,
    pub(crate) measured: MeasuredScratch,
}

/// Buffers of graded flights ([`graded_flights`]).
#[derive(Default)]
pub(crate) struct GradedScratch {
    counts: Vec<u32>,
    jumps: Vec<usize>,
    cells: Vec<usize>,
    row_jumps: Vec<usize>,
    land: Vec<usize>,
}

impl ScalarScratch {
    pub fn new(nx: usize, ny: usize) -> Self {
        Self {
            lf: vec![0; nx * ny],
            new: vec![0; nx * ny],
            snap: vec![0; nx * ny],
            flies: vec![false; nx * ny],
            impacts: Vec::with_capacity(nx * ny),
            graded: GradedScratch {
                counts: vec![0; nx],
                jumps: vec![0; nx],
                ..GradedScratch::default()
            },
            measured: MeasuredScratch::default(),
        }
    }
}

#[inline]
fn bit(key: u64, stream: Stream, i: usize, p: u32) -> bool {
    (rng::bernoulli(key, stream, i / 64, p) >> (i % 64)) & 1 == 1
}

/// One half step on heights `h` (index `j * nx + i`).
pub(crate) fn half_step(nx: usize, ny: usize, h: &mut [u8], r: &Resolved, tick: Tick, sc: &mut ScalarScratch) {
    let Tick { seed, t, left } = tick;
    let map = |i: usize| if left { nx - 1 - i } else { i };
    for j in 0..ny {
        for i in 0..nx {
            sc.lf[j * nx + map(i)] = h[j * nx + i];
        }
    }
    sc.new.copy_from_slice(&sc.lf);
    let cap = r.cap.min(nx);
    let lf = &sc.lf;
    // A grain at level z of row jn, column c, that touches an x-neighbour at its level.
    let clustered = |jn: usize, c: usize, z: u8| -> bool {
        lf[jn * nx + c] > z && (lf[jn * nx + (c + 1) % nx] > z || lf[jn * nx + (c + nx - 1) % nx] > z)
    };
    // A grain of the neighbouring row jn, column c, level z that stops a flight sideways.
    let lateral = |jn: usize, c: usize, z: u8| -> bool {
        match r.lateral {
            Lateral::None => false,
            Lateral::Neighbours => lf[jn * nx + c] > z,
            Lateral::Clusters => clustered(jn, c, z),
        }
    };
    // The top grains that fly this half step (filled below, row by row).
    let flies = &mut sc.flies;
    flies.iter_mut().for_each(|f| *f = false);
    if !r.frozen {
        for j in 0..ny {
            let key = rng::row_key(seed, t, j);
            let neighbour_keys: [u64; 8] = std::array::from_fn(|d| rng::neighbour_key(key, d));
            for i in 0..nx {
                let hi = lf[j * nx + i];
                if hi == 0 || !bit(key, Stream::Activation, i, r.activation) {
                    continue;
                }
                let z = hi - 1;
                // Frustration: each occupied neighbouring cell at the grain's level holds it
                // with the drawn probability.
                let held = r.hold > 0
                    && NEIGHBOURS.iter().zip(&neighbour_keys).any(|(&(dj, di), &nkey)| {
                        offset_row(j, dj, ny, r.periodic_y).is_some_and(|jn| {
                            lf[jn * nx + (i + nx).wrapping_add_signed(di) % nx] > z && bit(nkey, Stream::Frustration, i, r.hold)
                        })
                    });
                flies[j * nx + i] = !held;
            }
        }
    }
    let flies = &sc.flies;
    // With trains, a top grain of the own row at level z that flies too is no obstacle.
    let flyer = |j: usize, c: usize, z: u8| r.trains && lf[j * nx + c] == z + 1 && flies[j * nx + c];
    let obstacle = |j: usize, c: usize, z: u8| -> bool {
        if lf[j * nx + c] > z && !flyer(j, c, z) {
            return true;
        }
        let side = [false, true]
            .iter()
            .any(|&up| neighbour_row(j, up, ny, r.periodic_y).is_some_and(|jn| lateral(jn, c, z)));
        // With knock-through a lateral contact holds with probability 1 - p_knock; at the
        // floor level the draw is the cell's [`Stream::Activation`] number (the cell has no
        // grain of its own here, so its activation is never drawn), above it the cell's
        // [`Stream::Hold`] number.
        let stream = if z == 0 { Stream::Activation } else { Stream::Hold };
        side && (r.knock == 0 || bit(rng::row_key(seed, t, j), stream, c, rng::ONE - r.knock))
    };
    sc.impacts.clear();
    if !r.frozen {
        if let Some(m) = &r.measured {
            let swing = if r.swing { m.swing.as_ref() } else { None };
            measured_rule::flights(
                nx,
                ny,
                lf,
                &mut sc.new,
                m,
                seed,
                t,
                left,
                r.periodic_y,
                r.x_walls,
                swing,
                &mut sc.measured,
            );
        } else if let Some(g) = &r.graded {
            graded_flights(nx, ny, lf, flies, &mut sc.new, g, cap, r.trains, &mut sc.graded);
        } else {
            for j in 0..ny {
                let key = rng::row_key(seed, t, j);
                for i in 0..nx {
                    if !flies[j * nx + i] {
                        continue;
                    }
                    let z = lf[j * nx + i] - 1;
                    // k: the first obstacle ahead; m: the flying grains of a train before it,
                    // which land ahead of this one. Past `cap` free cells the flight is capped.
                    let (mut k, mut m) = (1, 0);
                    while k < nx && !obstacle(j, (i + k) % nx, z) {
                        m += flyer(j, (i + k) % nx, z) as usize;
                        if k - m > cap {
                            break;
                        }
                        k += 1;
                    }
                    let gap = k - 1;
                    let dist = if k == nx { gap.min(cap) } else { (gap - m).min(cap) };
                    if dist > 0 {
                        sc.new[j * nx + i] -= 1;
                        sc.new[j * nx + (i + dist) % nx] += 1;
                    }
                    let p = (i + k) % nx;
                    if m == 0 && gap < cap && gap >= 1 && r.knock > 0 && bit(key, Stream::Knock, p, r.knock) {
                        sc.impacts.push((j, p, z));
                    }
                }
            }
        }
        // The bit-parallel step visits impacts by row, then by hit cell.
        sc.impacts.sort_unstable();
        for &(j0, p, z) in &sc.impacts {
            // The row of the grain that stopped the flight: own row first, then below, above.
            let hit = if lf[j0 * nx + p] > z {
                Some(j0)
            } else {
                [false, true]
                    .into_iter()
                    .filter_map(|up| neighbour_row(j0, up, ny, r.periodic_y))
                    .find(|&jn| lateral(jn, p, z))
            };
            let Some(j) = hit else {
                continue;
            };
            if sc.new[j * nx + p] <= z {
                continue; // the hit grain has flown off itself
            }
            let mut f = p;
            for _ in 0..nx {
                let next = (f + 1) % nx;
                if sc.new[j * nx + next] <= z || next == p {
                    break;
                }
                f = next;
            }
            let mut land = f;
            for step in 1..=cap {
                let c = (f + step) % nx;
                if sc.new[j * nx + c] > z {
                    break;
                }
                land = c;
            }
            if land != f {
                sc.new[j * nx + f] -= 1;
                sc.new[j * nx + land] += 1;
            }
        }
        if r.sideways > 0 {
            for up in [true, false] {
                sc.snap.copy_from_slice(&sc.new);
                for j in 0..ny {
                    let Some(jn) = neighbour_row(j, up, ny, r.periodic_y).filter(|&jn| jn != j) else {
                        continue;
                    };
                    let key = rng::row_key(seed, t, j);
                    for i in 0..nx {
                        let (a, b) = (sc.snap[j * nx + i], sc.snap[jn * nx + i]);
                        if a > 0 && b < a && (rng::sideways(key, i / 64, r.sideways, up) >> (i % 64)) & 1 == 1 {
                            sc.new[j * nx + i] -= 1;
                            sc.new[jn * nx + i] += 1;
                        }
                    }
                }
            }
        }
    }
    let rested = rest(nx, ny, &mut sc.new);
    // Moves are traced for the measured rule's floor grains only; a pile that came down
    // moved grains the trace does not know.
    sc.measured.rested = rested;
    for j in 0..ny {
        for i in 0..nx {
            h[j * nx + i] = sc.new[j * nx + map(i)];
        }
    }
}

/// Graded flights ([`crate::params::Transport::Graded`]), in the flight frame `lf` into
/// `new`: the grains of each column (all rows and levels) give the packing of its strip and
/// the jump of a grain there ([`Graded::jumps`]); in each row every lone grain at the floor
/// drawn to fly goes its jump, queueing behind the grain ahead of it with `trains`, or
/// stopping before the start of the grain ahead without ([`landings`]). Piles rest. No
/// impacts are recorded (no knock-through).
#[allow(clippy::too_many_arguments)]
fn graded_flights(
    nx: usize,
    ny: usize,
    lf: &[u8],
    flies: &[bool],
    new: &mut [u8],
    g: &Graded,
    cap: usize,
    trains: bool,
    gs: &mut GradedScratch,
) {
    for (i, c) in gs.counts.iter_mut().enumerate() {
        *c = (0..ny).map(|j| lf[j * nx + i] as u32).sum();
    }
    g.jumps(cap, &gs.counts, &mut gs.jumps);
    for j in 0..ny {
        gs.cells.clear();
        gs.row_jumps.clear();
        for i in 0..nx {
            let h = lf[j * nx + i];
            if h == 0 {
                continue;
            }
            gs.cells.push(i);
            gs.row_jumps.push(if h == 1 && flies[j * nx + i] { gs.jumps[i] } else { 0 });
        }
        landings(nx, &gs.cells, &gs.row_jumps, trains, false, &mut gs.land);
        for (&c, &l) in gs.cells.iter().zip(&gs.land) {
            if l != c {
                new[j * nx + c] -= 1;
                new[j * nx + l % nx] += 1;
            }
        }
    }
}

/// The resting rule (thesis 3.1 rule 2 for piles): until every x-slope is at most 1, a top
/// grain with a neighbour two or more grains lower moves onto the lower neighbour (towards
/// +i on a tie). Returns the number of grains moved.
pub(crate) fn rest(nx: usize, ny: usize, h: &mut [u8]) -> u64 {
    let mut moved = 0;
    if nx < 2 {
        return 0;
    }
    loop {
        let mut changed = false;
        for j in 0..ny {
            let row = &mut h[j * nx..(j + 1) * nx];
            for i in 0..nx {
                let (l, c, rr) = ((i + nx - 1) % nx, i, (i + 1) % nx);
                let hc = row[c];
                let (hl, hr) = (row[l], row[rr]);
                if hc >= hr.saturating_add(2) && hr <= hl {
                    row[c] -= 1;
                    row[rr] += 1;
                } else if hc >= hl.saturating_add(2) {
                    row[c] -= 1;
                    row[l] += 1;
                } else {
                    continue;
                }
                changed = true;
                moved += 1;
            }
        }
        if !changed {
            return moved;
        }
    }
}
