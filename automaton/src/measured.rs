//! The automaton's parameter file, `RUN/mechanism/automaton.toml`, as `stripes mechanism`
//! writes it from a DEM run (issue 40, step 1; the writer is the root crate's
//! `pipeline::coarse::Parameters`). This is the reader: a serde mirror of the fields the
//! `measured` rule needs ([`crate::measured_rule`]); other fields of the file are ignored.
//! The root crate reads the text (this crate knows no file format) and names the file in
//! every error; the errors here name the key.
//!
//! Lengths are metres, as written.

use serde::{Deserialize, Serialize};

/// The file: where it was measured, the cell, the excursions and the bands.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct MeasuredFile {
    pub source: Source,
    pub cell: Cell,
    pub excursion: Excursions,
    /// The swing against the local packing over the whole run (the `swing` rule's numbers;
    /// absent in files written before it was measured).
    pub swing_field: Option<SwingFieldFile>,
    pub bands: Bands,
}

/// `[swing_field]`: the swing at each class of window packing over every half period of the
/// run.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct SwingFieldFile {
    /// The packing window's half-length along x, in mean diameters.
    pub local_radius_diameters: f64,
    /// Its half-height across the tray (m): as far as the DEM's moves stay correlated.
    pub across_m: f64,
    pub classes: Vec<SwingClassFile>,
}

/// `[[swing_field.classes]]`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub struct SwingClassFile {
    pub low: f64,
    pub high: f64,
    /// The class's mean packing.
    pub packing: f64,
    /// `|dx|` per half period (m).
    pub swing: Spread,
    /// A grain's signed move less its neighbours' mean move (m; its `sd` is read).
    pub relative: Spread,
}

/// The DEM run the file was measured on: what a scene that uses the file must share.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Source {
    pub run: String,
    pub grains: usize,
    pub mean_diameter_m: f64,
    pub length_m: f64,
    pub width_m: f64,
    /// x periodic (no end walls).
    pub periodic: bool,
    /// The drive's stages: (start s, frequency Hz, amplitude m).
    pub drive: Vec<[f64; 3]>,
}

/// `[cell]`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct Cell {
    /// Absent when the run held no band.
    pub size_m: Option<f64>,
}

/// Mean, spread and quantiles of a length (m): `[excursion.*.excursion]` and the like.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub struct Spread {
    pub samples: usize,
    pub mean: f64,
    /// Standard deviation (0 in files written before it was).
    #[serde(default)]
    pub sd: f64,
    pub q10: f64,
    pub q25: f64,
    pub median: f64,
    pub q75: f64,
    pub q90: f64,
}

/// One class of local state: `|dx|` and `|dy|` per half period relative to the tray.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub struct ClassMoves {
    /// Contact number `low` (= `high`; the last class holds every number from it on).
    pub low: f64,
    pub high: f64,
    pub excursion: Spread,
    pub sideways: Spread,
}

/// `[excursion]`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct Excursions {
    pub all: ClassMoves,
    pub by_contacts: Vec<ClassMoves>,
    /// `dx1 + dx2` over two consecutive half periods, signed along x: a grain's drift over
    /// its swing out and back (absent in files written before it was measured).
    pub drift_signed: Option<Spread>,
}

/// `[bands]`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub struct Bands {
    pub core_packing: Option<f64>,
    /// Fraction of a band's edge grains in no band one period later (same turning point).
    pub edge_escape_per_period: Option<f64>,
}

/// A value of the file that the rule cannot use, naming its dotted key.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredError {
    pub key: String,
    pub message: String,
}

impl std::fmt::Display for MeasuredError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "`{}`: {}", self.key, self.message)
    }
}

impl std::error::Error for MeasuredError {}

fn err(key: impl Into<String>, message: impl Into<String>) -> MeasuredError {
    MeasuredError {
        key: key.into(),
        message: message.into(),
    }
}

impl Spread {
    /// Every length finite and >= 0, the quantiles in order.
    fn validate(&self, key: &str) -> Result<(), MeasuredError> {
        let q = [self.q10, self.q25, self.median, self.q75, self.q90];
        for (name, v) in [("mean", self.mean)]
            .into_iter()
            .chain(["q10", "q25", "median", "q75", "q90"].into_iter().zip(q))
        {
            if !(v.is_finite() && v >= 0.0) {
                return Err(err(format!("{key}.{name}"), format!("must be a finite length >= 0 (m), got {v}")));
            }
        }
        if q.windows(2).any(|w| w[1] < w[0]) {
            return Err(err(key, format!("quantiles q10..q90 must not decrease, got {q:?}")));
        }
        Ok(())
    }
}

