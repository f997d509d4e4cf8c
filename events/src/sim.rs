//! The event loop: the only place that knows the order in which events are predicted,
//! checked and carried out.
//!
//! Each particle has one predicted event (the earliest of: a collision with a neighbour, a
//! wall contact, leaving its cell, or a look again where the bounded search of a moving wall
//! ended) and a lazy clock: its
//! position and velocity are stored at the time of its last event and flown forward only
//! when needed. A pair event remembers the partner's collision count, and is dropped when the
//! partner has collided since. After a particle's motion changes, only its own event is
//! predicted again; a neighbour that would now meet it earlier is found because the pair is
//! predicted from this particle's side.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::cells::Grid;
use crate::collision::{collide, Body};
use crate::config::{Config, SideWalls};
use crate::error::EventsError;
use crate::flight::{fly, pair_time};
use crate::queue::Queue;
use crate::sawtooth::Sawtooth;
use crate::thinned::Thinned;
use crate::wall::{Motion, Search, Wall, WallKind, Waveform};
use crate::Vec2;

/// A copy of a neighbourhood (at most nine cells), so that the grid is not borrowed while
/// the prediction writes.
fn copy9(cells: &[u32]) -> ([u32; 9], usize) {
    let mut out = [0u32; 9];
    out[..cells.len()].copy_from_slice(cells);
    (out, cells.len())
}

/// What a particle's next event is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Next {
    Pair {
        j: usize,
        count: u64,
    },
    Wall {
        w: usize,
    },
    /// A piece (0 left side, 1 tip, 2 right side) of a tooth of the sawtooth base.
    Tooth {
        tooth: i64,
        piece: u8,
    },
    Cell {
        to: (usize, usize),
        wrap: f64,
    },
    Look,
    Nothing,
}

/// The complete state of a simulation as plain data (see [`Simulation::export_state`]). The
/// engine knows no byte layout: whoever stores it chooses one.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub time: f64,
    /// Per particle, at its own clock `t`: position, velocity, spin.
    pub r: Vec<Vec2>,
    pub v: Vec<Vec2>,
    pub w: Vec<f64>,
    pub t: Vec<f64>,
    pub radius: Vec<f64>,
    pub species: Vec<usize>,
    pub cell: Vec<(usize, usize)>,
    pub collisions: Vec<u64>,
    pub last_collision: Vec<f64>,
    pub next: Vec<Next>,
    pub beyond_cell: Vec<(f64, Next)>,
    pub window: Vec<(f64, u32)>,
    pub last_partner: Vec<usize>,
    /// The particles of each cell, in their order.
    pub members: Vec<Vec<usize>>,
    /// Each particle's scheduled event time, if any.
    pub scheduled: Vec<Option<f64>>,
    pub counts: Counts,
    pub ledger: Ledger,
    pub free_times: [Thinned; 2],
}

/// Which rules a surface collision uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Surface {
    Floor,
    Lid,
    Side,
}

/// Counters of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counts {
    pub pair: u64,
    pub wall: u64,
    pub cell: u64,
    /// Events dropped because a partner had moved on (not counted as work done).
    pub stale: u64,
}

/// The energy ledger (J): work done by the walls, energy dissipated in collisions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ledger {
    pub wall_work: f64,
    pub dissipated: f64,
}

/// A running event-driven simulation.
pub struct Simulation {
    pub config: Config,
    /// Time of the simulation (s): every event up to it has been carried out.
    pub time: f64,
    // Per particle, at its own clock `t`:
    r: Vec<Vec2>,
    v: Vec<Vec2>,
    pub w: Vec<f64>,
    t: Vec<f64>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    pub species: Vec<usize>,
    cell: Vec<(usize, usize)>,
    collisions: Vec<u64>,
    last_collision: Vec<f64>,
    next: Vec<Next>,
    /// The earliest pair or look event found by the last prediction, kept for when the
    /// scheduled event is a cell crossing before it.
    beyond_cell: Vec<(f64, Next)>,
    // Collapse watch: start of the window and collisions in it, per particle.
    window: Vec<(f64, u32)>,
    last_partner: Vec<usize>,
    grid: Grid,
    members: Vec<Vec<usize>>,
    walls: Vec<Wall>,
    queue: Queue,
    pub counts: Counts,
    pub ledger: Ledger,
    /// Free times between successive pair collisions of a particle (s), per species, an
    /// even subsample of at most `Thinned::CAP` of them.
    pub free_times: [Thinned; 2],
    horizon: f64,
}

