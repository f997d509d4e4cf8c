//! What a command returns: its typed summary, which `main` serialises once as the last line of
//! stdout (the same JSON as `summary.json`), and the [`Headline`] it reads the line for people
//! from, so that nothing parses the JSON back.

use serde::Serialize;

use analysis::report::PhaseVotes;

use crate::rundir::output::{CliError, Written};

/// The fields of a summary that its line for people reads (`done: ...` on stderr); a summary
/// sets those it has.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Headline {
    pub simulated_s: Option<f64>,
    pub wall_s: Option<f64>,
    pub snapshots: Option<u64>,
    /// The phase the run was classified as, where it was.
    pub phase: Option<PhaseLine>,
    pub warnings: usize,
    /// The failed runs of a sweep.
    pub failed: Option<usize>,
    /// The output directory and the number of files written into it.
    pub out: Option<(String, usize)>,
}

/// A classification's part of the line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhaseLine {
    /// The phase's name; none where there were too few frames for one.
    pub phase: Option<String>,
    pub stripe_count_final: Option<usize>,
    /// Whether every threshold set tried gives the same label, with their votes when not.
    pub robust: Option<Result<(), PhaseVotes>>,
}

impl Headline {
    /// A headline with the warnings and the written directory only.
    pub fn written(warnings: usize, written: &Written) -> Self {
        Self {
            warnings,
            out: Some((written.out.clone(), written.files.len())),
            ..Self::default()
        }
    }

    /// The line for people (stderr): what was simulated, found and written, and how many
    /// warnings there were.
    pub fn line(&self) -> String {
        let mut parts = Vec::new();
        if let (Some(t), Some(w)) = (self.simulated_s, self.wall_s) {
            parts.push(format!("{t:.3} s simulated in {w:.1} s"));
        } else if let Some(w) = self.wall_s {
            parts.push(format!("{w:.1} s"));
        }
        if let Some(n) = self.snapshots {
            parts.push(format!("{n} snapshots"));
        }
        if let Some(p) = &self.phase {
            let stripes = p.stripe_count_final.map_or(String::new(), |c| format!(", {c} stripes at the end"));
            let robust = match p.robust {
                Some(Ok(())) => " (the same under every threshold set tried)".to_string(),
                Some(Err(v)) => format!(
                    " (not robust: of 27 threshold sets, {} say stripes, {} gas, {} nothing; see phase_sensitivity.csv)",
                    v.stripes, v.gas, v.nothing
                ),
                None => String::new(),
            };
            parts.push(format!(
                "phase {}{robust}{stripes}",
                p.phase.as_deref().unwrap_or("none (too few frames)")
            ));
        }
        parts.push(format!("{} warning(s)", self.warnings));
        if let Some(failed) = self.failed {
            parts.push(format!("{failed} failed run(s)"));
        }
        if let Some((out, files)) = &self.out {
            parts.push(format!("{files} files in {out}"));
        }
        format!("done: {}", parts.join("; "))
    }
}

/// A command's typed summary: serialises as its `summary.json` and says its headline.
pub trait Summary: Serialize {
    fn headline(&self) -> Headline;
}

/// What every command returns; `main` prints [`Report::headline`]'s line on stderr and
/// [`Report::json_line`] on stdout.
pub trait Report {
    fn headline(&self) -> Headline;
    /// The summary as one line of JSON, keys in the order of `summary.json` (sorted).
    fn json_line(&self) -> Result<String, serde_json::Error>;
}

impl<T: Summary> Report for T {
    fn headline(&self) -> Headline {
        Summary::headline(self)
    }

    fn json_line(&self) -> Result<String, serde_json::Error> {
        // Through a `Value`, whose keys are sorted, as `summary.json` is written.
        serde_json::to_string(&serde_json::to_value(self)?)
    }
}

/// What a command's adapter returns.
pub type Reported = Result<Box<dyn Report>, CliError>;

/// A typed summary as a command's result.
pub fn report(summary: impl Report + 'static) -> Reported {
    Ok(Box::new(summary))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweeps_account_counts_its_failed_runs() {
        let h = Headline {
            wall_s: Some(3.0),
            failed: Some(2),
            ..Headline::default()
        };
        assert_eq!(h.line(), "done: 3.0 s; 0 warning(s); 2 failed run(s)");
        let h = Headline {
            wall_s: Some(1.0),
            phase: Some(PhaseLine::default()),
            out: Some(("d".into(), 1)),
            ..Headline::default()
        };
        assert_eq!(h.line(), "done: 1.0 s; phase none (too few frames); 0 warning(s); 1 files in d");
        // An event-driven run's summary: its `phase` is the drive phase, no classification,
        // and its warnings are counted (the line said "0 warning(s)" beside a warning).
        let h = Headline {
            simulated_s: Some(0.3),
            wall_s: Some(0.5),
            warnings: 1,
            ..Headline::default()
        };
        assert_eq!(h.line(), "done: 0.300 s simulated in 0.5 s; 1 warning(s)");
    }

    #[test]
    fn a_classified_run_says_its_phase_stripes_and_votes() {
        let mut h = Headline {
            snapshots: Some(40),
            phase: Some(PhaseLine {
                phase: Some("stripes".into()),
                stripe_count_final: Some(7),
                robust: Some(Ok(())),
            }),
            ..Headline::default()
        };
        assert_eq!(
            h.line(),
            "done: 40 snapshots; phase stripes (the same under every threshold set tried), 7 stripes at the end; 0 warning(s)"
        );
        h.phase.as_mut().unwrap().robust = Some(Err(PhaseVotes {
            stripes: 20,
            gas: 5,
            nothing: 2,
        }));
        assert!(h
            .line()
            .contains("not robust: of 27 threshold sets, 20 say stripes, 5 gas, 2 nothing"));
    }
}
