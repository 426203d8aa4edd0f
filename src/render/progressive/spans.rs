//! Where a frame's time goes: named spans of the UI thread's work, summed over a frame and
//! printed with its line of `QJULIA_EXPLORE_LOG=frames` (the soak's figures name the slow part
//! of a long frame, not only its length).
//!
//! A span costs two clock reads; with the log off none is kept.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// The clock's anchor: an instant and the wall-clock time at it, taken once.
static ANCHOR: std::sync::OnceLock<(Instant, std::time::SystemTime)> = std::sync::OnceLock::new();

/// Milliseconds since the Unix epoch at `t`, on one anchor for the process, so that the frames
/// log and a script's `date +%s%3N` read the same clock.
pub fn epoch_ms(t: Instant) -> f64 {
    let (at, wall) = *ANCHOR.get_or_init(|| (Instant::now(), std::time::SystemTime::now()));
    let since_epoch = wall
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default()
        .as_secs_f64();
    let offset = match t.checked_duration_since(at) {
        Some(after) => after.as_secs_f64(),
        None => -at.duration_since(t).as_secs_f64(),
    };
    (since_epoch + offset) * 1e3
}

/// Whether spans are kept (the frames log is on).
static ON: AtomicBool = AtomicBool::new(false);

thread_local! {
    /// This frame's spans on this thread: a name and its milliseconds, in first-seen order.
    static SPANS: RefCell<Vec<(&'static str, f64)>> = const { RefCell::new(Vec::new()) };
}

/// Keeps spans from now on (`on`), or not.
pub fn keep(on: bool) {
    ON.store(on, Ordering::Relaxed);
}

/// Runs `work`, adding its time to the span `name` of this frame.
pub fn span<T>(name: &'static str, work: impl FnOnce() -> T) -> T {
    if !ON.load(Ordering::Relaxed) {
        return work();
    }
    let start = Instant::now();
    let value = work();
    let ms = start.elapsed().as_secs_f64() * 1e3;
    SPANS.with_borrow_mut(|spans| match spans.iter_mut().find(|(n, _)| *n == name) {
        Some((_, total)) => *total += ms,
        None => spans.push((name, ms)),
    });
    value
}

/// This frame's spans of at least `min_ms`, as `name 1.23` joined by commas, and a new frame
/// begun.
pub fn take(min_ms: f64) -> String {
    let spans = SPANS.with_borrow_mut(std::mem::take);
    spans
        .iter()
        .filter(|(_, ms)| *ms >= min_ms)
        .map(|(name, ms)| format!("{name} {ms:.2}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_sum_by_name_within_a_frame_and_start_afresh() {
        keep(true);
        span("a", || {
            std::thread::sleep(std::time::Duration::from_millis(2))
        });
        span("b", || ());
        span("a", || {
            std::thread::sleep(std::time::Duration::from_millis(2))
        });
        let line = take(0.0);
        let a: f64 = line
            .split(", ")
            .find_map(|s| s.strip_prefix("a "))
            .expect("a kept")
            .parse()
            .unwrap();
        assert!(a >= 4.0, "{line}");
        assert!(line.contains("b "), "{line}");
        assert!(!take(1.0).contains('a'), "a new frame starts empty");
        keep(false);
        span("c", || ());
        assert_eq!(take(0.0), "");
    }
}
