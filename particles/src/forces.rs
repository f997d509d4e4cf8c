//! Force gathering: the force and torque on every particle from gravity, its neighbour-list
//! pairs and the walls, evaluated per particle in fixed blocks (so that partial sums, and
//! therefore every result, are the same for any number of threads). [`crate::sim`] decides
//! when this runs; this module only knows how one evaluation is done.
//!
//! An evaluation has two passes over the blocks, the second after the first has ended on
//! every block ([`crate::sim`] puts a barrier between them):
//! 1. [`gather_block`]: gravity, each pair of the (half) neighbour list once, in the list of
//!    its smaller index `i`, whose force and torque it adds to `i` and whose reaction
//!    (`-F`, the torque on `j`) it leaves in the pair's slot of [`Reaction`]s; then the walls;
//! 2. [`add_reactions`]: each particle adds the reactions of the pairs in which it is the
//!    partner, in increasing order of the other index ([`NeighborList::incoming_of`]).
//!
//! So each grain sums gravity, its own pairs, its walls and its reactions in an order that
//! the list alone fixes, whichever thread evaluated which block.
//!
//! Hot-path choices, none of which changes a force law:
//! - walls whose normal is a coordinate axis (the tray's floor and side walls) get their
//!   geometry from `ContactGeometry::axis_wall` with an [`AxisNormal`], whose dot and cross
//!   products with the normal collapse; the kernels are the same generic
//!   [`contact::evaluate`] for every contact;
//! - a grain pinned to the floor (jumping off) takes its floor load `m g` as given
//!   ([`contact::evaluate_with_normal`]), precomputed per grain, on a geometry built
//!   directly (`ContactGeometry::resting_on_floor`: zero overlap, arm `R`): no normal law,
//!   gap test or overlap check there;
//! - a wall's gap is tested before anything else of a grain is read; two consecutive walls
//!   across the same axis (the tray's sides) share one pass that tests both gaps;
//! - the floor (an axis wall that is not a pinned floor) is evaluated four grains at a time
//!   on lanes (`floor_pass`), by the same kernels as every other contact
//!   ([`contact::evaluate_lanes`], of which [`contact::evaluate`] is the one-lane case), so
//!   it gives the same bits; runs that record contacts keep the one-contact path;
//! - gravity uses masses computed once (no division per step);
//! - per-contact history is only read, written and reset where the law has it (the
//!   Cundall-Strack tangential spring, the spring-dashpot-slider's rolling spring, each
//!   decided per copy of the law), and a side wall's springs only when its flag says they
//!   may be non-zero;
//! - the per-grain rolling coefficients are read only by a law with a rolling spring, and
//!   only where the scene spreads them (otherwise every contact takes the law's mean).

use crate::contact::geometry::Sphere;
use crate::contact::lane::F64x4;
use crate::contact::{self, AxisNormal, ContactGeometry, ContactLaw, History, Lane, LaneGeometry, Normal, V3};
use crate::neighbor::NeighborList;
use crate::setup::{ContactRecord, Partner, Setup, Vertical, MAX_OVERLAP_FRACTION};
use crate::Vec3;

/// How the geometry of a wall contact is computed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum PlaneKind {
    /// Normal `sign * e_axis`: `ContactGeometry::<AxisNormal<axis>>::axis_wall`.
    Axis { axis: usize, sign: f64 },
    /// Any other orientation: [`ContactGeometry::wall`].
    General,
}

/// A wall at the time of one force evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WallPlane {
    origin: Vec3,
    normal: Vec3,
    velocity: Vec3,
    kind: PlaneKind,
    /// The floor of a pinned layer: carries `m g` as a given normal load.
    support: bool,
}

impl WallPlane {
    /// Sign of the normal along its axis (1 for a general wall).
    fn sign(&self) -> f64 {
        match self.kind {
            PlaneKind::Axis { sign, .. } => sign,
            PlaneKind::General => 1.0,
        }
    }
}

/// The walls of `setup` at time `t`.
pub(crate) fn wall_planes(setup: &Setup, t: f64) -> Vec<WallPlane> {
    let pinned = setup.vertical == Vertical::Pinned;
    setup
        .walls
        .iter()
        .map(|w| {
            let n = w.normal;
            let axis = (0..3).find(|&k| n[k].abs() == 1.0 && n[(k + 1) % 3] == 0.0 && n[(k + 2) % 3] == 0.0);
            WallPlane {
                origin: w.origin_at(t),
                normal: n,
                velocity: w.motion.velocity(t),
                kind: axis.map_or(PlaneKind::General, |axis| PlaneKind::Axis { axis, sign: n[axis] }),
                support: pinned && n == Vec3::z(),
            }
        })
        .collect()
}

