//! `stripes automaton --bench`: the automaton's speed on a scene's tray, one thread, in cell
//! and grain updates per second of on-CPU time.

use std::path::Path;
use std::time::Instant;

use automaton::{Automaton, Direction, RuleSet};
use std::collections::BTreeMap;

use automaton::Params;
use serde::Serialize;
use serde_json::Value;

use crate::automaton::lattice::{self, Cells};
use crate::host::clock::Stopwatch;
use crate::rundir::output::{CliError, RunDir, Written};
use crate::rundir::report::{Headline, Summary};
use crate::scene::file::SceneFile;

/// What `stripes automaton --bench` measured: `summary.json`, field for field.
#[derive(Clone, Debug, Serialize)]
pub struct BenchSummary {
    pub scene: String,
    pub grains: u64,
    pub cells: Cells,
    pub threads: usize,
    /// Each rule's speed, by its name (`strict`, `physical`).
    pub cases: BTreeMap<&'static str, Case>,
    pub flight_cap_cells: f64,
    #[serde(flatten)]
    pub written: Written,
}

/// One rule's speed.
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    pub cell_updates_per_s: f64,
    pub grain_updates_per_s: f64,
    pub cell_updates_per_wall_s: f64,
    pub half_steps: u64,
    pub cpu_s: f64,
    pub wall_s: f64,
    pub frozen: bool,
    pub params: Params,
}

impl Summary for BenchSummary {
    fn headline(&self) -> Headline {
        Headline::written(0, &self.written)
    }
}

/// Speed on the scene's tray: a random layer of the scene's grain count, `strict` and
/// `physical`, each for about `bench_seconds`.
pub fn bench(path: &Path, file: &SceneFile, out: &Path, force: bool, seconds: f64, config: &Value) -> Result<BenchSummary, CliError> {
    crate::automaton::lattice::validate_lattice(file)?;
    let scene = &file.dem;
    crate::rundir::output::claim(out, force)?;
    let mut dir = RunDir::create(out, config)?;
    let cells = Cells::of(file);
    // Grain positions from a SplitMix64 stream of the scene's seed.
    let mut s = scene.run.seed;
    let mut uniform = || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let pos: Vec<[f64; 2]> = (0..scene.particles.count)
        .map(|_| [uniform() * scene.tray.length, uniform() * scene.tray.width])
        .collect();
    let (lattice, _, _) = lattice::lattice_from_positions(&cells, scene.tray.length, &pos);
    let slide = lattice::slide_dem(scene)?;
    let mut rows = Vec::new();
    let mut cases = BTreeMap::new();
    for (name, rule) in [("strict", RuleSet::Strict), ("physical", RuleSet::Physical)] {
        let params = lattice::params(file, rule, &slide, &file.automaton.free_params());
        let mut a = Automaton::new(lattice.clone(), params, Direction::Plus)?;
        // Warm up, then time batches until the budget is spent.
        for _ in 0..100 {
            a.half_step();
        }
        let (start, watch, mut steps) = (Instant::now(), Stopwatch::start(true), 0u64);
        while start.elapsed().as_secs_f64() < seconds {
            for _ in 0..1000 {
                a.half_step();
            }
            steps += 1000;
        }
        let wall = start.elapsed().as_secs_f64();
        // On a shared machine the wall clock counts other processes' time slices too; the
        // thread's own CPU time measures one core's throughput.
        let cpu = watch.seconds();
        let cells_per_step = (cells.nx * cells.ny) as f64;
        let cell_rate = cells_per_step * steps as f64 / cpu;
        let grain_rate = lattice.mass() as f64 * steps as f64 / cpu;
        rows.push(vec![cell_rate, grain_rate, steps as f64, cpu, wall]);
        cases.insert(
            name,
            Case {
                cell_updates_per_s: cell_rate,
                grain_updates_per_s: grain_rate,
                cell_updates_per_wall_s: cells_per_step * steps as f64 / wall,
                half_steps: steps,
                cpu_s: cpu,
                wall_s: wall,
                frozen: a.frozen(),
                params,
            },
        );
    }
    dir.csv(
        "bench.csv",
        &["cell_updates_per_s", "grain_updates_per_s", "half_steps", "cpu_s", "wall_s"],
        &rows,
    )?;
    let summary = BenchSummary {
        scene: path.display().to_string(),
        grains: lattice.mass(),
        cells,
        threads: 1,
        cases,
        flight_cap_cells: (slide.displacement / cells.dx).round(),
        written: dir.written(),
    };
    dir.finish_typed(&summary)?;
    Ok(summary)
}
