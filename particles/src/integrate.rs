//! Time integrators. Each splits a step into the part before the force evaluation and the
//! part after it, as kernels over a block of particles; [`crate::sim`] calls them in that
//! order.

use crate::state::{State, StateBlock};
use crate::Vec3;

/// Velocity Verlet's first stage for the particles of one block, translation with
/// [`translate_half`] (only x and y when `PLANAR`) and, in the same loop, `spin(k)` for the
/// rotation of particle `k`; adds each displacement velocity to `span`. The two cases are
/// separate instances, so the planar test is decided at compile time.
#[inline(always)]
fn verlet_first_half<const PLANAR: bool>(
    pos: &mut [Vec3],
    vel: &mut [Vec3],
    vel_half: &mut [Vec3],
    kick: Kick,
    span: &mut Span,
    mut spin: impl FnMut(usize),
) {
    let n = pos.len();
    let Kick { force, inv_mass, dt } = kick;
    let (vel, vel_half, force, inv_mass) = (&mut vel[..n], &mut vel_half[..n], &force[..n], &inv_mass[..n]);
    for k in 0..n {
        let u = translate_half(
            &mut pos[k],
            &mut vel[k],
            &mut vel_half[k],
            &force[k],
            0.5 * dt * inv_mass[k],
            dt,
            PLANAR,
        );
        span.add(&u);
        spin(k);
    }
}

/// What kicks a block's velocities: the forces (N) and inverse masses (1/kg) of its
/// particles, and the step (s).
#[derive(Clone, Copy)]
struct Kick<'a> {
    force: &'a [Vec3],
    inv_mass: &'a [f64],
    dt: f64,
}

/// Velocity Verlet's first half-kick, drift and force predictor for one particle: with
/// `c = dt / (2 m)`, `v_half = v + F c`, `x += v_half dt`, `v = v_half + F c`; in x and y
/// only when `planar`. Returns the new `v_half`, from registers: reading it back from memory
/// after the planar case's two 8-byte stores would be one 16-byte load that the processor
/// cannot forward from those stores (a stall of about ten cycles per particle).
#[inline(always)]
fn translate_half(x: &mut Vec3, v: &mut Vec3, v_half: &mut Vec3, f: &Vec3, c: f64, dt: f64, planar: bool) -> Vec3 {
    if planar {
        let (kx, ky) = (f.x * c, f.y * c);
        let u = Vec3::new(v.x + kx, v.y + ky, v_half.z);
        *v_half = u;
        x.x += u.x * dt;
        x.y += u.y * dt;
        v.x = u.x + kx; // predictor for the forces
        v.y = u.y + ky;
        u
    } else {
        let half_kick = f * c;
        let u = *v + half_kick;
        *v_half = u;
        *x += u * dt;
        *v = u + half_kick; // predictor for the forces
        u
    }
}

/// Velocity Verlet's half-kick of the spin and its predictor for one particle: with
/// `c = dt / (2 I)`, `omega_half = omega + T c`, `omega = omega_half + T c`.
#[inline(always)]
fn rotate_half(omega: &mut Vec3, omega_half: &mut Vec3, torque: &Vec3, c: f64) {
    let half_kick = torque * c;
    *omega_half = *omega + half_kick;
    *omega = *omega_half + half_kick;
}

/// Component-wise bounds of a set of vectors.
struct Span {
    lo: Vec3,
    hi: Vec3,
}

impl Span {
    fn new() -> Self {
        Self {
            lo: Vec3::repeat(f64::INFINITY),
            hi: Vec3::repeat(f64::NEG_INFINITY),
        }
    }

    /// `if` rather than `inf`/`sup`: one minsd/maxsd per component (equal results).
    #[inline(always)]
    fn add(&mut self, u: &Vec3) {
        for k in 0..3 {
            self.lo[k] = if u[k] < self.lo[k] { u[k] } else { self.lo[k] };
            self.hi[k] = if u[k] > self.hi[k] { u[k] } else { self.hi[k] };
        }
    }
}

