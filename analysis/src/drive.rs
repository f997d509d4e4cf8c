//! The tray's horizontal motion as the analysis knows it: `x_tray(t)`, piecewise harmonic.
//!
//! A drive is a list of stages ([`Stage`]); from its `start` (s) on, stage `k` moves the tray
//! by `x_tray(t) = A_k sin(phi_k + 2 pi nu_k (t - start_k))`. The first stage also covers the
//! times before its start. The drive of today's scenes (`drive.frequency`, `drive.amplitude`:
//! `A sin(2 pi nu t)`, `particles::tray::drive`) is one stage starting at 0 with phase 0
//! ([`TrayDrive::harmonic`]); a schedule of several frequencies and amplitudes is several
//! stages ([`TrayDrive::from_stages`]), so nothing here assumes one frequency for a run.
//!
//! The camera of the experiment (thesis 2.2.6) filmed "at every second turning point of the
//! shaker": the tray at rest at one end of its stroke. Here that is the `+A` turning point,
//! phase `pi / 2` of each stage's sine ([`TrayDrive::turning_point`]).

use std::f64::consts::{FRAC_PI_2, TAU};

/// One stage of the drive: `x_tray(t) = amplitude sin(phase + 2 pi frequency (t - start))`
/// from `start` (s) on. Amplitude in m, frequency in Hz, phase in rad.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Stage {
    pub start: f64,
    pub frequency: f64,
    pub amplitude: f64,
    pub phase: f64,
}

/// The tray's displacement along x over a run: stages sorted by start (see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TrayDrive {
    stages: Vec<Stage>,
}

/// Why a list of stages is not a drive; each names the stage.
#[derive(Clone, Debug, PartialEq)]
pub enum DriveError {
    /// No stage at all.
    NoStages,
    /// A stage's field is not a finite number, or the frequency or amplitude is negative.
    Field { stage: usize, field: &'static str, value: f64 },
    /// A stage does not start after the one before it.
    StartOrder { stage: usize, start: f64, previous: f64 },
}

impl std::fmt::Display for DriveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DriveError::NoStages => write!(f, "a drive needs at least one stage"),
            DriveError::Field { stage, field, value } => {
                write!(
                    f,
                    "drive stage {stage}: {field} = {value} must be a finite number (frequency and amplitude >= 0)"
                )
            }
            DriveError::StartOrder { stage, start, previous } => write!(
                f,
                "drive stage {stage} starts at {start} s, not after stage {} (at {previous} s)",
                stage - 1
            ),
        }
    }
}

impl std::error::Error for DriveError {}

/// Where a time lies relative to the drive's `+A` turning points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurningPoint {
    /// Index of the stage in force.
    pub stage: usize,
    /// Which turning point of the stage is nearest (0: the first after the stage's start, or
    /// the one before it when that is nearer).
    pub index: i64,
    /// Time from that turning point to the given time, as a fraction of the stage's period,
    /// in `[-0.5, 0.5)`.
    pub offset: f64,
    /// The same in seconds.
    pub offset_s: f64,
}

impl TrayDrive {
    /// `A sin(2 pi nu t)`: one stage from t = 0 (today's scenes).
    pub fn harmonic(amplitude: f64, frequency: f64) -> Result<Self, DriveError> {
        Self::from_stages(vec![Stage {
            start: 0.0,
            frequency,
            amplitude,
            phase: 0.0,
        }])
    }

    /// A drive of several stages, each starting after the one before.
    pub fn from_stages(stages: Vec<Stage>) -> Result<Self, DriveError> {
        if stages.is_empty() {
            return Err(DriveError::NoStages);
        }
        for (k, s) in stages.iter().enumerate() {
            for (field, value, nonneg) in [
                ("start", s.start, false),
                ("frequency", s.frequency, true),
                ("amplitude", s.amplitude, true),
                ("phase", s.phase, false),
            ] {
                if !value.is_finite() || (nonneg && value < 0.0) {
                    return Err(DriveError::Field { stage: k, field, value });
                }
            }
            if k > 0 && s.start <= stages[k - 1].start {
                return Err(DriveError::StartOrder {
                    stage: k,
                    start: s.start,
                    previous: stages[k - 1].start,
                });
            }
        }
        Ok(Self { stages })
    }