/// Read-only inputs of one force evaluation.
pub(crate) struct Inputs<'a> {
    pub setup: &'a Setup,
    pub planes: &'a [WallPlane],
    pub list: &'a NeighborList,
    pub pos: &'a [Vec3],
    pub vel: &'a [Vec3],
    pub omega: &'a [Vec3],
    pub radius: &'a [f64],
    /// Masses (kg), `1 / inv_mass` computed once.
    pub mass: &'a [f64],
    /// Each grain's tangential mobility at its contact points (1/kg), `1/m + R^2/I` (`1/m`
    /// when spins are not integrated), computed once: a pair's contact has the sum of its
    /// grains', a wall contact its grain's ([`ContactGeometry`]'s `mobility`).
    pub mobility: &'a [f64],
    /// Pinned layer: each grain's floor load `-g_z / inv_mass` (N), computed once (empty
    /// otherwise).
    pub load: &'a [f64],
    /// Each grain's rolling coefficient `mu_r` (spring-dashpot-slider), empty where every
    /// contact takes the law's.
    pub rolling_mu: &'a [f64],
    /// Keep per-contact diagnostics.
    pub record: bool,
}

impl Inputs<'_> {
    /// The rolling coefficient of the pair `(i, j)` under `law`: the mean of the grains'
    /// values, or the law's own.
    #[inline(always)]
    fn pair_mu_r(&self, law: &ContactLaw, i: usize, j: usize) -> f64 {
        if law.rolling.has_history() && !self.rolling_mu.is_empty() {
            0.5 * (self.rolling_mu[i] + self.rolling_mu[j])
        } else {
            law.rolling.mu_r()
        }
    }

    /// The rolling coefficient of grain `i` against a wall under `law`: the grain's value, or
    /// the law's own.
    #[inline(always)]
    fn wall_mu_r(&self, law: &ContactLaw, i: usize) -> f64 {
        if law.rolling.has_history() && !self.rolling_mu.is_empty() {
            self.rolling_mu[i]
        } else {
            law.rolling.mu_r()
        }
    }
}

/// The springs of a run of contacts (neighbour-list slots, or wall slots), aligned: the
/// tangential springs `slide`, and the rolling springs `roll` (empty unless the law has a
/// rolling spring). Reads and writes go through a law's [`Kept`], so a law without a spring
/// never touches its array.
pub(crate) struct Springs<'a> {
    pub slide: &'a mut [Vec3],
    pub roll: &'a mut [Vec3],
}

/// Which springs a law keeps (decided per copy of the law in [`ContactLaw::unswitched`]).
#[derive(Clone, Copy)]
struct Kept {
    slide: bool,
    roll: bool,
}

impl Kept {
    #[inline(always)]
    fn of(law: &ContactLaw) -> Self {
        Self {
            slide: law.tangential.has_history(),
            roll: law.rolling.has_history(),
        }
    }

    #[inline(always)]
    fn any(self) -> bool {
        self.slide | self.roll
    }
}

impl Springs<'_> {
    /// The history of slot `k`.
    #[inline(always)]
    fn get(&self, k: usize, kept: Kept) -> History {
        History {
            slide: if kept.slide { self.slide[k] } else { Vec3::zeros() },
            roll: if kept.roll { self.roll[k] } else { Vec3::zeros() },
        }
    }

    /// Stores the history of slot `k`.
    #[inline(always)]
    fn set(&mut self, k: usize, h: History, kept: Kept) {
        if kept.slide {
            self.slide[k] = h.slide;
        }
        if kept.roll {
            self.roll[k] = h.roll;
        }
    }

    /// Zeroes the springs of slot `k` (a contact that ended).
    #[inline(always)]
    fn clear(&mut self, k: usize, kept: Kept) {
        self.set(k, History::default(), kept);
    }

    /// The histories of the slots `k`, on lanes.
    #[inline(always)]
    fn gather(&self, k: [usize; 4], kept: Kept) -> History<V3<F64x4>> {
        History {
            slide: if kept.slide { V3::gather(self.slide, k) } else { V3::zeros() },
            roll: if kept.roll { V3::gather(self.roll, k) } else { V3::zeros() },
        }
    }

    /// Stores lane `l` of `h` in slot `k`.
    #[inline(always)]
    fn set_lane(&mut self, k: usize, h: &History<V3<F64x4>>, l: usize, kept: Kept) {
        if kept.slide {
            self.slide[k] = h.slide.lane(l);
        }
        if kept.roll {
            self.roll[k] = h.roll.lane(l);
        }
    }

    /// The springs of slots `range`.
    #[inline(always)]
    fn part(&mut self, range: std::ops::Range<usize>, kept: Kept) -> Springs<'_> {
        Springs {
            slide: if kept.slide { &mut self.slide[range.clone()] } else { &mut [] },
            roll: if kept.roll { &mut self.roll[range] } else { &mut [] },
        }
    }
}

/// What a pair evaluated from its smaller index `i` leaves for its partner `j`: the force
/// `-F_ij` and the torque on `j`. Zero for a pair not in contact.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Reaction {
    pub force: Vec3,
    pub torque: Vec3,
    /// `-drag` of the pair ([`contact::ContactForce::drag`]), for the ledger.
    pub drag: Vec3,
}

/// Partial results of one block of particles.
#[derive(Default)]
pub(crate) struct BlockSums {
    pub pair_contacts: u64,
    pub wall_contacts: u64,
    /// Elastic energy stored in contacts (J).
    pub stored: f64,
    /// Dissipated power (W).
    pub dissipated: f64,
    /// Power injected by moving walls (W).
    pub injected: f64,
    /// Energy (J) by which the step's kick leaves the dissipation short of `dissipated`
    /// booked over the step ([`crate::integrate::verlet_excess`]).
    pub excess: f64,
    pub records: Vec<ContactRecord>,
    /// First particle of the block found non-finite or outside the container, if checked.
    pub first_bad: Option<usize>,
    /// Worst overlap beyond [`MAX_OVERLAP_FRACTION`] of the smaller radius:
    /// `(fraction, particle, partner, overlap, radius)`.
    pub violation: Option<(f64, usize, Partner, f64, f64)>,
}

