//! Rigid bodies made of member spheres ([`crate::clump`]): their state, the reduction of the
//! members' forces to each body, and the integration of the bodies.
//!
//! The spheres stay the contact entities: the neighbour list, the force laws, the contact
//! history, the walls and the drive see only spheres (pairs within one body are left out of
//! the neighbour list). After each force evaluation every body sums its members' forces and
//! their torques about its centre of mass, `T = sum_k (tau_k + r_k x F_k)`, and moves as one
//! rigid body; then every member is put back at `x + Q b_k` with velocity `v + omega x r_k`
//! and spin `omega` (`Q` the body's rotation, `b_k` its offset in the body frame,
//! `r_k = Q b_k`).
//!
//! Translation is velocity Verlet as for spheres, with the same predictor for the forces
//! (`v(t + dt/2) + F(t) dt / (2 M)`). Rotation is the NO_SQUISH scheme of Miller, Eleftheriou,
//! Pattnaik, Ndirango, Newns and Martyna (J. Chem. Phys. 116, 8649 (2002)), as LAMMPS'
//! `fix rigid/nve` uses it: the orientation is a unit quaternion `q` and its conjugate
//! momentum `p = 2 S(q) I omega_body` (a 4-vector); a step is a half kick of `p` by the
//! torque, the free rotation split into five exact rotations about the principal axes
//! (3, 2, 1, 2, 3 with half, half, full, half, half steps), and a second half kick. It is
//! symplectic and time-reversible and keeps `|q| = 1` to round-off. The spin the contacts
//! see at the new positions is predicted as the velocity is: `p` kicked by the old torque.

use crate::boundary::Boundary;
use crate::clump::ClumpShape;
use crate::state::State;
use crate::Vec3;

/// A quaternion `(w, x, y, z)`.
pub type Quat = [f64; 4];

/// The rigid bodies of a simulation: body `b` is made of the members
/// `b * spheres..(b + 1) * spheres` of the state.
#[derive(Clone, Debug, PartialEq)]
pub struct Bodies {
    /// Spheres per body.
    pub spheres: usize,
    /// The members' offsets in the body frame over their radius.
    unit_offsets: Vec<Vec3>,
    /// Centre of mass (m), wrapped into the periodic box as the members are.
    pub x: Vec<Vec3>,
    /// Velocity of the centre of mass (m/s).
    pub v: Vec<Vec3>,
    /// Half-step velocity (m/s), between the stages of a step.
    v_half: Vec<Vec3>,
    /// Orientation: rotation from the body frame to space.
    pub q: Vec<Quat>,
    /// Conjugate quaternion momentum (kg m^2/s), NO_SQUISH's `p`.
    p: Vec<Quat>,
    /// Mass (kg).
    pub mass: Vec<f64>,
    /// Principal moments of inertia (kg m^2) about the body axes.
    pub inertia: Vec<Vec3>,
    /// Member radius (m).
    radius: Vec<f64>,
    /// Total force (N) and torque about the centre of mass (N m) of the last evaluation.
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
}

