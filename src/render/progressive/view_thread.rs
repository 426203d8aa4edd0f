//! The live views on a thread of their own ([`ViewThread`]), so that the UI's thread never runs
//! a tile. On a CPU adapter (lavapipe) a submission's work can run inside `queue.submit`, on
//! the thread that submits it, and a new pipeline compiles at its first dispatch: a view that
//! submitted from the UI's frame made that frame wait for its tiles, and for the compile (the
//! soak's longest frames). Here the 3D view ([`LiveView`]) and the 2D view ([`Live2d`]) run on
//! the thread, on a device of their own, and show their images on [`HostCanvas`]es.
//!
//! The device is made on the thread, from an instance of its own, on the window's adapter (the
//! same name, backend and device id): the window's submissions never wait behind the view's,
//! nor the view's behind the window's, and on GL the two do not share one context and wgpu's
//! lock on it. The thread runs at the UI's priority: on lavapipe, a lower one (nice 10, which
//! the driver's worker threads made under it inherit) kept the window's frames about 15% more
//! even but made a drag's image trail by twice as long (docs/book/robustness.md). The UI asks for what to show
//! ([`ViewThread::ask`], the newest ask wins) and reads what the thread published last
//! ([`ViewThread::shown`]: the image shown, in host memory, and the view's figures); the
//! thread hands each new image to the UI's presenter first (the explorer's writes it into its
//! texture on the window's device, so that the UI's frame only draws it), and wakes the UI when
//! it publishes something new.

use std::sync::{Arc, Condvar, Mutex, OnceLock};
use std::time::{Duration, Instant};

use super::Quality;
use super::host_canvas::{HostCanvas, HostFrame};
use super::julia2d::Live2d;
use super::live::LiveView;
use super::session::{KeptRadiance, TextureStats};
use crate::gpu::GpuKernels;
use crate::precision::Precision;
use crate::scene::Scene;

/// How long the thread waits, while its view waits for something not on its device (the
/// denoiser's thread), before it looks again (a new ask wakes it at once).
const WAIT: Duration = Duration::from_millis(2);
/// How long it waits at most for its device to finish a tile, before it looks at its asks.
const DEVICE_WAIT: Duration = Duration::from_millis(20);
/// How long it waits while its view waits for a pipeline's build.
const BUILD_WAIT: Duration = Duration::from_millis(20);

/// What the UI asks the views to show.
#[derive(Clone, Debug, PartialEq)]
pub enum Ask {
    /// The 3D slice of `scene` at `size` pixels; `interacting`: the user drags or the scene
    /// plays ([`super::session::Session::update`]).
    Slice {
        scene: Scene,
        size: [u32; 2],
        interacting: bool,
    },
    /// The 2D Julia set of `scene` at its image's size.
    Julia2d { scene: Scene },
}

impl Ask {
    /// The same ask, but for whether the user interacts: the view's picture is the same.
    fn same_picture(&self, other: &Ask) -> bool {
        match (self, other) {
            (
                Ask::Slice {
                    scene: a, size: x, ..
                },
                Ask::Slice {
                    scene: b, size: y, ..
                },
            ) => a == b && x == y,
            (a, b) => a == b,
        }
    }
}

/// What the thread published last: the image shown and the view's figures, as of the ask
/// numbered `ask`.
#[derive(Clone, Default)]
pub struct Shown {
    /// The number of the ask this is of (0: none yet).
    pub ask: u64,
    /// Whether it is the 2D view's.
    pub julia2d: bool,
    /// The image shown, once there is one.
    pub image: Option<HostFrame>,
    /// When the render of the image shown began: an ask given before then is in it.
    pub began: Option<Instant>,
    /// Whether the image is the full-resolution render of exactly the ask.
    pub refined: bool,
    /// Whether the view still has work to do for it.
    pub busy: bool,
    pub building_pipeline: bool,
    pub precision: Precision,
    pub precision_note: String,
    /// The 3D view: its figures, whether it is path traced, why path mode cannot run here.
    pub stats: TextureStats,
    pub path_traced: bool,
    pub path_unavailable: Option<String>,
    /// Tiles dispatched by the 3D views, and images they encoded on the host.
    pub dispatches: u64,
    pub encodes: u64,
    /// Path mode, or with a denoiser: the mean shown.
    pub kept: Option<Arc<KeptRadiance>>,
    /// The 2D view: seconds its last render took.
    pub render_seconds: f64,
    /// Why the views cannot run (their kernels failed to build).
    pub error: Option<String>,
}

