//! `stripes collide`: one binary impact of two spheres, or of a sphere on a wall (thesis 3.2.5
//! and chapter 4). With `--table`, the restitution table: the impact swept over the normal
//! speed and the ratio g_t/g_n, for pairs (`restitution.csv`) and for the floor
//! (`restitution_floor.csv`), with columns `g_n, g_t_over_g_n, eps_n, beta` (the table the
//! event-driven model reads as its collision rule; a value the lab measures outside the
//! rule's range is clamped into it, with a warning naming its row) and maps of beta and
//! eps_n over the whole table; `--scene` takes the laws, radius and density from a tray
//! scene. Without `--out`, one impact is a calculator: printed, nothing written.

use std::path::PathBuf;

use particles::contact::choice::{LawChoice, LawParameters, Missing, NormalKind, RollingKind, TangentialKind};
use particles::contact::ContactLaw;
use particles::experiment::collide::{Collision, CollisionResult, Impact, StepSize, Target};
use particles::integrate::Integrator;
use particles::material::Material;
use particles::Vec3;
use serde::Serialize;

use analysis::plot::Heatmap;

use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Report, Summary};

/// The contact laws of `stripes collide` and their parameters (SI units), as one piece of
/// its options.
#[derive(Clone, Debug, Serialize)]
pub struct Laws {
    /// Normal law: hertz (eq 3.8; --young, --poisson, --dissipation) or linear (eq 4.21;
    /// --kn, --gamma-n).
    pub normal: NormalKind,
    /// Tangential law: none, haff-werner (eq 3.12; --gamma-t, --mu) or cundall-strack
    /// (eq 4.32-4.34; --kt, --mu).
    pub tangential: TangentialKind,
    /// Rolling law: none, brilliantov-poschel (eq 3.15; --mu-r) or sds (spring-dashpot-slider;
    /// --mu-roll, --k-roll, --gamma-roll).
    pub rolling: RollingKind,
    /// Young's modulus Y (Pa), Hertz only.
    pub young: f64,
    /// Poisson ratio, Hertz only.
    pub poisson: f64,
    /// Dissipative constant A (s), Hertz only (eq 3.8).
    pub dissipation: f64,
    /// Normal stiffness k_n (N/m), linear only.
    pub kn: Option<f64>,
    /// Normal damping gamma_n (kg/s), linear only.
    pub gamma_n: f64,
    /// Tangential spring stiffness k_t (N/m), Cundall-Strack only.
    pub kt: Option<f64>,
    /// Coulomb friction coefficient.
    pub mu: f64,
    /// Tangential damping gamma_t (N s/m), Haff-Werner only.
    pub gamma_t: f64,
    /// Rolling friction mu_r (s), Brilliantov-Pöschel only.
    pub mu_r: f64,
    /// Rolling resistance mu_r (dimensionless), spring-dashpot-slider only.
    pub mu_roll: Option<f64>,
    /// Rolling stiffness k_roll (N/m; spring torque k_roll R_eff^2 per radian),
    /// spring-dashpot-slider only; default 2.25 mu_r^2 k_n.
    pub k_roll: Option<f64>,
    /// Rolling damping gamma_roll (N s/m), spring-dashpot-slider only.
    pub gamma_roll: f64,
}