impl BlockSums {
    /// Notes a contact whose overlap exceeds [`MAX_OVERLAP_FRACTION`] of `radius`.
    #[inline(always)]
    fn check_overlap(&mut self, i: usize, partner: Partner, overlap: f64, radius: f64) {
        if overlap > MAX_OVERLAP_FRACTION * radius {
            self.note_violation(i, partner, overlap, radius);
        }
    }

    /// The rare branch of [`Self::check_overlap`], kept out of the force loops (`cold`: the
    /// compiler lays it out of the way of the common path).
    #[cold]
    #[inline(never)]
    fn note_violation(&mut self, i: usize, partner: Partner, overlap: f64, radius: f64) {
        let frac = overlap / radius;
        if self.violation.is_none_or(|v| frac > v.0) {
            self.violation = Some((frac, i, partner, overlap, radius));
        }
    }

    /// Keeps a contact's record (diagnostics runs only: out of the force loops' way).
    #[cold]
    #[inline(never)]
    fn record<N: Normal>(&mut self, i: usize, partner: Partner, g: &ContactGeometry<N>, c: &contact::ContactForce, mu: f64) {
        self.records.push(ContactRecord::new(i, partner, g, c, mu));
    }
}

/// The first pass ([module docs](self)) on the particles `first..first + force.len()`: their
/// forces and torques from gravity, their own pairs and the walls. `pair_springs` holds the
/// springs of their neighbour-list slots (from `list.offsets[first]` on), and `reactions`
/// receives those slots' reactions; `wall_springs` holds the springs of their wall contacts,
/// `walls.len().max(1)` per particle, with a flag per slot that is 1 while its springs may be
/// non-zero. The pinned layer's vertical force is dropped by [`add_reactions`].
pub(crate) fn gather_block(
    inp: &Inputs,
    first: usize,
    (force, torque, drag): (&mut [Vec3], &mut [Vec3], &mut [Vec3]),
    (mut pair_springs, reactions): (Springs, &mut [Reaction]),
    (wall_springs, wall_touched): (Springs, &mut [u8]),
) -> BlockSums {
    let setup = inp.setup;
    let (list, pos, vel, omega, radius) = (inp.list, inp.pos, inp.vel, inp.omega, inp.radius);
    let pair_law = &setup.pair_law;
    let (dt, gravity) = (setup.dt, setup.gravity);
    let base_slot = list.offsets[first];
    let mut sums = BlockSums::default();
    // Gravity.
    let n = force.len();
    for ((f, t), &m) in force.iter_mut().zip(torque.iter_mut()).zip(&inp.mass[first..first + n]) {
        // The mass precomputed: no division. The torque's zero is not a constant store, which
        // LLVM would split off into a memset whose `rep stosb` valgrind counts per byte;
        // `0 m` is +0 for a mass m > 0: one multiplication.
        *f = gravity * m;
        *t = Vec3::repeat(0.0 * m);
    }
    drag.fill(Vec3::zeros());
    // Particle pairs, each evaluated once from its smaller index (the whole energies), in
    // one flat loop over the block's neighbour-list slots: in a dilute layer most particles
    // have zero to two candidates, and a loop nested per particle would mispredict its exit
    // each time. Each particle still adds its partners in slot order.
    let slots = base_slot..list.offsets[first + n];
    if !inp.record {
        // Four slots at a time on lanes (diagnostics runs keep the per-contact path below,
        // which records each contact): the same kernels, the same bits.
        on_lanes(
            #[inline(always)]
            || {
                pair_pass(
                    inp,
                    (first, slots),
                    (force, torque, drag),
                    (&mut pair_springs, reactions),
                    &mut sums,
                )
            },
        );
    } else {
        pair_law.unswitched(|pair_law| {
            let kept = Kept::of(pair_law);
            for (k, ((&i, &j), reaction)) in list.owner[slots.clone()]
                .iter()
                .zip(&list.partners[slots])
                .zip(reactions.iter_mut())
                .enumerate()
            {
                let (i, j) = (i as usize, j as usize);
                let xi = pos[i];
                let d = setup.boundary.min_image(xi - pos[j]);
                let a = Sphere {
                    x: xi,
                    v: vel[i],
                    w: omega[i],
                    r: radius[i],
                };
                let b = Sphere {
                    x: xi - d,
                    v: vel[j],
                    w: omega[j],
                    r: radius[j],
                };
                let Some(g) = ContactGeometry::pair(a, b).map(|g| g.with_mobility(inp.mobility[i] + inp.mobility[j])) else {
                    pair_springs.clear(k, kept);
                    *reaction = Reaction::default();
                    continue;
                };
                let mut h = pair_springs.get(k, kept);
                let c = contact::evaluate_with(pair_law, &g, None, &mut h, inp.pair_mu_r(pair_law, i, j), dt);
                pair_springs.set(k, h, kept);
                force[i - first] += c.force;
                torque[i - first] += c.torque_i;
                drag[i - first] += c.drag;
                *reaction = Reaction {
                    force: -c.force,
                    torque: c.torque_j,
                    drag: -c.drag,
                };
                sums.pair_contacts += 1;
                sums.check_overlap(i, Partner::Particle(j), g.overlap, radius[i].min(radius[j]));
                sums.stored += c.stored_energy;
                sums.dissipated += c.dissipation_rate;
                sums.record(i, Partner::Particle(j), &g, &c, pair_law.tangential.mu());
            }
        });
    }
    // Walls, one wall at a time over the block: the loop body is short enough for the
    // processor to overlap the square roots and divisions of consecutive particles. Each
    // particle still sums gravity, pairs and walls in the same order.
    // The geometry closures test the gap first: a grain away from a wall reads nothing else.
    let (pos, vel, omega, radius) = (
        &pos[first..first + n],
        &vel[first..first + n],
        &omega[first..first + n],
        &radius[first..first + n],
    );
    let out = &mut BlockOut {
        first,
        force,
        torque,
        drag,
        wall_springs,
        wall_touched,
    };
    let mut w = 0;
    while w < inp.planes.len() {
        let plane = &inp.planes[w];
        let (origin, v_wall, sign) = (plane.origin, plane.velocity, plane.sign());
        // Two consecutive walls across the same axis (the tray's sides) share one pass.
        let pair = match (plane.kind, inp.planes.get(w + 1)) {
            (PlaneKind::Axis { axis, .. }, Some(next)) => {
                !plane.support && !next.support && matches!(next.kind, PlaneKind::Axis { axis: a, .. } if a == axis)
            }
            _ => false,
        };
        if pair {
            match plane.kind {
                PlaneKind::Axis { axis: 0, .. } => axis_pair_pass::<0>(inp, w, out, &mut sums),
                PlaneKind::Axis { axis: 1, .. } => axis_pair_pass::<1>(inp, w, out, &mut sums),
                _ => axis_pair_pass::<2>(inp, w, out, &mut sums),
            }
            w += 2;
            continue;
        }
        if plane.support {
            // A pinned grain rests on the floor: the contact is always there, without overlap.
            wall_pass::<_, true>(inp, (w, plane), out, &mut sums, |k| {
                Some(ContactGeometry::resting_on_floor(vel[k], omega[k], radius[k], v_wall))
            });
            w += 1;
            continue;
        }
        match plane.kind {
            PlaneKind::Axis { axis: 0, .. } => wall_pass::<_, false>(inp, (w, plane), out, &mut sums, |k| {
                if radius[k] - sign * (pos[k].x - origin.x) < 0.0 {
                    return None;
                }
                ContactGeometry::<AxisNormal<0>>::axis_wall(pos[k], vel[k], omega[k], radius[k], origin, sign, v_wall)
            }),
            PlaneKind::Axis { axis: 1, .. } => wall_pass::<_, false>(inp, (w, plane), out, &mut sums, |k| {
                if radius[k] - sign * (pos[k].y - origin.y) < 0.0 {
                    return None;
                }
                ContactGeometry::<AxisNormal<1>>::axis_wall(pos[k], vel[k], omega[k], radius[k], origin, sign, v_wall)
            }),
            // The floor: four grains at a time (diagnostics runs keep the per-contact path,
            // which records each contact).
            PlaneKind::Axis { axis: 2, .. } if !inp.record => on_lanes(
                #[inline(always)]
                || floor_pass::<2>(inp, (w, plane), out, &mut sums),
            ),
            PlaneKind::Axis { .. } => wall_pass::<_, false>(inp, (w, plane), out, &mut sums, |k| {
                if radius[k] - sign * (pos[k].z - origin.z) < 0.0 {
                    return None;
                }
                ContactGeometry::<AxisNormal<2>>::axis_wall(pos[k], vel[k], omega[k], radius[k], origin, sign, v_wall)
            }),
            PlaneKind::General => wall_pass::<_, false>(inp, (w, plane), out, &mut sums, |k| {
                ContactGeometry::wall(pos[k], vel[k], omega[k], radius[k], origin, plane.normal, v_wall)
            }),
        }
        w += 1;
    }
    sums
}

