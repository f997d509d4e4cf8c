//! Typed edits of a scene: what a job of a sweep or a setting of a study changes, applied
//! to the scene itself, not written as `key=value` text and parsed back. Each edit is one
//! scene key; [`DemEdit::to_set`] gives the `--set` text of the same change, for the
//! records that are written to disk.

use particles::contact::choice::{NormalKind, TangentialKind};
use particles::scene::{AutoDt, Scene, TimeStep};
use serde::{Deserialize, Serialize};

use crate::scene::file::SceneFile;

/// One of the DEM's toggles (`[toggles]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DemToggle {
    Friction,
    Jumping,
    Dissipation,
    Walls,
    Rolling,
}

/// One change of the DEM's scene.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DemEdit {
    /// `drive.frequency` (Hz).
    Frequency(f64),
    /// `drive.amplitude` (m).
    Amplitude(f64),
    /// `run.seed`, and so the prepared sample.
    Seed(u64),
    /// `particles.count` in the same box.
    Count(usize),
    /// `run.threads`.
    Threads(usize),
    /// `run.dt = "auto"`.
    AutoStep,
    /// `run.dt` fixed (s): an ablation's toggles run at the reference's step.
    Step(f64),
    /// `toggles.<name> = false`.
    Off(DemToggle),
    /// `material.young` (Pa).
    Young(f64),
    /// `contact.normal`.
    Normal(NormalKind),
    /// `contact.kn` (N/m).
    Kn(f64),
    /// `contact.gamma_n` (kg/s).
    GammaN(f64),
    /// `contact.tangential`.
    Tangential(TangentialKind),
    /// `contact.tangential_stiffness` (N/m).
    TangentialStiffness(f64),
    /// `contact.friction` (`inf`: no Coulomb cap).
    Friction(f64),
    /// `contact.wall_friction`.
    WallFriction(f64),
}

impl DemToggle {
    fn key(self) -> &'static str {
        match self {
            DemToggle::Friction => "friction",
            DemToggle::Jumping => "jumping",
            DemToggle::Dissipation => "dissipation",
            DemToggle::Walls => "walls",
            DemToggle::Rolling => "rolling",
        }
    }
}

impl DemEdit {
    /// Applies the edit, as `--set` of [`DemEdit::to_set`] would.
    pub fn apply(self, scene: &mut Scene) {
        match self {
            DemEdit::Frequency(f) => scene.drive.frequency = f,
            DemEdit::Amplitude(x) => scene.drive.amplitude = x,
            DemEdit::Seed(s) => scene.run.seed = s,
            DemEdit::Count(n) => scene.particles.count = n,
            DemEdit::Threads(n) => scene.run.threads = n,
            DemEdit::AutoStep => scene.run.dt = TimeStep::Auto(AutoDt::Auto),
            DemEdit::Step(dt) => scene.run.dt = TimeStep::Seconds(dt),
            DemEdit::Off(t) => {
                let toggles = &mut scene.toggles;
                *match t {
                    DemToggle::Friction => &mut toggles.friction,
                    DemToggle::Jumping => &mut toggles.jumping,
                    DemToggle::Dissipation => &mut toggles.dissipation,
                    DemToggle::Walls => &mut toggles.walls,
                    DemToggle::Rolling => &mut toggles.rolling,
                } = false;
            }
            DemEdit::Young(y) => scene.material.young = y,
            DemEdit::Normal(k) => scene.contact.normal = k,
            DemEdit::Kn(k) => scene.contact.kn = Some(k),
            DemEdit::GammaN(g) => scene.contact.gamma_n = Some(g),
            DemEdit::Tangential(k) => scene.contact.tangential = k,
            DemEdit::TangentialStiffness(k) => scene.contact.tangential_stiffness = Some(k),
            DemEdit::Friction(mu) => scene.contact.friction = mu,
            DemEdit::WallFriction(mu) => scene.contact.wall_friction = mu,
        }
    }

