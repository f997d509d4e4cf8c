//! A drive schedule: the tray shaken in consecutive stages, each harmonic with its own
//! frequency and amplitude (the experiment's protocol, thesis 2.2.5: 5 Hz / 20 mm to
//! fluidise, then 3 Hz / 10 mm for an hour).
//!
//! Stage `k` starts at `t_k` (the sum of the durations before it) and moves the tray by
//! `u(t) = A_k sin(2 pi nu_k (t - t_k))`: every stage starts at a zero crossing, moving
//! forwards. Every stage but the last lasts a whole number of its periods
//! ([`Scene::validate`](crate::scene::Scene::validate) refuses others), so it also ends at a
//! zero crossing: the tray's position is continuous at every switch, and its velocity jumps
//! from `2 pi nu_k A_k` to `2 pi nu_{k+1} A_{k+1}` (both forwards; 0.63 to 0.19 m/s in the
//! experiment's protocol). The last stage goes on past its end.
//!
//! One stage starting at 0 is the single harmonic drive, to the bit: `t - 0` is `t`.

use std::f64::consts::PI;

/// One stage of a schedule: from `start` on, `u(t) = amplitude sin(2 pi frequency (t - start))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stage {
    /// Start (s).
    pub start: f64,
    /// Hz.
    pub frequency: f64,
    /// m.
    pub amplitude: f64,
}

impl Stage {
    /// Period (s).
    pub fn period(&self) -> f64 {
        1.0 / self.frequency
    }

    /// Peak speed `2 pi nu A` (m/s).
    pub fn peak_speed(&self) -> f64 {
        2.0 * PI * self.frequency * self.amplitude
    }
}

/// Consecutive stages, each starting where the one before ends; the last goes on forever.
#[derive(Clone, Debug, PartialEq)]
pub struct Schedule {
    stages: Vec<Stage>,
}

impl Schedule {
    /// The stages of `(frequency (Hz), amplitude (m), duration (s))`, one after another from
    /// t = 0 (the last one's duration only says where the schedule ends: it goes on after).
    /// `None` for an empty list.
    pub fn new(stages: &[(f64, f64, f64)]) -> Option<Self> {
        if stages.is_empty() {
            return None;
        }
        let mut start = 0.0;
        let stages = stages
            .iter()
            .map(|&(frequency, amplitude, duration)| {
                let stage = Stage {
                    start,
                    frequency,
                    amplitude,
                };
                start += duration;
                stage
            })
            .collect();
        Some(Self { stages })
    }

    /// The stages, in order.
    pub fn stages(&self) -> &[Stage] {
        &self.stages
    }

    /// The stage in force at time `t` (s): the last one started at or before `t` (the first
    /// one before 0).
    #[inline]
    pub fn stage_at(&self, t: f64) -> &Stage {
        let k = self.stages.partition_point(|s| s.start <= t);
        &self.stages[k.saturating_sub(1)]
    }

    /// `(amplitude, angular frequency w, phase w (t - start))` at time `t`.
    #[inline]
    pub fn phase(&self, t: f64) -> (f64, f64, f64) {
        let s = self.stage_at(t);
        let w = 2.0 * PI * s.frequency;
        (s.amplitude, w, w * (t - s.start))
    }

    /// Largest amplitude of any stage (m).
    pub fn largest_amplitude(&self) -> f64 {
        self.stages.iter().map(|s| s.amplitude.abs()).fold(0.0, f64::max)
    }

    /// Largest peak acceleration `A (2 pi nu)^2` of any stage (m/s^2).
    pub fn peak_acceleration(&self) -> f64 {
        self.stages
            .iter()
            .map(|s| s.amplitude * (2.0 * PI * s.frequency).powi(2))
            .fold(0.0, f64::max)
    }