impl Bodies {
    /// The bodies of a state whose grains are clumps of `shape`, each run of `spheres`
    /// members one grain with one radius: the centre of mass is the mean of the members'
    /// centres (nearest periodic images of the first member), the orientation is read off
    /// the members' positions, the velocity is the mean of the members' and the spin the
    /// mean of their spins. The mass is the sum of the members' (each carries `1/n`), the
    /// inertia that of the union of the spheres at that density ([`ClumpShape::mass_and_inertia`]).
    /// Then every member is placed exactly where the body puts it (a change of round-off
    /// size in a rigid state).
    pub fn of(shape: &ClumpShape, state: &mut State, boundary: &Boundary) -> Result<Self, String> {
        let n = shape.spheres;
        if !(1..=crate::clump::MAX_SPHERES).contains(&n) {
            return Err(format!("a clump of {n} spheres: at most {}", crate::clump::MAX_SPHERES));
        }
        if !state.len().is_multiple_of(n) {
            return Err(format!("{} spheres are no whole number of clumps of {n}", state.len()));
        }
        let bodies = state.len() / n;
        let unit_offsets = shape.offsets();
        let (unit_mass, unit_inertia) = shape.mass_and_inertia();
        let mut b = Bodies {
            spheres: n,
            unit_offsets,
            x: Vec::with_capacity(bodies),
            v: Vec::with_capacity(bodies),
            v_half: Vec::with_capacity(bodies),
            q: Vec::with_capacity(bodies),
            p: Vec::with_capacity(bodies),
            mass: Vec::with_capacity(bodies),
            inertia: Vec::with_capacity(bodies),
            radius: Vec::with_capacity(bodies),
            force: vec![Vec3::zeros(); bodies],
            torque: vec![Vec3::zeros(); bodies],
        };
        for g in 0..bodies {
            let m = g * n..(g + 1) * n;
            let r = state.radius[m.start];
            if state.radius[m.clone()].iter().any(|&ri| ri != r) {
                return Err(format!("the members {m:?} of clump {g} differ in radius"));
            }
            let x0 = state.pos[m.start];
            let rel: Vec<Vec3> = m.clone().map(|k| boundary.min_image(state.pos[k] - x0)).collect();
            let centre = rel.iter().sum::<Vec3>() / n as f64;
            let arms: Vec<Vec3> = rel.iter().map(|d| d - centre).collect();
            let rot = frame_of(&arms)?;
            let mass: f64 = m.clone().map(|k| state.mass(k)).sum();
            let rho = mass / (unit_mass * r.powi(3));
            let inertia = unit_inertia * (rho * r.powi(5));
            let v = m.clone().map(|k| state.vel[k]).sum::<Vec3>() / n as f64;
            let w = m.clone().map(|k| state.omega[k]).sum::<Vec3>() / n as f64;
            let q = quat_of(&rot);
            // p = 2 q (0, I omega_body) (LAMMPS' `quatvec` of the body angular momentum).
            let l_body = rotate_back(&q, &w).component_mul(&inertia);
            let p = scale(quatvec(&q, &l_body), 2.0);
            b.x.push(boundary.wrap(x0 + centre));
            b.v.push(v);
            b.v_half.push(v);
            b.q.push(q);
            b.p.push(p);
            b.mass.push(mass);
            b.inertia.push(inertia);
            b.radius.push(r);
        }
        for g in 0..bodies {
            let w = b.omega(g);
            b.put_members(g, state, boundary, b.v[g], w);
        }
        Ok(b)
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True without bodies.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Arm of member `k` of body `g` in space (m): `Q b_k R`.
    fn arm(&self, g: usize, k: usize) -> Vec3 {
        rotate(&self.q[g], &(self.unit_offsets[k] * self.radius[g]))
    }

    /// Angular velocity (rad/s, space frame) of body `g` from its momentum `p`.
    pub fn omega(&self, g: usize) -> Vec3 {
        omega_of(&self.q[g], &self.p[g], &self.inertia[g])
    }

    /// Angular momentum (kg m^2/s, space frame) of body `g` about its centre of mass.
    pub fn angular_momentum(&self, g: usize) -> Vec3 {
        rotate(&self.q[g], &(body_momentum(&self.q[g], &self.p[g])))
    }

    /// Places the members of body `g` and gives them the body's velocity `v` and spin `w`.
    fn put_members(&self, g: usize, state: &mut State, boundary: &Boundary, v: Vec3, w: Vec3) {
        for k in 0..self.spheres {
            let i = g * self.spheres + k;
            let r = self.arm(g, k);
            state.pos[i] = boundary.wrap(self.x[g] + r);
            state.vel[i] = v + w.cross(&r);
            state.omega[i] = w;
            state.vel_half[i] = state.vel[i];
            state.omega_half[i] = w;
        }
    }

    /// Sums the members' forces and torques of the last evaluation into each body:
    /// `F = sum F_k`, `T = sum (tau_k + r_k x F_k)`, members in order.
    pub fn gather(&mut self, state: &State) {
        for g in 0..self.len() {
            let (mut f, mut t) = (Vec3::zeros(), Vec3::zeros());
            for k in 0..self.spheres {
                let i = g * self.spheres + k;
                f += state.force[i];
                t += state.torque[i] + self.arm(g, k).cross(&state.force[i]);
            }
            self.force[g] = f;
            self.torque[g] = t;
        }
    }

    /// The stage before the forces: each body's half kick, drift and rotation by NO_SQUISH
    /// over `dt`, then its members placed, with the predicted velocity and spin
    /// (`v_half + F dt / 2M`, and `p` kicked by the old torque at the new orientation).
    /// Returns the box `(lo, hi)` of the members' displacements over `dt` divided by `dt`
    /// (for the neighbour list's drift bound).
    pub fn before_forces(&mut self, state: &mut State, boundary: &Boundary, dt: f64) -> (Vec3, Vec3) {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for g in 0..self.len() {
            let c = 0.5 * dt / self.mass[g];
            let half = self.v[g] + self.force[g] * c;
            self.v_half[g] = half;
            // The old arms on the stack (at most MAX_SPHERES members, as `ClumpShape::new`
            // checks), not a Vec per body and step.
            let mut old_arms = [Vec3::zeros(); crate::clump::MAX_SPHERES];
            for (k, a) in old_arms.iter_mut().enumerate().take(self.spheres) {
                *a = self.arm(g, k);
            }
            let step = half * dt;
            self.x[g] += step;
            // Half kick of p by the torque (in the body frame), then the free rotation.
            let tq = rotate_back(&self.q[g], &self.torque[g]);
            self.p[g] = add(self.p[g], scale(quatvec(&self.q[g], &tq), dt));
            no_squish(&mut self.q[g], &mut self.p[g], &self.inertia[g], dt);
            for (k, old) in old_arms.iter().enumerate().take(self.spheres) {
                let u = (step + self.arm(g, k) - old) / dt;
                lo = lo.inf(&u);
                hi = hi.sup(&u);
            }
            self.x[g] = boundary.wrap(self.x[g]);
            // The predicted velocity and spin for the forces.
            let v = half + self.force[g] * c;
            let tq = rotate_back(&self.q[g], &self.torque[g]);
            let p = add(self.p[g], scale(quatvec(&self.q[g], &tq), dt));
            let w = omega_of(&self.q[g], &p, &self.inertia[g]);
            self.put_members(g, state, boundary, v, w);
        }
        (lo, hi)
    }

    /// The stage after the forces: the members' forces gathered ([`Self::gather`]), each
    /// body's second half kick, and the members' velocities and spins at `t + dt`. Returns
    /// `sum_k drag_k . (v_k - v_k^pred) dt` (+ the torques' `tau_k . (w - w^pred) dt` with
    /// `spins`): what velocity Verlet's kick leaves the dissipative forces' work short of the
    /// power booked at the predicted velocities, as [`crate::integrate::verlet_excess`] does
    /// for spheres, on the members' velocities.
    pub fn after_forces(&mut self, state: &mut State, drag: &[Vec3], dt: f64, spins: bool) -> f64 {
        self.gather(state);
        let mut excess = 0.0;
        for g in 0..self.len() {
            let v = self.v_half[g] + self.force[g] * (0.5 * dt / self.mass[g]);
            self.v[g] = v;
            let tq = rotate_back(&self.q[g], &self.torque[g]);
            self.p[g] = add(self.p[g], scale(quatvec(&self.q[g], &tq), dt));
            let w = self.omega(g);
            for k in 0..self.spheres {
                let i = g * self.spheres + k;
                let vk = v + w.cross(&self.arm(g, k));
                excess += drag[i].dot(&(vk - state.vel[i])) * dt;
                if spins {
                    excess += state.torque[i].dot(&(w - state.omega[i])) * dt;
                }
                state.vel[i] = vk;
                state.omega[i] = w;
                state.vel_half[i] = vk;
                state.omega_half[i] = w;
            }
        }
        excess
    }

    /// Kinetic energies `(sum M v^2 / 2, sum omega_body . I omega_body / 2)` (J).
    pub fn kinetic_energies(&self) -> (f64, f64) {
        let mut k = 0.0;
        let mut r = 0.0;
        for g in 0..self.len() {
            k += 0.5 * self.mass[g] * self.v[g].norm_squared();
            let l = body_momentum(&self.q[g], &self.p[g]);
            r += 0.5 * l.component_div(&self.inertia[g]).dot(&l);
        }
        (k, r)
    }

    /// Potential energy `-sum M g . x` (J) in the field `gravity`.
    pub fn potential_energy(&self, gravity: Vec3) -> f64 {
        (0..self.len()).map(|g| -self.mass[g] * gravity.dot(&self.x[g])).sum()
    }

    /// Sets body `g`'s velocity (m/s) and spin (rad/s, space frame), and its members'.
    pub fn set_motion(&mut self, g: usize, state: &mut State, boundary: &Boundary, v: Vec3, w: Vec3) {
        self.v[g] = v;
        self.v_half[g] = v;
        let l_body = rotate_back(&self.q[g], &w).component_mul(&self.inertia[g]);
        self.p[g] = scale(quatvec(&self.q[g], &l_body), 2.0);
        self.put_members(g, state, boundary, v, w);
    }
}

/// A body's dynamic state between steps, as plain data for checkpoints: centre of mass (m),
/// velocity (m/s), orientation quaternion and NO_SQUISH's conjugate momentum (kg m^2/s).
/// Its force and torque are not stored: they are the members' (which are), gathered again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SavedBody {
    pub x: Vec3,
    pub v: Vec3,
    pub q: Quat,
    pub p: Quat,
}

