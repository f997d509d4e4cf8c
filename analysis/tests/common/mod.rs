//! Synthetic layers of grains for the analysis tests and benchmark: random sequential
//! addition of non-overlapping disks (radii uniform in [0.25, 0.5] mm, the thesis' layer)
//! in chosen x ranges of a tray periodic in x with side walls in y.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Thesis tray: length, width (m), radius range (m).
pub const L: f64 = 0.4;
pub const W: f64 = 0.02;
pub const RMIN: f64 = 2.5e-4;
pub const RMAX: f64 = 5e-4;

/// A layer: x, y positions and radii.
pub struct Layer {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub r: Vec<f64>,
}

/// Buckets of 1 mm along x (>= 2 RMAX), so overlap checks look at three buckets only.
const BUCKET: f64 = 1e-3;
const BUCKETS: usize = (L / BUCKET) as usize;

struct Grid(Vec<Vec<usize>>);

impl Grid {
    fn of(layer: &Layer) -> Self {
        let mut g = Grid(vec![Vec::new(); BUCKETS]);
        for (i, &x) in layer.x.iter().enumerate() {
            g.0[Self::bucket(x)].push(i);
        }
        g
    }

    fn bucket(x: f64) -> usize {
        ((x / BUCKET) as usize).min(BUCKETS - 1)
    }

    /// Whether a disk (x, y, r) overlaps no grain of `layer` (x periodic).
    fn free(&self, layer: &Layer, x: f64, y: f64, r: f64) -> bool {
        let b = Self::bucket(x);
        [BUCKETS - 1, 0, 1].iter().all(|&o| {
            self.0[(b + o) % BUCKETS].iter().all(|&j| {
                let mut dx = (x - layer.x[j]).abs();
                dx = dx.min(L - dx);
                let rr = r + layer.r[j];
                dx >= rr || dx * dx + (y - layer.y[j]).powi(2) >= rr * rr
            })
        })
    }

    fn push(&mut self, layer: &mut Layer, x: f64, y: f64, r: f64) {
        self.0[Self::bucket(x)].push(layer.x.len());
        layer.x.push(x);
        layer.y.push(y);
        layer.r.push(r);
    }
}

/// Adds grains by random sequential addition until the region `[a, a + len)` (periodic)
/// reaches the projected area fraction `phi`. Grains never overlap one another.
pub fn fill(layer: &mut Layer, rng: &mut ChaCha8Rng, a: f64, len: f64, phi: f64) {
    fill_with(layer, rng, a, len, phi, false)
}

/// [`fill`], but with `overlap` the grains sit at independent uniform positions and may
/// overlap: how a synthetic band reaches the area fraction of a jammed DEM band (0.75),
/// beyond the 0.55 at which random sequential addition of disks jams. The projected area
/// the analysis reads is the same either way.
pub fn fill_with(layer: &mut Layer, rng: &mut ChaCha8Rng, a: f64, len: f64, phi: f64, overlap: bool) {
    let mut grid = Grid::of(layer);
    let target = phi * len * W;
    let mut area = 0.0;
    let mut misses = 0;
    while area < target && misses < 100_000 {
        let r = rng.gen_range(RMIN..RMAX);
        let x = (a + rng.gen_range(0.0..len)).rem_euclid(L);
        let y = rng.gen_range(r..W - r);
        if overlap || grid.free(layer, x, y, r) {
            grid.push(layer, x, y, r);
            area += std::f64::consts::PI * r * r;
            misses = 0;
        } else {
            misses += 1;
        }
    }
    assert!(area >= target, "region [{a}, {}) cannot reach phi = {phi}", a + len);
}

/// A homogeneous random layer of `n` grains over the whole tray.
pub fn random_layer(n: usize, seed: u64) -> Layer {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut layer = Layer {
        x: Vec::new(),
        y: Vec::new(),
        r: Vec::new(),
    };
    let mut grid = Grid::of(&layer);
    let mut misses = 0;
    while layer.x.len() < n {
        let r = rng.gen_range(RMIN..RMAX);
        let x = rng.gen_range(0.0..L);
        let y = rng.gen_range(r..W - r);
        if grid.free(&layer, x, y, r) {
            grid.push(&mut layer, x, y, r);
        } else {
            misses += 1;
            assert!(misses < 1_000_000, "cannot place {n} grains");
        }
    }
    layer
}

/// `k` dense bands (area fraction `dense`, width `band` m) centred at
/// `offset + j L / k`, on a sparse background (area fraction `sparse`).
pub fn banded_layer(k: usize, offset: f64, band: f64, dense: f64, sparse: f64, seed: u64) -> Layer {
    banded_layer_with(k, offset, band, dense, sparse, seed, false)
}

/// [`banded_layer`] whose bands may be as dense as a jammed DEM band: grains in the bands
/// at independent positions ([`fill_with`] with `overlap`).
pub fn jammed_banded_layer(k: usize, offset: f64, band: f64, dense: f64, sparse: f64, seed: u64) -> Layer {
    banded_layer_with(k, offset, band, dense, sparse, seed, true)
}

fn banded_layer_with(k: usize, offset: f64, band: f64, dense: f64, sparse: f64, seed: u64, overlap: bool) -> Layer {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut layer = Layer {
        x: Vec::new(),
        y: Vec::new(),
        r: Vec::new(),
    };
    for j in 0..k {
        let c = offset + j as f64 * L / k as f64;
        // Keep RMAX clear of the band edges so grains stay inside.
        fill_with(&mut layer, &mut rng, c - 0.5 * band + RMAX, band - 2.0 * RMAX, dense, overlap);
    }
    for j in 0..k {
        let start = offset + j as f64 * L / k as f64 + 0.5 * band + RMAX;
        fill(&mut layer, &mut rng, start, L / k as f64 - band - 2.0 * RMAX, sparse);
    }
    layer
}
