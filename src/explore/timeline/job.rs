//! The "Render animation…" job: the frames of the timeline's animation rendered on a thread of
//! their own through `qjulia animate`'s own code ([`crate::animate::run`], on the planner the
//! explorer gives it), with progress and cancel.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use crate::animate::{FrameRange, Progress};
use crate::animation::Animation;
use crate::render::Planner;
use crate::scene::Scene;

/// What to render: which frames, where, and the video if one is asked for (the "Render
/// animation…" window's choice).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderRequest {
    pub first: u32,
    /// None: to the last frame.
    pub last: Option<u32>,
    /// The output folder.
    pub dir: PathBuf,
    /// Skip the frames already complete.
    pub resume: bool,
    /// A video of the frames (`.mp4` or `.webm`).
    pub video: Option<PathBuf>,
}

/// What a render job has done so far, shared with its thread.
#[derive(Default)]
struct JobProgress {
    /// Frames complete: rendered, or skipped as complete already (resume).
    done: u32,
    /// Frames rendered in this job.
    rendered: u32,
    /// When the job ended: a line for the status, and whether it is an error.
    finished: Option<(String, bool)>,
}

/// A "Render animation..." job on its own thread.
pub struct RenderJob {
    total: u32,
    dir: PathBuf,
    started: Instant,
    shared: Arc<Shared>,
}

/// What a job and its thread share: the progress, and the request to stop.
#[derive(Default)]
struct Shared {
    progress: Mutex<JobProgress>,
    cancel: AtomicBool,
}

impl RenderJob {
    /// Starts rendering the frames `request` asks for of `animation` over `base` (as its saved
    /// file reads back), each frame decided by `planner` as `animate` decides it. Refused, with
    /// the line to show, where the range is empty or the video cannot be made (its kind, then
    /// ffmpeg, checked as `animate` checks them, before anything is rendered).
    pub fn start(
        planner: Planner,
        base: Scene,
        animation: Animation,
        request: RenderRequest,
    ) -> Result<Self, String> {
        let last = request.last.unwrap_or(animation.frames - 1);
        if request.first > last {
            return Err(format!(
                "error: the first frame {} is after the last {last}",
                request.first
            ));
        }
        let range = FrameRange {
            first: request.first,
            last,
        };
        if let Some(video) = &request.video {
            let checked = crate::video::Codec::for_path(video)
                .map_err(crate::Error::from)
                .and_then(|_| crate::video::find_ffmpeg());
            if let Err(e) = checked {
                return Err(format!("error: {e}"));
            }
        }
        let shared = Arc::new(Shared::default());
        let job = Self {
            total: range.len(),
            dir: request.dir.clone(),
            started: Instant::now(),
            shared: shared.clone(),
        };
        let spec = JobSpec {
            base,
            animation,
            range,
            dir: request.dir,
            resume: request.resume,
            video: request.video,
        };
        std::thread::spawn(move || {
            let finished = run_job(planner, spec, shared.clone());
            shared.progress.lock().unwrap().finished = Some(finished);
        });
        Ok(job)
    }

    /// Frames done and the total.
    pub fn counts(&self) -> (u32, u32) {
        (self.shared.progress.lock().unwrap().done, self.total)
    }

    /// Frames rendered per second so far.
    pub fn frames_per_second(&self) -> f64 {
        let rendered = self.shared.progress.lock().unwrap().rendered;
        f64::from(rendered) / self.started.elapsed().as_secs_f64().max(1e-9)
    }

    /// The folder the frames go to.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Asks the job to stop after the frames in hand.
    pub fn cancel(&self) {
        self.shared.cancel.store(true, Ordering::Relaxed);
    }

    /// Whether the job was asked to stop.
    pub fn cancelling(&self) -> bool {
        self.shared.cancel.load(Ordering::Relaxed)
    }

    /// Once the job has ended: how (a line for the status, and whether it is an error); given
    /// once.
    pub fn finished(&self) -> Option<(String, bool)> {
        self.shared.progress.lock().unwrap().finished.take()
    }
}

/// What a render job does: which frames, into which folder, and the video if one is asked for.
struct JobSpec {
    base: Scene,
    animation: Animation,
    range: FrameRange,
    dir: PathBuf,
    resume: bool,
    video: Option<PathBuf>,
}

/// The job's thread: the frames as `qjulia animate` renders them (the one call of
/// [`crate::animate::run`] in the explorer), counted into the shared progress; Cancel stops it
/// after the frames in hand, the frames written staying and an incomplete video not written.
fn run_job(mut planner: Planner, spec: JobSpec, shared: Arc<Shared>) -> (String, bool) {
    let (progress, cancel) = (&shared.progress, &shared.cancel);
    let job = crate::animate::Job {
        base: &spec.base,
        animation: &spec.animation,
        range: spec.range,
        out: Some(&spec.dir),
        resume: spec.resume,
        hdr: false,
        video: spec.video.as_deref(),
        stop: Some(cancel),
    };
    let result = crate::animate::run(&mut planner, &mut |_| {}, &job, &mut |p| {
        let mut p_ = progress.lock().unwrap();
        match p {
            Progress::Start { skipped, .. } => p_.done += skipped,
            Progress::Frame { .. } => {
                p_.done += 1;
                p_.rendered += 1;
            }
        }
    });
    let dir = spec.dir.display();
    match result {
        Err(e) => (format!("error: render animation: {e}"), true),
        Ok(stats) if stats.stopped => {
            let done = progress.lock().unwrap().done;
            let total = spec.range.len();
            (
                format!("render cancelled: {done} of {total} frames in {dir}"),
                false,
            )
        }
        Ok(stats) => {
            let video = spec
                .video
                .map(|v| format!(" and {}", v.display()))
                .unwrap_or_default();
            let line = format!(
                "rendered {} frames ({} already complete) to {dir}{video}",
                stats.frames, stats.skipped
            );
            (line, false)
        }
    }
}
