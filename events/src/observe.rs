//! What a run measures, sampled at fixed drive phases: per-species number density and
//! granular temperatures (x, z, rotation) against height and across the box (along x), the
//! mean height of the centres above the floor's mean position, the mean horizontal velocity
//! `<v_x>`, the velocity distributions, and the energy ledger.
//!
//! Per phase of the drive (phase 0: the floor at its mean position moving up at its peak
//! speed, `A sin(2 pi f t + phi)` with `2 pi f t + phi` a multiple of `2 pi`), the observer
//! also keeps the mass-weighted centre-of-mass height and the kinetic energies of
//! translation and rotation: the rough-sphere paper's `H` is the centre of mass at phase 0
//! minus its value at rest ([`rest_height`]), and its `K/R` is taken at phase 0 too. With
//! [`Observer::with_phases`]`(n, true)` every profile is also kept per phase.

use crate::config::SideWalls;
use crate::phase_field::PhaseField;
use crate::sawtooth::Sawtooth;
use crate::segregation::Mixing;
use crate::side;
use crate::sim::Simulation;
use crate::thinned::Thinned;
use crate::Vec2;

/// Profiles of one species along one axis (height, or x across the box), accumulated over
/// samples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Profile {
    /// Particles counted per bin (summed over samples).
    pub count: Vec<f64>,
    /// Sums of `m v_x^2`, `m v_z^2` and `I w^2` per bin (J).
    pub mvx2: Vec<f64>,
    pub mvz2: Vec<f64>,
    pub iw2: Vec<f64>,
    /// Sums of `v_x` and `v_z` per bin (m/s), for the local mean flow.
    pub vx: Vec<f64>,
    pub vz: Vec<f64>,
    pub m: Vec<f64>,
}

impl Profile {
    fn zero(bins: usize) -> Self {
        Profile {
            count: vec![0.0; bins],
            mvx2: vec![0.0; bins],
            mvz2: vec![0.0; bins],
            iw2: vec![0.0; bins],
            vx: vec![0.0; bins],
            vz: vec![0.0; bins],
            m: vec![0.0; bins],
        }
    }

    fn add(&mut self, b: usize, m: f64, vx: f64, vz: f64, iw2: f64) {
        self.count[b] += 1.0;
        self.mvx2[b] += m * vx * vx;
        self.mvz2[b] += m * vz * vz;
        self.iw2[b] += iw2;
        self.vx[b] += vx;
        self.vz[b] += vz;
        self.m[b] += m;
    }

    /// Per bin of size `bin`: `(centre, count per m per sample, T_x, T_z, T_rot)`, the
    /// temperatures about the bin's mean flow; empty bins give NaN temperatures.
    fn rows(&self, bin: f64, samples: u64) -> Vec<[f64; 5]> {
        let s = samples.max(1) as f64;
        (0..self.count.len())
            .map(|b| {
                let c = self.count[b];
                let mean_m = self.m[b] / c;
                let (ux, uz) = (self.vx[b] / c, self.vz[b] / c);
                [
                    (b as f64 + 0.5) * bin,
                    c / s / bin,
                    self.mvx2[b] / c - mean_m * ux * ux,
                    self.mvz2[b] / c - mean_m * uz * uz,
                    self.iw2[b] / c,
                ]
            })
            .collect()
    }
}

/// Sums over the samples taken at one phase of the drive.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseSums {
    pub samples: u64,
    /// Sum of the mass-weighted centre-of-mass heights above the floor's mean position (m).
    pub com: f64,
    /// Sums of `m v^2` (translation) and `I w^2` (rotation) over all grains (J, twice the
    /// kinetic energies).
    pub k: f64,
    pub r: f64,
}

impl PhaseSums {
    /// Mean centre-of-mass height (m).
    pub fn com_height(&self) -> f64 {
        self.com / self.samples.max(1) as f64
    }

    /// `K/R` (infinite when nothing spins).
    pub fn kinetic_ratio(&self) -> f64 {
        if self.r > 0.0 {
            self.k / self.r
        } else {
            f64::INFINITY
        }
    }
}

/// The centre of mass of the grains at rest, estimated as the rough-sphere paper does from
/// the number of full layers and of grains per layer: `per_layer = floor(width / d)` grains
/// of the mean diameter `d` per layer, `full_layers = floor(N / per_layer)` full layers
/// stacked `d` apart with their centres at `d/2, 3d/2, ...`, and the `top` remaining grains
/// in the next layer; every grain weighs the same in the estimate (a mixture's species are
/// taken as mixed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestHeight {
    pub diameter: f64,
    pub per_layer: usize,
    pub full_layers: usize,
    pub top: usize,
    /// The centre of mass at rest above the floor (m).
    pub height: f64,
}

