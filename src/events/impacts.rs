//! `stripes events-collide`: single impacts of the event-driven rule (Walton's, with any `e`,
//! `mu`, `beta0` and `q` in (0, 1]), on a wall or on a second grain at rest, from a given
//! state; the rough-sphere paper's check of its rule. One impact prints its outcome; with
//! `--sweep N`, the impact angle is swept over N angles for every `--mu` and `--beta0`
//! given, and `impacts.csv` (one row per impact, beside the rule's closed form),
//! `rebound.png` (psi' against psi in degrees, the contact point's rebound against impact
//! angle) and `beta.png` are written to `--out`.

use std::path::PathBuf;

use analysis::plot::{LinePlot, Mark};
use events::impact::{self, Impact, Target, Walton};
use serde::Serialize;

use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Report, Summary};

/// Options of `stripes events-collide`. SI units; angles in degrees.
/// What the study is given (the command's arguments, without the command line); serialised
/// as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    /// What grain 1 hits: "wall" (a floor at rest) or "pair" (an equal grain at rest below).
    pub target: String,
    /// Grain 1's speed before the impact (m/s, > 0).
    pub speed: f64,
    /// Grain 1's impact angle from the normal (degrees, [0, 90)), one impact.
    pub angle: f64,
    /// Grain 1's spin before the impact (rad/s, counter-clockwise in the x-z plane).
    pub spin: f64,
    /// Grain 1's centre above the wall, or above grain 2's centre (m); default: in contact
    /// (R, or 2 R). Any other value is refused: the grains must touch.
    pub z1: Option<f64>,
    /// Normal restitution e in [0, 1].
    pub e: f64,
    /// Coulomb friction mu (>= 0); several, comma-separated, for a sweep.
    pub mu: Vec<f64>,
    /// Tangential restitution of sticking contacts beta0 in [-1, 1] (-1 smooth, +1 perfectly
    /// rough); several, comma-separated, for a sweep.
    pub beta0: Vec<f64>,
    /// Inertia factor q = I / (m R^2) in (0, 1] (sphere 0.4, disk 0.5, hollow sphere 2/3).
    pub q: f64,
    /// Radius of each grain (m).
    pub radius: f64,
    /// Mass of each grain (kg).
    pub mass: f64,
    /// Sweep the impact angle over this many angles from 0 to --max-angle.
    pub sweep: Option<usize>,
    /// The largest impact angle of a sweep (degrees, < 90).
    pub max_angle: f64,
    /// Output directory of a sweep (one impact is printed and nothing is written).
    pub out: PathBuf,
    pub force: bool,
    pub quiet: bool,
}

/// One impact's outcome, as printed.
#[derive(Serialize)]
struct One {
    target: String,
    branch: &'static str,
    tan_psi_in: f64,
    tan_psi_out: f64,
    closed_form_tan_psi_out: f64,
    switch_tan_psi: f64,
    e: f64,
    beta: f64,
    v1_after: [f64; 2],
    w1_after: f64,
    v2_after: [f64; 2],
    w2_after: f64,
    dissipated_j: f64,
}

impl Summary for One {
    fn headline(&self) -> Headline {
        Headline::default()
    }
}

/// The option that an engine field comes from.
fn option_of(field: &str) -> &'static str {
    match field {
        "q" => "--q",
        "rule.e" => "--e",
        "rule.mu" => "--mu",
        "rule.beta0" => "--beta0",
        "grain.position" => "--z1",
        "grain.velocity" => "--speed",
        "speed" => "--speed",
        f if f.ends_with(".radius") => "--radius",
        f if f.ends_with(".mass") => "--mass",
        _ => "--angle",
    }
}

fn named(e: events::EventsError) -> CliError {
    match e {
        events::EventsError::Invalid { field, message } => format!("{}: {message}", option_of(&field)).into(),
        other => other.to_string().into(),
    }
}