/// The mailbox between the UI and the thread: the newest ask and its number, and whether the
/// UI is gone.
#[derive(Default)]
struct Inbox {
    ask: Option<(u64, Ask)>,
    closed: bool,
}

/// What the UI and the thread share: the mailbox, what was published, the waker and the
/// presenter.
#[derive(Default)]
struct Shared {
    inbox: (Mutex<Inbox>, Condvar),
    shown: Mutex<Arc<Shown>>,
    waker: Mutex<Option<Waker>>,
    presenter: Mutex<Option<Presenter>>,
}

/// What the UI holds: what it shares with the thread, the views' kernels once made, and its
/// last ask.
pub struct ViewThread {
    shared: Arc<Shared>,
    kernels: Arc<OnceLock<Arc<GpuKernels>>>,
    asks: Mutex<(u64, Option<Ask>)>,
}

/// Tells the UI that something new was published (the explorer's: a repaint).
pub type Waker = Box<dyn Fn() + Send + Sync>;

/// Puts a new image where the UI draws it, on the view thread, before it is published
/// (`true`: the 2D view's). The explorer's writes it into its texture on the window's device.
pub type Presenter = Box<dyn FnMut(bool, &HostFrame) + Send>;

impl ViewThread {
    /// Starts the thread of the views, on a device it makes on the adapter `on` describes
    /// (the window's). The device and the views are made on the thread; where they cannot
    /// be, [`Shown::error`] says why.
    pub fn start(on: wgpu::AdapterInfo) -> Self {
        let shared: Arc<Shared> = Arc::default();
        let kernels: Arc<OnceLock<Arc<GpuKernels>>> = Arc::default();
        let (s, k) = (shared.clone(), kernels.clone());
        let spawned = std::thread::Builder::new()
            .name("qjulia view".into())
            .spawn(move || {
                let made = device_like(&on).map(|ctx| Arc::new(GpuKernels::new(ctx)));
                let made = made.map(|kernels| k.get_or_init(|| kernels).clone());
                run(made, &s)
            });
        if let Err(e) = spawned {
            *shared.shown.lock().unwrap() = Arc::new(Shown {
                error: Some(format!("the view's thread did not start: {e}")),
                ..Shown::default()
            });
        }
        Self {
            shared,
            kernels,
            asks: Mutex::new((0, None)),
        }
    }

    /// Sets what puts each new image where the UI draws it.
    pub fn set_presenter(&self, presenter: Presenter) {
        *self.shared.presenter.lock().unwrap() = Some(presenter);
    }

    /// The views' device's kernels, once the thread has made them (the explorer's exports run
    /// on them).
    pub fn kernels(&self) -> Option<Arc<GpuKernels>> {
        self.kernels.get().cloned()
    }

    /// Sets what the thread calls when it publishes something new.
    pub fn set_waker(&self, waker: Waker) {
        *self.shared.waker.lock().unwrap() = Some(waker);
    }

    /// Asks the views for `ask`, and returns its number: the same picture as the last ask
    /// keeps its number (a change of `interacting` alone is passed on, numbered the same).
    pub fn ask(&self, ask: Ask) -> u64 {
        let mut asks = self.asks.lock().unwrap();
        if asks.1.as_ref() == Some(&ask) {
            return asks.0;
        }
        if !asks.1.as_ref().is_some_and(|last| last.same_picture(&ask)) {
            asks.0 += 1;
        }
        asks.1 = Some(ask.clone());
        let number = asks.0;
        drop(asks);
        let (inbox, wake) = &self.shared.inbox;
        inbox.lock().unwrap().ask = Some((number, ask));
        wake.notify_one();
        number
    }

    /// What the thread published last.
    pub fn shown(&self) -> Arc<Shown> {
        self.shared.shown.lock().unwrap().clone()
    }
}

impl Drop for ViewThread {
    /// Tells the thread to end (it ends after its step in progress; not waited for).
    fn drop(&mut self) {
        let (inbox, wake) = &self.shared.inbox;
        inbox.lock().unwrap().closed = true;
        wake.notify_one();
    }
}

/// The views the thread runs.
struct Views {
    kernels: Arc<GpuKernels>,
    live: LiveView<HostCanvas>,
    live2d: Live2d<HostCanvas>,
}

impl Views {
    fn new(kernels: Arc<GpuKernels>) -> crate::Result<Self> {
        let device = kernels.context().device.clone();
        let new_canvas: super::canvas::NewCanvas<HostCanvas> =
            Arc::new(move || HostCanvas::new(device.clone()));
        Ok(Self {
            live: LiveView::new(kernels.clone(), new_canvas.clone())?,
            live2d: Live2d::new(kernels.clone(), new_canvas)?,
            kernels,
        })
    }