impl MeasuredFile {
    /// The cell size (m), checked.
    pub fn cell_size(&self) -> Result<f64, MeasuredError> {
        match self.cell.size_m {
            None => Err(err("cell.size_m", "absent: the DEM run held no band, so it gives no cell")),
            Some(s) if s.is_finite() && s > 0.0 => Ok(s),
            Some(s) => Err(err("cell.size_m", format!("must be a positive length (m), got {s}"))),
        }
    }

    /// The edge escape per period, checked.
    pub fn edge_escape(&self) -> Result<f64, MeasuredError> {
        match self.bands.edge_escape_per_period {
            None => Err(err("bands.edge_escape_per_period", "absent: the DEM run held no band edge")),
            Some(p) if (0.0..=1.0).contains(&p) => Ok(p),
            Some(p) => Err(err("bands.edge_escape_per_period", format!("must lie in [0, 1], got {p}"))),
        }
    }

    /// The signed drift per period, checked: finite, quantiles in order.
    pub fn drift_signed(&self) -> Result<&Spread, MeasuredError> {
        let key = "excursion.drift_signed";
        let Some(s) = &self.excursion.drift_signed else {
            return Err(err(
                key,
                "absent: the file predates it; run `stripes mechanism RUN --coarse-only` again",
            ));
        };
        let q = [s.q10, s.q25, s.median, s.q75, s.q90];
        if !(s.mean.is_finite() && q.iter().all(|v| v.is_finite())) {
            return Err(err(key, format!("must be finite lengths (m), got mean {} and {q:?}", s.mean)));
        }
        if q.windows(2).any(|w| w[1] < w[0]) {
            return Err(err(key, format!("quantiles q10..q90 must not decrease, got {q:?}")));
        }
        Ok(s)
    }

    /// The swing field, checked: classes of increasing packing with finite, non-negative
    /// swings and spreads, and a positive disk radius.
    pub fn swing_field(&self) -> Result<&SwingFieldFile, MeasuredError> {
        let key = "swing_field";
        let Some(f) = &self.swing_field else {
            return Err(err(
                key,
                "absent: the file predates it; run `stripes mechanism RUN --coarse-only` again",
            ));
        };
        for (name, v) in [("local_radius_diameters", f.local_radius_diameters), ("across_m", f.across_m)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(err(format!("swing_field.{name}"), format!("must be positive, got {v}")));
            }
        }
        if f.classes.iter().all(|c| c.swing.samples == 0) {
            return Err(err("swing_field.classes", "no class holds a measured swing"));
        }
        for (k, c) in f.classes.iter().enumerate() {
            for (name, v) in [("packing", c.packing), ("swing.mean", c.swing.mean), ("relative.sd", c.relative.sd)] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(err(
                        format!("swing_field.classes[{k}].{name}"),
                        format!("must be finite and >= 0, got {v}"),
                    ));
                }
            }
            if k > 0 && c.packing <= f.classes[k - 1].packing {
                return Err(err(format!("swing_field.classes[{k}].packing"), "classes must increase in packing"));
            }
        }
        Ok(f)
    }

    /// Checks what the rule reads; errors name the dotted key.
    pub fn validate(&self) -> Result<(), MeasuredError> {
        self.cell_size()?;
        self.edge_escape()?;
        self.excursion.all.excursion.validate("excursion.all.excursion")?;
        self.excursion.all.sideways.validate("excursion.all.sideways")?;
        self.drift_signed()?;
        if self.excursion.all.excursion.samples == 0 {
            return Err(err("excursion.all.excursion.samples", "no excursion was measured"));
        }
        for (k, c) in self.excursion.by_contacts.iter().enumerate() {
            c.excursion.validate(&format!("excursion.by_contacts[{k}].excursion"))?;
            c.sideways.validate(&format!("excursion.by_contacts[{k}].sideways"))?;
            if !(c.low.is_finite() && c.low >= 0.0) {
                return Err(err(
                    format!("excursion.by_contacts[{k}].low"),
                    format!("must be a contact number >= 0, got {}", c.low),
                ));
            }
            if k > 0 && c.low <= self.excursion.by_contacts[k - 1].low {
                return Err(err(
                    format!("excursion.by_contacts[{k}].low"),
                    "classes must increase in contact number",
                ));
            }
        }
        Ok(())
    }

    /// The class of grains with `n` contacts: the class of the largest contact number `<= n`
    /// that holds samples (the last class holds every number from its own on); the overall
    /// distribution if none does.
    pub fn class(&self, n: usize) -> &ClassMoves {
        self.excursion
            .by_contacts
            .iter()
            .rev()
            .find(|c| c.low <= n as f64 && c.excursion.samples > 0)
            .unwrap_or(&self.excursion.all)
    }
}