/// [`RestHeight`] of `count` grains of mean diameter `diameter` in a box `width` wide.
pub fn rest_height(count: usize, diameter: f64, width: f64) -> RestHeight {
    let per_layer = ((width / diameter).floor() as usize).max(1);
    let full_layers = count / per_layer;
    let top = count - full_layers * per_layer;
    // Sum of the centres' heights: per_layer d (1/2 + 3/2 + ...) + top d (full_layers + 1/2).
    let full = per_layer as f64 * diameter * (full_layers as f64).powi(2) / 2.0;
    let partial = top as f64 * diameter * (full_layers as f64 + 0.5);
    RestHeight {
        diameter,
        per_layer,
        full_layers,
        top,
        height: (full + partial) / count.max(1) as f64,
    }
}

/// The rest estimate of a run's grains: their mean diameter (the species' mid radii, weighted
/// by count) in the box's width.
pub fn rest_height_of(config: &crate::config::Config) -> RestHeight {
    let count: usize = config.species.iter().map(|s| s.count).sum();
    let diameter = config
        .species
        .iter()
        .map(|s| s.count as f64 * (s.radius_min + s.radius_max))
        .sum::<f64>()
        / count.max(1) as f64;
    rest_height(count, diameter, config.width)
}

/// Sums of one species over the grains whose centres lie in the bulk at a sample, the middle
/// third `[h/3, 2h/3)` of the box's height `h` (between the floor's and the lid's mean
/// positions): the mixture paper's "bulk", away from the walls that heat each species. Taken
/// grain by grain, with no height bins.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BulkSums {
    /// Grains counted (summed over samples).
    pub count: u64,
    /// Sums of `m v_x^2` and `m v_z^2` (J).
    pub mvx2: f64,
    pub mvz2: f64,
}

/// The bulk of a box `height` high: the middle third `[height/3, 2 height/3)` (m above the
/// floor's mean position).
pub fn bulk_range(height: f64) -> (f64, f64) {
    (height / 3.0, 2.0 * height / 3.0)
}

/// The height above which a grain has left the box (m above the floor's mean position): the
/// lid's highest position, or without a lid the box's height, its open top.
pub fn box_top(config: &crate::config::Config) -> f64 {
    config.height + config.lid.map_or(0.0, |m| m.amplitude.abs())
}

/// Everything sampled.
#[derive(Clone, Debug, PartialEq)]
pub struct Observer {
    /// Bin size (m), the same along both axes, and the number of bins in height, from `z = 0`.
    pub bin: f64,
    pub bins: usize,
    /// Per species, the profiles against height.
    pub species: Vec<Profile>,
    /// Number of bins across the box, from `x = 0` to its width.
    pub across_bins: usize,
    /// Per species, the profiles across the box (the mixture paper's Figs 6-7).
    pub across: Vec<Profile>,
    pub samples: u64,
    /// Sum over samples of the mean height of the centres (m).
    pub height_sum: f64,
    /// Sum over samples of the mean `v_x` (m/s).
    pub vx_sum: f64,
    /// The sampled `v_x`, `v_z` and `w` per species, of every `velocity_stride`-th sample:
    /// all of them until a list would pass [`Observer::VELOCITY_CAP`], then every other kept
    /// sample is dropped and the stride doubles, so that they stay an even subsample in time.
    pub vx: Vec<Vec<f64>>,
    pub vz: Vec<Vec<f64>>,
    pub w: Vec<Vec<f64>>,
    /// The heights of the same grains at the same samples (m, above the floor's mean
    /// position), for distributions by region (the mixture paper's Fig. 12).
    pub z: Vec<Vec<f64>>,
    pub velocity_stride: u64,
    /// Samples since the last one whose velocities were kept, and how many were kept.
    pub velocity_skipped: u64,
    pub velocity_samples: u64,
    /// The left-right imbalance of the grains at every sample ([`crate::side`]), evenly
    /// thinned on long runs: one value per `side.stride` samples; empty in a periodic box.
    pub side: Thinned,
    /// On a sawtooth base, the mass and momentum over one tooth per phase of the drive
    /// ([`crate::phase_field`]); `None` elsewhere.
    pub field: Option<PhaseField>,
    /// In a mixture, the near neighbours of each species' grains and how many are of its
    /// own kind ([`crate::segregation`]); `None` for one species, and until the first sample.
    pub mixing: Option<Mixing>,
    /// Whether the samples also fill the profiles across the box, the velocity lists and
    /// the side imbalance (true unless [`Observer::means_and_heights`] turned them off).
    pub distributions: bool,
    /// Per phase of the drive, `phases.len()` per period from phase 0: the centre of mass
    /// and the kinetic energies ([`Observer::with_phases`]; one phase until then).
    pub phases: Vec<PhaseSums>,
    /// Per phase, per species, the profiles against height and across the box (empty
    /// unless [`Observer::with_phases`] asked for them).
    pub phase_heights: Vec<Vec<Profile>>,
    pub phase_across: Vec<Vec<Profile>>,
    /// Per species, the sums over the grains in the bulk ([`BulkSums`]), for
    /// [`Observer::bulk_temperature_ratio`].
    pub bulk: Vec<BulkSums>,
    /// Grains whose centres were above the box's top ([`box_top`]) at a sample, summed over
    /// samples, and the samples with at least one: without a lid a grain can fly out of the
    /// box. The profiles count such a grain in their top bin and the means at its height.
    pub escaped: u64,
    pub escaped_samples: u64,
}

