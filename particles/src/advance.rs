//! Advancing a run with observers: how code outside the physics sees a run. The physics crate knows no file
//! format; [`advance`] steps a [`Simulation`] and hands it, read-only, to each observer after
//! every step. An observer decides itself whether it is due (a snapshot at the next phase, a
//! checkpoint every so many steps, a thermo row at its interval) and does its work: the
//! formats live with the observers (the `stripes` crate and `analysis`), not here.
//!
//! Observers run in the order given, after the step and before the next one, so an observer
//! always sees the state at `sim.time` with the forces of that state.

use std::time::Instant;

use crate::sim::Simulation;
use crate::SimError;

/// Error of an observer (e.g. a file that cannot be written): a message for the user.
pub type ObserverError = Box<dyn std::error::Error + Send + Sync>;

/// Something that looks at a running simulation after every step.
pub trait Observer {
    /// Called after each step with the simulation at its new time. Cheap when not due.
    fn observe(&mut self, sim: &Simulation) -> Result<(), ObserverError>;

    /// Whether the observer needs the per-contact diagnostics ([`Simulation::contact_records`]) of
    /// step `step` (counted from 1), the step about to run. Recording costs time, so
    /// [`advance`] turns it on only for the steps some observer asks for.
    fn wants_contacts(&self, _step: u64) -> bool {
        false
    }
}

impl<F: FnMut(&Simulation) -> Result<(), ObserverError>> Observer for F {
    fn observe(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        self(sim)
    }
}

/// Why [`advance`] stopped before `until`.
#[derive(Debug)]
pub enum Stop {
    /// The physics refused a step (non-finite value, escaped grain, excessive overlap).
    Sim(SimError),
    /// An observer failed.
    Observer(ObserverError),
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::Sim(e) => write!(f, "{e}"),
            Stop::Observer(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for Stop {}

/// Steps `sim` until it has completed `until` steps, calling every observer after each step.
/// Returns the wall-clock seconds spent in the steps themselves (not in the observers).
pub fn advance(sim: &mut Simulation, until: u64, observers: &mut [&mut dyn Observer]) -> Result<f64, Stop> {
    advance_while(sim, |s| s.steps < until, observers)
}

/// Steps `sim` until its time reaches `until_s`: the last step is the first whose end lies at
/// or after `until_s` less half a step. Observers and the returned seconds as [`advance`].
/// With [`AtTimes`], this is the sample loop of a run measured in memory.
pub fn advance_to(sim: &mut Simulation, until_s: f64, observers: &mut [&mut dyn Observer]) -> Result<f64, Stop> {
    advance_while(sim, |s| s.time < until_s - 0.5 * s.setup.dt, observers)
}

fn advance_while(sim: &mut Simulation, more: impl Fn(&Simulation) -> bool, observers: &mut [&mut dyn Observer]) -> Result<f64, Stop> {
    let mut stepping = 0.0;
    let mut recording = false;
    while more(sim) {
        let record = observers.iter().any(|o| o.wants_contacts(sim.steps + 1));
        if record != recording {
            sim.record_contacts(record);
            recording = record;
        }
        let t0 = Instant::now();
        sim.step().map_err(Stop::Sim)?;
        stepping += t0.elapsed().as_secs_f64();
        for o in observers.iter_mut() {
            o.observe(sim).map_err(Stop::Observer)?;
        }
    }
    if recording {
        sim.record_contacts(false);
    }
    Ok(stepping)
}

/// An observer that calls `at(sim, t)` once for each of its times `t` (s, increasing), after
/// the first step whose end lies at or after `t` less half a step: a run sampled at given
/// times, in memory.
pub struct AtTimes<F> {
    times: Vec<f64>,
    next: usize,
    at: F,
}

impl<F: FnMut(&Simulation, f64) -> Result<(), ObserverError>> AtTimes<F> {
    pub fn new(times: Vec<f64>, at: F) -> Self {
        AtTimes { times, next: 0, at }
    }

    /// The last time, where a run sampled by this observer may stop ([`advance_to`]).
    pub fn last(&self) -> Option<f64> {
        self.times.last().copied()
    }
}

impl<F: FnMut(&Simulation, f64) -> Result<(), ObserverError>> Observer for AtTimes<F> {
    fn observe(&mut self, sim: &Simulation) -> Result<(), ObserverError> {
        while let Some(&t) = self.times.get(self.next) {
            if sim.time < t - 0.5 * sim.setup.dt {
                break;
            }
            self.next += 1;
            (self.at)(sim, t)?;
        }
        Ok(())
    }
}
