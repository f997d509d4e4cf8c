//! The ParaView series of `stripes run --vtk`: `vtk/series.pvd` (open it in ParaView) with,
//! per snapshot, one `.vtp` of the grains (id, radius, velocity, angular velocity) and one of
//! the tray's floor and side walls. The file formats are `analysis::vtk`'s; this file knows
//! how a [`Simulation`] maps onto them.

use std::path::{Path, PathBuf};

use analysis::vtk::{Grains, Pvd, Quad};
use particles::sim::Simulation;

/// A run's VTK series, continued after `--resume`.
pub struct VtkSeries {
    dir: PathBuf,
    pvd: Pvd,
    /// Box length, width, and the height drawn for the side walls (m).
    size: (f64, f64, f64),
}

impl VtkSeries {
    /// The series in `dir` (created if needed), keeping the entries up to time `t` of an
    /// existing series. Side walls are drawn up to `height`.
    pub fn open(dir: &Path, t: f64, length: f64, width: f64, height: f64) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let mut pvd = Pvd::open(&dir.join("series.pvd"));
        pvd.keep_until(t);
        Ok(Self {
            dir: dir.to_path_buf(),
            pvd,
            size: (length, width, height),
        })
    }

    /// The `.pvd` file of the series.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join("series.pvd")
    }

    /// Writes snapshot `k` of `sim`: the grains, the tray, and the updated `.pvd`.
    pub fn frame(&mut self, sim: &Simulation, k: u64) -> std::io::Result<()> {
        let state = sim.state();
        let s = &*state;
        let v3 = |v: &particles::Vec3| [v.x, v.y, v.z];
        let (pos, vel, omega): (Vec<_>, Vec<_>, Vec<_>) = (
            s.pos.iter().map(v3).collect(),
            s.vel.iter().map(v3).collect(),
            s.omega.iter().map(v3).collect(),
        );
        let grains = format!("grains_{k:05}.vtp");
        let tray = format!("tray_{k:05}.vtp");
        analysis::vtk::write_grains(
            &self.dir.join(&grains),
            &Grains {
                time: sim.time,
                radius: &s.radius,
                pos: &pos,
                vel: &vel,
                omega: &omega,
            },
        )?;
        analysis::vtk::write_quads(&self.dir.join(&tray), sim.time, &self.tray(sim))?;
        self.pvd.push(sim.time, 0, &grains)?;
        self.pvd.push(sim.time, 1, &tray)
    }

    /// The floor and side walls at the simulation's time, as quadrilaterals over the periodic
    /// cell `[0, L]`; side walls up to the drawn height.
    fn tray(&self, sim: &Simulation) -> Vec<Quad> {
        let (length, width, height) = self.size;
        sim.setup
            .walls
            .iter()
            .map(|w| {
                let o = w.origin_at(sim.time);
                let v = w.motion.velocity(sim.time);
                let corners = if w.normal.z.abs() > 0.5 {
                    [[0.0, 0.0, o.z], [length, 0.0, o.z], [length, width, o.z], [0.0, width, o.z]]
                } else {
                    [[0.0, o.y, 0.0], [length, o.y, 0.0], [length, o.y, height], [0.0, o.y, height]]
                };
                Quad {
                    corners,
                    velocity: [v.x, v.y, v.z],
                }
            })
            .collect()
    }
}
