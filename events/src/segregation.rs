//! Whether the species of a mixture gather with their own kind: the mixture paper's
//! "spontaneous tendency of the system to segregate the species ... more apparent at high
//! densities", which it explains by inelasticity ("particles with smaller restitution
//! coefficient tend to group together"; its section 3.3).
//!
//! The record counts, at each sample, the near neighbours of every grain: the grains whose
//! centres are closer than `reach` times the sum of the two radii. For species `s`, the
//! fraction of its grains' neighbours that are of species `s` is compared with the fraction
//! a random labelling of the same positions would give, `(N_s - 1) / (N - 1)`:
//!
//! `R_s = (same_s / neighbours_s) / ((N_s - 1) / (N - 1))`.
//!
//! `R_s = 1` for a mixture whose labels are independent of where the grains are; above 1 the
//! species' grains have more of their own kind around them than chance gives, that is, they
//! gather. Any cause counts, including the species' different mean heights under gravity,
//! so a mechanism is told apart only by runs that change one ingredient (the restitution
//! coefficients, the density) and compare `R_s`.

/// Neighbours closer than this many times the sum of two radii count (1.2: touching and
/// nearly touching grains, the first shell of a dense packing).
pub const REACH: f64 = 1.2;

/// Neighbour counts per species, summed over samples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mixing {
    /// Per species: all neighbours of its grains, and those of the same species.
    pub neighbours: Vec<u64>,
    pub same: Vec<u64>,
    /// Grains per species.
    pub count: Vec<usize>,
    /// Samples added.
    pub samples: u64,
}

impl Mixing {
    /// An empty record for grains of these species (one entry per grain).
    pub fn new(species: &[usize]) -> Self {
        let kinds = species.iter().max().map_or(0, |&k| k + 1);
        let mut count = vec![0; kinds];
        for &k in species {
            count[k] += 1;
        }
        Mixing {
            neighbours: vec![0; kinds],
            same: vec![0; kinds],
            count,
            samples: 0,
        }
    }

    /// Adds one configuration: centres `x`, `z` (in the plane of the box), radii, species,
    /// and the box's width when it is periodic along x (the nearest image counts).
    pub fn add(&mut self, x: &[f64], z: &[f64], radius: &[f64], species: &[usize], periodic_width: Option<f64>) {
        let n = x.len();
        for i in 0..n {
            for j in i + 1..n {
                let mut dx = x[j] - x[i];
                if let Some(w) = periodic_width {
                    dx -= w * (dx / w).round();
                }
                let reach = REACH * (radius[i] + radius[j]);
                let dz = z[j] - z[i];
                if dx.abs() >= reach || dz.abs() >= reach || dx * dx + dz * dz >= reach * reach {
                    continue;
                }
                let (a, b) = (species[i], species[j]);
                self.neighbours[a] += 1;
                self.neighbours[b] += 1;
                if a == b {
                    self.same[a] += 2;
                }
            }
        }
        self.samples += 1;
    }

    /// `R_s` of the module docs, per species (NaN where it is undefined: a species of one
    /// grain, or no neighbours).
    pub fn ratio(&self) -> Vec<f64> {
        let total: usize = self.count.iter().sum();
        (0..self.count.len())
            .map(|s| {
                let chance = (self.count[s] as f64 - 1.0) / (total as f64 - 1.0);
                if self.neighbours[s] == 0 || chance <= 0.0 {
                    f64::NAN
                } else {
                    self.same[s] as f64 / self.neighbours[s] as f64 / chance
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};

    /// Two species in two separate halves of the box: every neighbour is of the grain's own
    /// kind, `R_s = (N - 1) / (N_s - 1)`.
    #[test]
    fn separated_species_have_only_their_own_kind_around_them() {
        let (mut x, mut z, mut species) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..2 {
            for i in 0..10 {
                for j in 0..5 {
                    x.push(k as f64 * 100.0 + i as f64 * 2.0);
                    z.push(j as f64 * 2.0);
                    species.push(k);
                }
            }
        }
        let radius = vec![1.0; x.len()];
        let mut m = Mixing::new(&species);
        m.add(&x, &z, &radius, &species, None);
        assert_eq!(m.count, vec![50, 50]);
        // A square lattice of spacing 2 = the sum of two radii: 4 neighbours inside, fewer
        // at the edges: 2 * (10 * 4 + 9 * 5) bonds per species.
        assert_eq!(m.neighbours, vec![170, 170]);
        assert_eq!(m.same, m.neighbours);
        for r in m.ratio() {
            assert!((r - 99.0 / 49.0).abs() < 1e-12, "{r}");
        }
    }

    /// Labels drawn at random for fixed positions: `R_s` near 1 for both species, within the
    /// statistics of the number of bonds.
    #[test]
    fn random_labels_give_one() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let n = 400;
        let x: Vec<f64> = (0..n).map(|i| (i % 20) as f64 * 2.0 + rng.gen_range(-0.1..0.1)).collect();
        let z: Vec<f64> = (0..n).map(|i| (i / 20) as f64 * 2.0 + rng.gen_range(-0.1..0.1)).collect();
        let radius = vec![1.0; n];
        let mut species: Vec<usize> = (0..n).map(|i| usize::from(i >= 100)).collect();
        let mut m = Mixing::new(&species);
        for _ in 0..200 {
            species.shuffle(&mut rng);
            m.add(&x, &z, &radius, &species, None);
        }
        let r = m.ratio();
        assert!((r[0] - 1.0).abs() < 0.03 && (r[1] - 1.0).abs() < 0.01, "{r:?}");
    }

    /// Across the seam of a periodic box two grains are neighbours; without the period they
    /// are not.
    #[test]
    fn the_nearest_image_counts_in_a_periodic_box() {
        let (x, z, radius, species) = ([0.5, 9.7], [1.0, 1.0], [0.5, 0.5], [0, 0]);
        let mut open = Mixing::new(&species);
        open.add(&x, &z, &radius, &species, None);
        assert_eq!(open.neighbours, vec![0]);
        let mut periodic = Mixing::new(&species);
        periodic.add(&x, &z, &radius, &species, Some(10.0));
        assert_eq!(periodic.neighbours, vec![2]);
        assert_eq!(periodic.ratio(), vec![1.0], "one species: its own kind is all there is");
    }
}
