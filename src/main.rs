//! `stripes`: the command-line front end. It parses arguments, calls the library crates and
//! writes outputs; physics lives in `particles` and `automaton`, analysis and plots in
//! `analysis`.
//!
//! Every subcommand that computes numbers writes a directory with the resolved configuration
//! (`config.json`) and `summary.json`, and prints that summary as the last line of stdout.

mod analyze;
mod automaton;
mod cli;
mod dem;
mod events;
mod host;
mod rundir;
mod scene;
mod studies;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "stripes",
    version,
    about = "Stripe formation in a horizontally shaken submonolayer: DEM, cellular automaton, analysis"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The shaken tray: DEM run of a scene file (thesis 3.5).
    Run(cli::run::Args),
    /// Density map, stripes, MSD, tracer and phase of a run, automaton run or LAMMPS dump
    /// (thesis 3.5.4, Appendix A).
    Analyze(cli::analyze::Args),
    /// Two-sphere or sphere-wall collision experiment (thesis 3.2.5, chapter 4).
    Collide(cli::collide::Args),
    /// eps_n^HS, eps_n and phi against impact eccentricity (thesis chapter 4, Fig 4.4-4.10).
    Eccentricity(cli::eccentricity::Args),
    /// Contact duration against A, R, Y and v next to eq 3.19 (thesis Fig 3.5).
    ContactTime(cli::contact_time::Args),
    /// Ablation study over prepared samples: reference and five toggles (thesis 3.5.4).
    Ablate(cli::ablate::Args),
    /// (nu, A) phase diagram of one or both models (thesis Figs 3.30-3.31).
    PhaseMap(cli::phase_map::Args),
    /// Merge the results of a sweep's shards into its tables, plots and report.
    Collect(cli::collect::Args),
    /// One sphere on the shaken plate, with and without rolling friction, and the
    /// rolling-friction stopping test (thesis 3.3, 3.5.2).
    Single(cli::single::Args),
    /// The Strassburger cellular automaton on a scene (thesis 3.1); --bench, --calibrate.
    Automaton(cli::automaton::Args),
    /// DEM and automaton on the same scene and sample, analysed alike: report.md.
    Compare(cli::compare::Args),
    /// Several analysed runs of one scene side by side: pooled structure with errors,
    /// pattern distances between runs, spacing and band count over time.
    Seeds(cli::seeds::Args),
    /// One long run analysed in windows, joined over time: the count on log axes, the
    /// coarsening law on the joined count, each window's stripe lifetimes.
    Windows(cli::windows::Args),
    /// Held, rolling and sliding grains inside and outside the dense bands of a finished run,
    /// continued from its checkpoint (thesis 3.4, 3.5).
    Mechanism(cli::mechanism::Args),
    /// The event-driven model of a vibrated box (hard disks or spheres in a vertical plane,
    /// Walton's collisions) on an event-driven scene (model = "events").
    #[command(mut_arg("scene", |a| a.help("Event-driven scene file (TOML, model = \"events\"), e.g. scenes/mixture.toml")))]
    Events(cli::events::Args),
    /// The event-driven model over a grid of scene values and seeds, in parallel: tables of
    /// the current, height, K/R and temperatures, with plots.
    EventsSweep(cli::events_sweep::Args),
    /// Single impacts of the event-driven rule on a wall or a grain, from a given state, and
    /// sweeps over the impact angle beside the rule's closed form.
    EventsCollide(cli::events_collide::Args),
    /// Speed against error of every accuracy-for-speed choice (time step, Young's modulus,
    /// integrator, 2D/3D, normal law, neighbour skin): Markdown table and Pareto plot.
    Bench(cli::bench::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => cli::run::run(a),
        Command::Analyze(a) => cli::analyze::run(a),
        Command::Collide(a) => cli::collide::run(a),
        Command::Eccentricity(a) => cli::eccentricity::run(a),
        Command::ContactTime(a) => cli::contact_time::run(a),
        Command::Single(a) => cli::single::run(a),
        Command::Ablate(a) => cli::ablate::run(a),
        Command::PhaseMap(a) => cli::phase_map::run(a),
        Command::Collect(a) => cli::collect::run(a),
        Command::Automaton(a) => cli::automaton::run(a),
        Command::Compare(a) => cli::compare::run(a),
        Command::Seeds(a) => cli::seeds::run(a),
        Command::Windows(a) => cli::windows::run(a),
        Command::Bench(a) => cli::bench::run(a),
        Command::Events(a) => cli::events::run(a),
        Command::EventsSweep(a) => cli::events_sweep::run(a),
        Command::EventsCollide(a) => cli::events_collide::run(a),
        Command::Mechanism(a) => cli::mechanism::run(a),
    };
    match result {
        Ok(report) => match report.json_line() {
            Ok(line) => {
                eprintln!("{}", report.headline().line());
                println!("{line}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: cannot write the summary: {e}");
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Regression: `ablate` and `phase-map` printed a long help for `--help` while every
    /// other command printed the short one; every command's `-h` and `--help` now agree, and
    /// the options every command shares are described in the same words.
    #[test]
    fn help_is_one_form_and_shared_options_read_alike() {
        let mut shared: std::collections::BTreeMap<&str, std::collections::BTreeSet<String>> = Default::default();
        for sub in Cli::command().get_subcommands() {
            for arg in sub.get_arguments() {
                // clap prints the long form for `--help` as soon as one argument, or one
                // value of a choice, has a long description.
                let long = arg.get_long_help().is_some() || arg.get_possible_values().iter().any(|v| v.get_help().is_some());
                assert!(
                    !long,
                    "`stripes {} --help` prints the long form for {:?}",
                    sub.get_name(),
                    arg.get_id()
                );
                for name in ["quiet", "sample-cache"] {
                    if arg.get_long() == Some(name) {
                        shared
                            .entry(name)
                            .or_default()
                            .insert(arg.get_help().map(|h| h.to_string()).unwrap_or_default());
                    }
                }
            }
        }
        for (name, helps) in shared {
            assert_eq!(helps.len(), 1, "--{name} is described in {} ways: {helps:?}", helps.len());
        }
    }

    /// Issue 43: `--quiet`, `--force` and `--out` are alike on every command that writes a
    /// directory: each has all three (a resumable run has `--resume` beside `--force`), and
    /// each is described in one way wherever it appears.
    #[test]
    fn quiet_force_and_out_are_on_every_command() {
        let mut missing = Vec::new();
        let mut helps: std::collections::BTreeMap<&str, std::collections::BTreeSet<String>> = Default::default();
        for sub in Cli::command().get_subcommands() {
            // `collect` writes into the sweep directory it is given.
            if sub.get_name() == "collect" {
                continue;
            }
            for name in ["quiet", "force", "out"] {
                match sub.get_arguments().find(|a| a.get_long() == Some(name)) {
                    None => missing.push(format!("{} --{name}", sub.get_name())),
                    Some(a) if name != "out" => {
                        helps
                            .entry(name)
                            .or_default()
                            .insert(a.get_help().map(|h| h.to_string()).unwrap_or_default());
                    }
                    Some(_) => {}
                }
            }
        }
        assert!(missing.is_empty(), "commands without the shared options: {missing:?}");
        for (name, h) in helps {
            assert_eq!(h.len(), 1, "--{name} is described in {} ways: {h:?}", h.len());
        }
    }

    /// Every option (and every value of a choice) of every subcommand has
    /// a description, and no default prints as a long decimal such as `0.000008`.
    #[test]
    fn every_option_is_described_and_defaults_are_short() {
        let (mut missing, mut long) = (Vec::new(), Vec::new());
        for sub in Cli::command().get_subcommands() {
            for arg in sub.get_arguments().filter(|a| !a.is_hide_set()) {
                let id = arg.get_id().as_str();
                if id == "help" || id == "version" {
                    continue;
                }
                let name = format!("{} {}", sub.get_name(), arg.get_long().map_or(id.to_string(), |l| format!("--{l}")));
                if arg.get_help().is_none() && arg.get_long_help().is_none() {
                    missing.push(name.clone());
                }
                let choices = if arg.get_action().takes_values() {
                    arg.get_possible_values()
                } else {
                    Vec::new()
                };
                // A choice is described by its own help or by name in the option's help.
                let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
                for v in choices.iter().filter(|v| !v.is_hide_set()) {
                    if v.get_help().is_none() && !help.contains(v.get_name()) {
                        missing.push(format!("{name} {}", v.get_name()));
                    }
                }
                for d in arg.get_default_values() {
                    let d = d.to_string_lossy();
                    if d.contains("0.0000") || d.contains("000000") {
                        long.push(format!("{name} = {d}"));
                    }
                }
            }
        }
        assert!(missing.is_empty(), "options without a description: {missing:?}");
        assert!(long.is_empty(), "defaults printed as long decimals: {long:?}");
    }
}
