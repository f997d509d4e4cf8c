//! Time integrators. Each splits a step into the part before the force evaluation and the
//! part after it, as kernels over a block of particles; [`crate::sim`] calls them in that
//! order.

use crate::state::{State, StateBlock};
use crate::Vec3;

/// The components of a slice of vectors, `[x0, y0, z0, x1, ...]`.
#[inline(always)]
pub(crate) fn flat(v: &[Vec3]) -> &[f64] {
    bytemuck::cast_slice(v)
}

/// [`flat`], mutable.
#[inline(always)]
pub(crate) fn flat_mut(v: &mut [Vec3]) -> &mut [f64] {
    bytemuck::cast_slice_mut(v)
}

/// Velocity Verlet's half-kick coefficients `c = dt / (2 m)` and `dt / (2 I)` of every
/// particle, each repeated for its three components: the stages then run as flat loops over
/// the components of a block, which the compiler vectorises, with the same arithmetic per
/// component as a loop over particles (so the same bits).
#[derive(Clone, Debug, Default)]
pub(crate) struct HalfKicks {
    /// The step they were computed for.
    dt: f64,
    /// `dt / (2 m_i)`, three times per particle (s/kg).
    pub v: Vec<f64>,
    /// `dt / (2 I_i)`, three times per particle (s/(kg m^2)).
    pub w: Vec<f64>,
}

impl HalfKicks {
    /// Recomputes the coefficients if the step or the number of particles changed.
    pub fn refresh(&mut self, s: &State, dt: f64) {
        if self.dt == dt && self.v.len() == 3 * s.len() {
            return;
        }
        let repeat = |inv: &[f64]| inv.iter().flat_map(|&inv| [0.5 * dt * inv; 3]).collect();
        (self.dt, self.v, self.w) = (dt, repeat(&s.inv_mass), repeat(&s.inv_inertia));
    }
}

/// Velocity Verlet's first stage over the components of one block: with the half-kick
/// coefficient `c`, `v_half = v + F c`, `x += v_half dt`, `v = v_half + F c` (the predictor
/// for the forces), and, when `rotate`, `omega_half = omega + T c_I`, `omega = omega_half +
/// T c_I`. A pinned layer's vertical components are exact zeros of force and velocity, so
/// its z and v_z stay exactly as they are.
#[inline(always)]
fn verlet_first_half(b: &mut StateBlock, kv: &[f64], kw: &[f64], dt: f64, rotate: bool) {
    let x = flat_mut(b.pos);
    let n = x.len();
    let (v, vh, f, c) = (
        &mut flat_mut(b.vel)[..n],
        &mut flat_mut(b.vel_half)[..n],
        &flat(b.force)[..n],
        &kv[..n],
    );
    if rotate {
        let (w, wh, t, ci) = (
            &mut flat_mut(b.omega)[..n],
            &mut flat_mut(b.omega_half)[..n],
            &flat(b.torque)[..n],
            &kw[..n],
        );
        for k in 0..n {
            let half_kick = f[k] * c[k];
            vh[k] = v[k] + half_kick;
            x[k] += vh[k] * dt;
            v[k] = vh[k] + half_kick;
            let half_turn = t[k] * ci[k];
            wh[k] = w[k] + half_turn;
            w[k] = wh[k] + half_turn;
        }
    } else {
        for k in 0..n {
            let half_kick = f[k] * c[k];
            vh[k] = v[k] + half_kick;
            x[k] += vh[k] * dt;
            v[k] = vh[k] + half_kick;
        }
    }
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

/// Integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Velocity Verlet for translation and rotation (default). Positions advance with the
    /// half-step velocity `v(t + dt/2)`; velocity-dependent forces (damping, friction) are
    /// evaluated with the predicted full-step velocity `v(t + dt/2) + a(t) dt/2` rather than
    /// the half-step one (which lags by `dt/2` and makes restitution only first order).
    /// Second order for dissipative contacts, symplectic for conservative ones, and exact
    /// conservation of linear and angular momentum.
    VelocityVerlet,
    /// The thesis' scheme (sec 3.5.1): Verlet positions (eq 3.26, written in its leapfrog
    /// form), velocities from the central-difference estimator eq 3.27, Euler rotation
    /// (eq 3.22-3.23), started by the backward Euler step below eq 3.27.
    Thesis,
}

impl Integrator {
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
    /// `t + dt`, and velocities and spins to where the force evaluation needs them. `kicks`
    /// are the block's [`HalfKicks`] `(v, w)` (used by velocity Verlet).
    ///
    /// Returns the box `(lo, hi)` spanned by the displacement velocities of this step
    /// (`position += u dt`), for the neighbour list's drift bound.
    #[inline(always)]
    pub fn before_forces(&self, b: &mut StateBlock, kicks: (&[f64], &[f64]), dt: f64, rotate: bool) -> (Vec3, Vec3) {
        let mut span = Span::new();
        match self {
            Integrator::VelocityVerlet => {
                verlet_first_half(b, kicks.0, kicks.1, dt, rotate);
                b.vel_half.iter().for_each(|u| span.add(u));
            }
            Integrator::Thesis => {
                let n = b.pos.len();
                let (pos, vel, vel_half, force, inv_mass) = (
                    &mut b.pos[..n],
                    &mut b.vel[..n],
                    &mut b.vel_half[..n],
                    &b.force[..n],
                    &b.inv_mass[..n],
                );
                for k in 0..n {
                    let a = force[k] * inv_mass[k];
                    vel_half[k] += a * dt; // u_{n+1/2} = u_{n-1/2} + dt a_n
                    pos[k] += vel_half[k] * dt; // eq 3.26
                    vel[k] = vel_half[k] + a * (0.5 * dt); // eq 3.27
                    span.add(&vel_half[k]);
                }
                if rotate {
                    let (omega, torque, inv_inertia) = (&mut b.omega[..n], &b.torque[..n], &b.inv_inertia[..n]);
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
    /// particles, over their components: `half[k]`, the half-step value, becomes the value at
    /// `t + dt` given the new force (or torque) `rate[k]` and the half-kick coefficient `c[k]`
    /// ([`HalfKicks`]): `half + rate c` (velocity Verlet; nothing for schemes without an after
    /// stage). [`crate::sim`] runs it on the half-step arrays, out of place, while other
    /// particles still read the predicted velocities.
    pub fn after_kick(&self, half: &mut [Vec3], rate: &[Vec3], c: &[f64]) {
        match self {
            Integrator::VelocityVerlet => {
                let half = flat_mut(half);
                let n = half.len();
                let (rate, c) = (&flat(rate)[..n], &c[..n]);
                for k in 0..n {
                    half[k] += rate[k] * c[k];
                }
            }
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