    /// One step of the view `ask` shows (the other gives its memory back), then the rows its
    /// tiles copied brought to host memory.
    fn step(&mut self, ask: &Ask) {
        match ask {
            Ask::Slice {
                scene,
                size,
                interacting,
            } => {
                self.live2d.release();
                self.live.update(scene, *size, *interacting);
                super::spans::span("harvest", || self.live.shown_canvas_mut().harvest());
            }
            Ask::Julia2d { scene } => {
                self.live.release();
                self.live2d.update(scene);
                super::spans::span("harvest", || self.live2d.shown_canvas_mut().harvest());
            }
        }
    }

    /// Waits (at most [`DEVICE_WAIT`]) for the device to finish what was submitted; false
    /// where nothing was, or it did not finish in time (the view waits for something else).
    ///
    /// It polls rather than waits with a timeout: in wgpu-core 30.0.1 a `PollType::Wait` that
    /// times out while another thread's poll (the view timer's) finds the queue drained trips
    /// an assertion in `Device::maintain` ("If the queue is empty, the current submission index
    /// (34) should be at least the wait submission index (36)": its fence sample is older than
    /// the other thread's; gfx-rs/wgpu#9958 fixes it after 30.0.1). A `Poll` waits for no index,
    /// so it asserts nothing.
    fn wait_for_device(&self) -> bool {
        let device = &self.kernels.context().device;
        let deadline = Instant::now() + DEVICE_WAIT;
        let mut in_flight = false;
        loop {
            match device.poll(wgpu::PollType::Poll) {
                Ok(wgpu::PollStatus::QueueEmpty) => return in_flight,
                Ok(_) => in_flight = true,
                Err(_) => return false,
            }
            if Instant::now() >= deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// What the views show for `ask`, numbered `number`; `last`: what was published before
    /// (its mean kept is shared where it is the same).
    fn shown(&self, number: u64, ask: &Ask, last: &Shown) -> Shown {
        match ask {
            Ask::Slice { scene, size, .. } => {
                let live = &self.live;
                let kept = live.kept_radiance().map(|k| match &last.kept {
                    Some(old) if old.same_as(k) => old.clone(),
                    _ => Arc::new(k.clone()),
                });
                Shown {
                    ask: number,
                    julia2d: false,
                    image: live.shown_image().and_then(|(c, q, _)| c.image(q)),
                    began: live.shown_began(),
                    refined: live.is_refined(scene, *size),
                    busy: live.busy(),
                    building_pipeline: live.building_pipeline(),
                    precision: live.precision(),
                    precision_note: live.precision_note().to_string(),
                    stats: live.stats().clone(),
                    path_traced: live.path_traced(),
                    path_unavailable: live.path_unavailable().map(str::to_string),
                    dispatches: live.dispatches(),
                    encodes: live.encodes(),
                    kept,
                    render_seconds: 0.0,
                    error: None,
                }
            }
            Ask::Julia2d { scene } => {
                let view = &self.live2d;
                Shown {
                    ask: number,
                    julia2d: true,
                    image: view.shown_image().and_then(|(c, _)| c.image(Quality::Full)),
                    began: view.shown_began(),
                    refined: view.is_refined(scene),
                    busy: view.busy(),
                    precision: view.precision(),
                    precision_note: view.precision_note().to_string(),
                    render_seconds: view.render_seconds,
                    dispatches: self.live.dispatches(),
                    encodes: self.live.encodes(),
                    ..Shown::default()
                }
            }
        }
    }
}

/// The thread: waits for an ask, steps the view it shows while it is busy, publishes what it
/// shows after each step that changed it.
fn run(kernels: crate::Result<Arc<GpuKernels>>, shared: &Shared) {
    let (inbox, shown) = (&shared.inbox, &shared.shown);
    let wake = || {
        if let Some(w) = shared.waker.lock().unwrap().as_ref() {
            w()
        }
    };
    let mut views = match kernels.and_then(Views::new) {
        Ok(views) => views,
        Err(e) => {
            *shown.lock().unwrap() = Arc::new(Shown {
                error: Some(e.to_string()),
                ..Shown::default()
            });
            wake();
            return;
        }
    };
    let mut current: Option<(u64, Ask)> = None;
    let mut wait: Option<Duration> = None;
    // With `QJULIA_EXPLORE_LOG=frames`, a line a step: its time and its spans.
    let log = std::env::var_os("QJULIA_EXPLORE_LOG").is_some_and(|v| v == "frames");
    let mut steps = 0u64;
    let mut pipelines = String::new();
    loop {
        {
            let (lock, ready) = inbox;
            let mut inbox = lock.lock().unwrap();
            // Idle: wait for an ask; busy: look at once, or after `wait`.
            loop {
                if inbox.closed {
                    return;
                }
                if inbox.ask.is_some() {
                    break;
                }
                match (current.is_some(), wait) {
                    (true, None) => break,
                    (true, Some(w)) => {
                        inbox = ready.wait_timeout(inbox, w).unwrap().0;
                        break;
                    }
                    (false, _) => inbox = ready.wait(inbox).unwrap(),
                }
            }
            if inbox.closed {
                return;
            }
            if let Some(ask) = inbox.ask.take() {
                current = Some(ask);
            }
        }
        let Some((number, ask)) = &current else {
            continue;
        };
        let before = (views.live.dispatches(), views.live.encodes());
        let started = Instant::now();
        views.step(ask);
        if log {
            steps += 1;
            let spans = super::spans::take(1.0);
            eprintln!(
                "explore view step {steps}: {:.2} ms, ask {number}{}{spans}",
                started.elapsed().as_secs_f64() * 1e3,
                if spans.is_empty() { "" } else { "; " }
            );
            // What the device holds of compiled code, when it changed: the explorer's memory
            // is bounded by it (docs/book/robustness.md, "The explorer without a GPU").
            let held = views.kernels.pipelines_held();
            if held != pipelines {
                let resident = crate::memory::resident_bytes().unwrap_or(0) as f64 / 1e6;
                let at = super::spans::epoch_ms(Instant::now());
                eprintln!(
                    "explore view pipelines held: {held}; resident {resident:.0} MB; at {at:.1}"
                );
                pipelines = held;
            }
        }
        let last = shown.lock().unwrap().clone();
        let now = views.shown(*number, ask, &last);
        let changed = now.ask != last.ask
            || now.image.as_ref().map(|i| i.generation)
                != last.image.as_ref().map(|i| i.generation)
            || now.refined != last.refined
            || now.busy != last.busy
            || now.building_pipeline != last.building_pipeline
            || now.dispatches != last.dispatches
            || now.encodes != last.encodes
            || !same_kept(&now.kept, &last.kept)
            || now.stats.steps_generation != last.stats.steps_generation
            || now.stats.counts_generation != last.stats.counts_generation
            || now.stats.denoised_samples != last.stats.denoised_samples
            || now.precision != last.precision
            || now.path_traced != last.path_traced;
        let busy = now.busy;
        let building = now.building_pipeline;
        if let Some(image) = &now.image
            && last.image.as_ref().map(|i| i.generation) != Some(image.generation)
            && let Some(present) = shared.presenter.lock().unwrap().as_mut()
        {
            super::spans::span("present", || present(now.julia2d, image));
        }
        if changed {
            *shown.lock().unwrap() = Arc::new(now);
            wake();
        }
        let progressed = (views.live.dispatches(), views.live.encodes()) != before;
        wait = match (busy, building, progressed) {
            (false, ..) => {
                // Done: nothing more until the next ask.
                current = None;
                None
            }
            (true, true, _) => Some(BUILD_WAIT),
            (true, false, true) => None,
            // Waiting for the device: until its tile is done (the next step follows at once),
            // else for the denoiser, a short while.
            (true, false, false) => match views.wait_for_device() {
                true => None,
                false => Some(WAIT),
            },
        };
    }
}

/// A device of the thread's own instance on the adapter `on` describes (the same name, backend
/// and device id), else on the adapter qjulia would choose.
fn device_like(on: &wgpu::AdapterInfo) -> crate::Result<crate::gpu::GpuContext> {
    let adapters = pollster::block_on(crate::gpu::available_adapters());
    let same = |a: &wgpu::Adapter| {
        let info = a.get_info();
        info.name == on.name && info.backend == on.backend && info.device == on.device
    };
    let adapter = match adapters.iter().position(same) {
        Some(k) => adapters.into_iter().nth(k).expect("found above"),
        None => crate::gpu::choose_adapter(adapters)?,
    };
    crate::gpu::GpuContext::from_adapter(adapter)
}

/// Whether two published means are the same one.
fn same_kept(a: &Option<Arc<KeptRadiance>>, b: &Option<Arc<KeptRadiance>>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => Arc::ptr_eq(a, b),
        (None, None) => true,
        _ => false,
    }
}
