//! Speed against error: every choice that trades accuracy for speed, measured on the collision
//! lab and on a small shaken tray, against a converged reference computed in the same run.
//!
//! What varies: steps per contact (the time step), Young's modulus (softer contacts last
//! longer, so the same steps per contact give a larger step), the integrator (velocity Verlet
//! or the thesis' scheme), 3D against pinned 2D (tray), a cheaper normal law (a linear
//! spring-dashpot matched to the Hertz law's restitution and contact time: no square roots),
//! the neighbour skin and the rebuild policy (skin 0: rebuild every step), and the defaults
//! (`dt = "auto"` at the default restitution tolerance, see [`particles::experiment::step_control`]).
//!
//! What is measured, per setting:
//! - `speed_ratio`: time of the reference setting divided by the setting's, both measured
//!   here, for the same simulated time. With one worker thread the times are the on-CPU
//!   times of that thread ([`crate::host::clock::Stopwatch`]), which is the wall time on an idle core. The lab's
//!   impacts last microseconds and their time is dominated by setting each one up, so its
//!   speed ratio counts steps per simulated second of contact instead (the wall-time ratio
//!   of a long run at equal cost per step; the tray rows time the cost per step);
//! - collision lab: `error` is the restitution error, the largest `|d eps_n|`, `|d eps_t|`
//!   over the probe impacts of [`particles::experiment::step_control`] against velocity Verlet at
//!   [`particles::experiment::step_control::REFERENCE_STEPS`] steps per contact with the reference material;
//!   `energy_error` is the largest relative energy error of the same impacts made elastic
//!   (no dissipation, no friction, no rolling resistance);
//! - tray: `error` is the distance between density maps, the mean over sampled times (four
//!   per period) of `mean_x |phi(x) - phi_ref(x)| / <phi>` on 1 mm cells of the exact area
//!   fraction ([`analysis::density::area_fraction_cells`]) against a run at
//!   `tray.reference_steps` steps per contact; also the stripe count at the end and the onset
//!   time ([`analysis::stripes`]), and `energy_error`, how far the energy ledger misses
//!   closing: `|E(t) - E(0) - (injected - dissipated)| / injected`.
//!
//! The tray is chaotic: two runs that differ in the last bit diverge, so the density distance
//! of any setting that changes the numbers has a floor set by that divergence over the
//! simulated time (reported as the `noise floor` row: the reference with one grain moved by
//! 1 nm, compared with the reference itself). Settings that do not change a single bit (the
//! neighbour skin and rebuild policy) have exactly the reference's error.

pub mod bench;
mod friction;
mod lab;
mod setting;
mod shaken;

pub use friction::{friction_law_keys, friction_laws, friction_table};
pub use setting::{Config, Row, Study};
pub use shaken::dense_packing;

use particles::SimError;

/// Marks the Pareto front within each study.
pub fn mark_front(rows: &mut [Row]) {
    let eligible = |r: &Row| r.axis != "noise floor" && r.study != Study::HardCase && r.error.is_finite();
    let flags: Vec<bool> = rows
        .iter()
        .map(|r| {
            eligible(r)
                && !rows.iter().any(|o| {
                    eligible(o)
                        && o.study == r.study
                        && o.speed_ratio >= r.speed_ratio
                        && o.error <= r.error
                        && (o.speed_ratio > r.speed_ratio || o.error < r.error)
                })
        })
        .collect();
    for (r, f) in rows.iter_mut().zip(flags) {
        r.on_front = f;
    }
}

/// Runs both studies and the dense-packing hard case. `progress` receives a line per row.
pub fn run(config: &Config, mut progress: impl FnMut(&str)) -> Result<Vec<Row>, SimError> {
    let mut rows = lab::collision_study(config, &mut progress)?;
    rows.extend(shaken::tray_study(config, &mut progress)?);
    if config.dense_steps > 0 {
        rows.push(dense_packing(config.dense_steps, config.cpu_time)?);
        progress(&rows.last().expect("pushed").name);
    }
    mark_front(&mut rows);
    Ok(rows)
}

/// The rows as a Markdown table.
pub fn markdown_table(rows: &[Row]) -> String {
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2e}"));
    let mut out = String::from(
        "| study | setting | dt (s) | steps/contact | speed ratio | error | eps error | energy error | density distance | stripes | onset (s) | front |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let study = match r.study {
            Study::Collision => "lab",
            Study::Tray => "tray",
            Study::HardCase => "hard case",
        };
        out.push_str(&format!(
            "| {study} | {} | {:.2e} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.name,
            r.dt,
            if r.steps_per_contact.is_finite() {
                format!("{:.1}", r.steps_per_contact)
            } else {
                "-".into()
            },
            r.speed_ratio,
            if r.error == 0.0 {
                "0 (bit-identical)".to_string()
            } else if r.error.is_nan() {
                "refused, see below".to_string()
            } else {
                format!("{:.2e}", r.error)
            },
            opt(r.eps_error),
            opt(r.energy_error),
            opt(r.density_distance),
            r.stripes.map_or("-".into(), |s| s.to_string()),
            r.onset_s.map_or("-".into(), |t| format!("{t:.3}")),
            if r.on_front { "yes" } else { "" }
        ));
    }
    let notes: Vec<&Row> = rows
        .iter()
        .filter(|r| r.error.is_nan() || r.study == Study::HardCase || r.axis == "default")
        .collect();
    if !notes.is_empty() {
        out.push_str("\nOutcomes:\n\n");
        for r in notes {
            out.push_str(&format!("- {}: {}\n", r.name, r.outcome));
        }
    }
    out.replace("| NaN |", "| - |")
}

#[cfg(test)]
mod tests {
    use super::lab::matched_linear;
    use super::*;
    use particles::experiment::closed_form::linear_dashpot;

    fn row(study: Study, speed: f64, error: f64) -> Row {
        Row {
            speed_ratio: speed,
            error,
            wall_s: 1.0,
            dt: 1.0,
            steps_per_contact: 1.0,
            ..Row::blank(format!("{speed} {error}"), study, "time step")
        }
    }

    #[test]
    fn the_front_keeps_exactly_the_undominated_rows_per_study() {
        let mut rows = vec![
            row(Study::Collision, 1.0, 1e-3),
            row(Study::Collision, 2.0, 1e-2),
            row(Study::Collision, 0.5, 1e-2), // dominated by the first
            row(Study::Collision, 2.0, 1e-1), // dominated by the second
            row(Study::Tray, 0.1, 1.0),       // alone in its study
        ];
        mark_front(&mut rows);
        let front: Vec<bool> = rows.iter().map(|r| r.on_front).collect();
        assert_eq!(front, vec![true, true, false, false, true]);
    }

    #[test]
    fn matched_linear_law_reproduces_restitution_and_contact_time() {
        let (m, eps, tc, v) = (8e-8, 0.83, 1e-4, 3.0);
        let (k, g) = matched_linear(m, eps, tc, v);
        let (tc2, eps2) = linear_dashpot(m, k, g, v);
        assert!((eps2 - eps).abs() < 1e-12, "{eps2}");
        assert!((tc2 - tc).abs() < 1e-12 * tc, "{tc2}");
    }

    #[test]
    fn identical_profiles_have_zero_distance() {
        use super::shaken::density_distance;
        let a = vec![vec![0.2, 0.3, 0.1]; 3];
        assert_eq!(density_distance(&a, &a, 0.2), 0.0);
        let mut b = a.clone();
        b[1][0] = 0.5;
        assert!((density_distance(&a, &b, 0.2) - 0.3 / 3.0 / 3.0 / 0.2).abs() < 1e-15);
    }
}
