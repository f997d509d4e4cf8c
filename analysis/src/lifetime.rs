//! How long stripes live: stripes followed from frame to frame in the tray's frame, and the
//! correlation time of the tray-frame density profile (the thesis' 3.5.5 read a lifetime of
//! about 100 s off the density profiles).
//!
//! - Tracking ([`track`]): a stripe of frame `k + 1` continues a stripe of frame `k` when the
//!   two overlap on the (periodic) x axis; pairs are matched one to one, largest overlap
//!   first, so when two stripes merge the merged one continues one of them and the other
//!   ends, and when one splits one part continues it and the other is born. A stripe unseen
//!   for up to [`BRIDGE_FRAMES`] frames and found again at an overlapping place continues
//!   its track (it is compared with its last place). A track's
//!   lifetime runs from the first frame that holds it to the first frame that no longer does;
//!   tracks already there in the first frame or still there in the last are censored (their
//!   lifetime is only bounded below) and left out of the mean ([`Lifetimes`]).
//! - Correlation ([`profile_correlation`]): `C(lag) = <dphi_k . dphi_{k+lag}> / <dphi_k . dphi_k>`,
//!   `dphi` the profile less its mean, averaged over all frame pairs `lag` apart; the
//!   correlation time is the first lag at which `C` falls below `1/e`.

use serde::Serialize;

use crate::stripes::Stripe;

/// One stripe followed over frames.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Track {
    /// Time (s) of the first frame holding it.
    pub born: f64,
    /// Time (s) of the first frame that no longer holds it (None: still there at the end).
    pub ended: Option<f64>,
    /// Whether it was there in the first frame (its birth is not seen).
    pub from_start: bool,
    /// Its centre (m) in the last frame holding it.
    pub center: f64,
}

impl Track {
    /// `ended - born` when both ends are seen.
    pub fn lifetime(&self) -> Option<f64> {
        self.ended.filter(|_| !self.from_start).map(|e| e - self.born)
    }
}

/// The stripes' lifetimes in summary.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Lifetimes {
    pub tracks: usize,
    /// Tracks whose birth and end are both seen.
    pub complete: usize,
    /// Mean lifetime of the complete tracks (s) and its standard error.
    pub mean_s: Option<f64>,
    pub stderr_s: Option<f64>,
    /// Longest time a track was seen (s), censored or not: a lower bound on the longest life.
    pub longest_seen_s: Option<f64>,
    /// Tracks there at the start or at the end (lifetime only bounded below).
    pub censored: usize,
    /// Median spacing of the frames (s): the resolution of every lifetime.
    pub resolution_s: Option<f64>,
}

/// Overlap (m) of `[a0, a0 + aw)` and `[b0, b0 + bw)` on a periodic axis of length `l`.
fn overlap(a: &Stripe, b: &Stripe, l: f64) -> f64 {
    [-l, 0.0, l]
        .iter()
        .map(|s| {
            let lo = a.start.max(b.start + s);
            let hi = (a.start + a.width).min(b.start + s + b.width);
            (hi - lo).max(0.0)
        })
        .sum()
}

/// Frames a stripe may go unseen and still continue its track when it is found again at an
/// overlapping place: a band whose peak dips under the threshold for one picture is the same
/// band (the automaton's bands, tilted across the tray, flicker so).
pub const BRIDGE_FRAMES: usize = 1;

/// An open track: the track, its last stripe, and the time of the first frame it has been
/// missing from (None: seen in the last frame).
struct Open {
    track: Track,
    last: Stripe,
    missing_since: Option<f64>,
    missed: usize,
}