impl Bodies {
    /// Every body's dynamic state (see [`SavedBody`]).
    pub fn export(&self) -> Vec<SavedBody> {
        (0..self.len())
            .map(|g| SavedBody {
                x: self.x[g],
                v: self.v[g],
                q: self.q[g],
                p: self.p[g],
            })
            .collect()
    }

    /// Takes back the bodies' states of [`Self::export`] and gathers their forces and
    /// torques from the members' of `state` (already restored), as the step that wrote
    /// them did: a run continued from them goes on bit for bit. `false` if the count differs.
    pub fn import(&mut self, saved: &[SavedBody], state: &State) -> bool {
        if saved.len() != self.len() {
            return false;
        }
        for (g, b) in saved.iter().enumerate() {
            self.x[g] = b.x;
            self.v[g] = b.v;
            self.v_half[g] = b.v;
            self.q[g] = b.q;
            self.p[g] = b.p;
        }
        self.gather(state);
        true
    }
}

/// The body's axes in space from the members' arms about the centre of mass: the columns of
/// the rotation. Dimer: e1 along member 0's arm, e2 horizontal (or along y for an upright
/// dimer). Trimer: e2 along member 0's arm, e1 from member 1 to member 2.
fn frame_of(arms: &[Vec3]) -> Result<[Vec3; 3], String> {
    let bad = || "a clump's members do not sit as its shape puts them".to_string();
    let (e1, e2) = match arms.len() {
        2 => {
            let e1 = arms[0].try_normalize(0.0).ok_or_else(bad)?;
            let side = if e1.z.abs() < 0.9 { Vec3::z().cross(&e1) } else { Vec3::y() };
            let e2 = (side - e1 * side.dot(&e1)).normalize();
            (e1, e2)
        }
        3 => {
            let e2 = arms[0].try_normalize(0.0).ok_or_else(bad)?;
            let a = arms[2] - arms[1];
            let e1 = (a - e2 * a.dot(&e2)).try_normalize(0.0).ok_or_else(bad)?;
            (e1, e2)
        }
        _ => return Err(bad()),
    };
    Ok([e1, e2, e1.cross(&e2)])
}