impl Observer {
    /// An empty observer of `species` species, with bins of `bin` metres over `height` (from
    /// the floor's mean position) and over `width` (across the box).
    pub fn new(species: usize, bin: f64, height: f64, width: f64) -> Self {
        let bins = (height / bin).ceil().max(1.0) as usize;
        let across_bins = (width / bin).round().max(1.0) as usize;
        Observer {
            bin,
            bins,
            species: (0..species).map(|_| Profile::zero(bins)).collect(),
            across_bins,
            across: (0..species).map(|_| Profile::zero(across_bins)).collect(),
            samples: 0,
            height_sum: 0.0,
            vx_sum: 0.0,
            vx: vec![Vec::new(); species],
            vz: vec![Vec::new(); species],
            w: vec![Vec::new(); species],
            z: vec![Vec::new(); species],
            velocity_stride: 1,
            velocity_skipped: 0,
            velocity_samples: 0,
            side: Thinned::new(),
            field: None,
            mixing: None,
            distributions: true,
            phases: vec![PhaseSums::default()],
            phase_heights: Vec::new(),
            phase_across: Vec::new(),
            bulk: vec![BulkSums::default(); species],
            escaped: 0,
            escaped_samples: 0,
        }
    }

    /// The same, keeping the centre of mass and the kinetic energies at `count` phases per
    /// period (samples are assigned to the nearest), and with `profiles`, every profile per
    /// phase too.
    pub fn with_phases(mut self, count: usize, profiles: bool) -> Self {
        let count = count.max(1);
        self.phases = vec![PhaseSums::default(); count];
        if profiles {
            let species = self.species.len();
            self.phase_heights = vec![vec![Profile::zero(self.bins); species]; count];
            self.phase_across = vec![vec![Profile::zero(self.across_bins); species]; count];
        }
        self
    }

    /// The phase bin of the simulation's time: the drive's phase `f t + phi / 2 pi` (in
    /// periods) to the nearest of `phases.len()` per period; 0 without a moving floor.
    fn phase_bin(&self, sim: &Simulation) -> usize {
        let n = self.phases.len();
        match sim.config.floor {
            Some(m) if m.frequency > 0.0 && n > 1 => {
                let p = (m.frequency * sim.time + m.phase / std::f64::consts::TAU).rem_euclid(1.0);
                ((p * n as f64).round() as usize) % n
            }
            _ => 0,
        }
    }

    /// Adds the sample's centre of mass, energies and (if kept) phase profiles to its phase.
    fn add_phase(&mut self, sim: &Simulation) {
        let p = self.phase_bin(sim);
        let (mut mz, mut m_total, mut k, mut r) = (0.0, 0.0, 0.0, 0.0);
        let resolved = !self.phase_heights.is_empty();
        for i in 0..sim.len() {
            let (pos, v) = sim.state(i);
            let m = sim.mass[i];
            let iw2 = sim.config.q * m * sim.radius[i].powi(2) * sim.w[i].powi(2);
            mz += m * pos.y;
            m_total += m;
            k += m * v.norm_squared();
            r += iw2;
            if resolved {
                let s = sim.species[i];
                let b = ((pos.y / self.bin).max(0.0) as usize).min(self.bins - 1);
                self.phase_heights[p][s].add(b, m, v.x, v.y, iw2);
                if self.distributions {
                    let x = pos.x.rem_euclid(sim.config.width) / sim.config.width;
                    let c = ((x * self.across_bins as f64) as usize).min(self.across_bins - 1);
                    self.phase_across[p][s].add(c, m, v.x, v.y, iw2);
                }
            }
        }
        let ph = &mut self.phases[p];
        ph.samples += 1;
        ph.com += mz / m_total;
        ph.k += k;
        ph.r += r;
    }

