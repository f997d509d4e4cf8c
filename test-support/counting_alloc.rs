//! A global allocator that counts the bytes live at once and their peak, for the tests that
//! bound what a reader holds by its input's size. Included with `#[path]` by each such test
//! crate (a global allocator belongs to one binary). `SERIAL` keeps the tests of a binary
//! from sharing the counter.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

pub struct Counting;

pub static LIVE: AtomicUsize = AtomicUsize::new(0);
pub static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let now = LIVE.fetch_add(layout.size(), Ordering::SeqCst) + layout.size();
        PEAK.fetch_max(now, Ordering::SeqCst);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The tests of one binary share the counter: one at a time.
pub static SERIAL: Mutex<()> = Mutex::new(());

/// Runs `read` and fails the test if the bytes it holds live at once, beyond those live
/// before, pass `factor * len + allowance` for an input of `len` bytes.
pub fn held_within<T>(factor: usize, allowance: usize, len: usize, what: &str, read: impl FnOnce() -> T) -> T {
    let base = LIVE.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let out = read();
    let peak = PEAK.load(Ordering::SeqCst).saturating_sub(base);
    let limit = factor * len + allowance;
    assert!(
        peak <= limit,
        "{what}: {len} input bytes made the reader hold {peak} bytes (limit {limit})"
    );
    out
}
