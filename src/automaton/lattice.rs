//! The automaton on a scene: its lattice from the DEM's prepared sample and its parameters
//! from the tray, through the single-sphere DEM (the CLI is the only place that knows both
//! crates; `automaton` never depends on `particles`).
//!
//! - Cells: square-ish, one mean grain diameter `d = r_min + r_max`: `nx = round(L / d)`,
//!   `ny = max(1, round(W / d))`, cell `(L / nx) x (W / ny)`.
//! - Lattice: every grain of the sample goes to the cell holding its centre; if that is
//!   taken, to the nearest free cell (searched in rings of growing distance, same row
//!   first), and only if none is free within 3 cells it is stacked on its own cell. The
//!   sample is a monolayer at packing 0.23, so a few percent of grains are displaced by at
//!   most a cell and none is stacked (the run's summary reports both counts).
//! - Flight cap: the single-sphere DEM (`particles::experiment::single`, radius = the mean
//!   radius, the scene's material and floor law, at rest in the lab at t = 0) on the scene's
//!   drive for `SLIDE_PERIODS` periods; its displacement relative to the tray between the
//!   last turning points, in cells ([`automaton::mapping::slide_from_samples`]). The Coulomb
//!   block ([`automaton::mapping::coulomb_slide`]) is reported next to it as a check.
//! - Sliding threshold `A (2 pi nu)^2 > mu_wall g` (with `[automaton] rolling`, the default,
//!   free grains roll below it by the single sphere's excursion; see
//!   `automaton::mapping::physical`); knock probability from the DEM's peak
//!   sliding speed.

use std::path::Path;
use std::time::Instant;

use analysis::snapshot::{Header, SnapshotWriter};
use automaton::mapping::{self, FreeParams, SlideMeasure, TrayDrive};
use automaton::{Automaton, Direction, Tracks};
use automaton::{Lattice, Params, RuleSet, YBoundary};
use indicatif::ProgressBar;
use particles::constants::GRAVITY;
use particles::experiment::single::SphereOnFloor;
use particles::scene::{Scene, SceneError};
use serde::Serialize;

use crate::rundir::output::{progress_bar, CliError};
use crate::scene::file::SceneFile;

/// Periods of the single-sphere run behind the flight cap.
pub const SLIDE_PERIODS: f64 = 4.0;

/// Lattice geometry of a scene.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Cells {
    pub nx: usize,
    pub ny: usize,
    /// Cell length along x and y (m).
    pub dx: f64,
    pub dy: f64,
}

impl Cells {
    pub fn of(file: &SceneFile) -> Self {
        let scene = &file.dem;
        let d = file
            .automaton
            .parameters_cell
            .or(file.automaton.cell)
            .unwrap_or(scene.particles.radius_min + scene.particles.radius_max);
        let nx = ((scene.tray.length / d).round() as usize).max(1);
        let ny = ((scene.tray.width / d).round() as usize).max(1);
        Self {
            nx,
            ny,
            dx: scene.tray.length / nx as f64,
            dy: scene.tray.width / ny as f64,
        }
    }
}

