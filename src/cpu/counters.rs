//! The work counters of the CPU tracers, per thread: distance estimates, and quaternion
//! iterations (z <- z^2 + c, in estimates and normals). The tracers count into them (trace/,
//! path/); `count_work` and the row renderers in cpu/mod.rs read them.

use std::cell::Cell;

thread_local! {
    /// Work done on this thread: distance estimates, and quaternion iterations (z <- z^2 + c,
    /// in estimates and normals). Read through [`count_work`](super::count_work).
    pub(crate) static ESTIMATES: Cell<u64> = const { Cell::new(0) };
    pub(crate) static ITERATIONS: Cell<u64> = const { Cell::new(0) };
}