/// Options of `stripes collide`. SI units. Defaults: the thesis' glass beads (Table 3.1).
/// What the study is given (the command's arguments, without the command line); serialised
/// as the arguments into `config.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Options {
    #[serde(flatten)]
    pub laws: Laws,
    /// Radius of sphere 1 (m).
    pub r1: f64,
    /// Radius of sphere 2 (m); defaults to --r1.
    pub r2: Option<f64>,
    /// Density (kg/m^3), used for masses not given by --m1/--m2.
    pub rho: f64,
    /// Mass of sphere 1 (kg); defaults to rho 4/3 pi r1^3.
    pub m1: Option<f64>,
    /// Mass of sphere 2 (kg); defaults to rho 4/3 pi r2^3.
    pub m2: Option<f64>,
    /// Normal approach speed (m/s); with --eccentricity, the relative speed.
    pub v: f64,
    /// Tangential speed at impact (m/s).
    pub vt: f64,
    /// Impact eccentricity e = d / (R1 + R2) in [0, 1) (Fig 4.2).
    pub eccentricity: Option<f64>,
    /// Initial spin of sphere 1, "x,y,z" (rad/s).
    pub omega1: [f64; 3],
    /// Initial spin of sphere 2, "x,y,z" (rad/s).
    pub omega2: [f64; 3],
    /// Sphere 1 hits a fixed flat wall instead of sphere 2.
    pub wall: bool,
    /// Time step (s); otherwise --steps-per-contact.
    pub dt: Option<f64>,
    /// Steps per estimated (undamped) contact time.
    pub steps_per_contact: f64,
    /// Time integrator: velocity-verlet or thesis (sec 3.5.1).
    pub integrator: Integrator,
    /// Sweep the impact over --g-n and --ratios, for pairs and for the floor, and write the
    /// restitution tables (restitution.csv, restitution_floor.csv) with plots.
    pub table: bool,
    /// With --table: the normal impact speeds g_n (m/s).
    pub g_n: Vec<f64>,
    /// With --table: the ratios g_t / g_n of tangential to normal contact-point speed (> 0).
    pub ratios: Vec<f64>,
    /// With --table: take the pair and wall laws, the mean radius and the density from this
    /// tray scene (with its toggles) instead of the law options.
    pub scene: Option<PathBuf>,
    /// Output directory (default: none for one impact, which is then printed and nothing is
    /// written, as a calculator; out/collide for --table).
    pub out: Option<PathBuf>,
    pub force: bool,
    pub quiet: bool,
}

impl Options {
    /// The contact law these options describe, built by the same function as a scene's
    /// laws; missing or bad parameters are errors naming the option.
    pub fn law(&self) -> Result<ContactLaw, CliError> {
        let m = Material {
            density: self.rho,
            young: self.laws.young,
            poisson: self.laws.poisson,
            dissipation: self.laws.dissipation,
        };
        if self.laws.normal == NormalKind::Hertz && !(m.young > 0.0 && m.poisson > -1.0 && m.poisson < 0.5 + 1e-12 && m.dissipation >= 0.0)
        {
            return Err("--young must be > 0, --poisson in (-1, 0.5], --dissipation >= 0".into());
        }
        if self.laws.normal == NormalKind::Linear && !(self.laws.kn.is_none_or(|kn| kn > 0.0) && self.laws.gamma_n >= 0.0) {
            return Err("--kn must be > 0 and --gamma-n >= 0".into());
        }
        if self.laws.mu < 0.0 {
            return Err("--mu must be >= 0".into());
        }
        if self.laws.mu_roll.is_some_and(|m| m < 0.0) || self.laws.k_roll.is_some_and(|k| k <= 0.0) || self.laws.gamma_roll < 0.0 {
            return Err("--mu-roll must be >= 0, --k-roll > 0 and --gamma-roll >= 0".into());
        }
        let choice = LawChoice {
            normal: self.laws.normal,
            tangential: self.laws.tangential,
            rolling: self.laws.rolling,
        };
        let parameters = LawParameters {
            reduced_modulus: m.reduced_modulus(),
            dissipation: m.dissipation,
            kn: self.laws.kn,
            gamma_n: self.laws.gamma_n,
            mu: self.laws.mu,
            gamma_t: self.laws.gamma_t,
            kt: self.laws.kt,
            mu_r: self.laws.mu_r,
            rolling_resistance: self.laws.mu_roll,
            k_roll: self.laws.k_roll,
            gamma_roll: self.laws.gamma_roll,
        };
        choice.build(&parameters).map_err(|missing| {
            match missing {
                Missing::Kn => "--normal linear needs --kn (N/m)",
                Missing::Kt => "--tangential cundall-strack needs --kt (N/m)",
                Missing::RollingResistance => "--rolling sds needs --mu-roll (dimensionless)",
            }
            .into()
        })
    }