pub fn impacts(args: &Options) -> Result<Box<dyn Report>, CliError> {
    let target = match args.target.as_str() {
        "wall" => Target::Wall,
        "pair" => Target::Pair,
        v => return Err(format!("--target: must be \"wall\" or \"pair\", got {v:?}").into()),
    };
    if !(args.speed.is_finite() && args.speed > 0.0) {
        return Err(format!("--speed: must be a positive speed, got {}", args.speed).into());
    }
    let rule = |mu: f64, beta0: f64| Walton {
        e: args.e,
        mu,
        beta0,
        q: args.q,
    };
    let Some(count) = args.sweep else {
        if args.mu.len() != 1 || args.beta0.len() != 1 {
            return Err("--mu and --beta0: one value each for one impact (several need --sweep)".into());
        }
        if !(0.0..90.0).contains(&args.angle) {
            return Err(format!("--angle: must lie in [0, 90) degrees, got {}", args.angle).into());
        }
        let rule = rule(args.mu[0], args.beta0[0]);
        let mut imp = Impact::at_angle(target, rule, args.speed, args.angle.to_radians(), args.spin, args.radius, args.mass);
        if let Some(z) = args.z1 {
            imp.grain.r.y = z;
        }
        let r = imp.run().map_err(named)?;
        let o = r.outcome;
        return Ok(Box::new(One {
            target: args.target.clone(),
            branch: r.branch.name(),
            tan_psi_in: r.tan_in,
            tan_psi_out: r.tan_out,
            closed_form_tan_psi_out: rule.rebound_tangent(r.tan_in).0,
            switch_tan_psi: rule.switch_tangent(),
            e: o.e,
            beta: o.beta,
            v1_after: [o.v1.x, o.v1.y],
            w1_after: o.w1,
            v2_after: [o.v2.x, o.v2.y],
            w2_after: o.w2,
            dissipated_j: o.dissipated,
        }));
    };
    if count < 2 {
        return Err(format!("--sweep: needs at least 2 angles, got {count}").into());
    }
    if !(args.max_angle > 0.0 && args.max_angle < 90.0) {
        return Err(format!("--max-angle: must lie in (0, 90) degrees, got {}", args.max_angle).into());
    }
    // Every rule is checked before anything is written.
    for &mu in &args.mu {
        for &beta0 in &args.beta0 {
            rule(mu, beta0).validate().map_err(named)?;
        }
    }
    crate::rundir::output::claim(&args.out, args.force)?;
    let mut dir = RunDir::create(&args.out, &args)?;
    let mut rows = Vec::new();
    let mut rebound = LinePlot::new(
        &format!("Rebound against impact, {} (e = {}, q = {})", args.target, args.e, args.q),
        "psi, impact (degrees)",
        "psi', rebound (degrees)",
    );
    let mut beta = LinePlot::new("Tangential restitution against impact angle", "psi, impact (degrees)", "beta");
    let deg = |tan: f64| tan.atan().to_degrees();
    let mut worst: f64 = 0.0;
    let mut switches = Vec::new();
    for &mu in &args.mu {
        for &beta0 in &args.beta0 {
            let w = rule(mu, beta0);
            let sweep = impact::sweep(target, w, args.speed, args.max_angle.to_radians(), count, args.radius, args.mass).map_err(named)?;
            for s in &sweep {
                let r = &s.rebound;
                worst = worst.max((r.tan_out - s.closed_tan_out).abs() / (1.0 + s.closed_tan_out.abs()));
                let branch = match r.branch {
                    impact::Branch::Smooth => 0.0,
                    impact::Branch::Sticking => 1.0,
                    impact::Branch::Coulomb => 2.0,
                };
                rows.push(vec![
                    mu,
                    beta0,
                    s.angle.to_degrees(),
                    r.tan_in,
                    r.tan_out,
                    s.closed_tan_out,
                    r.outcome.beta,
                    branch,
                    r.outcome.dissipated,
                ]);
            }
            let label = format!("mu = {mu}, beta0 = {beta0}");
            rebound = rebound.series(
                &label,
                sweep.iter().map(|s| (deg(s.rebound.tan_in), deg(s.rebound.tan_out))).collect(),
                Mark::LinePoints,
            );
            beta = beta.series(
                &label,
                sweep.iter().map(|s| (deg(s.rebound.tan_in), s.rebound.outcome.beta)).collect(),
                Mark::LinePoints,
            );
            switches.push(Switch {
                mu,
                beta0,
                switch_tan_psi: w.switch_tangent(),
                switch_angle_deg: w.switch_tangent().atan().to_degrees(),
            });
        }
    }
    dir.csv(
        "impacts.csv",
        &[
            "mu",
            "beta0",
            "angle_deg",
            "tan_psi_in",
            "tan_psi_out",
            "closed_form_tan_psi_out",
            "beta",
            "branch",
            "dissipated_j",
        ],
        &rows,
    )?;
    dir.plot("rebound", &rebound)?;
    dir.plot("beta", &beta.include_y(-1.0).include_y(1.0))?;
    let summary = SweepSummary {
        impacts: rows.len(),
        max_closed_form_error: worst,
        branch_codes: "0 smooth, 1 sticking, 2 coulomb",
        switches,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(Box::new(summary))
}

/// `summary.json` of a sweep over the impact angle.
#[derive(Debug, Serialize)]
struct SweepSummary {
    impacts: usize,
    /// The largest `|tan psi' - closed form| / (1 + |closed form|)` over the sweep.
    max_closed_form_error: f64,
    branch_codes: &'static str,
    switches: Vec<Switch>,
    #[serde(flatten)]
    written: Written,
}

/// Where a rule switches from sticking to sliding.
#[derive(Debug, Serialize)]
struct Switch {
    mu: f64,
    beta0: f64,
    switch_tan_psi: f64,
    switch_angle_deg: f64,
}

impl Summary for SweepSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}