/// Follows the stripes of `frames` (times in `times`) on a periodic axis of length `l`; a
/// stripe unseen for up to [`BRIDGE_FRAMES`] frames continues its track.
pub fn track(times: &[f64], frames: &[Vec<Stripe>], l: f64) -> Vec<Track> {
    assert_eq!(times.len(), frames.len(), "one time per frame");
    let mut done = Vec::new();
    let mut open: Vec<Open> = Vec::new();
    for (k, stripes) in frames.iter().enumerate() {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (o, entry) in open.iter().enumerate() {
            for (j, s) in stripes.iter().enumerate() {
                let w = overlap(&entry.last, s, l);
                if w > 0.0 {
                    pairs.push((w, o, j));
                }
            }
        }
        // Largest overlap first; at equal overlap the track seen last frame first.
        pairs.sort_by(|a, b| {
            b.0.total_cmp(&a.0)
                .then(open[a.1].missed.cmp(&open[b.1].missed))
                .then(a.1.cmp(&b.1))
                .then(a.2.cmp(&b.2))
        });
        // match_of[o]: the stripe of this frame that continues open track o.
        let (mut match_of, mut taken) = (vec![None; open.len()], vec![false; stripes.len()]);
        for (_, o, j) in pairs {
            if match_of[o].is_none() && !taken[j] {
                match_of[o] = Some(j);
                taken[j] = true;
            }
        }
        let mut next: Vec<Open> = Vec::new();
        for (mut entry, m) in open.into_iter().zip(match_of) {
            if let Some(j) = m {
                entry.last = stripes[j];
                entry.track.center = stripes[j].center;
                entry.missing_since = None;
                entry.missed = 0;
                next.push(entry);
                continue;
            }
            entry.missed += 1;
            let since = *entry.missing_since.get_or_insert(times[k]);
            if entry.missed > BRIDGE_FRAMES {
                done.push(Track {
                    ended: Some(since),
                    ..entry.track
                });
            } else {
                next.push(entry);
            }
        }
        for (_, s) in stripes.iter().enumerate().filter(|(j, _)| !taken[*j]) {
            next.push(Open {
                track: Track {
                    born: times[k],
                    ended: None,
                    from_start: k == 0,
                    center: s.center,
                },
                last: *s,
                missing_since: None,
                missed: 0,
            });
        }
        open = next;
    }
    done.extend(open.into_iter().map(|o| Track {
        ended: o.missing_since,
        ..o.track
    }));
    done.sort_by(|a, b| a.born.total_cmp(&b.born).then(a.center.total_cmp(&b.center)));
    done
}

/// The summary of `tracks` over frames at `times`.
pub fn lifetimes(tracks: &[Track], times: &[f64]) -> Lifetimes {
    let lives: Vec<f64> = tracks.iter().filter_map(Track::lifetime).collect();
    let (mean, stderr) = if lives.is_empty() {
        (None, None)
    } else {
        let (m, e) = crate::stats::mean_stderr(&lives);
        (Some(m), (lives.len() > 1).then_some(e))
    };
    let end = times.last().copied().unwrap_or(f64::NAN);
    let mut gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    Lifetimes {
        tracks: tracks.len(),
        complete: lives.len(),
        mean_s: mean,
        stderr_s: stderr,
        longest_seen_s: tracks.iter().map(|t| t.ended.unwrap_or(end) - t.born).max_by(f64::total_cmp),
        censored: tracks.len() - lives.len(),
        resolution_s: gaps.get(gaps.len() / 2).copied(),
    }
}

/// One lag of the profile's autocorrelation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CorrelationPoint {
    pub lag: usize,
    /// Mean time between the frames `lag` apart (s).
    pub lag_s: f64,
    pub c: f64,
}