    /// The same change as a `--set` override (`key=value`).
    pub fn to_set(self) -> String {
        match self {
            DemEdit::Frequency(f) => format!("drive.frequency={f:?}"),
            DemEdit::Amplitude(x) => format!("drive.amplitude={x:?}"),
            DemEdit::Seed(s) => format!("run.seed={s}"),
            DemEdit::Count(n) => format!("particles.count={n}"),
            DemEdit::Threads(n) => format!("run.threads={n}"),
            DemEdit::AutoStep => "run.dt=\"auto\"".into(),
            DemEdit::Step(dt) => format!("run.dt={dt:e}"),
            DemEdit::Off(t) => format!("toggles.{}=false", t.key()),
            DemEdit::Young(y) => format!("material.young={y:e}"),
            DemEdit::Normal(k) => format!("contact.normal=\"{}\"", k.name()),
            DemEdit::Kn(k) => format!("contact.kn={k:e}"),
            DemEdit::GammaN(g) => format!("contact.gamma_n={g:e}"),
            DemEdit::Tangential(k) => format!("contact.tangential=\"{}\"", k.name()),
            DemEdit::TangentialStiffness(k) => format!("contact.tangential_stiffness={k}"),
            DemEdit::Friction(mu) => format!("contact.friction={}", number(mu)),
            DemEdit::WallFriction(mu) => format!("contact.wall_friction={}", number(mu)),
        }
    }
}

/// A number as scene text (`inf` for infinity, as TOML writes it).
fn number(x: f64) -> String {
    if x == f64::INFINITY {
        "inf".into()
    } else {
        format!("{x:?}")
    }
}

/// One ingredient of the automaton's `physical` rule (`[automaton]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AutomatonToggle {
    Threshold,
    FlightCap,
    Stochastic,
    Knock,
    Sideways,
    Rolling,
    Frustration,
    Trains,
}

/// One change of the automaton's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AutomatonEdit {
    /// `automaton.<name> = false`.
    Off(AutomatonToggle),
    /// `automaton.lateral = "none"`.
    LateralNone,
    /// `automaton.rule = "strict"`.
    StrictRule,
}

impl AutomatonEdit {
    /// Applies the edit, as `--set` of the same key would.
    pub fn apply(self, a: &mut automaton::Spec) {
        match self {
            AutomatonEdit::Off(t) => {
                *match t {
                    AutomatonToggle::Threshold => &mut a.threshold,
                    AutomatonToggle::FlightCap => &mut a.flight_cap,
                    AutomatonToggle::Stochastic => &mut a.stochastic,
                    AutomatonToggle::Knock => &mut a.knock,
                    AutomatonToggle::Sideways => &mut a.sideways,
                    AutomatonToggle::Rolling => &mut a.rolling,
                    AutomatonToggle::Frustration => &mut a.frustration,
                    AutomatonToggle::Trains => &mut a.trains,
                } = false;
            }
            AutomatonEdit::LateralNone => a.lateral = automaton::Lateral::None,
            AutomatonEdit::StrictRule => a.rule = automaton::RuleSet::Strict,
        }
    }
}

/// One change of an event-driven scene: a key the user varies (`events-sweep --vary`), read
/// by the event-driven scene's own loader as `--set` of the same key is, or the seed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EventsEdit {
    Set { key: String, value: f64 },
    Seed(u64),
}

impl EventsEdit {
    /// The `--set` text of the same change.
    pub fn to_set(&self) -> String {
        match self {
            EventsEdit::Set { key, value } => format!("{key}={value}"),
            EventsEdit::Seed(s) => format!("run.seed={s}"),
        }
    }
}

/// One change of a scene: of a tray scene file's DEM tables or its `[automaton]` table, or of
/// an event-driven scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Edit {
    Dem(DemEdit),
    Automaton(AutomatonEdit),
    Events(EventsEdit),
}

impl Edit {
    /// Applies the edit to its table of a tray scene file. An event-driven edit has no place
    /// in one: a sweep's jobs are checked to be of one scene kind before any runs
    /// (`studies::sweep::check_jobs`).
    pub fn apply(&self, file: &mut SceneFile) {
        match self {
            Edit::Dem(e) => e.apply(&mut file.dem),
            Edit::Automaton(e) => e.apply(&mut file.automaton),
            Edit::Events(e) => unreachable!("an event-driven edit ({}) on a tray scene", e.to_set()),
        }
    }
}