/// The scene's side of [`Source`]: what the scene runs on.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSource {
    pub grains: usize,
    pub mean_diameter_m: f64,
    pub length_m: f64,
    pub width_m: f64,
    pub periodic: bool,
    /// (frequency Hz, amplitude m) of each stage.
    pub drive: Vec<[f64; 2]>,
}

/// Relative tolerance on the mean diameter: the file measures the sample's radii, the scene
/// gives their range.
pub const DIAMETER_TOLERANCE: f64 = 0.01;

impl Source {
    /// The first key of `[source]` whose value the scene does not share, with both values:
    /// grains, mean diameter (within [`DIAMETER_TOLERANCE`]), tray length and width,
    /// periodic x, and the drive's frequencies and amplitudes (relative 1e-9).
    pub fn mismatch(&self, scene: &SceneSource) -> Option<MeasuredError> {
        let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * a.abs().max(b.abs());
        let differ = |key: &str, file: String, scene: String| {
            Some(err(
                format!("source.{key}"),
                format!("the file was measured with {file}, the scene has {scene}"),
            ))
        };
        if self.grains != scene.grains {
            return differ("grains", self.grains.to_string(), scene.grains.to_string());
        }
        if !close(self.mean_diameter_m, scene.mean_diameter_m, DIAMETER_TOLERANCE) {
            return differ(
                "mean_diameter_m",
                format!("{} m", self.mean_diameter_m),
                format!("{} m (more than 1 % apart)", scene.mean_diameter_m),
            );
        }
        if !close(self.length_m, scene.length_m, 1e-9) {
            return differ("length_m", format!("{} m", self.length_m), format!("{} m", scene.length_m));
        }
        if !close(self.width_m, scene.width_m, 1e-9) {
            return differ("width_m", format!("{} m", self.width_m), format!("{} m", scene.width_m));
        }
        if self.periodic != scene.periodic {
            return differ("periodic", self.periodic.to_string(), scene.periodic.to_string());
        }
        let file: Vec<[f64; 2]> = self.drive.iter().map(|s| [s[1], s[2]]).collect();
        let same = file.len() == scene.drive.len()
            && file
                .iter()
                .zip(&scene.drive)
                .all(|(a, b)| close(a[0], b[0], 1e-9) && close(a[1], b[1], 1e-9));
        if !same {
            return differ("drive", format!("{file:?} (Hz, m)"), format!("{:?}", scene.drive));
        }
        None
    }
}

/// The fractions of the knots of a [`Quantiles`]: 0, the five measured quantiles, 1.
pub const KNOTS: [f64; 7] = [0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0];

/// An inverse cumulative distribution `Q(u)` of a length, piecewise linear through the
/// measured quantiles q10, q25, median, q75, q90 at their fractions. The two tails are
/// straight too; their ends `Q(0)`, `Q(1)` start as the straight continuation of the
/// neighbouring piece (never below 0), and are then moved so that the mean of `Q` is the
/// measured mean: `Q(0)` first (down to 0) when the mean must fall, then `Q(1)` (down to
/// q90); `Q(1)` when it must rise. So a draw `Q(u)`, `u` uniform, reproduces the five
/// quantiles exactly and the mean wherever the tails can carry it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quantiles {
    /// `Q` at [`KNOTS`] (m).
    pub at_knots: [f64; 7],
}

impl Quantiles {
    pub fn of(s: &Spread) -> Self {
        let (q10, q25, q50, q75, q90) = (s.q10, s.q25, s.median, s.q75, s.q90);
        let mut q = [
            (q10 - (q25 - q10) * 0.1 / 0.15).max(0.0),
            q10,
            q25,
            q50,
            q75,
            q90,
            q90 + (q90 - q75) * 0.1 / 0.15,
        ];
        let mean = |q: &[f64; 7]| -> f64 {
            KNOTS
                .windows(2)
                .zip(q.windows(2))
                .map(|(u, x)| (u[1] - u[0]) * 0.5 * (x[0] + x[1]))
                .sum()
        };
        // Each tail end weighs 0.1 / 2 in the mean.
        let diff = s.mean - mean(&q);
        if diff < 0.0 {
            let down = (-diff / 0.05).min(q[0]);
            q[0] -= down;
            let rest = s.mean - mean(&q);
            if rest < 0.0 {
                q[6] -= (-rest / 0.05).min(q[6] - q90);
            }
        } else {
            q[6] += diff / 0.05;
        }
        Self { at_knots: q }
    }