/// The unit quaternion of the rotation whose columns are `e` (Shepperd's method).
fn quat_of(e: &[Vec3; 3]) -> Quat {
    let m = |r: usize, c: usize| e[c][r];
    let tr = m(0, 0) + m(1, 1) + m(2, 2);
    let q = if tr > 0.0 {
        let s = 2.0 * (tr + 1.0).sqrt();
        [0.25 * s, (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s]
    } else if m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2) {
        let s = 2.0 * (1.0 + m(0, 0) - m(1, 1) - m(2, 2)).sqrt();
        [(m(2, 1) - m(1, 2)) / s, 0.25 * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s]
    } else if m(1, 1) > m(2, 2) {
        let s = 2.0 * (1.0 + m(1, 1) - m(0, 0) - m(2, 2)).sqrt();
        [(m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, 0.25 * s, (m(1, 2) + m(2, 1)) / s]
    } else {
        let s = 2.0 * (1.0 + m(2, 2) - m(0, 0) - m(1, 1)).sqrt();
        [(m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, 0.25 * s]
    };
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    scale(q, 1.0 / n)
}

/// `a v` rotated into space: `Q(q) v`.
pub fn rotate(q: &Quat, v: &Vec3) -> Vec3 {
    let (w, u) = (q[0], Vec3::new(q[1], q[2], q[3]));
    let t = u.cross(v) * 2.0;
    v + t * w + u.cross(&t)
}

/// `Q(q)^T v`: a space vector in the body frame.
pub fn rotate_back(q: &Quat, v: &Vec3) -> Vec3 {
    rotate(&[q[0], -q[1], -q[2], -q[3]], v)
}

/// The quaternion product `a (0, b)` (LAMMPS `MathExtra::quatvec`).
fn quatvec(a: &Quat, b: &Vec3) -> Quat {
    [
        -a[1] * b[0] - a[2] * b[1] - a[3] * b[2],
        a[0] * b[0] + a[2] * b[2] - a[3] * b[1],
        a[0] * b[1] + a[3] * b[0] - a[1] * b[2],
        a[0] * b[2] + a[1] * b[1] - a[2] * b[0],
    ]
}

/// The vector part of `a* b` (LAMMPS `MathExtra::invquatvec`).
fn invquatvec(a: &Quat, b: &Quat) -> Vec3 {
    Vec3::new(
        -a[1] * b[0] + a[0] * b[1] + a[3] * b[2] - a[2] * b[3],
        -a[2] * b[0] - a[3] * b[1] + a[0] * b[2] + a[1] * b[3],
        -a[3] * b[0] + a[2] * b[1] - a[1] * b[2] + a[0] * b[3],
    )
}

/// The angular momentum in the body frame, `(q* p) / 2`.
fn body_momentum(q: &Quat, p: &Quat) -> Vec3 {
    invquatvec(q, p) * 0.5
}

/// The angular velocity in space, `Q I^-1 (q* p) / 2`.
fn omega_of(q: &Quat, p: &Quat, inertia: &Vec3) -> Vec3 {
    rotate(q, &body_momentum(q, p).component_div(inertia))
}

fn add(a: Quat, b: Quat) -> Quat {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

fn scale(a: Quat, s: f64) -> Quat {
    [a[0] * s, a[1] * s, a[2] * s, a[3] * s]
}

/// NO_SQUISH's free rotation over `dt`: exact rotations about the body axes 3, 2, 1, 2, 3
/// over `dt/2, dt/2, dt, dt/2, dt/2` (Miller et al. 2002, eq 2.13-2.20; LAMMPS
/// `FixRigidNH::no_squish_rotate` with `dtq = dt/2`).
pub fn no_squish(q: &mut Quat, p: &mut Quat, inertia: &Vec3, dt: f64) {
    let h = 0.5 * dt;
    rotate_about(3, p, q, inertia, h);
    rotate_about(2, p, q, inertia, h);
    rotate_about(1, p, q, inertia, dt);
    rotate_about(2, p, q, inertia, h);
    rotate_about(3, p, q, inertia, h);
}

/// One exact free rotation about body axis `k` (1, 2 or 3) over `dt`.
fn rotate_about(k: usize, p: &mut Quat, q: &mut Quat, inertia: &Vec3, dt: f64) {
    let perm = |a: &Quat| -> Quat {
        match k {
            1 => [-a[1], a[0], a[3], -a[2]],
            2 => [-a[2], -a[3], a[0], a[1]],
            _ => [-a[3], a[2], -a[1], a[0]],
        }
    };
    let (kq, kp) = (perm(q), perm(p));
    let phi = (p[0] * kq[0] + p[1] * kq[1] + p[2] * kq[2] + p[3] * kq[3]) / (4.0 * inertia[k - 1]);
    let (s, c) = (dt * phi).sin_cos();
    for a in 0..4 {
        p[a] = c * p[a] + s * kp[a];
        q[a] = c * q[a] + s * kq[a];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A free body with principal moments `inertia` and spin `w` (space), its `(q, p)`.
    fn free_body(inertia: Vec3, w: Vec3) -> (Quat, Quat) {
        let q = quat_of(&[Vec3::x(), Vec3::y(), Vec3::z()]);
        let p = scale(quatvec(&q, &rotate_back(&q, &w).component_mul(&inertia)), 2.0);
        (q, p)
    }

    fn energy(q: &Quat, p: &Quat, inertia: &Vec3) -> f64 {
        let l = body_momentum(q, p);
        0.5 * l.component_div(inertia).dot(&l)
    }

    #[test]
    fn a_free_asymmetric_body_keeps_its_energy_and_angular_momentum() {
        // Principal moments 1, 2, 3; spin mostly about the intermediate... no: near the
        // major axis with a tilt, so that it tumbles (Euler's equations, torque-free).
        let inertia = Vec3::new(1.0, 2.0, 3.0);
        let (mut q, mut p) = free_body(inertia, Vec3::new(0.3, 0.2, 2.0));
        let (e0, l0) = (energy(&q, &p, &inertia), rotate(&q, &body_momentum(&q, &p)));
        // The nutation period is of order 2 pi / |omega| ~ 3 s: run 20 periods.
        let dt = 1e-3;
        let (mut de, mut dl) = (0.0f64, 0.0f64);
        for _ in 0..60_000 {
            no_squish(&mut q, &mut p, &inertia, dt);
            let l = rotate(&q, &body_momentum(&q, &p));
            de = de.max(((energy(&q, &p, &inertia) - e0) / e0).abs());
            dl = dl.max((l - l0).norm() / l0.norm());
        }
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-13, "|q| = {norm}");
        // NO_SQUISH conserves |L| and the energy of each sub-rotation exactly; the splitting
        // error of the energy is O(dt^2) and bounded.
        assert!(de < 1e-5, "energy drift {de}");
        assert!(dl < 1e-5, "angular momentum drift {dl}");
    }

    #[test]
    fn a_symmetric_top_precesses_at_the_closed_form_rate() {
        // I1 = I2 = 1, I3 = 2: omega_body precesses about axis 3 at
        // Omega = (I3 - I1) / I1 omega3 (torque-free symmetric top).
        let inertia = Vec3::new(1.0, 1.0, 2.0);
        let (w1, w3) = (0.4, 1.5);
        let (mut q, mut p) = free_body(inertia, Vec3::new(w1, 0.0, w3));
        let rate = (inertia.z - inertia.x) / inertia.x * w3;
        let dt = 1e-4;
        let t_end = 3.0 * 2.0 * std::f64::consts::PI / rate; // three precession periods
        let steps = (t_end / dt).round() as usize;
        for _ in 0..steps {
            no_squish(&mut q, &mut p, &inertia, dt);
        }
        let t = steps as f64 * dt;
        let wb = body_momentum(&q, &p).component_div(&inertia);
        // Euler: w1(t) = w1 cos(Omega t), w2(t) = w1 sin(Omega t), w3 constant.
        let want = Vec3::new(w1 * (rate * t).cos(), w1 * (rate * t).sin(), w3);
        assert!((wb - want).norm() < 1e-6, "{wb:?} against {want:?}");
    }

    #[test]
    fn quaternions_rotate_as_their_frames() {
        let e = [Vec3::new(0.0, 1.0, 0.0), Vec3::new(-0.6, 0.0, 0.8), Vec3::new(0.8, 0.0, 0.6)];
        let q = quat_of(&e);
        for k in 0..3 {
            let mut b = Vec3::zeros();
            b[k] = 1.0;
            assert!((rotate(&q, &b) - e[k]).norm() < 1e-15);
            assert!((rotate_back(&q, &e[k]) - b).norm() < 1e-15);
        }
    }
}