/// The lattice of a scene file, checked by every command that runs the automaton (not by a
/// DEM-only run, whose scene may be too dense or small for a lattice). It must be a lattice:
/// at least 3 cells along the shaking, room for every grain in a cell of its own (the
/// automaton models a submonolayer), and not far more cells than grains (the size is
/// checked before anything is allocated).
pub fn validate_lattice(file: &SceneFile) -> Result<(), SceneError> {
    if !file.dem.drive.stages.is_empty() {
        return Err(SceneError {
            key: "drive.stages".into(),
            message: "the automaton runs one drive for the whole run, not a schedule: give drive.frequency and \
                      drive.amplitude instead (e.g. the last stage's)"
                .into(),
        });
    }
    // Its periods and snapshot bytes first (crate::scene::bounds).
    for w in crate::scene::bounds::automaton(&file.dem)? {
        eprintln!("warning: {w}");
    }
    let periods = (file.dem.run.duration * file.dem.drive.frequency).round().max(1.0);
    let every = file.automaton.snapshot_every;
    if every as f64 > periods {
        return Err(SceneError {
            key: "automaton.snapshot_every".into(),
            message: format!("{every} periods between snapshots is more than the run's {periods} periods"),
        });
    }
    let c = Cells::of(file);
    let grains = file.dem.particles.count as f64;
    let cells = c.nx as f64 * c.ny as f64;
    let fail = |message: String| {
        Err(SceneError {
            key: "automaton.cell".into(),
            message,
        })
    };
    if c.nx < 3 {
        return fail(format!(
            "gives {} cell(s) along box.length = {} m; the automaton needs at least 3 (a cell of at most {} m)",
            c.nx,
            file.dem.tray.length,
            file.dem.tray.length / 3.0
        ));
    }
    if cells < grains {
        return fail(format!(
            "gives {} x {} = {cells} cells for {grains} grains: the automaton models a submonolayer, one grain per cell; use a smaller cell",
            c.nx, c.ny
        ));
    }
    let most = 64.0 * grains + (1u64 << 20) as f64;
    if cells > most {
        return fail(format!(
            "gives {cells:.3e} cells ({:.1e} bytes of lattice) for {grains} grains; at most {most:.3e} (64 per grain) are allowed: use a larger cell",
            cells
        ));
    }
    Ok(())
}

/// The tray seen by the automaton's mapping.
pub fn tray_drive(scene: &Scene) -> TrayDrive {
    TrayDrive {
        frequency: scene.drive.frequency,
        amplitude: scene.drive.amplitude,
        mu: scene.contact.wall_friction,
        gravity: GRAVITY,
    }
}

/// A free grain's slide on the scene's tray, from the single-sphere DEM at the DEM's own
/// step ([`particles::time_step::for_scene`]: explicit, or chosen by the collision lab for
/// `dt = "auto"`), so that both models see one step. (It used to take `shortest contact time
/// / run.steps_per_contact` for `"auto"`, twice the DEM's step on `scenes/stripes.toml`;
/// the slide is converged at both: 3e-6 relative, the same 24-cell flight cap and the same
/// automaton states.)
pub fn slide_dem(scene: &Scene) -> Result<SlideMeasure, CliError> {
    let dt = particles::time_step::for_scene(scene)?;
    let sphere = SphereOnFloor::on_scene(scene, 0.5 * (scene.particles.radius_min + scene.particles.radius_max), dt)?;
    let duration = SLIDE_PERIODS / scene.drive.frequency;
    let every = ((1.0 / scene.drive.frequency) / dt / 400.0).max(1.0) as u64;
    let samples = sphere.shake(scene.drive.amplitude, scene.drive.frequency, duration, every)?;
    let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let x: Vec<f64> = samples.iter().map(|s| s.x - s.floor_x).collect();
    let u: Vec<f64> = samples.iter().map(|s| s.vx - s.floor_vx).collect();
    mapping::slide_from_samples(scene.drive.frequency, &t, &x, &u).ok_or_else(|| "single-sphere run too short to measure the slide".into())
}

/// The lattice of grains at `(x, y)`, and how many were displaced to a neighbouring free cell
/// or stacked.
pub fn lattice_from_positions(cells: &Cells, length: f64, pos: &[[f64; 2]]) -> (Lattice, usize, usize) {
    let (nx, ny) = (cells.nx, cells.ny);
    let mut h = vec![0u8; nx * ny];
    let (mut displaced, mut stacked) = (0, 0);
    // Ring offsets by distance, same row first on ties.
    let mut ring: Vec<(i64, i64)> = (-3i64..=3).flat_map(|dj| (-3i64..=3).map(move |di| (di, dj))).collect();
    ring.sort_by_key(|&(di, dj)| (di * di + dj * dj, dj.abs(), dj, di));
    for p in pos {
        let i = ((p[0].rem_euclid(length) / cells.dx).floor() as i64).rem_euclid(nx as i64);
        let j = ((p[1] / cells.dy).floor() as i64).clamp(0, ny as i64 - 1);
        let free = ring.iter().find_map(|&(di, dj)| {
            let jj = j + dj;
            if !(0..ny as i64).contains(&jj) {
                return None;
            }
            let ii = (i + di).rem_euclid(nx as i64);
            let k = jj as usize * nx + ii as usize;
            (h[k] == 0).then_some(k)
        });
        match free {
            Some(k) => {
                if k != j as usize * nx + i as usize {
                    displaced += 1;
                }
                h[k] = 1;
            }
            None => {
                let k = j as usize * nx + i as usize;
                h[k] = h[k].saturating_add(1);
                stacked += 1;
            }
        }
    }
    (Lattice::from_heights(nx, ny, &h).expect("sizes match"), displaced, stacked)
}

