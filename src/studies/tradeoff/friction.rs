//! The speed of each friction law on the bench's tray, as ratios against Haff-Werner timed
//! in the same call: no friction, Haff-Werner (eq 3.12, the thesis' law: the reference),
//! Haff-Werner with `friction = inf` (the viscous branch alone), the stripe work's uncapped
//! floor (`wall_friction = inf`: the viscous branch at the floor and side walls, Coulomb
//! between grains) and Cundall-Strack (eq 4.32-4.34, `k_t = 50 N/m`), each at two drives:
//! the thesis' 20 Hz / 25 mm and the experiment's 3 Hz / 10 mm (thesis 2.2.5).
//!
//! Two ratios per law and drive, each the median over pairs of runs (Haff-Werner, law) timed
//! back to back on the same lattice start, so that both runs of a pair see the same machine
//! load:
//! - at the same step (Haff-Werner's `dt = "auto"`): the cost of one particle-step;
//! - each at its own `dt = "auto"`, for the same simulated time: what a user of the law pays,
//!   including the step the law's restitution error allows.
//!
//! A run the simulation stops (for example on an overlap beyond the limit: the uncapped
//! floor launches grains at 20 Hz / 25 mm) gives no ratio; its row says why.

use serde::Serialize;

use super::setting::{base_scene, with, Config, Setting};
use super::shaken::run_tray;
use crate::scene::edit::DemEdit;
use particles::contact::choice::TangentialKind;
use particles::prepare::initial_state;
use particles::scene::Scene;
use particles::state::State;
use particles::time_step;
use particles::timescale;
use particles::SimError;

/// Stiffness (N/m) of the Cundall-Strack row: the value of the friction-law runs on the quick
/// scene (docs/results/friction-laws).
pub const CUNDALL_STRACK_KT: f64 = 50.0;

/// Timing pairs per ratio (at least; more if [`Config::tray_repeats`] asks for more).
const MIN_PAIRS: u32 = 3;

/// The drives of the table, `(frequency (Hz), amplitude (m))`.
pub const DRIVES: [(f64, f64); 2] = [(20.0, 0.025), (3.0, 0.01)];

/// One friction law at one drive and its speed relative to Haff-Werner.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawSpeed {
    /// Short name: `haff-werner`, `none`, `haff-werner-inf`, `uncapped-floor`, `cundall-strack`.
    pub key: &'static str,
    pub name: String,
    /// Drive frequency (Hz) and amplitude (m).
    pub frequency: f64,
    pub amplitude: f64,
    /// The law's edits of the bench's scene, as `--set` overrides (the record of the table).
    pub overrides: Vec<String>,
    /// Step chosen by `dt = "auto"` for this law (s), and its steps per shortest contact.
    pub dt_auto: f64,
    pub steps_per_contact_auto: f64,
    /// Haff-Werner's time over this law's at the same step and steps: the inverse of the
    /// relative cost of a particle-step (1 for Haff-Werner by definition; NaN if a run
    /// stopped).
    pub speed_same_step: f64,
    /// Haff-Werner's time over this law's, each at its own `dt = "auto"`, for the same
    /// simulated time (1 for Haff-Werner by definition; NaN if a run stopped).
    pub speed_auto: f64,
    /// Timing details in words (the spread of the pair ratios), or why a run stopped.
    pub outcome: String,
}

/// The laws of the table, as `(key, name, edits)`; Haff-Werner first.
pub fn laws() -> Vec<(&'static str, String, Vec<DemEdit>)> {
    vec![
        ("haff-werner", "Haff-Werner, mu = 0.7 (reference)".into(), Vec::new()),
        (
            "none",
            "none (frictionless)".into(),
            vec![DemEdit::Tangential(TangentialKind::None)],
        ),
        (
            "haff-werner-inf",
            "Haff-Werner, friction = inf (viscous branch alone)".into(),
            vec![DemEdit::Friction(f64::INFINITY), DemEdit::WallFriction(f64::INFINITY)],
        ),
        (
            "uncapped-floor",
            "Haff-Werner, uncapped floor (wall_friction = inf, mu = 0.7 between grains)".into(),
            vec![DemEdit::WallFriction(f64::INFINITY)],
        ),
        (
            "cundall-strack",
            format!("Cundall-Strack, k_t = {CUNDALL_STRACK_KT} N/m, mu = 0.7"),
            vec![
                DemEdit::Tangential(TangentialKind::CundallStrack),
                DemEdit::TangentialStiffness(CUNDALL_STRACK_KT),
            ],
        ),
    ]
}

/// The keys of [`laws`], in table order.
pub fn friction_law_keys() -> Vec<&'static str> {
    laws().into_iter().map(|(key, _, _)| key).collect()
}

/// Median of a non-empty list.
fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    let k = xs.len();
    if k % 2 == 1 {
        xs[k / 2]
    } else {
        0.5 * (xs[k / 2 - 1] + xs[k / 2])
    }
}

/// The timing of one law against the reference.
struct Timing {
    /// Median over the pairs of (reference time / law time).
    median: f64,
    ratios: Vec<f64>,
    /// Neighbour-list builds of the reference's run and of the law's (the same in every
    /// pair: the runs are deterministic). A law whose layer turns into a gas rebuilds the
    /// list more often and meets more grains: its particle-steps cost more for that reason.
    builds: (u64, u64),
}