    /// The experiment these options describe.
    pub fn collision(&self) -> Result<Collision, CliError> {
        let mass = |r: f64| self.rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let r2 = self.r2.unwrap_or(self.r1);
        let target = if self.wall {
            Target::Wall
        } else {
            Target::Sphere {
                r: r2,
                m: self.m2.unwrap_or_else(|| mass(r2)),
                omega: Vec3::from(self.omega2),
            }
        };
        Ok(Collision {
            law: self.law()?,
            r1: self.r1,
            m1: self.m1.unwrap_or_else(|| mass(self.r1)),
            omega1: Vec3::from(self.omega1),
            target,
            impact: match self.eccentricity {
                Some(e) => Impact::Eccentric { v: self.v, e },
                None => Impact::Components { vn: self.v, vt: self.vt },
            },
            step: match self.dt {
                Some(dt) => StepSize::Dt(dt),
                None => StepSize::PerContact(self.steps_per_contact),
            },
            integrator: self.integrator,
        })
    }
}

/// One impact: the experiment's result, and the directory it was written to (none for the
/// calculator, which writes nothing).
#[derive(Clone, Debug, Serialize)]
pub struct ImpactSummary {
    #[serde(flatten)]
    pub result: CollisionResult,
    #[serde(flatten)]
    pub written: Option<Written>,
}

impl Report for ImpactSummary {
    fn headline(&self) -> Headline {
        self.written.as_ref().map_or_else(Headline::default, |w| Headline::written(0, w))
    }

    fn json_line(&self) -> Result<String, serde_json::Error> {
        match self.written {
            // The calculator's line: the result's fields in their own order.
            None => serde_json::to_string(&self.result),
            Some(_) => serde_json::to_string(&serde_json::to_value(self)?),
        }
    }
}

/// One impact; written into `--out` with its `config.json` and `summary.json` if given.
pub fn collide(args: &Options) -> Result<ImpactSummary, CliError> {
    let collision = args.collision()?;
    let result = collision.run()?;
    // Without --out, a calculator: the result is printed, nothing is written, and a second
    // call needs neither --force nor a new directory.
    let Some(out) = &args.out else {
        return Ok(ImpactSummary { result, written: None });
    };
    crate::rundir::output::claim(out, args.force)?;
    let dir = RunDir::create(out, &args)?;
    let mut summary = ImpactSummary { result, written: None };
    summary.written = Some(dir.written());
    dir.finish_typed(&summary)?;
    Ok(summary)
}

/// The restitution table as two maps, `<name>_beta` and `<name>_eps_n`: every impact of the
/// table, g_t/g_n across and g_n up, one cell each, on the rule's whole range (beta from
/// -1 to 1, eps_n from 0 to 1), so nothing of the table is hidden and the scale fits.
fn restitution_maps(name: &str, rows: &[Row], g_n: &[f64], ratios: &[f64]) -> Vec<(String, Heatmap)> {
    let what = if name == "restitution" { "pairs" } else { "the floor" };
    let names = |v: &[f64]| v.iter().map(|x| format!("{x}")).collect::<Vec<_>>();
    let grid = |f: fn(&Row) -> f64| -> Vec<Vec<f64>> {
        g_n.iter()
            .map(|&vn| {
                ratios
                    .iter()
                    .map(|&q| rows.iter().find(|r| r.g_n == vn && r.g_t_over_g_n == q).map_or(f64::NAN, f))
                    .collect()
            })
            .collect()
    };
    let map = |title: String, label: &str, values: Vec<Vec<f64>>, scale: (f64, f64)| Heatmap {
        title,
        x_label: "g_t / g_n".into(),
        y_label: "g_n (m/s)".into(),
        x_range: (-0.5, ratios.len() as f64 - 0.5),
        y_range: (-0.5, g_n.len() as f64 - 0.5),
        values,
        colorbar_label: label.into(),
        scale: Some(scale),
        cell_names: Some((names(ratios), names(g_n))),
    };
    vec![
        (
            format!("{name}_beta"),
            map(
                format!("Tangential restitution beta, {what} (-1 smooth, 1 rough)"),
                "beta",
                grid(|r| r.beta),
                (-1.0, 1.0),
            ),
        ),
        (
            format!("{name}_eps_n"),
            map(format!("Normal restitution eps_n, {what}"), "eps_n", grid(|r| r.eps_n), (0.0, 1.0)),
        ),
    ]
}

/// One row of a restitution table: `g_n, g_t/g_n, eps_n, beta`.
pub type Row = particles::experiment::restitution::Row;