/// The second pass ([module docs](self)) on the particles `first..first + force.len()`: each
/// adds the reactions of the pairs whose partner it is, in increasing order of the other
/// index, once every block's first pass has ended; a pinned layer then drops the vertical
/// force (eq 3.28).
pub(crate) fn add_reactions(
    inp: &Inputs,
    reactions: &[Reaction],
    first: usize,
    (force, torque, drag): (&mut [Vec3], &mut [Vec3], &mut [Vec3]),
) {
    let list = inp.list;
    let n = force.len();
    let (torque, drag) = (&mut torque[..n], &mut drag[..n]);
    // One flat loop over the block's incoming slots, as the pairs' loop over its own.
    let incoming = &list.incoming[list.incoming_offsets[first]..list.incoming_offsets[first + n]];
    for &s in incoming {
        let s = s as usize;
        let k = list.partners[s] as usize - first;
        let r = &reactions[s];
        force[k] += r.force;
        torque[k] += r.torque;
        drag[k] += r.drag;
    }
    if inp.setup.vertical == Vertical::Pinned {
        for f in force.iter_mut() {
            f.z = 0.0;
        }
    }
}

/// The per-particle outputs of one block: forces and torques of the particles
/// `first..first + force.len()`, and their wall springs (`walls.len().max(1)` slots each)
/// with the flags of the slots whose springs may be non-zero.
struct BlockOut<'a> {
    first: usize,
    force: &'a mut [Vec3],
    torque: &'a mut [Vec3],
    /// [`contact::ContactForce::drag`] summed per particle.
    drag: &'a mut [Vec3],
    wall_springs: Springs<'a>,
    wall_touched: &'a mut [u8],
}