/// The normalised autocorrelation of the profiles (module docs) up to `max_lag` frames (every
/// lag up to 32, then lags 10 % apart), and the correlation time (s): the first of those lags
/// with `C < 1/e`, None when `C` stays above it.
pub fn profile_correlation(times: &[f64], profiles: &[Vec<f64>], max_lag: usize) -> (Vec<CorrelationPoint>, Option<f64>) {
    let d: Vec<Vec<f64>> = profiles
        .iter()
        .map(|p| {
            let m = p.iter().sum::<f64>() / p.len().max(1) as f64;
            p.iter().map(|v| v - m).collect()
        })
        .collect();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let n = d.len();
    let var = d.iter().map(|v| dot(v, v)).sum::<f64>() / n.max(1) as f64;
    let mut out = Vec::new();
    let mut time = None;
    // Every lag up to 32, then lags 10 % apart: the cost stays near 100 n cells however
    // long the run.
    let top = max_lag.min(n.saturating_sub(1));
    let mut lags: Vec<usize> = (0..=top.min(32)).collect();
    let mut next = 33.0f64;
    while (next as usize) <= top {
        lags.push(next as usize);
        next = (next * 1.1).max(next + 1.0);
    }
    for lag in lags {
        let pairs = n - lag;
        let c = (0..pairs).map(|k| dot(&d[k], &d[k + lag])).sum::<f64>() / pairs as f64 / var;
        let lag_s = (0..pairs).map(|k| times[k + lag] - times[k]).sum::<f64>() / pairs as f64;
        if time.is_none() && c < (-1.0f64).exp() {
            time = Some(lag_s);
        }
        out.push(CorrelationPoint { lag, lag_s, c });
    }
    (out, time)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stripe(center: f64, width: f64, l: f64) -> Stripe {
        Stripe {
            start: (center - 0.5 * width).rem_euclid(l),
            center,
            width,
            mass: width,
        }
    }

    #[test]
    fn stripes_that_appear_and_vanish_at_known_times_have_those_lifetimes() {
        let l = 1.0;
        let times: Vec<f64> = (0..=20).map(f64::from).collect();
        let frames: Vec<Vec<Stripe>> = times
            .iter()
            .map(|&t| {
                let wobble = 0.003 * (t * 1.7).sin();
                let mut s = vec![stripe(0.98 + wobble, 0.06, l)]; // across the seam, always there
                if (3.0..8.0).contains(&t) {
                    s.push(stripe(0.5 + wobble, 0.05, l));
                }
                if (10.0..16.0).contains(&t) {
                    s.push(stripe(0.25 - wobble, 0.04, l));
                }
                s
            })
            .collect();
        let tracks = track(&times, &frames, l);
        assert_eq!(tracks.len(), 3, "{tracks:?}");
        let lives: Vec<Option<f64>> = tracks.iter().map(Track::lifetime).collect();
        assert_eq!(lives, vec![None, Some(5.0), Some(6.0)]);
        let s = lifetimes(&tracks, &times);
        assert_eq!((s.complete, s.censored), (2, 1));
        assert_eq!(s.mean_s, Some(5.5));
        assert_eq!(s.longest_seen_s, Some(20.0));
        assert_eq!(s.resolution_s, Some(1.0));
    }

    #[test]
    fn a_stripe_missing_from_one_frame_continues_and_from_two_ends() {
        let l = 1.0;
        let times: Vec<f64> = (0..10).map(f64::from).collect();
        let seen = |gaps: &[usize]| -> Vec<Vec<Stripe>> {
            (0..10)
                .map(|k| if gaps.contains(&k) { vec![] } else { vec![stripe(0.5, 0.05, l)] })
                .collect()
        };
        // Born at 1 (absent at 0), missing at 4 only, ends at 8.
        let tracks = track(&times, &seen(&[0, 4, 8, 9]), l);
        assert_eq!(tracks.len(), 1, "{tracks:?}");
        assert_eq!(tracks[0].lifetime(), Some(7.0));
        // Missing at 4 and 5: two tracks, the first ends at 4.
        let tracks = track(&times, &seen(&[0, 4, 5, 9]), l);
        let lives: Vec<Option<f64>> = tracks.iter().map(Track::lifetime).collect();
        assert_eq!(lives, vec![Some(3.0), Some(3.0)]);
    }

    #[test]
    fn a_merger_ends_one_track_and_a_split_starts_one() {
        let l = 1.0;
        let times = [0.0, 1.0, 2.0, 3.0];
        let frames = vec![
            vec![stripe(0.40, 0.05, l), stripe(0.47, 0.05, l)],
            vec![stripe(0.44, 0.10, l)],
            vec![stripe(0.44, 0.10, l)],
            vec![stripe(0.40, 0.05, l), stripe(0.48, 0.05, l)],
        ];
        let tracks = track(&times, &frames, l);
        // Two from the start (one ends at the merger, t = 1), one born at the split (t = 3).
        assert_eq!(tracks.len(), 3, "{tracks:?}");
        assert_eq!(tracks.iter().filter(|t| t.ended == Some(1.0)).count(), 1);
        assert_eq!(tracks.iter().filter(|t| t.born == 3.0).count(), 1);
    }

    #[test]
    fn a_fixed_pattern_stays_correlated_and_a_shuffled_one_does_not() {
        let times: Vec<f64> = (0..30).map(f64::from).collect();
        let fixed: Vec<Vec<f64>> = times.iter().map(|_| (0..50).map(|i| (i as f64 * 0.6).sin()).collect()).collect();
        let (c, time) = profile_correlation(&times, &fixed, 10);
        assert!(c.iter().all(|p| (p.c - 1.0).abs() < 1e-12) && time.is_none());
        // A long run: every lag to 32, then lags 10 % apart.
        let long: Vec<f64> = (0..200).map(f64::from).collect();
        let fixed_long = vec![fixed[0].clone(); 200];
        let (c, _) = profile_correlation(&long, &fixed_long, 100);
        let lags: Vec<usize> = c.iter().map(|p| p.lag).collect();
        assert_eq!(&lags[..33], &(0..=32).collect::<Vec<_>>()[..]);
        assert!(
            lags.windows(2).all(|w| w[1] > w[0]) && *lags.last().unwrap() <= 100 && lags.len() < 50,
            "{lags:?}"
        );
        assert!(c.iter().all(|p| (p.lag_s - p.lag as f64).abs() < 1e-12));
        // A band that jumps to a new place every frame: correlated only with itself.
        let moving: Vec<Vec<f64>> = (0..30)
            .map(|k| (0..50).map(|i| if i == (k * 7) % 50 { 1.0 } else { 0.0 }).collect())
            .collect();
        let (c, time) = profile_correlation(&times, &moving, 5);
        assert!((c[0].c - 1.0).abs() < 1e-12 && c[1].c < 0.0);
        assert_eq!(time, Some(1.0));
    }
}