    /// The sums at phase `k` of `phases.len()` per period.
    pub fn phase(&self, k: usize) -> PhaseSums {
        self.phases[k]
    }

    /// Per phase `k`, the profiles of species `s` against height (as [`Observer::profile`]);
    /// `None` unless kept.
    pub fn phase_profile(&self, k: usize, s: usize) -> Option<Vec<[f64; 5]>> {
        let p = self.phase_heights.get(k)?.get(s)?;
        Some(p.rows(self.bin, self.phases[k].samples))
    }

    /// The same across the box, per bin of x.
    pub fn phase_profile_across(&self, k: usize, s: usize, width: f64) -> Option<Vec<[f64; 5]>> {
        let p = self.phase_across.get(k)?.get(s)?;
        Some(p.rows(width / self.across_bins as f64, self.phases[k].samples))
    }

    /// The same, sampling only what a sweep or a comparison reads: the means (height,
    /// `v_x`) and the profiles against height, from which come the temperatures and K/R.
    /// The profiles across the box, the velocity lists and the side imbalance stay empty.
    pub fn means_and_heights(mut self) -> Self {
        self.distributions = false;
        self
    }

    /// The same, also recording the phase-resolved field over one tooth of `base` up to
    /// `height` above its valleys, in a box `width` wide.
    pub fn with_phase_field(mut self, base: &Sawtooth, width: f64, height: f64) -> Self {
        self.field = Some(PhaseField::new(base.width, width, height));
        self
    }

    /// The most velocities kept per species and component.
    pub const VELOCITY_CAP: usize = 1 << 20;