/// The energy (J) by which velocity Verlet's kick leaves the work of the dissipative forces
/// `drag` (per grain, or torques per grain) short of the power booked for them at the
/// predicted velocities `predicted` over a step `dt`, given the velocities `kicked` after the
/// kick: `sum_k drag_k . (kicked_k - predicted_k) dt`.
///
/// The ledger books a contact's dissipation as its power `-D . p` at the velocity `p` the
/// force saw, the predicted `v(t) + F(t) dt / m`, times `dt`. The kick then sets
/// `v(t + dt) = p + (F(t + dt) - F(t)) dt / (2 m)`, and over the steps the work of `D` is
/// (up to terms that telescope, and the trapezoid's cross term below)
/// `sum D . v dt = sum D . p dt + sum D . (v - p) dt`. Where `D` changes little over a step
/// the second sum is of second order; where a force relaxes its own slip (the Haff-Werner
/// viscous branch removing a fraction `b` of it per step) it is
/// `sum |D(t) - D(t - dt)|^2 dt^2 / (4 m)`, and the booking without it overstates the loss:
/// by 0.13 % at `b = 0.05`, 11 % at `b = 0.4` and half at the cap `b = 2/3` for a slip
/// relaxing from a contact's start
/// (`contact::tangential::tests::the_ledger_books_the_energy_a_relaxing_slip_loses`).
/// Velocity Verlet's step changes the kinetic energy by exactly
/// `(F(t) + F(t + dt)) . (v(t) + v(t + dt)) dt / 4`; its other difference from the sums
/// above, `-(D(t + dt) - D(t)) . (v(t + dt) - v(t)) dt / 4`, telescopes where `D` is the
/// only force, and is left out.
#[inline]
pub fn verlet_excess(drag: &[Vec3], predicted: &[Vec3], kicked: &[Vec3], dt: f64) -> f64 {
    let n = drag.len();
    let (predicted, kicked) = (&predicted[..n], &kicked[..n]);
    let mut sum = 0.0;
    for k in 0..n {
        sum += drag[k].dot(&(kicked[k] - predicted[k]));
    }
    sum * dt
}

/// Integration scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Velocity Verlet for translation and rotation (default). Positions advance with the
    /// half-step velocity `v(t + dt/2)`; velocity-dependent forces (damping, friction) are
    /// evaluated with the predicted full-step velocity `v(t + dt/2) + a(t) dt/2` rather than
    /// the half-step one (which lags by `dt/2` and makes restitution only first order).
    /// Second order for dissipative contacts, symplectic for conservative ones, and exact
    /// conservation of linear and angular momentum.
    #[default]
    VelocityVerlet,
    /// The thesis' scheme (sec 3.5.1): Verlet positions (eq 3.26, written in its leapfrog
    /// form), velocities from the central-difference estimator eq 3.27, Euler rotation
    /// (eq 3.22-3.23), started by the backward Euler step below eq 3.27.
    Thesis,
}

impl std::str::FromStr for Integrator {
    type Err = crate::error::UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "velocity-verlet" => Ok(Integrator::VelocityVerlet),
            "thesis" => Ok(Integrator::Thesis),
            _ => Err(crate::error::UnknownName {
                what: "integrator",
                given: s.into(),
                expected: Self::NAMES,
            }),
        }
    }
}