impl<'a> BlockOut<'a> {
    /// `(first, (force, torque, drag), wall_springs, wall_touched)`.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn parts(&mut self) -> (usize, (&mut [Vec3], &mut [Vec3], &mut [Vec3]), &mut Springs<'a>, &mut [u8]) {
        (
            self.first,
            (self.force, self.torque, self.drag),
            &mut self.wall_springs,
            self.wall_touched,
        )
    }
}

/// Which springs wall contacts keep, and how many wall slots each particle has.
#[inline(always)]
fn wall_histories(inp: &Inputs) -> (Kept, usize) {
    (Kept::of(&inp.setup.wall_law), inp.planes.len().max(1))
}

/// Contacts of the block's particles with wall `w` (`plane`), whose geometry `geometry(k)`
/// gives for particle `first + k`; forces and torques are added to the block's. `SUPPORT`:
/// the wall is a pinned layer's floor ([`WallPlane::support`]), decided at compile time.
/// A function of its own (one per wall kind and law), not inlined into [`gather_block`]:
/// the loop keeps its own registers, and changes elsewhere in the force pass do not move its
/// code (inlined, a one-line change there cost Cundall-Strack 7-10 %).
#[inline(never)]
fn wall_pass<N: Normal, const SUPPORT: bool>(
    inp: &Inputs,
    (w, plane): (usize, &WallPlane),
    out: &mut BlockOut,
    sums: &mut BlockSums,
    geometry: impl Fn(usize) -> Option<ContactGeometry<N>>,
) {
    let (first, (force, torque, drag), wall_springs, wall_touched) = out.parts();
    let (kept, wall_stride) = wall_histories(inp);
    let history_on = kept.any();
    let n = force.len();
    let (torque, drag) = (&mut torque[..n], &mut drag[..n]);
    let mut acc = WallSums::default();
    // Read once: through `inp` it would be reloaded per contact, and so would every
    // constant of the laws computed from it (such as Cundall-Strack's `1 / dt`).
    let dt = inp.setup.dt;
    inp.setup.wall_law.unswitched(|law| {
        for (((k, f), t), d) in force.iter_mut().enumerate().zip(torque.iter_mut()).zip(drag.iter_mut()) {
            let slot = k * wall_stride + w;
            let Some(g) = geometry(k) else {
                if history_on {
                    wall_springs.clear(slot, kept);
                    wall_touched[slot] = 0;
                }
                continue;
            };
            if history_on {
                wall_touched[slot] = 1;
            }
            let grain = Grain {
                i: first + k,
                springs: wall_springs.part(slot..slot + 1, kept),
                force: f,
                torque: t,
                drag: d,
            };
            add_wall_contact::<N, SUPPORT>(inp, law, (w, dt), &g, grain, &mut acc, sums);
        }
    });
    acc.add_to(plane, sums);
}

/// Contacts of the particles `first..first + force.len()` with the walls `w` and `w + 1`,
/// both normal to axis `AXIS` (neither a pinned floor), in one pass: both gaps are tested
/// first, and only a grain touching one of them reads anything else; per particle, the
/// walls in order.
#[inline(never)]
fn axis_pair_pass<const AXIS: usize>(inp: &Inputs, w: usize, out: &mut BlockOut, sums: &mut BlockSums) {
    let (first, (force, torque, drag), wall_springs, wall_touched) = out.parts();
    let (kept, wall_stride) = wall_histories(inp);
    let history_on = kept.any();
    let n = force.len();
    let (p0, p1) = (&inp.planes[w], &inp.planes[w + 1]);
    let (mut acc0, mut acc1) = (WallSums::default(), WallSums::default());
    let (s0, o0, s1, o1) = (p0.sign(), p0.origin[AXIS], p1.sign(), p1.origin[AXIS]);
    let dt = inp.setup.dt;
    let (pos, radius) = (&inp.pos[first..first + n], &inp.radius[first..first + n]);
    for k in 0..n {
        let (x, r) = (pos[k][AXIS], radius[k]);
        let (apart0, apart1) = (r - s0 * (x - o0) < 0.0, r - s1 * (x - o1) < 0.0);
        if apart0 & apart1 {
            // Most grains are away from both side walls, with springs that are zero already:
            // a flag is read instead of two springs written (writing them cost Cundall-Strack
            // 3 % of its time on the thesis tray; reading them, more).
            if history_on {
                for wk in [w, w + 1] {
                    let slot = k * wall_stride + wk;
                    if wall_touched[slot] != 0 {
                        wall_springs.clear(slot, kept);
                        wall_touched[slot] = 0;
                    }
                }
            }
            continue;
        }
        let i = first + k;
        for (wk, plane, apart, acc) in [(w, p0, apart0, &mut acc0), (w + 1, p1, apart1, &mut acc1)] {
            let slot = k * wall_stride + wk;
            let g = if apart {
                None
            } else {
                ContactGeometry::<AxisNormal<AXIS>>::axis_wall(
                    pos[k],
                    inp.vel[i],
                    inp.omega[i],
                    r,
                    plane.origin,
                    plane.sign(),
                    plane.velocity,
                )
            };
            match g {
                Some(g) => {
                    if history_on {
                        wall_touched[slot] = 1;
                    }
                    let grain = Grain {
                        i,
                        springs: wall_springs.part(slot..slot + 1, kept),
                        force: &mut force[k],
                        torque: &mut torque[k],
                        drag: &mut drag[k],
                    };
                    add_wall_contact::<_, false>(inp, &inp.setup.wall_law, (wk, dt), &g, grain, acc, sums)
                }
                None if history_on => {
                    wall_springs.clear(slot, kept);
                    wall_touched[slot] = 0;
                }
                None => {}
            }
        }
    }
    acc0.add_to(p0, sums);
    acc1.add_to(p1, sums);
}

