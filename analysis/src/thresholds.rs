//! The lift-off and melting thresholds of the drive, from a DEM phase map (issue 40, step 1):
//! one run has one drive, so the coarse model's thresholds come from the cells of a
//! `stripes phase-map --model dem` (its `phase_map.csv`).
//!
//! Per frequency, each amplitude's phase is the majority over its samples (a tie decides
//! nothing). Scanning the amplitudes upwards:
//! - **lift-off**: the first amplitude whose phase is not `nothing` (grains move on the
//!   tray), with the last `nothing` amplitude below it;
//! - **melting**: after the first `stripes` amplitude, the first whose phase is `gas`, with
//!   the last `stripes` amplitude below it.
//!
//! A threshold lies between its two amplitudes; `below` is None when no decided amplitude
//! lies below it (the map's lowest is already past it, or undecided).

use serde::Serialize;

use crate::classify::Phase;

/// One cell of a phase map: a run's drive and its phase.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapCell {
    pub frequency: f64,
    pub amplitude: f64,
    pub phase: Phase,
}

/// A threshold between two mapped amplitudes (m), and its tray accelerations
/// `A (2 pi f)^2 / g` (the DEM's `g`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bounds {
    pub below_m: Option<f64>,
    pub at_m: f64,
    pub gamma_below: Option<f64>,
    pub gamma_at: f64,
}

/// The thresholds at one frequency (Hz).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrequencyThresholds {
    pub frequency: f64,
    pub lift_off: Option<Bounds>,
    pub melting: Option<Bounds>,
}

/// The thresholds of every frequency of the map, in increasing frequency; `g` (m/s^2) for
/// the tray accelerations.
pub fn thresholds(cells: &[MapCell], g: f64) -> Vec<FrequencyThresholds> {
    let gamma = |a: f64, f: f64| a * (std::f64::consts::TAU * f).powi(2) / g;
    let mut freqs: Vec<f64> = cells.iter().map(|c| c.frequency).collect();
    freqs.sort_by(f64::total_cmp);
    freqs.dedup();
    freqs
        .into_iter()
        .map(|f| {
            let mut amps: Vec<f64> = cells.iter().filter(|c| c.frequency == f).map(|c| c.amplitude).collect();
            amps.sort_by(f64::total_cmp);
            amps.dedup();
            // The majority phase of each amplitude; a tie decides nothing.
            let decided: Vec<(f64, Phase)> = amps
                .into_iter()
                .filter_map(|a| {
                    let here: Vec<Phase> = cells
                        .iter()
                        .filter(|c| c.frequency == f && c.amplitude == a)
                        .map(|c| c.phase)
                        .collect();
                    [Phase::Nothing, Phase::Stripes, Phase::Gas]
                        .into_iter()
                        .find(|p| 2 * here.iter().filter(|q| *q == p).count() > here.len())
                        .map(|p| (a, p))
                })
                .collect();
            let bounds = |below: Option<f64>, at: f64| Bounds {
                below_m: below,
                at_m: at,
                gamma_below: below.map(|b| gamma(b, f)),
                gamma_at: gamma(at, f),
            };
            let lift = decided.iter().position(|&(_, p)| p != Phase::Nothing);
            let lift_off = lift.map(|k| {
                let below = decided[..k].iter().rev().find(|&&(_, p)| p == Phase::Nothing).map(|&(a, _)| a);
                bounds(below, decided[k].0)
            });
            let melting = decided.iter().position(|&(_, p)| p == Phase::Stripes).and_then(|s| {
                let g = s + decided[s..].iter().position(|&(_, p)| p == Phase::Gas)?;
                let below = decided[..g].iter().rev().find(|&&(_, p)| p == Phase::Stripes).map(|&(a, _)| a);
                Some(bounds(below, decided[g].0))
            });
            FrequencyThresholds {
                frequency: f,
                lift_off,
                melting,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(frequency: f64, amplitude: f64, phase: Phase) -> MapCell {
        MapCell {
            frequency,
            amplitude,
            phase,
        }
    }

    #[test]
    fn thresholds_lie_between_the_majority_phases() {
        use Phase::*;
        let cells = [
            // 3 Hz: nothing, nothing | gas (tie: undecided at 4 mm), stripes, stripes, gas.
            cell(3.0, 0.002, Nothing),
            cell(3.0, 0.002, Nothing),
            cell(3.0, 0.004, Gas),
            cell(3.0, 0.004, Nothing),
            cell(3.0, 0.006, Stripes),
            cell(3.0, 0.006, Gas),
            cell(3.0, 0.006, Stripes),
            cell(3.0, 0.010, Stripes),
            cell(3.0, 0.020, Gas),
            // 5 Hz: moving from the lowest amplitude, never stripes.
            cell(5.0, 0.002, Gas),
            cell(5.0, 0.010, Gas),
        ];
        let t = thresholds(&cells, 10.0);
        assert_eq!(t.len(), 2);
        let lift = t[0].lift_off.unwrap();
        assert_eq!((lift.below_m, lift.at_m), (Some(0.002), 0.006), "the tie at 4 mm decides nothing");
        let g = 0.006 * (std::f64::consts::TAU * 3.0).powi(2) / 10.0;
        assert!((lift.gamma_at - g).abs() < 1e-12);
        let melt = t[0].melting.unwrap();
        assert_eq!((melt.below_m, melt.at_m), (Some(0.010), 0.020));
        let lift5 = t[1].lift_off.unwrap();
        assert_eq!((lift5.below_m, lift5.at_m), (None, 0.002), "moving below the map");
        assert_eq!(t[1].melting, None, "no stripes, no melting");
    }
}
