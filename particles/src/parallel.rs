//! Deterministic data parallelism: work split into fixed blocks whose results come back in
//! block order, so that every result is the same for any number of threads.

use rayon::prelude::*;

/// `f` applied to every block, in block order. On the rayon pool, unless it has a single
/// thread: then a fork-join only costs (a thread switch per stage for a caller outside the
/// pool). On `T` threads the blocks are split into about `T` contiguous runs, one task each:
/// the blocks are of equal size, so finer tasks would only add splitting and stealing to
/// every stage. The per-block work and the order of the results are the same either way,
/// so the results do not depend on the number of threads.
pub(crate) fn on_blocks<B: Send, T: Send>(blocks: Vec<B>, f: impl Fn(B) -> T + Sync + Send) -> Vec<T> {
    let threads = rayon::current_num_threads();
    if threads == 1 {
        blocks.into_iter().map(f).collect()
    } else {
        let run = blocks.len().div_ceil(threads).max(1);
        blocks.into_par_iter().with_min_len(run).map(f).collect()
    }
}