/// Sums over the contacts of one wall pass, kept apart from the block's sums so that they
/// can stay in registers: added to them once per pass ([`WallSums::add_to`]).
#[derive(Default)]
struct WallSums {
    contacts: u64,
    stored: f64,
    dissipated: f64,
    /// Total force of the wall on the particles (N); its power is the wall velocity times it.
    force: Vec3,
}

impl WallSums {
    /// Adds these sums, and the power of wall `plane` on the pass's particles, to `sums`.
    fn add_to(self, plane: &WallPlane, sums: &mut BlockSums) {
        sums.wall_contacts += self.contacts;
        sums.stored += self.stored;
        sums.dissipated += self.dissipated;
        sums.injected += self.force.dot(&plane.velocity);
    }
}

/// One particle of a wall contact: its index, its springs with the wall (one slot, or none
/// for a law without them), and where its force and torque are summed.
struct Grain<'a> {
    i: usize,
    springs: Springs<'a>,
    force: &'a mut Vec3,
    torque: &'a mut Vec3,
    drag: &'a mut Vec3,
}

/// Adds the contact `g` of particle `i` with wall `w` (springs `springs`, time step `dt`) to
/// the particle's `force` and `torque` and to the pass's sums `acc`; the block's `sums` keep
/// overlap violations and records. `SUPPORT`: the wall is a pinned layer's floor, whose load is
/// given ([`WallPlane::support`]).
#[inline(always)]
fn add_wall_contact<N: Normal, const SUPPORT: bool>(
    inp: &Inputs,
    law: &ContactLaw,
    (w, dt): (usize, f64),
    g: &ContactGeometry<N>,
    grain: Grain,
    acc: &mut WallSums,
    sums: &mut BlockSums,
) {
    let Grain {
        i,
        mut springs,
        force,
        torque,
        drag,
    } = grain;
    let g = &g.with_mobility(inp.mobility[i]);
    let kept = Kept::of(law);
    let mut h = springs.get(0, kept);
    let load = if SUPPORT { Some(inp.load[i]) } else { None };
    let c = contact::evaluate_with(law, g, load, &mut h, inp.wall_mu_r(law, i), dt);
    springs.set(0, h, kept);
    *force += c.force;
    *torque += c.torque_i;
    *drag += c.drag;
    acc.contacts += 1;
    acc.stored += c.stored_energy;
    acc.dissipated += c.dissipation_rate;
    acc.force += c.force;
    if !SUPPORT {
        // A pinned grain's floor contact has no overlap.
        sums.check_overlap(i, Partner::Wall(w), g.overlap, inp.radius[i]);
    }
    if inp.record {
        sums.record(i, Partner::Wall(w), g, &c, law.tangential.mu());
    }
}