impl From<DemEdit> for Edit {
    fn from(e: DemEdit) -> Self {
        Edit::Dem(e)
    }
}

impl From<AutomatonEdit> for Edit {
    fn from(e: AutomatonEdit) -> Self {
        Edit::Automaton(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edit changes the scene exactly as `--set` of its key does, and changes it.
    #[test]
    fn each_edit_matches_its_set_override() {
        let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/stripes.toml"));
        let base = crate::scene::file::load(path, &[]).unwrap();
        let dem = [
            DemEdit::Frequency(7.5),
            DemEdit::Amplitude(0.02),
            DemEdit::Seed(9),
            DemEdit::Count(500),
            DemEdit::Threads(1),
            DemEdit::Step(5.0e-6),
            DemEdit::Off(DemToggle::Friction),
            DemEdit::Off(DemToggle::Jumping),
            DemEdit::Off(DemToggle::Dissipation),
            DemEdit::Off(DemToggle::Walls),
            DemEdit::Off(DemToggle::Rolling),
            DemEdit::Young(3e5),
            DemEdit::Normal(NormalKind::Linear),
            DemEdit::Kn(1.5e3),
            DemEdit::GammaN(2.5e-3),
            DemEdit::Tangential(TangentialKind::CundallStrack),
            DemEdit::TangentialStiffness(1000.0),
            DemEdit::Friction(f64::INFINITY),
            DemEdit::WallFriction(f64::INFINITY),
        ];
        for edit in dem {
            let mut edited = base.clone();
            Edit::from(edit).apply(&mut edited);
            let set = edit.to_set();
            let expected = crate::scene::file::load(path, std::slice::from_ref(&set)).unwrap();
            assert_eq!(edited, expected, "{edit:?} against --set {set}");
            assert_ne!(edited, base, "{edit:?} changes the stripe scene");
        }
        let automaton = [
            (AutomatonEdit::Off(AutomatonToggle::Threshold), "automaton.threshold=false"),
            (AutomatonEdit::Off(AutomatonToggle::FlightCap), "automaton.flight_cap=false"),
            (AutomatonEdit::Off(AutomatonToggle::Stochastic), "automaton.stochastic=false"),
            (AutomatonEdit::Off(AutomatonToggle::Knock), "automaton.knock=false"),
            (AutomatonEdit::Off(AutomatonToggle::Sideways), "automaton.sideways=false"),
            (AutomatonEdit::Off(AutomatonToggle::Rolling), "automaton.rolling=false"),
            (AutomatonEdit::Off(AutomatonToggle::Frustration), "automaton.frustration=false"),
            (AutomatonEdit::Off(AutomatonToggle::Trains), "automaton.trains=false"),
            (AutomatonEdit::StrictRule, "automaton.rule=strict"),
        ];
        for (edit, set) in automaton {
            let mut edited = base.clone();
            Edit::from(edit).apply(&mut edited);
            let expected = crate::scene::file::load(path, &[set.to_string()]).unwrap();
            assert_eq!(edited, expected, "{edit:?} against --set {set}");
            assert_ne!(edited, base, "{edit:?} changes the stripe scene");
        }
        // The stripe scene's lateral rule is already `none`: from `clusters` it comes back.
        let mut edited = crate::scene::file::load(path, &["automaton.lateral=clusters".into()]).unwrap();
        assert_ne!(edited, base);
        Edit::from(AutomatonEdit::LateralNone).apply(&mut edited);
        assert_eq!(edited, base);
        // The bench's scene is not on auto: the auto step is an edit there.
        let mut explicit = base.clone();
        explicit.dem.run.dt = TimeStep::Seconds(8e-6);
        let mut edited = explicit.clone();
        Edit::from(DemEdit::AutoStep).apply(&mut edited);
        assert_eq!(edited.dem.run.dt, base.dem.run.dt);
        assert_eq!(DemEdit::AutoStep.to_set(), "run.dt=\"auto\"");
    }
}