/// [`Timing`] over `pairs` pairs of runs, each pair run back to back.
fn timed_ratio(
    (ref_scene, ref_setting): (&Scene, &Setting),
    (scene, setting): (&Scene, &Setting),
    state: &State,
    pairs: u32,
    cpu_time: bool,
) -> Result<Timing, SimError> {
    let mut ratios = Vec::new();
    let mut builds = (0, 0);
    for _ in 0..pairs {
        let r = run_tray(ref_scene, ref_setting, state, None, cpu_time)?;
        let s = run_tray(scene, setting, state, None, cpu_time)?;
        ratios.push(r.wall_s / s.wall_s);
        builds = (r.builds, s.builds);
    }
    Ok(Timing {
        median: median(ratios.clone()),
        ratios,
        builds,
    })
}

/// Times every law of [`laws`] against Haff-Werner on the bench's tray
/// ([`Config::tray_count`] grains for [`Config::tray_duration`]) at each of [`DRIVES`].
/// `progress` receives a line per law and drive.
pub fn friction_laws(config: &Config, progress: &mut impl FnMut(&str)) -> Result<Vec<LawSpeed>, SimError> {
    let mut rows = Vec::new();
    for (frequency, amplitude) in DRIVES {
        let base = with(
            &base_scene(config.tray_count, config.tray_duration),
            &[DemEdit::Frequency(frequency), DemEdit::Amplitude(amplitude)],
        )?;
        rows.extend(at_drive(&base, config, progress)?);
    }
    Ok(rows)
}

/// [`friction_laws`] on one scene.
fn at_drive(base: &Scene, config: &Config, progress: &mut impl FnMut(&str)) -> Result<Vec<LawSpeed>, SimError> {
    let state = initial_state(base)?;
    let pairs = config.tray_repeats.max(MIN_PAIRS);
    let auto = |edits: &[DemEdit]| -> Result<Scene, SimError> {
        let mut e = edits.to_vec();
        e.push(DemEdit::AutoStep);
        with(base, &e)
    };
    let laws = laws();
    let hw_auto = auto(&laws[0].2)?;
    let t_c = timescale::shortest_contact_time(base)?;
    let common_steps = t_c / time_step::for_scene(&hw_auto)?;
    let same_step = |name: &str| Setting::new(name, "friction law").steps(common_steps);
    let own_step = |name: &str| Setting::new(name, "friction law");
    let hw_same = same_step(&laws[0].1);
    let hw_own = own_step(&laws[0].1);
    let (frequency, amplitude) = (base.drive.frequency, base.drive.amplitude);

    let mut rows = Vec::new();
    for (key, name, edits) in &laws {
        let scene = auto(edits)?;
        let dt_auto = time_step::for_scene(&scene)?;
        let reference = edits.is_empty();
        let timed = timed_ratio((&hw_auto, &hw_same), (&scene, &same_step(name)), &state, pairs, config.cpu_time).and_then(|same| {
            let own = timed_ratio((&hw_auto, &hw_own), (&scene, &own_step(name)), &state, pairs, config.cpu_time)?;
            Ok((same, own))
        });
        let spread = |v: &[f64]| v.iter().map(|x| format!("{x:.2}")).collect::<Vec<_>>().join(", ");
        let (speed_same_step, speed_auto, outcome) = match timed {
            Ok((same, own)) => (
                if reference { 1.0 } else { same.median },
                if reference { 1.0 } else { own.median },
                format!(
                    "pair ratios at the same step: {}; at dt = auto: {}; neighbour-list builds at the same step: {} (Haff-Werner: {}){}",
                    spread(&same.ratios),
                    spread(&own.ratios),
                    same.builds.1,
                    same.builds.0,
                    if reference {
                        " (the reference against itself: the timing noise)"
                    } else {
                        ""
                    }
                ),
            ),
            Err(e) => (f64::NAN, f64::NAN, format!("stopped: {e}")),
        };
        rows.push(LawSpeed {
            key,
            name: name.clone(),
            frequency,
            amplitude,
            overrides: edits.iter().map(|e| e.to_set()).collect(),
            dt_auto,
            steps_per_contact_auto: t_c / dt_auto,
            speed_same_step,
            speed_auto,
            outcome,
        });
        progress(&format!("friction law at {frequency} Hz, {amplitude} m: {name}"));
    }
    Ok(rows)
}

/// The rows as a Markdown table.
pub fn friction_table(rows: &[LawSpeed]) -> String {
    let mut out = String::from(
        "| drive | friction law | dt auto (s) | steps/contact (auto) | speed at the same step (Haff-Werner = 1) | speed at dt = auto (Haff-Werner = 1) |\n|---|---|---|---|---|---|\n",
    );
    let ratio = |x: f64| {
        if x.is_nan() {
            "stopped, see below".to_string()
        } else {
            format!("{x:.2}")
        }
    };
    for r in rows {
        out.push_str(&format!(
            "| {} Hz, {} mm | {} | {:.2e} | {:.1} | {} | {} |\n",
            r.frequency,
            r.amplitude * 1e3,
            r.name,
            r.dt_auto,
            r.steps_per_contact_auto,
            ratio(r.speed_same_step),
            ratio(r.speed_auto)
        ));
    }
    out.push_str("\nTimings:\n\n");
    for r in rows {
        out.push_str(&format!("- {} Hz, {}: {}\n", r.frequency, r.name, r.outcome));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_law_of_the_table_is_a_valid_scene_and_the_reference_comes_first() {
        let base = base_scene(20, 0.02);
        let laws = laws();
        assert!(laws[0].2.is_empty(), "Haff-Werner, the reference, has no edits");
        for (_, name, edits) in &laws {
            with(&base, edits).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