/// Contacts of the block's particles with wall `w` (`plane`, normal `sign * e_AXIS`, not a
/// pinned floor), four grains at a time: the geometry and the laws run on [`F64x4`] lanes,
/// the same kernels ([`contact::evaluate_lanes`]) that serve one contact, so every lane gives
/// the bits the one-contact path would. Grains away from the wall are skipped four at a time;
/// the results of the touching lanes are added in particle order, as [`wall_pass`] does.
#[inline(always)]
fn floor_pass<const AXIS: usize>(inp: &Inputs, (w, plane): (usize, &WallPlane), out: &mut BlockOut, sums: &mut BlockSums) {
    let (first, (force, torque, drag), wall_springs, wall_touched) = out.parts();
    let (_, wall_stride) = wall_histories(inp);
    let n = force.len();
    let (torque, drag) = (&mut torque[..n], &mut drag[..n]);
    let (pos, vel, omega, radius, mobility) = (
        &inp.pos[first..first + n],
        &inp.vel[first..first + n],
        &inp.omega[first..first + n],
        &inp.radius[first..first + n],
        &inp.mobility[first..first + n],
    );
    let mut acc = WallSums::default();
    let (dt, sign, origin, v_wall) = (inp.setup.dt, plane.sign(), plane.origin[AXIS], plane.velocity);
    inp.setup.wall_law.unswitched(
        #[inline(always)]
        |law| {
            // From the copy of the law whose variants each instance knows: decided at
            // compile time.
            let kept = Kept::of(law);
            let history_on = kept.any();
            let mut k = 0;
            while k < n {
                // Lanes past the block's end repeat its last grain and are dropped.
                let idx = [k, (k + 1).min(n - 1), (k + 2).min(n - 1), (k + 3).min(n - 1)];
                let live = (n - k).min(4);
                let r = F64x4::new([radius[idx[0]], radius[idx[1]], radius[idx[2]], radius[idx[3]]]);
                let x = F64x4::new([pos[idx[0]][AXIS], pos[idx[1]][AXIS], pos[idx[2]][AXIS], pos[idx[3]][AXIS]]);
                let overlap = r - F64x4::splat(sign) * (x - F64x4::splat(origin));
                // Bit l set: lane l touches (`overlap >= 0`, as the one-contact gap test).
                let touching = !Lane::lt(overlap, F64x4::splat(0.0)).bits() & ((1 << live) - 1);
                if touching == 0 {
                    if history_on {
                        for q in k..k + live {
                            wall_springs.clear(q * wall_stride + w, kept);
                            wall_touched[q * wall_stride + w] = 0;
                        }
                    }
                    k += 4;
                    continue;
                }
                let g = LaneGeometry::<AxisNormal<AXIS>, F64x4>::axis_wall(
                    x,
                    V3::gather(vel, idx),
                    V3::gather(omega, idx),
                    r,
                    origin,
                    sign,
                    v_wall,
                )
                .with_mobility(F64x4::new(idx.map(|q| mobility[q])));
                let slot = |l: usize| idx[l] * wall_stride + w;
                let slots = [slot(0), slot(1), slot(2), slot(3)];
                let mut h = wall_springs.gather(slots, kept);
                let mu_r = F64x4::new(four(
                    #[inline(always)]
                    |l| inp.wall_mu_r(law, first + idx[l]),
                ));
                let c = contact::evaluate_lanes(law, &g, &mut h, mu_r, dt);
                let (stored, dissipated, overlaps) = (c.stored_energy.to_array(), c.dissipation_rate.to_array(), overlap.to_array());
                for l in 0..live {
                    let q = k + l;
                    if touching & (1 << l) == 0 {
                        if history_on {
                            wall_springs.clear(slots[l], kept);
                            wall_touched[slots[l]] = 0;
                        }
                        continue;
                    }
                    if history_on {
                        wall_springs.set_lane(slots[l], &h, l, kept);
                        wall_touched[slots[l]] = 1;
                    }
                    let f = c.force.lane(l);
                    force[q] += f;
                    torque[q] += c.torque_i.lane(l);
                    drag[q] += c.drag.lane(l);
                    acc.contacts += 1;
                    acc.stored += stored[l];
                    acc.dissipated += dissipated[l];
                    acc.force += f;
                    sums.check_overlap(first + q, Partner::Wall(w), overlaps[l], radius[q]);
                }
                k += 4;
            }
        },
    );
    acc.add_to(plane, sums);
}

/// Runs a pass over lanes ([`floor_pass`], [`pair_pass`]) compiled twice: for the baseline
/// instruction set (two lanes per vector instruction on x86-64) and, where the processor has
/// AVX2, for four lanes per instruction, chosen at run time. Rust never fuses a
/// multiplication and an addition on its own, so both give the same bits (the test
/// `the_floor_and_pair_passes_in_lanes_give_the_bits_of_the_one_contact_path` runs both).
/// The pass, an `#[inline(always)]` closure, is compiled into each copy.
#[inline(always)]
fn on_lanes(pass: impl FnOnce()) {
    #[cfg(target_arch = "x86_64")]
    if avx2_lanes() {
        // SAFETY: the processor has AVX2 (checked at run time).
        return unsafe { on_avx2_lanes(pass) };
    }
    on_baseline_lanes(pass)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline(never)]
unsafe fn on_avx2_lanes(pass: impl FnOnce()) {
    pass()
}

#[inline(never)]
fn on_baseline_lanes(pass: impl FnOnce()) {
    pass()
}

/// Set to run the portable floor pass even where AVX2 is there (tests).
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) static PORTABLE_LANES: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// True if the floor pass uses AVX2.
#[cfg(target_arch = "x86_64")]
fn avx2_lanes() -> bool {
    static AVX2: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    // `STRIPES_PORTABLE_LANES` set: the portable copy (for instruction-counting profilers
    // that do not know every AVX2 instruction).
    *AVX2.get_or_init(|| std::is_x86_feature_detected!("avx2") && std::env::var_os("STRIPES_PORTABLE_LANES").is_none())
        && !PORTABLE_LANES.load(std::sync::atomic::Ordering::Relaxed)
}