    /// As [`Self::of`] for a signed length: the tails continue straight, without the floor
    /// at 0, and the measured mean is kept by moving `Q(0)` down or `Q(1)` up.
    pub fn signed(s: &Spread) -> Self {
        let mut q = [
            s.q10 - (s.q25 - s.q10) * 0.1 / 0.15,
            s.q10,
            s.q25,
            s.median,
            s.q75,
            s.q90,
            s.q90 + (s.q90 - s.q75) * 0.1 / 0.15,
        ];
        let diff = s.mean - Self { at_knots: q }.mean();
        if diff < 0.0 {
            q[0] += diff / 0.05;
        } else {
            q[6] += diff / 0.05;
        }
        Self { at_knots: q }
    }

    /// `Q(u)` for `u` in [0, 1] (m).
    pub fn at(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        let k = KNOTS.partition_point(|&x| x <= u).clamp(1, KNOTS.len() - 1);
        let (u0, u1) = (KNOTS[k - 1], KNOTS[k]);
        let (x0, x1) = (self.at_knots[k - 1], self.at_knots[k]);
        x0 + (x1 - x0) * (u - u0) / (u1 - u0)
    }

    /// The mean of `Q(u)` over uniform `u` (m).
    pub fn mean(&self) -> f64 {
        KNOTS
            .windows(2)
            .zip(self.at_knots.windows(2))
            .map(|(u, x)| (u[1] - u[0]) * 0.5 * (x[0] + x[1]))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spread(mean: f64, q: [f64; 5]) -> Spread {
        Spread {
            samples: 100,
            mean,
            sd: 0.0,
            q10: q[0],
            q25: q[1],
            median: q[2],
            q75: q[3],
            q90: q[4],
        }
    }

    #[test]
    fn the_inverse_cdf_passes_through_the_quantiles_and_keeps_the_mean() {
        // The stripe scene's overall excursion (seed 1) and its sideways steps, whose lower
        // quantiles are 0.
        for s in [
            spread(
                0.013250126770672077,
                [
                    0.010130457653176819,
                    0.01283641483061668,
                    0.01426233673158028,
                    0.014290059879498471,
                    0.014297988725621326,
                ],
            ),
            spread(
                0.0002507207666312752,
                [0.0, 0.0, 0.000007845461368560791, 0.000330016206135042, 0.0008673279080539944],
            ),
        ] {
            let q = Quantiles::of(&s);
            for (u, v) in [(0.1, s.q10), (0.25, s.q25), (0.5, s.median), (0.75, s.q75), (0.9, s.q90)] {
                assert!((q.at(u) - v).abs() < 1e-15, "{u}: {} against {v}", q.at(u));
            }
            assert!(
                (q.mean() - s.mean).abs() < 1e-12 * s.mean.max(1e-9),
                "{} against {}",
                q.mean(),
                s.mean
            );
            assert!(q.at_knots.windows(2).all(|w| w[1] >= w[0]) && q.at_knots[0] >= 0.0, "{q:?}");
        }
    }

    #[test]
    fn the_signed_inverse_cdf_passes_through_the_quantiles_and_keeps_the_mean() {
        // The stripe scene's signed drift per period (seed 1): mostly tiny, negative mean.
        let s = spread(-0.000149, [-0.00204, -0.00015, -2.9e-5, 2.1e-5, 0.00135]);
        let q = Quantiles::signed(&s);
        for (u, v) in [(0.1, s.q10), (0.25, s.q25), (0.5, s.median), (0.75, s.q75), (0.9, s.q90)] {
            assert!((q.at(u) - v).abs() < 1e-15, "{u}: {} against {v}", q.at(u));
        }
        assert!((q.mean() - s.mean).abs() < 1e-15, "{} against {}", q.mean(), s.mean);
        assert!(q.at_knots.windows(2).all(|w| w[1] >= w[0]), "{q:?}");
    }
}