    /// Adds the state at the simulation's time.
    pub fn sample(&mut self, sim: &Simulation) {
        if !self.distributions {
            self.sample_heights(sim);
            return;
        }
        self.velocity_skipped += 1;
        let keep = self.velocity_skipped >= self.velocity_stride;
        if keep {
            self.velocity_skipped = 0;
            self.velocity_samples += 1;
        }
        let n = sim.len();
        let (mut h, mut vx) = (0.0, 0.0);
        let escaped = self.escaped;
        for i in 0..n {
            let (r, v, k, m, iw2) = self.add_to_heights(sim, i);
            h += r.y;
            vx += v.x;
            let x = r.x.rem_euclid(sim.config.width) / sim.config.width;
            let c = ((x * self.across_bins as f64) as usize).min(self.across_bins - 1);
            self.across[k].add(c, m, v.x, v.y, iw2);
            if keep {
                self.vx[k].push(v.x);
                self.vz[k].push(v.y);
                self.w[k].push(sim.w[i]);
                self.z[k].push(r.y);
            }
        }
        // Sides exist only between side walls; a periodic box has none.
        if sim.config.side_walls != SideWalls::Periodic {
            let width = sim.config.width;
            self.side.push(side::imbalance((0..n).map(|i| sim.state(i).0.x), width));
        }
        if self.species.len() > 1 {
            let mixing = self.mixing.get_or_insert_with(|| Mixing::new(&sim.species));
            let (x, z): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (sim.state(i).0.x, sim.state(i).0.y)).unzip();
            let period = (sim.config.side_walls == SideWalls::Periodic).then_some(sim.config.width);
            mixing.add(&x, &z, &sim.radius, &sim.species, period);
        }
        if let Some(f) = &mut self.field {
            f.add(sim);
        }
        if keep && self.vx.iter().any(|v| v.len() >= Self::VELOCITY_CAP) {
            self.thin_velocities();
        }
        self.add_phase(sim);
        self.escaped_samples += u64::from(self.escaped > escaped);
        self.height_sum += h / n as f64;
        self.vx_sum += vx / n as f64;
        self.samples += 1;
    }

    /// Adds grain `i` to its species' profile against height, to the bulk's sums if its
    /// centre lies in the bulk, and to the escaped grains if it is above the box's top;
    /// returns its position,
    /// velocity, species, mass and `q m R^2 w^2` for the caller's other records.
    fn add_to_heights(&mut self, sim: &Simulation, i: usize) -> (Vec2, Vec2, usize, f64, f64) {
        let (r, v) = sim.state(i);
        let (k, m) = (sim.species[i], sim.mass[i]);
        let iw2 = sim.config.q * m * sim.radius[i].powi(2) * sim.w[i].powi(2);
        // Truncation is the floor for a non-negative height (and 0 below the floor).
        let b = ((r.y / self.bin).max(0.0) as usize).min(self.bins - 1);
        self.species[k].add(b, m, v.x, v.y, iw2);
        let (lo, hi) = bulk_range(sim.config.height);
        if r.y >= lo && r.y < hi {
            let bulk = &mut self.bulk[k];
            bulk.count += 1;
            bulk.mvx2 += m * v.x * v.x;
            bulk.mvz2 += m * v.y * v.y;
        }
        if r.y > box_top(&sim.config) {
            self.escaped += 1;
        }
        (r, v, k, m, iw2)
    }

    /// [`Observer::sample`] without the distributions: the means and the profiles against
    /// height, added in the same order, so that they hold the same sums to the last bit.
    fn sample_heights(&mut self, sim: &Simulation) {
        let n = sim.len();
        let (mut h, mut vx) = (0.0, 0.0);
        let escaped = self.escaped;
        for i in 0..n {
            let (r, v, ..) = self.add_to_heights(sim, i);
            h += r.y;
            vx += v.x;
        }
        if let Some(f) = &mut self.field {
            f.add(sim);
        }
        self.add_phase(sim);
        self.escaped_samples += u64::from(self.escaped > escaped);
        self.height_sum += h / n as f64;
        self.vx_sum += vx / n as f64;
        self.samples += 1;
    }

    /// Drops every other kept sample's velocities (each sample holds the same number of
    /// grains of a species) and doubles the stride.
    fn thin_velocities(&mut self) {
        let samples = self.velocity_samples as usize;
        for lists in [&mut self.vx, &mut self.vz, &mut self.w, &mut self.z] {
            for v in lists.iter_mut() {
                let chunk = v.len() / samples.max(1);
                let kept: Vec<f64> = v.chunks(chunk.max(1)).skip(1).step_by(2).flatten().copied().collect();
                *v = kept;
            }
        }
        self.velocity_samples /= 2;
        self.velocity_stride *= 2;
    }

    /// Mean height of the centres above the floor's mean position (m).
    pub fn mean_height(&self) -> f64 {
        self.height_sum / self.samples.max(1) as f64
    }

    /// Mean horizontal velocity (m/s).
    pub fn mean_vx(&self) -> f64 {
        self.vx_sum / self.samples.max(1) as f64
    }

    /// Per bin of species `k`: `(z, number density per m of height per sample, T_x, T_z,
    /// T_rot)`, temperatures `m <(v - <v>)^2>` per degree of freedom (J); bins without
    /// particles give NaN temperatures.
    pub fn profile(&self, k: usize) -> Vec<[f64; 5]> {
        self.species[k].rows(self.bin, self.samples)
    }

    /// The same across the box, per bin of x of species `k`: `(x, number density per m of
    /// width per sample, T_x, T_z, T_rot)`; the bins divide the width evenly.
    pub fn profile_across(&self, k: usize, width: f64) -> Vec<[f64; 5]> {
        self.across[k].rows(width / self.across_bins as f64, self.samples)
    }

    /// The ratio K/R of translational to rotational kinetic energy, over every sample and
    /// species (infinite when nothing spins).
    pub fn kinetic_ratio(&self) -> f64 {
        let sum = |f: fn(&Profile) -> &Vec<f64>| self.species.iter().map(|p| f(p).iter().sum::<f64>()).sum::<f64>();
        let k = sum(|p| &p.mvx2) + sum(|p| &p.mvz2);
        let r = sum(|p| &p.iw2);
        if r > 0.0 {
            k / r
        } else {
            f64::INFINITY
        }
    }

    /// The bulk's translational temperature ratio `T_2 / T_1`, with `T_k = (T_x + T_z) / 2 =
    /// sum(m v_x^2 + m v_z^2) / (2 N_k)` over the grains of species k whose centres lay in the
    /// middle third of the box's height at each sample ([`BulkSums`]; the mixture paper's
    /// `gamma`, its Figs 2-3). Grain by grain, so it does not depend on the profiles' bin.
    /// NaN with one species or when a species never entered the bulk.
    pub fn bulk_temperature_ratio(&self) -> f64 {
        if self.bulk.len() < 2 {
            return f64::NAN;
        }
        let t = |b: &BulkSums| 0.5 * (b.mvx2 + b.mvz2) / b.count as f64;
        t(&self.bulk[1]) / t(&self.bulk[0])
    }

    /// The same ratio from the height profiles, over the bins whose centres lie in
    /// `[z_lo, z_hi)`: it depends on the bin (the summary's bulk ratio is
    /// [`Observer::bulk_temperature_ratio`]); NaN with one species or an empty range.
    pub fn temperature_ratio(&self, z_lo: f64, z_hi: f64) -> f64 {
        if self.species.len() < 2 {
            return f64::NAN;
        }
        let t = |p: &Profile| {
            let (mut e, mut c) = (0.0, 0.0);
            for b in 0..self.bins {
                let z = (b as f64 + 0.5) * self.bin;
                if z >= z_lo && z < z_hi {
                    e += 0.5 * (p.mvx2[b] + p.mvz2[b]);
                    c += p.count[b];
                }
            }
            e / c
        };
        t(&self.species[1]) / t(&self.species[0])
    }

    /// Whole-box temperatures of species `k`: `(T_x, T_z, T_rot)` (J).
    pub fn temperatures(&self, k: usize) -> (f64, f64, f64) {
        let p = &self.species[k];
        let c: f64 = p.count.iter().sum();
        (
            p.mvx2.iter().sum::<f64>() / c,
            p.mvz2.iter().sum::<f64>() / c,
            p.iw2.iter().sum::<f64>() / c,
        )
    }
}