    /// Time of snapshot `k >= 1` with `per` snapshots per period: each stage takes its
    /// snapshots at its own turning points `u = +A` (a quarter period after its start) and
    /// evenly spaced after them, `t_k + (1/4 + j/per) / nu_k`, for as long as they fall
    /// before the next stage's start; the last stage's go on. With one stage this is the
    /// single drive's `1/(4 nu) + (k - 1)/(per nu)`, to the bit.
    pub fn snapshot_time(&self, k: u64, per: u32) -> f64 {
        let mut j = k.saturating_sub(1);
        let last = self.stages.len() - 1;
        for (i, s) in self.stages.iter().enumerate() {
            let at = |j: u64| s.start + 0.25 / s.frequency + j as f64 / (per as f64 * s.frequency);
            if i == last || at(j) < self.stages[i + 1].start {
                return at(j);
            }
            // The snapshots of stage i: the j with at(j) < the next start, counted by the same
            // test (the closed form, per (D nu - 1/4), only as the first guess).
            let end = self.stages[i + 1].start;
            let guess = ((end - s.start) * s.frequency * per as f64 - 0.25 * per as f64).ceil().max(0.0) as u64;
            let mut taken = guess;
            while at(taken) < end {
                taken += 1;
            }
            while taken > 0 && at(taken - 1) >= end {
                taken -= 1;
            }
            j -= taken;
        }
        unreachable!("the last stage returns")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn protocol() -> Schedule {
        Schedule::new(&[(5.0, 0.02, 2.0), (3.0, 0.01, 3600.0)]).unwrap()
    }

    #[test]
    fn stages_follow_each_other_and_the_position_is_continuous_at_the_switch() {
        let s = protocol();
        assert_eq!(s.stages()[1].start, 2.0);
        assert_eq!(s.stage_at(-1.0).frequency, 5.0);
        assert_eq!(s.stage_at(1.999).frequency, 5.0);
        assert_eq!(s.stage_at(2.0).frequency, 3.0);
        assert_eq!(s.stage_at(1e6).frequency, 3.0);
        let u = |t: f64| {
            let (a, _, phase) = s.phase(t);
            a * phase.sin()
        };
        let h = 1e-9;
        // Both sides of the switch at the zero crossing: |u| below the speed times h.
        assert!(
            u(2.0 - h).abs() < 0.7 * h && u(2.0 + h).abs() < 0.2 * h,
            "{} {}",
            u(2.0 - h),
            u(2.0 + h)
        );
        // The velocity jumps from 2 pi 5 0.02 to 2 pi 3 0.01, both forwards.
        let v = |t: f64| {
            let (a, w, phase) = s.phase(t);
            a * w * phase.cos()
        };
        assert!((v(2.0 - h) - s.stages()[0].peak_speed()).abs() < 1e-6);
        assert!((v(2.0) - s.stages()[1].peak_speed()).abs() < 1e-12);
        assert_eq!(s.largest_amplitude(), 0.02);
        assert!((s.peak_acceleration() - 0.02 * (10.0 * PI).powi(2)).abs() < 1e-12);
    }

    #[test]
    fn snapshots_sit_at_each_stage_turning_points_in_order() {
        let s = protocol();
        for per in [1u32, 3, 4, 7] {
            let times: Vec<f64> = (1..200).map(|k| s.snapshot_time(k, per)).collect();
            assert!(times.windows(2).all(|w| w[1] > w[0]), "per {per}: not increasing");
            // Stage 1: 10 periods at 5 Hz; stage 2 from 2 s at 3 Hz.
            let first = times.iter().filter(|&&t| t < 2.0).count();
            let expect = (0..).take_while(|j| (0.25 + *j as f64 / per as f64) / 5.0 < 2.0).count();
            assert_eq!(first, expect, "per {per}");
            assert!((times[0] - 0.05).abs() < 1e-15);
            // The first of the second stage at its turning point, a quarter period after 2 s.
            assert!((times[first] - (2.0 + 0.25 / 3.0)).abs() < 1e-12, "per {per}: {}", times[first]);
            for (i, &t) in times.iter().enumerate() {
                let stage = s.stage_at(t);
                let cycles = (t - stage.start) * stage.frequency * per as f64 - 0.25 * per as f64;
                assert!((cycles - cycles.round()).abs() < 1e-6, "per {per}, snapshot {}: {t}", i + 1);
            }
        }
        // One stage: the single drive's times, to the bit.
        let one = Schedule::new(&[(3.0, 0.01, 10.0)]).unwrap();
        for k in 1..100u64 {
            assert_eq!(one.snapshot_time(k, 4), 0.25 / 3.0 + (k - 1) as f64 / (4.0 * 3.0));
        }
        assert!(Schedule::new(&[]).is_none());
    }
}
