//! The thread that builds the explorer views' pipelines, so that a new variant's compile (on
//! lavapipe half a second and more) never holds up a frame. One thread for the process's life,
//! its builds one after another: a thread of its own for each build would give the compiler's
//! allocations a new malloc arena each time, and keep them.

use std::panic::AssertUnwindSafe;
use std::sync::mpsc;
use std::sync::{Arc, Mutex, OnceLock};

/// A build handed to the thread.
type Work = Box<dyn FnOnce() + Send>;

/// What a build gives back, once done: its value, or Err where it panicked.
pub struct Pending<T> {
    slot: Arc<Mutex<Option<std::thread::Result<T>>>>,
}

impl<T> Pending<T> {
    /// Whether the build is done.
    pub fn is_finished(&self) -> bool {
        self.slot.lock().expect("pending build").is_some()
    }

    /// The build's outcome, once done (taken: a second call gives None).
    pub fn take(&self) -> Option<std::thread::Result<T>> {
        self.slot.lock().expect("pending build").take()
    }
}

/// The builder's queue, its thread started at the first build; None where no thread could
/// be started.
fn queue() -> Option<&'static Mutex<mpsc::Sender<Work>>> {
    static QUEUE: OnceLock<Option<Mutex<mpsc::Sender<Work>>>> = OnceLock::new();
    QUEUE
        .get_or_init(|| {
            let (send, receive) = mpsc::channel::<Work>();
            std::thread::Builder::new()
                .name("qjulia pipeline builder".into())
                .spawn(move || {
                    while let Ok(work) = receive.recv() {
                        work();
                    }
                })
                .ok()
                .map(|_| Mutex::new(send))
        })
        .as_ref()
}

/// Runs `work` on the builder's thread, after the builds before it; where there is no such
/// thread, here and now.
pub fn build<T: Send + 'static>(work: impl FnOnce() -> T + Send + 'static) -> Pending<T> {
    let slot = Arc::new(Mutex::new(None));
    let done = slot.clone();
    let job: Work = Box::new(move || {
        let outcome = std::panic::catch_unwind(AssertUnwindSafe(work));
        *done.lock().expect("pending build") = Some(outcome);
    });
    match queue() {
        Some(send) => {
            if let Err(mpsc::SendError(job)) = send.lock().expect("builder queue").send(job) {
                job();
            }
        }
        None => job(),
    }
    Pending { slot }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_run_off_the_calling_thread_in_order_and_a_panic_is_an_outcome() {
        let here = std::thread::current().id();
        let first = build(move || std::thread::current().id() != here);
        let panics = build(|| -> u32 { panic!("a failed build") });
        let last = build(|| 7);
        while !last.is_finished() {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        // In order: the last done means the first two are.
        assert!(first.take().expect("done").expect("no panic"));
        assert!(panics.take().expect("done").is_err());
        assert_eq!(last.take().expect("done").expect("no panic"), 7);
        assert!(last.take().is_none(), "taken once");
    }
}
