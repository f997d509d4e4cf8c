//! Typed edits of a sweep's scene: what one job changes, applied to the scene itself, not
//! written as `key=value` text and parsed back. Stored in `sweep.json` by name.

use serde::{Deserialize, Serialize};

use crate::scene_file::SceneFile;

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

/// One change of a job to the sweep's scene.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Edit {
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
    /// `toggles.<name> = false`.
    DemOff(DemToggle),
    /// `automaton.<name> = false`.
    AutomatonOff(AutomatonToggle),
    /// `automaton.lateral = "none"`.
    LateralNone,
    /// `automaton.rule = "strict"`.
    StrictRule,
}

impl Edit {
    /// Applies the edit to a scene file (both tables), as `--set` of the same key would.
    pub fn apply(self, file: &mut SceneFile) {
        let (scene, a) = (&mut file.dem, &mut file.automaton);
        match self {
            Edit::Frequency(f) => scene.drive.frequency = f,
            Edit::Amplitude(x) => scene.drive.amplitude = x,
            Edit::Seed(s) => scene.run.seed = s,
            Edit::Count(n) => scene.particles.count = n,
            Edit::Threads(n) => scene.run.threads = n,
            Edit::DemOff(t) => {
                let toggles = &mut scene.toggles;
                *match t {
                    DemToggle::Friction => &mut toggles.friction,
                    DemToggle::Jumping => &mut toggles.jumping,
                    DemToggle::Dissipation => &mut toggles.dissipation,
                    DemToggle::Walls => &mut toggles.walls,
                    DemToggle::Rolling => &mut toggles.rolling,
                } = false;
            }
            Edit::AutomatonOff(t) => {
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
            Edit::LateralNone => a.lateral = automaton::Lateral::None,
            Edit::StrictRule => a.rule = automaton::RuleSet::Strict,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edit changes the scene exactly as `--set` of its key does.
    #[test]
    fn each_edit_matches_its_set_override() {
        let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/stripes.toml"));
        let base = crate::scene_file::load(path, &[]).unwrap();
        let cases = [
            (Edit::Frequency(7.5), "drive.frequency=7.5"),
            (Edit::Amplitude(0.02), "drive.amplitude=0.02"),
            (Edit::Seed(9), "run.seed=9"),
            (Edit::Count(500), "particles.count=500"),
            (Edit::Threads(1), "run.threads=1"),
            (Edit::DemOff(DemToggle::Friction), "toggles.friction=false"),
            (Edit::DemOff(DemToggle::Jumping), "toggles.jumping=false"),
            (Edit::DemOff(DemToggle::Dissipation), "toggles.dissipation=false"),
            (Edit::DemOff(DemToggle::Walls), "toggles.walls=false"),
            (Edit::DemOff(DemToggle::Rolling), "toggles.rolling=false"),
            (Edit::AutomatonOff(AutomatonToggle::Threshold), "automaton.threshold=false"),
            (Edit::AutomatonOff(AutomatonToggle::FlightCap), "automaton.flight_cap=false"),
            (Edit::AutomatonOff(AutomatonToggle::Stochastic), "automaton.stochastic=false"),
            (Edit::AutomatonOff(AutomatonToggle::Knock), "automaton.knock=false"),
            (Edit::AutomatonOff(AutomatonToggle::Sideways), "automaton.sideways=false"),
            (Edit::AutomatonOff(AutomatonToggle::Rolling), "automaton.rolling=false"),
            (Edit::AutomatonOff(AutomatonToggle::Frustration), "automaton.frustration=false"),
            (Edit::AutomatonOff(AutomatonToggle::Trains), "automaton.trains=false"),
            (Edit::LateralNone, "automaton.lateral=none"),
            (Edit::StrictRule, "automaton.rule=strict"),
        ];
        for (edit, set) in cases {
            let mut edited = base.clone();
            edit.apply(&mut edited);
            let expected = crate::scene_file::load(path, &[set.to_string()]).unwrap();
            assert_eq!(edited, expected, "{edit:?} against --set {set}");
            if set != "automaton.lateral=none" {
                assert_ne!(edited, base, "{edit:?} changes the stripe scene");
            }
        }
    }
}