/// The ledger's residual `|E - E0 - (W - D)|` relative to the largest of `E0`, `W` and `D`.
pub fn ledger_error(sim: &Simulation, e0: f64) -> f64 {
    let e = sim.energy();
    let l = sim.ledger;
    let scale = e0.abs().max(l.wall_work.abs()).max(l.dissipated).max(1e-300);
    (e - e0 - (l.wall_work - l.dissipated)).abs() / scale
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Rule;
    use crate::config::{Config, Guard, Rules, Species};
    use crate::wall::Motion;

    #[test]
    fn the_rest_estimate_counts_full_layers_and_the_grains_of_the_top_one() {
        // 50 grains of 1 mm in 10 mm: 5 full layers of 10, centres at 0.5 ... 4.5 mm.
        let r = rest_height(50, 1e-3, 10e-3);
        assert_eq!((r.per_layer, r.full_layers, r.top), (10, 5, 0));
        assert!((r.height - 2.5e-3).abs() < 1e-15);
        // 55 grains: 5 more at 5.5 mm.
        let r = rest_height(55, 1e-3, 10.5e-3);
        assert_eq!((r.per_layer, r.full_layers, r.top), (10, 5, 5));
        assert!((r.height - (125.0 + 27.5) * 1e-3 / 55.0).abs() < 1e-15);
        // Fewer grains than a layer: all in the first, at d/2.
        let r = rest_height(3, 2e-3, 10e-3);
        assert_eq!((r.per_layer, r.full_layers, r.top), (5, 0, 3));
        assert!((r.height - 1e-3).abs() < 1e-18);
    }

    #[test]
    fn the_means_and_heights_observer_keeps_the_same_sums_as_the_full_one() {
        let config = Config {
            width: 5e-3,
            height: 0.03,
            side_walls: SideWalls::Fixed,
            gravity: 10.0,
            q: 0.4,
            species: vec![Species {
                count: 10,
                radius_min: 0.45e-3,
                radius_max: 0.55e-3,
                mass: crate::Mass::Density(2500.0),
            }],
            floor: Some(Motion {
                amplitude: 6.366e-4,
                frequency: 100.0,
                phase: 0.0,
            }),
            base: None,
            lid: None,
            waveform: crate::wall::Waveform::Sine,
            // Rough pairs, so that the grains spin and K/R is finite.
            rules: Rules::uniform(
                Rule::Walton {
                    e: crate::Restitution::Constant(0.9),
                    mu: 0.5,
                    beta0: 0.3,
                },
                Rule::smooth(1.0),
                1,
            ),
            guard: Guard {
                tc: Some(1e-5),
                ..Guard::default()
            },
            initial_speed: 0.1,
            seed: 5,
        };
        let mut sim = Simulation::new(config).unwrap();
        let mut full = Observer::new(1, 5e-4, 0.03, 5e-3).with_phases(8, true);
        let mut lean = Observer::new(1, 5e-4, 0.03, 5e-3).means_and_heights().with_phases(8, false);
        for k in 1..=200 {
            sim.run_until(k as f64 * 1.25e-3).unwrap();
            full.sample(&sim);
            lean.sample(&sim);
        }
        assert_eq!(lean.species, full.species);
        assert_eq!((&lean.bulk, lean.escaped), (&full.bulk, full.escaped));
        assert_eq!(
            (lean.height_sum, lean.vx_sum, lean.samples),
            (full.height_sum, full.vx_sum, full.samples)
        );
        assert_eq!(lean.kinetic_ratio(), full.kinetic_ratio());
        assert!(lean.vx[0].is_empty() && lean.side == Thinned::new() && lean.across[0].count.iter().all(|&c| c == 0.0));
        assert!(!full.vx[0].is_empty() && full.kinetic_ratio().is_finite());
        // Samples every 1/8 period of the 100 Hz floor: 25 at each phase, the phase sums
        // the same in both, and the phase profiles adding up to the profiles over all phases.
        assert_eq!(lean.phases, full.phases);
        assert!(full.phases.iter().all(|p| p.samples == 25));
        let (k, r) = full.phases.iter().fold((0.0, 0.0), |(k, r), p| (k + p.k, r + p.r));
        assert!(
            (k / r - full.kinetic_ratio()).abs() <= 1e-12 * full.kinetic_ratio(),
            "{} {}",
            k / r,
            full.kinetic_ratio()
        );
        for b in 0..full.bins {
            let count: f64 = full.phase_heights.iter().map(|p| p[0].count[b]).sum();
            assert_eq!(count, full.species[0].count[b]);
        }
        let across: f64 = full.phase_across.iter().map(|p| p[0].count.iter().sum::<f64>()).sum();
        assert_eq!(across, full.across[0].count.iter().sum::<f64>());
        assert!(full.phase_profile(3, 0).is_some() && lean.phase_profile(3, 0).is_none());
    }

    /// A `width` x `height` box with periodic sides and no lid, g = 10 m/s^2, on a floor
    /// shaken at 10 Hz and 0.1 mm, holding `species` as smooth grains (pair restitution 0.9,
    /// walls 1).
    fn shaken_box(width: f64, height: f64, species: Vec<Species>) -> Config {
        let kinds = species.len();
        Config {
            width,
            height,
            side_walls: SideWalls::Periodic,
            gravity: 10.0,
            q: 0.4,
            species,
            floor: Some(Motion {
                amplitude: 1e-4,
                frequency: 10.0,
                phase: 0.0,
            }),
            base: None,
            lid: None,
            waveform: crate::wall::Waveform::Sine,
            rules: Rules::uniform(Rule::smooth(0.9), Rule::smooth(1.0), kinds),
            guard: Guard::default(),
            initial_speed: 0.0,
            seed: 5,
        }
    }

    /// Two grains of each species placed by hand in a 0.03 m box without a lid, whose bulk
    /// (the middle third) is `[0.01, 0.02)` m.
    fn four_grains() -> Simulation {
        let species = |mass: f64| Species {
            count: 2,
            radius_min: 1e-3,
            radius_max: 1e-3,
            mass: crate::Mass::Each(mass),
        };
        let mut sim = Simulation::new(shaken_box(0.02, 0.03, vec![species(1e-6), species(2e-6)])).unwrap();
        // Species 1: one grain in the bulk moving (1, 2) m/s, one below it. Species 2: one
        // in the bulk moving (0.5, -1) m/s, one above the open top at 0.035 m. (The engine
        // shuffles the species over the grains: each grain takes the next state of its own.)
        let states = [
            [(0.015, Vec2::new(1.0, 2.0)), (0.005, Vec2::new(3.0, 0.0))],
            [(0.012, Vec2::new(0.5, -1.0)), (0.035, Vec2::new(0.0, 4.0))],
        ];
        let mut taken = [0, 0];
        let (mut r, mut v) = (Vec::new(), Vec::new());
        for (i, &s) in sim.species.iter().enumerate() {
            let (z, u) = states[s][taken[s]];
            taken[s] += 1;
            r.push(Vec2::new(0.002 + 0.004 * i as f64, z));
            v.push(u);
        }
        assert_eq!(taken, [2, 2]);
        sim.set_state(&r, &v, &[0.0; 4]).unwrap();
        sim
    }

    /// Issue 43, finding 8: the bulk ratio moved from 0.65 to 0.62 and 0.77 with `run.bin`
    /// (it averaged the height bins whose centres lay in the middle third) and was NaN at large
    /// bins. It is now summed grain by grain: the hand-computed value for every bin size,
    /// where the binned ratio over the same third moves with the bin.
    #[test]
    fn the_bulk_temperature_ratio_is_the_grains_in_the_middle_third_whatever_the_bin() {
        let sim = four_grains();
        // T_1 = (1e-6 (1 + 4)) / 2 over one grain, T_2 = (2e-6 (0.25 + 1)) / 2: T2/T1 = 0.5.
        let want = 0.5;
        let mut binned = Vec::new();
        for bin in [1e-3, 4e-3, 7e-3, 0.02, 0.05] {
            let mut obs = Observer::new(2, bin, 0.03, 0.02);
            obs.sample(&sim);
            obs.sample(&sim);
            let ratio = obs.bulk_temperature_ratio();
            assert!((ratio - want).abs() < 1e-12, "bin {bin}: T2/T1 = {ratio}, by hand {want}");
            assert_eq!(obs.bulk[0].count, 2, "bin {bin}: one grain of species 1 in the bulk, twice");
            assert_eq!(obs.bulk[1].count, 2, "bin {bin}");
            binned.push(obs.temperature_ratio(0.01, 0.02));
        }
        // The binned ratio over the same range: the 1 mm bins agree; 20 mm bins take the
        // grain below the bulk (the bin [0, 20) mm has its centre at 10 mm), 50 mm bins none.
        assert!((binned[0] - want).abs() < 1e-12, "{binned:?}");
        assert!((binned[3] - want).abs() > 0.1, "{binned:?}");
        assert!(binned[4].is_nan(), "{binned:?}");
        // One species has no ratio.
        assert!(Observer::new(1, 1e-3, 0.03, 0.02).bulk_temperature_ratio().is_nan());
    }

    /// Issue 43, finding 9: grains above a box without a lid piled into the top profile bin
    /// (H = 0.171 m in a 0.05 m box) with nothing said. The observer counts them per sample,
    /// with gravity as without, in the lean observer as in the full one.
    #[test]
    fn grains_above_the_open_top_are_counted_at_every_sample() {
        let sim = four_grains();
        for lean in [false, true] {
            let mut obs = Observer::new(2, 1e-3, 0.03, 0.02);
            if lean {
                obs = obs.means_and_heights();
            }
            for _ in 0..3 {
                obs.sample(&sim);
            }
            assert_eq!((obs.escaped, obs.escaped_samples, obs.samples), (3, 3, 3), "lean {lean}");
            // And in the top bin, as the warning says.
            assert_eq!(obs.species[1].count[obs.bins - 1], 3.0, "lean {lean}");
        }
        // Under a lid at the same height nothing is above the top.
        assert_eq!(box_top(&sim.config), 0.03);
        let mut lidded = sim.config.clone();
        lidded.lid = Some(Motion {
            amplitude: 0.01,
            frequency: 10.0,
            phase: 0.0,
        });
        assert_eq!(box_top(&lidded), 0.04);
    }

    /// At the sample times, the centre of mass of one grain is its height, and the phase is
    /// where the drive stands: a grain flying freely above the floor, sampled at phase 0
    /// and 1/2 of a 10 Hz drive, has its heights at those times in those bins.
    #[test]
    fn each_sample_goes_to_the_phase_of_the_drive() {
        let one = Species {
            count: 1,
            radius_min: 1e-3,
            radius_max: 1e-3,
            mass: crate::Mass::Each(1e-6),
        };
        let mut sim = Simulation::new(shaken_box(5e-3, 1.0, vec![one])).unwrap();
        sim.set_state(&[Vec2::new(1e-3, 0.5)], &[Vec2::new(0.0, 2.0)], &[3.0]).unwrap();
        let mut obs = Observer::new(1, 1e-3, 1.0, 5e-3).with_phases(2, false);
        sim.run_until(0.1).unwrap();
        obs.sample(&sim);
        sim.run_until(0.15).unwrap();
        obs.sample(&sim);
        let z = |t: f64| 0.5 + 2.0 * t - 5.0 * t * t;
        assert!((obs.phase(0).com_height() - z(0.1)).abs() < 1e-12);
        assert!((obs.phase(1).com_height() - z(0.15)).abs() < 1e-12);
        // K/R at phase 0: m v^2 / (q m R^2 w^2) with v = 2 - 10 t.
        let v = 2.0 - 10.0 * 0.1;
        assert!((obs.phase(0).kinetic_ratio() - v * v / (0.4 * 1e-6 * 9.0)).abs() < 1e-6);
    }
}