impl Integrator {
    /// Every name, as scene files and the command line write it.
    pub const NAMES: &'static [&'static str] = &["velocity-verlet", "thesis"];

    /// Prepares the first step after the initial force evaluation.
    pub fn start(&self, s: &mut State, dt: f64) {
        match self {
            Integrator::VelocityVerlet => {}
            Integrator::Thesis => {
                // r(t - dt) = r - dt (v - dt a)  =>  u_{-1/2} = (r - r(t-dt)) / dt = v - dt a.
                for i in 0..s.len() {
                    s.vel_half[i] = s.vel[i] - s.force[i] * (dt * s.inv_mass[i]);
                }
            }
        }
    }

    /// Stage before the force evaluation for every particle of block `b`: positions to
    /// `t + dt`, and velocities and spins to where the force evaluation needs them.
    ///
    /// `planar`: the particles move in the x-y plane only (pinned layer, with zero vertical
    /// force and velocity): velocity Verlet leaves z alone, which is what its arithmetic on
    /// z would give anyway (adding exact zeros).
    ///
    /// Returns the box `(lo, hi)` spanned by the displacement velocities of this step
    /// (`position += u dt`), for the neighbour list's drift bound, computed in the same loop.
    #[inline(always)]
    pub fn before_forces(&self, b: &mut StateBlock, dt: f64, rotate: bool, planar: bool) -> (Vec3, Vec3) {
        let n = b.pos.len();
        let (pos, vel, vel_half, force, inv_mass) = (
            &mut b.pos[..n],
            &mut b.vel[..n],
            &mut b.vel_half[..n],
            &b.force[..n],
            &b.inv_mass[..n],
        );
        let (omega, omega_half, torque, inv_inertia) = (&mut b.omega[..n], &mut b.omega_half[..n], &b.torque[..n], &b.inv_inertia[..n]);
        let mut span = Span::new();
        let kick = Kick { force, inv_mass, dt };
        match (self, planar) {
            // Translation and rotation in one loop (when both are integrated), with the
            // planar and the non-rotating cases as their own loops.
            (Integrator::VelocityVerlet, true) if rotate => verlet_first_half::<true>(pos, vel, vel_half, kick, &mut span, |k| {
                rotate_half(&mut omega[k], &mut omega_half[k], &torque[k], 0.5 * dt * inv_inertia[k]);
            }),
            (Integrator::VelocityVerlet, false) if rotate => verlet_first_half::<false>(pos, vel, vel_half, kick, &mut span, |k| {
                rotate_half(&mut omega[k], &mut omega_half[k], &torque[k], 0.5 * dt * inv_inertia[k]);
            }),
            (Integrator::VelocityVerlet, true) => verlet_first_half::<true>(pos, vel, vel_half, kick, &mut span, |_| {}),
            (Integrator::VelocityVerlet, false) => verlet_first_half::<false>(pos, vel, vel_half, kick, &mut span, |_| {}),
            (Integrator::Thesis, _) => {
                for k in 0..n {
                    let a = force[k] * inv_mass[k];
                    vel_half[k] += a * dt; // u_{n+1/2} = u_{n-1/2} + dt a_n
                    pos[k] += vel_half[k] * dt; // eq 3.26
                    vel[k] = vel_half[k] + a * (0.5 * dt); // eq 3.27
                    span.add(&vel_half[k]);
                }
                if rotate {
                    for k in 0..n {
                        omega[k] += torque[k] * (dt * inv_inertia[k]); // eq 3.23
                    }
                }
            }
        }
        (span.lo, span.hi)
    }

    /// True if the scheme has a stage after the force evaluation ([`Self::after_kick`]).
    pub fn has_after_stage(&self) -> bool {
        match self {
            Integrator::VelocityVerlet => true,
            Integrator::Thesis => false,
        }
    }

    /// Stage after the force evaluation, for the velocities (or spins) of a block of
    /// particles: `half[k]`, the half-step value, becomes the value at `t + dt` given the new
    /// force (or torque) `rate[k]` and inverse mass (or inverse inertia) `inv[k]`:
    /// `half + rate dt inv / 2` (velocity Verlet; nothing for schemes without an after
    /// stage). [`crate::sim`] runs it on the half-step arrays, out of place, while other
    /// particles still read the predicted velocities.
    pub fn after_kick(&self, half: &mut [Vec3], rate: &[Vec3], inv: &[f64], dt: f64) {
        match self {
            Integrator::VelocityVerlet => {
                let n = half.len();
                let (rate, inv) = (&rate[..n], &inv[..n]);
                for k in 0..n {
                    self.kick(&mut half[k], &rate[k], inv[k], dt);
                }
            }
            Integrator::Thesis => {}
        }
    }

    /// [`Self::after_kick`] for one particle: `half += rate dt inv / 2` (velocity Verlet), so
    /// that a caller can fuse it with other per-particle work.
    #[inline(always)]
    pub fn kick(&self, half: &mut Vec3, rate: &Vec3, inv: f64, dt: f64) {
        match self {
            Integrator::VelocityVerlet => *half += rate * (0.5 * dt * inv),
            Integrator::Thesis => {}
        }
    }

    /// Formal order of accuracy of the trajectory.
    pub fn order(&self) -> u32 {
        match self {
            Integrator::VelocityVerlet => 2,
            Integrator::Thesis => 1,
        }
    }
}