/// The lattice's cells and the scene's mean grain area `pi <r^2>`, with radii uniform in
/// `[r_min, r_max]` as the samples draw them: `<r^2> = (a^2 + a b + b^2) / 3`.
pub fn cell_shape(file: &SceneFile) -> mapping::CellShape {
    let (c, p) = (Cells::of(file), &file.dem.particles);
    let (a, b) = (p.radius_min, p.radius_max);
    mapping::CellShape {
        length: c.dx,
        width: c.dy,
        rows: c.ny,
        grain_area: std::f64::consts::PI * (a * a + a * b + b * b) / 3.0,
    }
}

/// The automaton's parameters for a scene, given the measured slide.
pub fn params(file: &SceneFile, rule: RuleSet, slide: &SlideMeasure, free: &FreeParams) -> Params {
    let scene = &file.dem;
    Params {
        rule,
        physical: mapping::physical(&tray_drive(scene), slide, &cell_shape(file), free),
        y: if scene.toggles.walls {
            YBoundary::Walls
        } else {
            YBoundary::Periodic
        },
        x_walls: scene.tray.x_walls,
        seed: scene.run.seed,
        measured: None,
    }
}

/// Writes automaton states as DEM snapshots: one grain per occupied cell and level at the
/// cell centre, shifted by the tray's displacement `offset` (the lattice is the tray frame),
/// z from the level, all radii `radius`.
pub struct StateWriter {
    writer: SnapshotWriter,
    cells: Cells,
    length: f64,
    radius: f64,
    diameter: f64,
}

impl StateWriter {
    pub fn create(
        path: &std::path::Path,
        cells: Cells,
        length: f64,
        width: f64,
        grains: usize,
        radius: f64,
        diameter: f64,
    ) -> Result<Self, CliError> {
        let header = Header {
            length,
            width,
            radii: vec![radius; grains],
        };
        Ok(Self {
            writer: SnapshotWriter::create(path, header).map_err(|e| format!("cannot create {}: {e}", path.display()))?,
            cells,
            length,
            radius,
            diameter,
        })
    }

    pub fn push(&mut self, time: f64, offset: f64, lattice: &Lattice) -> Result<(), CliError> {
        let c = self.cells;
        let (l, r, d) = (self.length, self.radius, self.diameter);
        let pos = lattice.grains().map(move |(i, j, z)| {
            [
                ((i as f64 + 0.5) * c.dx + offset).rem_euclid(l),
                (j as f64 + 0.5) * c.dy,
                r + z as f64 * d,
            ]
        });
        self.writer.push(time, pos, std::iter::repeat([0.0; 3]))?;
        Ok(())
    }

    /// As [`Self::push`], the grains in the order of `tracks` (grain `k` the same grain in
    /// every frame).
    pub fn push_tracked(&mut self, time: f64, offset: f64, tracks: &Tracks) -> Result<(), CliError> {
        let c = self.cells;
        let (l, r) = (self.length, self.radius);
        let pos = tracks
            .cells()
            .iter()
            .map(move |&(j, i)| [((i as f64 + 0.5) * c.dx + offset).rem_euclid(l), (j as f64 + 0.5) * c.dy, r]);
        self.writer.push(time, pos, std::iter::repeat([0.0; 3]))?;
        Ok(())
    }

    pub fn sync(&mut self) -> Result<(), CliError> {
        Ok(self.writer.sync()?)
    }
}

/// Quantiles of a sample (nearest rank), with its mean: `[q10, q25, median, q75, q90]`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Sample {
    pub samples: usize,
    pub mean: f64,
    pub q10: f64,
    pub q25: f64,
    pub median: f64,
    pub q75: f64,
    pub q90: f64,
    pub max: f64,
}