/// Brings each coefficient into the collision rule's range (`eps_n` in [0, 1], `beta` in
/// [-1, 1]), so that the table reads back as a rule; a value outside it is an integration
/// error of the impact (e.g. beta = -1.0075 for a grazing impact). Returns a note per value
/// moved, naming its row, for the summary's warnings.
pub fn clamp_to_rule(name: &str, rows: &mut [Row]) -> Vec<String> {
    let mut notes = Vec::new();
    for r in rows.iter_mut() {
        for (column, x, lo) in [("eps_n", &mut r.eps_n, 0.0), ("beta", &mut r.beta, -1.0)] {
            if !(lo..=1.0).contains(x) {
                let moved = x.clamp(lo, 1.0);
                notes.push(format!(
                    "{name}.csv row g_n = {}, g_t/g_n = {}: {column} = {x} is outside the rule's [{lo}, 1] (an integration error of the impact); written as {moved}",
                    r.g_n, r.g_t_over_g_n
                ));
                *x = moved;
            }
        }
    }
    notes
}

/// What `--table` wrote: `summary.json`, field for field.
#[derive(Clone, Debug, Serialize)]
pub struct TableSummary {
    pub restitution: TableRange,
    pub restitution_floor: TableRange,
    /// Where the laws came from: the law options or a scene.
    pub laws_from: String,
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub written: Written,
}

/// The impacts of one table and the range of their coefficients.
#[derive(Clone, Debug, Serialize)]
pub struct TableRange {
    pub impacts: usize,
    pub beta_min: f64,
    pub beta_max: f64,
    pub eps_n_min: f64,
    pub eps_n_max: f64,
}

impl Summary for TableSummary {
    fn headline(&self) -> Headline {
        Headline::written(self.warnings.len(), &self.written)
    }
}