impl Simulation {
    /// Places the particles (a random choice of sites of a square lattice of spacing
    /// `2.02 R_max`, species shuffled), gives them random velocities, and predicts every
    /// particle's first event.
    pub fn new(config: Config) -> Result<Self, EventsError> {
        config.validate()?;
        let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
        let mut walls = Vec::new();
        let rmax = config.radius_max();
        let floor_top = config.floor.map_or(0.0, |m| m.amplitude) + config.base.map_or(0.0, |b| b.height);
        let lid_low = config.height - config.lid.map_or(0.0, |m| m.amplitude);
        // A sawtooth floor or lid stands at its mean line and pushes at the sine's peak speed.
        let drive = |m: Motion| match config.waveform {
            Waveform::Sine => (m, 0.0),
            Waveform::Sawtooth => (Motion::FIXED, m.amplitude * 2.0 * std::f64::consts::PI * m.frequency),
        };
        if let (Some(m), None) = (config.floor, config.base) {
            let (motion, push) = drive(m);
            walls.push(Wall {
                kind: WallKind::Floor,
                position: 0.0,
                motion,
                push,
            });
        }
        if let Some(m) = config.lid {
            let (motion, push) = drive(m);
            walls.push(Wall {
                kind: WallKind::Lid,
                position: config.height,
                motion,
                push,
            });
        }
        if config.side_walls != SideWalls::Periodic {
            let motion = match (config.side_walls, config.floor) {
                (SideWalls::WithFloor, Some(m)) => m,
                _ => Motion::FIXED,
            };
            walls.push(Wall {
                kind: WallKind::Left,
                position: 0.0,
                motion,
                push: 0.0,
            });
            walls.push(Wall {
                kind: WallKind::Right,
                position: config.width,
                motion,
                push: 0.0,
            });
        }
        // Sites in the box between the walls' extreme positions.
        let spacing = 2.02 * rmax;
        let (x_lo, x_hi) = (rmax * 1.01, config.width - rmax * 1.01);
        let (z_lo, z_hi) = (floor_top + rmax * 1.01, lid_low - rmax * 1.01);
        let nx = ((x_hi - x_lo) / spacing).floor() as usize + 1;
        let nz = if z_hi >= z_lo {
            ((z_hi - z_lo) / spacing).floor() as usize + 1
        } else {
            0
        };
        let total: usize = config.species.iter().map(|s| s.count).sum();
        if nx * nz < total || x_hi < x_lo {
            return Err(EventsError::DoNotFit {
                placed: nx * nz,
                wanted: total,
                message: format!(
                    "a lattice of spacing {spacing:e} m holds {nx} x {nz} sites between the walls' extreme positions; enlarge width or height, or use fewer or smaller particles"
                ),
            });
        }
        // Under gravity the lowest sites, in random order within the rows used; without
        // gravity any sites, so that the gas starts spread over the box.
        let rows = if config.gravity > 0.0 { total.div_ceil(nx).min(nz) } else { nz };
        let mut sites: Vec<usize> = (0..nx * rows).collect();
        for k in (1..sites.len()).rev() {
            sites.swap(k, rng.gen_range(0..=k));
        }
        let mut species: Vec<usize> = config
            .species
            .iter()
            .enumerate()
            .flat_map(|(k, s)| std::iter::repeat_n(k, s.count))
            .collect();
        for k in (1..species.len()).rev() {
            species.swap(k, rng.gen_range(0..=k));
        }
        let (mut r, mut v, mut radius, mut mass) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (i, &k) in species.iter().enumerate() {
            let s = &config.species[k];
            let site = sites[i];
            r.push(Vec2::new(x_lo + (site % nx) as f64 * spacing, z_lo + (site / nx) as f64 * spacing));
            let u = config.initial_speed;
            let mut draw = || if u > 0.0 { rng.gen_range(-u..=u) } else { 0.0 };
            v.push(Vec2::new(draw(), draw()));
            let r = if s.radius_max > s.radius_min {
                rng.gen_range(s.radius_min..=s.radius_max)
            } else {
                s.radius_min
            };
            radius.push(r);
            mass.push(s.mass.of(r));
        }
        let n = r.len();
        let z_grid_lo = -config.floor.map_or(0.0, |m| m.amplitude);
        let z_grid_hi = config.height + config.lid.map_or(0.0, |m| m.amplitude);
        let grid = Grid::new(
            config.width,
            z_grid_lo,
            z_grid_hi,
            2.0 * rmax * 1.0001,
            config.side_walls == SideWalls::Periodic,
        );
        let cell: Vec<(usize, usize)> = r.iter().map(|p| grid.cell(*p)).collect();
        let mut members = vec![Vec::new(); grid.nx * grid.nz];
        for (i, c) in cell.iter().enumerate() {
            members[grid.index(*c)].push(i);
        }
        let fastest = walls.iter().map(|w| w.motion.frequency).fold(0.0, f64::max);
        let horizon = if fastest > 0.0 { 0.25 / fastest } else { f64::INFINITY };
        let mut sim = Simulation {
            time: 0.0,
            w: vec![0.0; n],
            t: vec![0.0; n],
            collisions: vec![0; n],
            last_collision: vec![f64::NEG_INFINITY; n],
            next: vec![Next::Nothing; n],
            beyond_cell: vec![(f64::INFINITY, Next::Nothing); n],
            window: vec![(0.0, 0); n],
            last_partner: vec![usize::MAX; n],
            queue: Queue::new(n),
            counts: Counts::default(),
            ledger: Ledger::default(),
            free_times: [Thinned::new(), Thinned::new()],
            r,
            v,
            radius,
            mass,
            species,
            cell,
            grid,
            members,
            walls,
            horizon,
            config,
        };
        for i in 0..n {
            sim.predict(i);
        }
        Ok(sim)
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// The walls (floor, lid, left, right, as present).
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// Position and velocity of particle `i` at the simulation time.
    pub fn state(&self, i: usize) -> (Vec2, Vec2) {
        fly(self.r[i], self.v[i], self.config.gravity, self.time - self.t[i])
    }

    /// Moves particle `i`'s clock to `t` (its trajectory does not change).
    fn advance(&mut self, i: usize, t: f64) {
        let (r, v) = fly(self.r[i], self.v[i], self.config.gravity, t - self.t[i]);
        self.r[i] = r;
        self.v[i] = v;
        self.t[i] = t;
    }

    /// Brings every particle's clock to the simulation time, then replaces their state.
    /// For tests and set-ups: every event is predicted again.
    pub fn set_state(&mut self, r: &[Vec2], v: &[Vec2], w: &[f64]) -> Result<(), EventsError> {
        if r.len() != self.len() || v.len() != self.len() || w.len() != self.len() {
            return Err(crate::error::invalid("state", "one position, velocity and spin per particle"));
        }
        for m in self.members.iter_mut() {
            m.clear();
        }
        for i in 0..self.len() {
            self.r[i] = r[i];
            self.v[i] = v[i];
            self.w[i] = w[i];
            self.t[i] = self.time;
            self.cell[i] = self.grid.cell(r[i]);
            let c = self.grid.index(self.cell[i]);
            self.members[c].push(i);
        }
        for i in 0..self.len() {
            self.predict(i);
        }
        Ok(())
    }

    /// The periodic separation `r_i - r_j` at the common time (both clocks there).
    fn separation(&self, i: usize, j: usize) -> Vec2 {
        let mut d = self.r[i] - self.r[j];
        if self.grid.periodic {
            let w = self.config.width;
            d.x -= w * (d.x / w).round();
        }
        d
    }

    /// Predicts particle `i`'s next event from its clock time and schedules it, looking at
    /// every neighbour and every wall.
    fn predict(&mut self, i: usize) {
        let cells = self.grid.near(self.grid.index(self.cell[i]));
        let (cells, n) = copy9(cells);
        self.predict_from(i, &cells[..n], (f64::INFINITY, Next::Nothing));
    }

    /// Predicts particle `i`'s next event after it entered a new cell from `from`. Its
    /// motion has not changed, so the earliest pair event found before the crossing still
    /// holds if its partner has not collided since; only the cells that have just come into
    /// reach are searched, and the walls again. If the remembered event went stale, every
    /// neighbour is searched.
    fn predict_after_crossing(&mut self, i: usize, from: (usize, usize)) {
        let remembered = self.beyond_cell[i];
        let valid = match remembered.1 {
            Next::Pair { j, count } => self.collisions[j] == count,
            Next::Look | Next::Nothing => true,
            Next::Wall { .. } | Next::Tooth { .. } | Next::Cell { .. } => false,
        };
        if !valid {
            self.predict(i);
            return;
        }
        let old = self.grid.near(self.grid.index(from));
        let new = self.grid.near(self.grid.index(self.cell[i]));
        let (mut fresh, mut n) = ([0u32; 9], 0);
        for &c in new {
            if !old.contains(&c) {
                fresh[n] = c;
                n += 1;
            }
        }
        self.predict_from(i, &fresh[..n], remembered);
    }

    /// The earliest event of particle `i` among its pairs with the particles of `cells`, the
    /// walls and its cell crossing, starting from the candidate `best`; scheduled.
    ///
    /// The search of a moving floor or lid is bounded: it covers at most `horizon` seconds
    /// after the particle first comes within the wall's reach. When that bound, and not an
    /// earlier event, ends a search, the particle looks again there (a `Look` event); a
    /// particle that cannot reach the wall before its next event needs no look.
    fn predict_from(&mut self, i: usize, cells: &[u32], mut best: (f64, Next)) {
        let t0 = self.t[i];
        let g = self.config.gravity;
        for &c in cells {
            let c = c as usize;
            for k in 0..self.members[c].len() {
                let j = self.members[c][k];
                if j == i {
                    continue;
                }
                let (rj, vj) = fly(self.r[j], self.v[j], g, t0 - self.t[j]);
                let mut d = self.r[i] - rj;
                if self.grid.periodic {
                    // Both particles are inside [0, width], give or take a flight in a cell.
                    let w = self.config.width;
                    if d.x > 0.5 * w {
                        d.x -= w;
                    } else if d.x < -0.5 * w {
                        d.x += w;
                    }
                }
                if let Some(s) = pair_time(d, self.v[i] - vj, self.radius[i] + self.radius[j]) {
                    if t0 + s < best.0 {
                        best = (
                            t0 + s,
                            Next::Pair {
                                j,
                                count: self.collisions[j],
                            },
                        );
                    }
                }
            }
        }
        // Kept for the crossing, if the particle leaves its cell first.
        self.beyond_cell[i] = best;
        let (r, v, radius) = (self.r[i], self.v[i], self.radius[i]);
        if let Some(c) = self.grid.crossing(self.cell[i], r, v, g, t0) {
            if c.time < best.0 {
                best = (c.time, Next::Cell { to: c.to, wrap: c.wrap });
            }
        }
        // The earliest time up to which a bounded search found nothing, if before `best`.
        let mut look = f64::INFINITY;
        for (w, wall) in self.walls.iter().enumerate() {
            let limit = best.0 - t0;
            let (span, bounded) = if wall.moves_along_normal() {
                let entry = wall.reach(r, v, radius, g);
                if entry >= limit {
                    continue;
                }
                let end = entry + self.horizon;
                if end < limit {
                    (end, true)
                } else {
                    (limit, false)
                }
            } else {
                (limit, false)
            };
            match wall.search(r, v, radius, g, t0, span) {
                Search::At(t) => {
                    if t < best.0 || (t == best.0 && !matches!(best.1, Next::Pair { .. })) {
                        best = (t, Next::Wall { w });
                    }
                }
                Search::Clear if bounded => look = look.min(t0 + span),
                Search::Clear => {}
                Search::GaveUp(t) => look = look.min(t),
            }
        }
        if let (Some(base), Some(motion)) = (self.config.base, self.config.floor) {
            let limit = best.0 - t0;
            let bounded = self.horizon < limit;
            let span = if bounded {
                self.horizon
            } else if limit.is_finite() {
                limit
            } else {
                f64::MAX
            };
            if !base.clear_of(&motion, r, v, radius, g, span) {
                // The particle stays in its column of cells until its next crossing.
                let cx = self.cell[i].0 as f64 * self.grid.dx;
                let (x_lo, x_hi) = (cx.min(r.x), (cx + self.grid.dx).max(r.x));
                let x_hi = if self.grid.nx == 1 { x_lo.max(self.config.width) } else { x_hi };
                for tooth in base.teeth(x_lo, x_hi, radius) {
                    for piece in 0..3u8 {
                        let shape = base.piece(tooth, piece as usize);
                        let horizon = (best.0 - t0).min(span);
                        if let Some(t) = Sawtooth::contact_time(&shape, &motion, r, v, radius, g, t0, horizon) {
                            if t < best.0 || (t == best.0 && !matches!(best.1, Next::Pair { .. })) {
                                best = (t, Next::Tooth { tooth, piece });
                            }
                        }
                    }
                }
            }
            if bounded {
                // The base was searched only up to the horizon.
                look = look.min(t0 + span);
            }
        }
        if look < best.0 {
            best = (look, Next::Look);
        }
        self.next[i] = best.1;
        if best.1 == Next::Nothing {
            self.queue.cancel(i);
        } else {
            self.queue.schedule(i, best.0);
        }
    }

    /// Carries out every event up to `t_end` and moves the simulation time there.
    pub fn run_until(&mut self, t_end: f64) -> Result<(), EventsError> {
        while let Some((t, i)) = self.queue.peek() {
            if t > t_end {
                break;
            }
            // The particle's entry stays at the top: the event reschedules it in place.
            self.time = t;
            self.event(i, t)?;
        }
        self.time = t_end;
        Ok(())
    }

    fn event(&mut self, i: usize, t: f64) -> Result<(), EventsError> {
        match self.next[i] {
            Next::Pair { j, count } => {
                if self.collisions[j] != count {
                    self.counts.stale += 1;
                    self.advance(i, t);
                    self.predict(i);
                    return Ok(());
                }
                self.advance(i, t);
                self.advance(j, t);
                self.pair_collision(i, j, t)?;
                self.predict(i);
                self.predict(j);
            }
            Next::Wall { w } => {
                self.advance(i, t);
                let wall = self.walls[w];
                let kind = match wall.kind {
                    WallKind::Floor => Surface::Floor,
                    WallKind::Lid => Surface::Lid,
                    WallKind::Left | WallKind::Right => Surface::Side,
                };
                self.surface_collision(i, wall.normal(), wall.strike_velocity(t), kind, t)?;
                self.predict(i);
            }
            Next::Tooth { tooth, piece } => {
                self.advance(i, t);
                let (base, motion) = match (self.config.base, self.config.floor) {
                    (Some(b), Some(m)) => (b, m),
                    _ => unreachable!("a tooth event needs a sawtooth base"),
                };
                let shape = base.piece(tooth, piece as usize);
                let (_, _, n) = Sawtooth::gap(&shape, &motion, self.r[i], self.v[i], self.radius[i], t);
                self.surface_collision(i, n, Vec2::new(0.0, motion.velocity(t)), Surface::Floor, t)?;
                self.predict(i);
            }
            Next::Cell { to, wrap } => {
                self.advance(i, t);
                self.r[i].x += wrap;
                let from = self.grid.index(self.cell[i]);
                if let Some(k) = self.members[from].iter().position(|&x| x == i) {
                    self.members[from].swap_remove(k);
                }
                let old = self.cell[i];
                self.cell[i] = to;
                self.members[self.grid.index(to)].push(i);
                self.counts.cell += 1;
                self.predict_after_crossing(i, old);
            }
            Next::Look => {
                self.advance(i, t);
                self.predict(i);
            }
            Next::Nothing => self.queue.cancel(i),
        }
        Ok(())
    }

    /// The coefficients forced by a guard, if any, for a collision of `i` (and `j`) at `t`.
    fn guarded(&self, i: usize, j: Option<usize>, t: f64) -> Option<(f64, f64)> {
        let tc = self.config.guard.tc?;
        let recent = |k: usize| t - self.last_collision[k] < tc;
        (recent(i) || j.is_some_and(recent)).then_some((1.0, -1.0))
    }

    /// Raises `e` so that the normal speed after is at least the guard's minimum, above 1
    /// for an approach slower than the minimum: the guard's documented energy input.
    fn min_rebound(&self, gn: f64, e: f64, beta: f64) -> Option<(f64, f64)> {
        let v = self.config.guard.min_rebound_speed?;
        (e * gn.abs() < v && gn != 0.0).then(|| (v / gn.abs(), beta))
    }

    /// Counts a collision of particle `i` (with `partner`, `usize::MAX` for a wall) at `t`
    /// with normal approach speed `gn` towards a collapse: only slow collisions count.
    fn watch(&mut self, i: usize, partner: usize, t: f64, gn: f64) -> Result<(), EventsError> {
        self.last_partner[i] = partner;
        let g = self.config.guard;
        let slow = self.config.collapse_speed();
        if gn.abs() >= slow {
            return Ok(());
        }
        let (start, count) = self.window[i];
        if t - start > g.collapse_window {
            self.window[i] = (t, 1);
        } else {
            self.window[i] = (start, count + 1);
            if count + 1 > g.collapse_events {
                let mut particles = vec![i];
                if partner != usize::MAX {
                    particles.push(partner);
                }
                return Err(EventsError::Collapse {
                    particles,
                    time: t,
                    events: self.counts.pair + self.counts.wall,
                    message: format!(
                        "particle {i} collided {} times within {:e} s, each at an approach speed below {slow:e} m/s (the last {:e} m/s); choose a collapse guard (guard.min_rebound_speed or guard.tc) or a velocity-dependent restitution",
                        count + 1,
                        g.collapse_window,
                        gn.abs()
                    ),
                });
            }
        }
        Ok(())
    }

    fn body(&self, i: usize) -> Body {
        Body {
            v: self.v[i],
            w: self.w[i],
            r: self.radius[i],
            m: self.mass[i],
            q: self.config.q,
        }
    }

    fn pair_collision(&mut self, i: usize, j: usize, t: f64) -> Result<(), EventsError> {
        let d = self.separation(i, j);
        let sigma = self.radius[i] + self.radius[j];
        if d.norm() < sigma * (1.0 - 1e-6) {
            return Err(EventsError::Overlap {
                particle: i,
                partner: format!("particle {j}"),
                time: t,
                depth: sigma - d.norm(),
            });
        }
        let n = d / d.norm();
        let rule = self.config.rules.pair(self.species[i], self.species[j]);
        let (b1, b2) = (self.body(i), self.body(j));
        let mut o = collide(b1, b2, n, rule, self.guarded(i, Some(j), t));
        if let Some(c) = self.min_rebound(o.gn, o.e, o.beta) {
            o = collide(b1, b2, n, rule, Some(c));
        }
        (self.v[i], self.w[i], self.v[j], self.w[j]) = (o.v1, o.w1, o.v2, o.w2);
        self.ledger.dissipated += o.dissipated;
        for (k, partner) in [(i, j), (j, i)] {
            let last = self.last_collision[k];
            if last.is_finite() {
                self.free_times[self.species[k]].push(t - last);
            }
            self.last_collision[k] = t;
            self.collisions[k] += 1;
            self.watch(k, partner, t, o.gn)?;
        }
        self.counts.pair += 1;
        Ok(())
    }

    /// A collision of particle `i` with a surface of infinite mass moving with `velocity`,
    /// `n` the unit normal from the surface towards the particle.
    fn surface_collision(&mut self, i: usize, n: Vec2, velocity: Vec2, kind: Surface, t: f64) -> Result<(), EventsError> {
        let rules = match kind {
            Surface::Floor => &self.config.rules.floor,
            Surface::Lid => &self.config.rules.lid,
            Surface::Side => &self.config.rules.side,
        };
        let rule = &rules[self.species[i]];
        let b1 = self.body(i);
        let b2 = Body {
            v: velocity,
            w: 0.0,
            r: 0.0,
            m: f64::INFINITY,
            q: self.config.q,
        };
        let mut o = collide(b1, b2, n, rule, self.guarded(i, None, t));
        if let Some(c) = self.min_rebound(o.gn, o.e, o.beta) {
            o = collide(b1, b2, n, rule, Some(c));
        }
        let kinetic = |v: Vec2, w: f64| 0.5 * b1.m * v.norm_squared() + 0.5 * b1.q * b1.m * b1.r * b1.r * w * w;
        let gained = kinetic(o.v1, o.w1) - kinetic(b1.v, b1.w);
        (self.v[i], self.w[i]) = (o.v1, o.w1);
        // Work of the wall = the particle's gain + what the collision dissipated.
        self.ledger.wall_work += gained + o.dissipated;
        self.ledger.dissipated += o.dissipated;
        self.collisions[i] += 1;
        self.last_collision[i] = t;
        self.counts.wall += 1;
        self.watch(i, usize::MAX, t, o.gn)
    }

    /// Total energy at the simulation time (J): translation, rotation and height `z` in
    /// gravity.
    pub fn energy(&self) -> f64 {
        (0..self.len())
            .map(|i| {
                let (r, v) = self.state(i);
                let m = self.mass[i];
                0.5 * m * v.norm_squared()
                    + 0.5 * self.config.q * m * self.radius[i].powi(2) * self.w[i].powi(2)
                    + m * self.config.gravity * r.y
            })
            .sum()
    }

    /// The complete state, lazy clocks and predicted events included, as plain data: what a
    /// run restored from it needs to continue bit for bit.
    pub fn export_state(&self) -> State {
        State {
            time: self.time,
            r: self.r.clone(),
            v: self.v.clone(),
            w: self.w.clone(),
            t: self.t.clone(),
            radius: self.radius.clone(),
            species: self.species.clone(),
            cell: self.cell.clone(),
            collisions: self.collisions.clone(),
            last_collision: self.last_collision.clone(),
            next: self.next.clone(),
            beyond_cell: self.beyond_cell.clone(),
            window: self.window.clone(),
            last_partner: self.last_partner.clone(),
            members: self.members.clone(),
            scheduled: (0..self.len()).map(|i| self.queue.time_of(i)).collect(),
            counts: self.counts,
            ledger: self.ledger,
            free_times: self.free_times.clone(),
        }
    }

    /// A simulation of `config` continued from `state` (from [`Simulation::export_state`]
    /// of a run of the same configuration). The state is checked against the configuration:
    /// an error names what does not match.
    pub fn import_state(config: Config, state: State) -> Result<Self, EventsError> {
        let mut sim = Simulation::new(config)?;
        let n = sim.len();
        let mismatch = |what: &str| crate::error::invalid("state", format!("{what} does not match the configuration"));
        let lengths = [
            state.r.len(),
            state.v.len(),
            state.w.len(),
            state.t.len(),
            state.radius.len(),
            state.species.len(),
            state.cell.len(),
            state.collisions.len(),
            state.last_collision.len(),
            state.next.len(),
            state.beyond_cell.len(),
            state.window.len(),
            state.last_partner.len(),
            state.scheduled.len(),
        ];
        if lengths.iter().any(|&l| l != n) {
            return Err(mismatch("the particle count"));
        }
        if state.radius != sim.radius || state.species != sim.species {
            return Err(mismatch("the radii or species"));
        }
        if state.members.len() != sim.members.len()
            || state.members.iter().map(Vec::len).sum::<usize>() != n
            || state.members.iter().flatten().any(|&i| i >= n)
            || state.cell.iter().any(|&(x, z)| x >= sim.grid.nx || z >= sim.grid.nz)
        {
            return Err(mismatch("the cell grid"));
        }
        sim.time = state.time;
        sim.r = state.r;
        sim.v = state.v;
        sim.w = state.w;
        sim.t = state.t;
        sim.cell = state.cell;
        sim.collisions = state.collisions;
        sim.last_collision = state.last_collision;
        sim.next = state.next;
        sim.beyond_cell = state.beyond_cell;
        sim.window = state.window;
        sim.last_partner = state.last_partner;
        sim.members = state.members;
        sim.counts = state.counts;
        sim.ledger = state.ledger;
        sim.free_times = state.free_times;
        sim.queue = Queue::new(n);
        for (i, t) in state.scheduled.iter().enumerate() {
            if let Some(t) = t {
                sim.queue.schedule(i, *t);
            }
        }
        Ok(sim)
    }

    /// Collisions (pair + wall) so far.
    pub fn collisions(&self) -> u64 {
        self.counts.pair + self.counts.wall
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::{Restitution, Rule};
    use crate::config::{Guard, Rules, Species};
    use crate::flight::pair_time;

    /// A small vibrated box like the vibrated-box scene's: 12 rough spheres, the floor moving
    /// 0.64 mm at 100 Hz (the lid too if `lid`), fixed or periodic sides.
    fn small_box(side_walls: SideWalls, lid: bool) -> Config {
        let drive = Motion {
            amplitude: 6.366e-4,
            frequency: 100.0,
            phase: 0.0,
        };
        Config {
            width: 5e-3,
            height: if lid { 0.012 } else { 0.03 },
            side_walls,
            gravity: 10.0,
            q: 0.4,
            species: vec![Species {
                count: 12,
                radius_min: 0.45e-3,
                radius_max: 0.55e-3,
                mass: crate::Mass::Density(2500.0),
            }],
            floor: Some(drive),
            base: None,
            lid: lid.then_some(Motion { phase: 1.0, ..drive }),
            waveform: Waveform::Sine,
            rules: Rules::uniform(
                Rule::Walton {
                    e: Restitution::Constant(0.9),
                    mu: 0.5,
                    beta0: 0.5,
                },
                Rule::smooth(0.95),
                1,
            ),
            guard: Guard {
                tc: Some(1e-5),
                ..Guard::default()
            },
            initial_speed: 0.1,
            seed: 3,
        }
    }

    /// The earliest collision (pair or wall) after the simulation time, found the simple way:
    /// every pair and every wall from the state at that time, no cells, no remembered
    /// events, the walls searched `horizon` seconds ahead.
    fn earliest_by_brute_force(sim: &Simulation, horizon: f64) -> f64 {
        let (t, g) = (sim.time, sim.config.gravity);
        let states: Vec<(Vec2, Vec2)> = (0..sim.len()).map(|i| sim.state(i)).collect();
        let mut best = f64::INFINITY;
        for i in 0..sim.len() {
            let (ri, vi) = states[i];
            for (j, &(rj, vj)) in states.iter().enumerate().skip(i + 1) {
                let mut d = ri - rj;
                if sim.grid.periodic {
                    d.x -= sim.config.width * (d.x / sim.config.width).round();
                }
                if let Some(s) = pair_time(d, vi - vj, sim.radius[i] + sim.radius[j]) {
                    best = best.min(t + s);
                }
            }
            for wall in &sim.walls {
                if let Some(s) = wall.contact_time(ri, vi, sim.radius[i], g, t, horizon) {
                    best = best.min(s);
                }
            }
        }
        best
    }

    /// The engine's cells, remembered events and bounded wall searches never miss a
    /// collision and never invent one: before each event, the queue's next event comes no
    /// later than the brute-force earliest collision, and when it is a collision it is that
    /// one (to 1e-9 s).
    fn agrees_with_brute_force(config: Config, events: usize) {
        let horizon = 0.02;
        let mut sim = Simulation::new(config).unwrap();
        let (mut physical, mut bookkeeping) = (0, 0);
        for _ in 0..events {
            let (t, i) = sim.queue.peek().unwrap();
            let earliest = earliest_by_brute_force(&sim, horizon);
            assert!(
                t <= earliest + 1e-9,
                "the engine's next event at {t} comes after a collision at {earliest}"
            );
            let collision = match sim.next[i] {
                Next::Pair { j, count } => sim.collisions[j] == count,
                Next::Wall { .. } => true,
                _ => false,
            };
            if collision {
                physical += 1;
                if t < sim.time + horizon {
                    assert!((t - earliest).abs() <= 1e-9, "a collision at {t}, the earliest at {earliest}");
                }
            } else {
                bookkeeping += 1;
            }
            sim.time = t;
            sim.event(i, t).unwrap();
        }
        assert!(
            physical > events / 8 && bookkeeping > 0,
            "{physical} collisions, {bookkeeping} other events"
        );
    }

    #[test]
    fn the_vibrated_box_meets_every_collision_that_a_brute_force_search_finds() {
        agrees_with_brute_force(small_box(SideWalls::Fixed, false), 4000);
    }

    #[test]
    fn a_periodic_box_under_a_vibrated_lid_meets_every_collision_that_a_brute_force_search_finds() {
        agrees_with_brute_force(small_box(SideWalls::Periodic, true), 4000);
    }
}