impl Sample {
    pub fn of(mut v: Vec<f64>) -> Self {
        if v.is_empty() {
            return Self::default();
        }
        v.sort_by(f64::total_cmp);
        let at = |p: f64| v[(p * (v.len() - 1) as f64).round() as usize];
        Self {
            samples: v.len(),
            mean: v.iter().sum::<f64>() / v.len() as f64,
            q10: at(0.1),
            q25: at(0.25),
            median: at(0.5),
            q75: at(0.75),
            q90: at(0.9),
            max: v[v.len() - 1],
        }
    }
}

/// What the `measured` rule's grains did, followed one by one ([`Tracks`]), and how full its
/// columns were: the numbers to set against the parameter file's.
#[derive(Clone, Debug, Default, Serialize)]
pub struct MeasuredTrace {
    /// `|dx|` over each drive period of each grain (m), against the file's
    /// `excursion.drift_per_period`.
    pub drift_per_period: Sample,
    /// Mean signed dx per period (m; + towards +x).
    pub drift_signed_mean: f64,
    /// `|dx|` over each half period of each grain (m), against `excursion.all.excursion`.
    pub excursion: Sample,
    /// `sqrt(<dx^2 + dy^2>)` per period over the mean diameter, over the whole run and over
    /// its last 10 % of periods (the analysis' tail).
    pub mobility_all: f64,
    pub mobility_tail: f64,
    /// Grains per column over the rows, at the end of every period (all columns).
    pub column_fill: Sample,
    /// The fill above which a column is a band column (the rule's).
    pub band_fill: f64,
    /// Per period: the fullest column's fill, and the columns above `band_fill`.
    pub fullest_column: Sample,
    pub band_columns: Sample,
    /// Per period: the longest run of adjacent columns above `band_fill` (a band needs
    /// `band.min_cells`).
    pub longest_run: Sample,
}

/// Accumulates a [`MeasuredTrace`].
struct Tracer {
    tracks: Tracks,
    dx: f64,
    dy: f64,
    diameter: f64,
    band_fill: f64,
    half_x: Vec<i64>,
    period_x: Vec<i64>,
    period_y: Vec<usize>,
    excursion: Vec<f64>,
    drift: Vec<f64>,
    signed: f64,
    /// Sum of squared displacements per period, per period.
    squares: Vec<f64>,
    fill: Vec<f64>,
    fullest: Vec<f64>,
    band_columns: Vec<f64>,
    longest: Vec<f64>,
}

impl Tracer {
    fn half_step(&mut self, moves: &[automaton::measured_rule::GrainMove]) {
        self.tracks.apply(moves);
        for (&x, h) in self.tracks.unwrapped_x().iter().zip(self.half_x.iter_mut()) {
            self.excursion.push((x - *h).unsigned_abs() as f64 * self.dx);
            *h = x;
        }
    }

    fn period(&mut self, l: &automaton::Lattice) {
        let mut sq = 0.0;
        for ((&x, &(j, _)), (px, py)) in self
            .tracks
            .unwrapped_x()
            .iter()
            .zip(self.tracks.cells())
            .zip(self.period_x.iter_mut().zip(self.period_y.iter_mut()))
        {
            let ddx = (x - *px) as f64 * self.dx;
            let ddy = (j as f64 - *py as f64) * self.dy;
            self.drift.push(ddx.abs());
            self.signed += ddx;
            sq += ddx * ddx + ddy * ddy;
            (*px, *py) = (x, j);
        }
        self.squares.push(sq / self.period_x.len().max(1) as f64);
        let (nx, ny) = (l.nx, l.ny);
        let fills: Vec<f64> = (0..nx)
            .map(|i| (0..ny).map(|j| l.height(i, j) as f64).sum::<f64>() / ny as f64)
            .collect();
        let above: Vec<bool> = fills.iter().map(|&f| f > self.band_fill).collect();
        let mut longest = 0;
        if above.iter().all(|&a| a) {
            longest = nx;
        } else {
            let mut run = 0;
            for k in 0..2 * nx {
                if above[k % nx] {
                    run += 1;
                    longest = longest.max(run.min(nx));
                } else {
                    run = 0;
                }
            }
        }
        self.fullest.push(fills.iter().copied().fold(0.0, f64::max));
        self.band_columns.push(above.iter().filter(|&&a| a).count() as f64);
        self.longest.push(longest as f64);
        self.fill.extend(fills);
    }