/// The particle pairs of a block's neighbour-list slots `slots` (those of the particles
/// `first..first + force.len()`, whose forces and torques are summed here; `pair_springs`
/// holds their springs and `reactions` receives their partners' shares), four slots at a
/// time: the nearest images are taken per slot, the geometry and the laws run on [`F64x4`]
/// lanes by the kernels that serve one contact, and the results of the lanes in contact are
/// added in slot order, as the one-contact loop in [`gather_block`] does (each pair once, from
/// its smaller index, with its whole energies).
#[inline(always)]
fn pair_pass(
    inp: &Inputs,
    (first, slots): (usize, std::ops::Range<usize>),
    (force, torque, drag): (&mut [Vec3], &mut [Vec3], &mut [Vec3]),
    (pair_springs, reactions): (&mut Springs, &mut [Reaction]),
    sums: &mut BlockSums,
) {
    let (list, pos, vel, omega, radius) = (inp.list, inp.pos, inp.vel, inp.omega, inp.radius);
    let (owner, partners) = (&list.owner[slots.clone()], &list.partners[slots]);
    let m = owner.len();
    let (dt, boundary) = (inp.setup.dt, inp.setup.boundary);
    inp.setup.pair_law.unswitched(
        #[inline(always)]
        |law| {
            let kept = Kept::of(law);
            let mut s = 0;
            while s < m {
                // Lanes past the block's last slot repeat it and are dropped.
                let live = (m - s).min(4);
                let at = [s, (s + 1).min(m - 1), (s + 2).min(m - 1), (s + 3).min(m - 1)];
                let i = four(
                    #[inline(always)]
                    |l| owner[at[l]] as usize,
                );
                let j = four(
                    #[inline(always)]
                    |l| partners[at[l]] as usize,
                );
                // The separation exactly as the one-contact path computes it: from the
                // nearest image `x_i - d` of `x_j`.
                let d = four(
                    #[inline(always)]
                    |l| {
                        let xi = pos[i[l]];
                        xi - (xi - boundary.min_image(xi - pos[j[l]]))
                    },
                );
                let d = V3::new(
                    F64x4::new([d[0].x, d[1].x, d[2].x, d[3].x]),
                    F64x4::new([d[0].y, d[1].y, d[2].y, d[3].y]),
                    F64x4::new([d[0].z, d[1].z, d[2].z, d[3].z]),
                );
                let (ri, rj) = (
                    F64x4::new(four(
                        #[inline(always)]
                        |l| radius[i[l]],
                    )),
                    F64x4::new(four(
                        #[inline(always)]
                        |l| radius[j[l]],
                    )),
                );
                let dist2 = d.norm_squared();
                let sum = ri + rj;
                // Bit l set: lane l in contact (as `ContactGeometry::pair`'s test).
                let apart = Lane::lt(sum * sum, dist2) | Lane::equal(dist2, F64x4::splat(0.0));
                let touching = !apart.bits() & ((1 << live) - 1);
                if touching != 0 {
                    let g = LaneGeometry::<V3<F64x4>, F64x4>::pair(
                        d,
                        dist2,
                        (V3::gather(vel, i), V3::gather(vel, j)),
                        (V3::gather(omega, i), V3::gather(omega, j)),
                        (ri, rj),
                    )
                    .with_mobility(F64x4::new(four(
                        #[inline(always)]
                        |l| inp.mobility[i[l]] + inp.mobility[j[l]],
                    )));
                    let mut h = pair_springs.gather(at, kept);
                    let mu_r = F64x4::new(four(
                        #[inline(always)]
                        |l| inp.pair_mu_r(law, i[l], j[l]),
                    ));
                    let c = contact::evaluate_lanes(law, &g, &mut h, mu_r, dt);
                    let (stored, dissipated, overlap) = (c.stored_energy.to_array(), c.dissipation_rate.to_array(), g.overlap.to_array());
                    let (ri, rj) = (ri.to_array(), rj.to_array());
                    for l in 0..live {
                        if touching & (1 << l) == 0 {
                            pair_springs.clear(s + l, kept);
                            reactions[s + l] = Reaction::default();
                            continue;
                        }
                        pair_springs.set_lane(s + l, &h, l, kept);
                        let (i, j) = (i[l], j[l]);
                        let f = c.force.lane(l);
                        force[i - first] += f;
                        torque[i - first] += c.torque_i.lane(l);
                        let d = c.drag.lane(l);
                        drag[i - first] += d;
                        reactions[s + l] = Reaction {
                            force: -f,
                            torque: c.torque_j.lane(l),
                            drag: -d,
                        };
                        sums.pair_contacts += 1;
                        sums.check_overlap(i, Partner::Particle(j), overlap[l], ri[l].min(rj[l]));
                        sums.stored += stored[l];
                        sums.dissipated += dissipated[l];
                    }
                } else {
                    if kept.slide {
                        pair_springs.slide[s..s + live].fill(Vec3::zeros());
                    }
                    if kept.roll {
                        pair_springs.roll[s..s + live].fill(Vec3::zeros());
                    }
                    reactions[s..s + live].fill(Reaction::default());
                }
                s += 4;
            }
        },
    );
}

/// `[f(0), f(1), f(2), f(3)]`, written out (`array::map` is not always inlined).
#[inline(always)]
fn four<T>(f: impl Fn(usize) -> T) -> [T; 4] {
    [f(0), f(1), f(2), f(3)]
}