/// `--table`: the restitution tables of pairs and of the floor, with plots.
pub fn restitution_table(args: &Options) -> Result<TableSummary, CliError> {
    for &x in args.g_n.iter().chain(&args.ratios) {
        if !(x.is_finite() && x > 0.0) {
            return Err(format!("--g-n and --ratios must be positive numbers, got {x}").into());
        }
    }
    let mut pair = Options {
        wall: false,
        eccentricity: None,
        ..args.clone()
    }
    .collision()?;
    let mut floor = pair;
    floor.target = Target::Wall;
    let mut source = "the law options".to_string();
    if let Some(path) = &args.scene {
        let scene = crate::scene::file::load(path, &[])?.dem;
        let (pair_law, wall_law) = scene.laws()?;
        let r = 0.5 * (scene.particles.radius_min + scene.particles.radius_max);
        let m = scene.material().density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        pair.law = pair_law;
        (pair.r1, pair.m1) = (r, m);
        pair.target = Target::Sphere {
            r,
            m,
            omega: Vec3::zeros(),
        };
        floor = pair;
        floor.law = wall_law;
        floor.target = Target::Wall;
        source = format!("{} (radius {r:e} m, density {} kg/m^3)", path.display(), scene.material().density);
    }
    // Every impact is computed before anything is written: a failed table leaves nothing,
    // so its corrected rerun needs no --force.
    let mut tables = Vec::new();
    let mut warnings = Vec::new();
    for (name, base) in [("restitution", pair), ("restitution_floor", floor)] {
        let mut rows = particles::experiment::restitution::table(&base, &args.g_n, &args.ratios)?;
        warnings.extend(clamp_to_rule(name, &mut rows));
        tables.push((name, rows));
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out/collide"));
    crate::rundir::output::claim(&out, args.force)?;
    let mut dir = RunDir::create(&out, &args)?;
    let mut ranges = Vec::new();
    for (name, rows) in tables {
        let table: Vec<Vec<f64>> = rows.iter().map(|r| vec![r.g_n, r.g_t_over_g_n, r.eps_n, r.beta]).collect();
        dir.csv(&format!("{name}.csv"), &["g_n", "g_t_over_g_n", "eps_n", "beta"], &table)?;
        for (stem, map) in restitution_maps(name, &rows, &args.g_n, &args.ratios) {
            let files = map.save(&out.join(&stem)).map_err(|e| format!("cannot draw {stem}: {e}"))?;
            dir.note_files(files);
        }
        let range = |f: fn(&Row) -> f64| {
            rows.iter()
                .map(f)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)))
        };
        let ((beta_min, beta_max), (eps_n_min, eps_n_max)) = (range(|r| r.beta), range(|r| r.eps_n));
        ranges.push(TableRange {
            impacts: rows.len(),
            beta_min,
            beta_max,
            eps_n_min,
            eps_n_max,
        });
    }
    let [restitution, restitution_floor] = <[TableRange; 2]>::try_from(ranges).map_err(|_| "two tables")?;
    let summary = TableSummary {
        restitution,
        restitution_floor,
        laws_from: source,
        warnings,
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(g_n: f64, q: f64, eps_n: f64, beta: f64) -> Row {
        Row {
            g_n,
            g_t_over_g_n: q,
            eps_n,
            beta,
        }
    }

    /// Issue 43: `collide --table` wrote beta = -1.0075, which the event-driven model's
    /// table reader refused; values outside the rule's range are brought into it, each
    /// named by its row, and the table reads back as a rule.
    #[test]
    fn a_table_is_clamped_to_the_rule_and_reads_back() {
        let mut rows = vec![
            row(0.1, 0.5, 0.9, 0.3),
            row(0.1, 10.0, 0.9, -1.0075),
            row(1.0, 0.5, 1.002, 0.2),
            row(1.0, 10.0, 0.8, -0.99),
        ];
        let notes = clamp_to_rule("restitution", &mut rows);
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(
            notes[0].contains("row g_n = 0.1, g_t/g_n = 10: beta = -1.0075") && notes[0].contains("written as -1"),
            "{notes:?}"
        );
        assert!(notes[1].contains("row g_n = 1, g_t/g_n = 0.5: eps_n = 1.002"), "{notes:?}");
        assert_eq!((rows[1].beta, rows[2].eps_n), (-1.0, 1.0));
        assert_eq!(rows[0], row(0.1, 0.5, 0.9, 0.3), "values inside the range are kept");
        let dir = std::env::temp_dir().join(format!("stripes-collide-clamp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("restitution.csv");
        let table: Vec<Vec<f64>> = rows.iter().map(|r| vec![r.g_n, r.g_t_over_g_n, r.eps_n, r.beta]).collect();
        analysis::io::write_csv_atomic(&csv, &["g_n", "g_t_over_g_n", "eps_n", "beta"], &table).unwrap();
        let t = crate::scene::events::read_table(&csv).unwrap();
        assert_eq!(t.beta[0][1], -1.0);
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Issue 43: the restitution plots show the whole table (one cell per impact, every
    /// ratio labelled) on the rule's range, not one unlabelled curve on an axis to 2.
    #[test]
    fn the_restitution_maps_show_every_impact_on_the_rules_range() {
        let (g_n, ratios) = ([0.1, 1.0], [0.5, 2.0, 10.0]);
        let rows: Vec<Row> = g_n
            .iter()
            .flat_map(|&v| ratios.iter().map(move |&q| row(v, q, 0.9 - 0.1 * v, (1.0 - q) / 10.0)))
            .collect();
        let maps = restitution_maps("restitution_floor", &rows, &g_n, &ratios);
        assert_eq!(maps[0].0, "restitution_floor_beta");
        assert_eq!(maps[1].0, "restitution_floor_eps_n");
        let (beta, eps) = (&maps[0].1, &maps[1].1);
        assert_eq!((beta.scale, eps.scale), (Some((-1.0, 1.0)), Some((0.0, 1.0))));
        assert_eq!(eps.values.len(), 2);
        assert!(eps.values.iter().all(|r| r.len() == 3));
        assert_eq!(eps.values[1][2], 0.8);
        assert_eq!(beta.values[0][2], -0.9);
        let (x, y) = beta.cell_names.clone().unwrap();
        assert_eq!(
            (x, y),
            (
                vec!["0.5".to_string(), "2".into(), "10".into()],
                vec!["0.1".to_string(), "1".into()]
            )
        );
        assert!(beta.title.contains("the floor") && eps.title.contains("eps_n"));
    }
}