    fn finish(self) -> MeasuredTrace {
        let n = self.squares.len();
        let tail = n - ((n as f64 * 0.1).ceil() as usize).clamp(1, n.max(1));
        let rms = |s: &[f64]| (s.iter().sum::<f64>() / s.len().max(1) as f64).sqrt() / self.diameter;
        let samples = self.drift.len().max(1) as f64;
        MeasuredTrace {
            drift_signed_mean: self.signed / samples,
            drift_per_period: Sample::of(self.drift),
            excursion: Sample::of(self.excursion),
            mobility_all: rms(&self.squares),
            mobility_tail: rms(&self.squares[tail..]),
            column_fill: Sample::of(self.fill),
            band_fill: self.band_fill,
            fullest_column: Sample::of(self.fullest),
            band_columns: Sample::of(self.band_columns),
            longest_run: Sample::of(self.longest),
        }
    }
}

/// Loads and checks a scene, including its [automaton] table.
pub fn load_scene(path: &Path, overrides: &[String]) -> Result<SceneFile, CliError> {
    let file = crate::scene::file::load(path, overrides)?;
    file.validate()?;
    Ok(file)
}

/// The result of one automaton run on a scene (before analysis).
pub struct Outcome {
    pub periods: u64,
    pub half_steps: u64,
    pub stepping_s: f64,
    pub cells: Cells,
    pub mass: (u64, u64),
    /// What the run changed of the scene, said aloud (e.g. the duration rounded to periods).
    pub warnings: Vec<String>,
    /// The `measured` rule's grains followed one by one (None for the other rules).
    pub trace: Option<MeasuredTrace>,
}

