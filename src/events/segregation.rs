//! The summary's `segregation` entry of an event-driven mixture: per species, how many near
//! neighbours its grains have and what share of them are of its own kind, against the share
//! random labels would give (`events::segregation`). The mixture paper's "spontaneous
//! tendency of the system to segregate the species" (seed 001, section 3.3).

use events::observe::Observer;
use events::segregation::REACH;
use serde::Serialize;

/// One species' neighbours.
#[derive(Clone, Debug, Serialize)]
pub struct SpeciesMixing {
    pub grains: usize,
    /// Near neighbours per grain, averaged over the samples.
    pub neighbours_per_grain: f64,
    /// Share of them of the grain's own species, and the share random labels give,
    /// `(N_s - 1) / (N - 1)`.
    pub same_fraction: f64,
    pub chance_fraction: f64,
    /// Their ratio: 1 for labels independent of place, above 1 when the species gathers.
    pub ratio: f64,
}

/// The `segregation` entry.
#[derive(Clone, Debug, Serialize)]
pub struct SegregationSummary {
    pub samples: u64,
    /// Neighbours are grains closer than this many times the sum of the two radii.
    pub reach: f64,
    pub species: Vec<SpeciesMixing>,
}

/// The entry of a mixture's observer, or `None` for one species or no samples.
pub fn summary(obs: &Observer) -> Option<SegregationSummary> {
    let m = obs.mixing.as_ref().filter(|m| m.samples > 0)?;
    let total: usize = m.count.iter().sum();
    let ratio = m.ratio();
    let species = (0..m.count.len())
        .map(|s| SpeciesMixing {
            grains: m.count[s],
            neighbours_per_grain: m.neighbours[s] as f64 / (m.count[s].max(1) as f64 * m.samples as f64),
            same_fraction: m.same[s] as f64 / m.neighbours[s].max(1) as f64,
            chance_fraction: (m.count[s] as f64 - 1.0) / (total as f64 - 1.0),
            ratio: ratio[s],
        })
        .collect();
    Some(SegregationSummary {
        samples: m.samples,
        reach: REACH,
        species,
    })
}