    pub fn stages(&self) -> &[Stage] {
        &self.stages
    }

    /// Index of the stage in force at `t` (the first one before its start).
    pub fn stage_at(&self, t: f64) -> usize {
        self.stages.partition_point(|s| s.start <= t).saturating_sub(1)
    }

    /// `x_tray(t)` (m).
    pub fn displacement(&self, t: f64) -> f64 {
        let s = &self.stages[self.stage_at(t)];
        s.amplitude * (s.phase + TAU * s.frequency * (t - s.start)).sin()
    }

    /// The `+A` turning point nearest `t` within the stage in force; None when that stage does
    /// not move the tray (frequency or amplitude 0).
    pub fn turning_point(&self, t: f64) -> Option<TurningPoint> {
        let stage = self.stage_at(t);
        let s = &self.stages[stage];
        if s.frequency <= 0.0 || s.amplitude <= 0.0 {
            return None;
        }
        // Periods since the first turning point of the stage's sine.
        let periods = (s.phase + TAU * s.frequency * (t - s.start) - FRAC_PI_2) / TAU;
        let index = periods.round();
        let mut offset = periods - index;
        if offset >= 0.5 {
            offset -= 1.0;
        }
        Some(TurningPoint {
            stage,
            index: index as i64,
            offset,
            offset_s: offset / s.frequency,
        })
    }

    /// The shortest period of the drive's moving stages (s); None when no stage moves.
    pub fn shortest_period(&self) -> Option<f64> {
        self.stages
            .iter()
            .filter(|s| s.frequency > 0.0 && s.amplitude > 0.0)
            .map(|s| 1.0 / s.frequency)
            .min_by(f64::total_cmp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_drive_turns_at_a_quarter_period_and_stages_switch_at_their_start() {
        let d = TrayDrive::harmonic(0.01, 3.0).unwrap();
        let t_turn = 0.25 / 3.0;
        assert!((d.displacement(t_turn) - 0.01).abs() < 1e-15);
        assert!(d.displacement(1.0).abs() < 1e-15);
        let tp = d.turning_point(t_turn + 2.0 / 3.0).unwrap();
        assert_eq!((tp.stage, tp.index), (0, 2));
        assert!(tp.offset.abs() < 1e-12);
        // The tray's centre, a quarter period before the turning point.
        let tp = d.turning_point(1.0).unwrap();
        assert!(
            (tp.offset + 0.25).abs() < 1e-12 && (tp.offset_s + 0.25 / 3.0).abs() < 1e-12,
            "{tp:?}"
        );
        // A second stage at 5 Hz, 5 mm from t = 2 s, starting at its turning point.
        let two = TrayDrive::from_stages(vec![
            Stage {
                start: 0.0,
                frequency: 3.0,
                amplitude: 0.01,
                phase: 0.0,
            },
            Stage {
                start: 2.0,
                frequency: 5.0,
                amplitude: 0.005,
                phase: FRAC_PI_2,
            },
        ])
        .unwrap();
        assert_eq!(two.displacement(1.5), d.displacement(1.5));
        assert!((two.displacement(2.0) - 0.005).abs() < 1e-15);
        assert!((two.displacement(2.2) - 0.005).abs() < 1e-12);
        let tp = two.turning_point(2.2).unwrap();
        assert_eq!((tp.stage, tp.index), (1, 1));
        assert_eq!(two.shortest_period(), Some(0.2));
        assert!(TrayDrive::harmonic(0.0, 3.0).unwrap().turning_point(1.0).is_none());
    }

    #[test]
    fn bad_stages_are_refused_by_name() {
        let s = |start: f64, frequency: f64| Stage {
            start,
            frequency,
            amplitude: 0.01,
            phase: 0.0,
        };
        assert_eq!(TrayDrive::from_stages(vec![]), Err(DriveError::NoStages));
        let e = TrayDrive::from_stages(vec![s(0.0, 3.0), s(0.0, 4.0)]).unwrap_err();
        assert!(e.to_string().contains("stage 1 starts at 0 s"), "{e}");
        let e = TrayDrive::from_stages(vec![s(0.0, -3.0)]).unwrap_err();
        assert!(e.to_string().contains("frequency = -3"), "{e}");
    }
}