/// Runs the automaton from `lattice` for the scene's duration, writing `snapshots.bin` into
/// `out` if given; calls `frame` with the first state and then with every
/// `automaton.snapshot_every`-th period's, the period's after it, and the last: the states
/// it writes.
pub fn evolve(
    file: &SceneFile,
    lattice: automaton::Lattice,
    params: automaton::Params,
    snapshots: Option<&Path>,
    radius: f64,
    bar: &ProgressBar,
    mut frame: impl FnMut(f64, &automaton::Lattice),
) -> Result<Outcome, CliError> {
    let (scene, cells) = (&file.dem, Cells::of(file));
    let nu = scene.drive.frequency;
    let periods = (scene.run.duration * nu).round().max(1.0) as u64;
    let mut warnings = Vec::new();
    let ran = periods as f64 / nu;
    if (ran - scene.run.duration).abs() > 1e-9 * scene.run.duration.max(ran) {
        warnings.push(format!(
            "run.duration = {} s is not a whole number of drive periods (1/{nu} s): the automaton, which steps by half periods, ran {periods} periods ({ran} s)",
            scene.run.duration
        ));
    }
    // Between 1 and the run's periods ([`validate_lattice`]).
    let every = file.automaton.snapshot_every.clamp(1, periods);
    let m0 = lattice.mass();
    let mut writer = match snapshots {
        Some(p) => Some(StateWriter::create(
            p,
            cells,
            scene.tray.length,
            scene.tray.width,
            m0 as usize,
            radius,
            scene.particles.radius_min + scene.particles.radius_max,
        )?),
        None => None,
    };
    // The measured rule's grains are followed one by one, and its states written in that
    // order, so that the analysis' displacements are the grains' own.
    let band_fill = params.measured.as_ref().map(|m| m.band.fill);
    let mut a = Automaton::new(lattice, params, Direction::Plus)?;
    let mut tracer = match (band_fill, Tracks::new(a.lattice())) {
        (Some(band_fill), Some(tracks)) => {
            let x: Vec<i64> = tracks.unwrapped_x().to_vec();
            let y: Vec<usize> = tracks.cells().iter().map(|c| c.0).collect();
            Some(Tracer {
                tracks,
                dx: cells.dx,
                dy: cells.dy,
                diameter: 2.0 * radius,
                band_fill,
                half_x: x.clone(),
                period_x: x,
                period_y: y,
                excursion: Vec::new(),
                drift: Vec::new(),
                signed: 0.0,
                squares: Vec::new(),
                fill: Vec::new(),
                fullest: Vec::new(),
                band_columns: Vec::new(),
                longest: Vec::new(),
            })
        }
        (Some(_), None) => {
            warnings.push("the measured rule's lattice holds piles: its grains are not followed one by one".into());
            None
        }
        _ => None,
    };
    let push = |w: &mut StateWriter, t: f64, offset: f64, a: &Automaton, tracer: &Option<Tracer>| match tracer {
        Some(tr) => w.push_tracked(t, offset, &tr.tracks),
        None => w.push(t, offset, a.lattice()),
    };
    if let Some(w) = writer.as_mut() {
        push(w, 0.0, 0.0, &a, &tracer)?;
    }
    frame(0.0, a.lattice());
    bar.set_length(periods);
    let mut stepping = 0.0;
    for k in 1..=periods {
        let t0 = Instant::now();
        for _ in 0..2 {
            a.half_step();
            if let Some(tr) = tracer.as_mut() {
                match a.measured_moves() {
                    Some(moves) => tr.half_step(moves),
                    None => return Err("the measured rule's resting rule moved grains: they cannot be followed".into()),
                }
            }
        }
        stepping += t0.elapsed().as_secs_f64();
        if let Some(tr) = tracer.as_mut() {
            tr.period(a.lattice());
        }
        let t = 0.25 / nu + (k - 1) as f64 / nu;
        // Every `automaton.snapshot_every`-th period and the one after it (a pair one period
        // apart, from which the analysis takes its mobility and phase), and the last.
        if k % every == 0 || (every > 1 && k % every == 1 && k > 1) || k == periods {
            if let Some(w) = writer.as_mut() {
                push(w, t, scene.drive.amplitude, &a, &tracer)?;
            }
            frame(t, a.lattice());
        }
        bar.set_message(format!("t = {t:.3} s of {} s", scene.run.duration));
        bar.set_position(k);
    }
    if let Some(w) = writer.as_mut() {
        w.sync()?;
    }
    let m1 = a.lattice().mass();
    if m1 != m0 {
        return Err(format!("automaton lost grains: {m0} -> {m1}").into());
    }
    if let Some(tr) = &tracer {
        if !tr.tracks.matches(a.lattice()) {
            return Err("the measured rule's followed grains are not the lattice's".into());
        }
    }
    Ok(Outcome {
        periods,
        half_steps: a.half_steps(),
        stepping_s: stepping,
        cells,
        mass: (m0, m1),
        warnings,
        trace: tracer.map(Tracer::finish),
    })
}

/// Everything the automaton takes from a scene and its sample.
pub struct Setup {
    pub lattice: automaton::Lattice,
    pub slide_dem: mapping::SlideMeasure,
    pub slide_coulomb: mapping::SlideMeasure,
    pub displaced: usize,
    pub stacked: usize,
    /// Radius written for every grain: sqrt(<r^2>) of the sample (same projected area).
    pub radius: f64,
}

pub fn setup(file: &SceneFile, samples: &Path, quiet: bool) -> Result<Setup, CliError> {
    // The lattice is checked before a sample is prepared for it.
    validate_lattice(file)?;
    let scene = &file.dem;
    let b = progress_bar(1000, quiet, "prepare");
    let (state, _) = crate::dem::samples::load_or_prepare(scene, samples, |f| b.set_position((f * 1000.0) as u64))?;
    b.finish_and_clear();
    let pos: Vec<[f64; 2]> = state.pos.iter().map(|p| [p.x, p.y]).collect();
    let (lattice, displaced, stacked) = lattice_from_positions(&Cells::of(file), scene.tray.length, &pos);
    let r2 = state.radius.iter().map(|r| r * r).sum::<f64>() / state.radius.len().max(1) as f64;
    Ok(Setup {
        lattice,
        slide_dem: slide_dem(scene)?,
        slide_coulomb: mapping::coulomb_slide(&tray_drive(scene), 6, 20000),
        displaced,
        stacked,
        radius: r2.sqrt(),
    })
}
