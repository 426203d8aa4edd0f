//! The writers of an `animate` run: a pool of threads that encode and write the PNG frames (and
//! with `--hdr` their EXRs, each after its PNG), and one that feeds ffmpeg every frame of the
//! range in order (the complete ones read back from disk between the rendered ones). At most
//! [`frames_in_flight`] rendered frames wait for them, so memory stays bounded.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::{Scope, ScopedJoinHandle};

use super::job::{FramePlan, Job, Progress};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::hdr::HdrImage;
use crate::output::{read_png_rgb, write_hdr, write_png};
use crate::scene::{Scene, View};
use crate::video::VideoWriter;

/// How many rendered frames may wait for the encoders at once: one per encoder thread, and as
/// many again in the queue, so that the renderer never waits on one slow frame.
pub fn frames_in_flight() -> usize {
    2 * encoder_threads()
}

/// The threads that encode and write PNG frames: the machine's cores, at most 8.
fn encoder_threads() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get().clamp(1, 8))
}

/// A rendered frame's image, as written: `[width, height]` RGB8 pixels.
struct Picture8 {
    size: [u32; 2],
    rgb: Vec<u8>,
}

/// A frame for the PNG encoders: its PNG, and with `--hdr` its EXR.
struct PngJob {
    frame: u32,
    scene: Scene,
    path: PathBuf,
    picture: Arc<Picture8>,
    exr: Option<(PathBuf, HdrImage)>,
    render_seconds: f64,
}

/// What an encoder reports of a frame.
type Written = (u32, PathBuf, f64, Result<()>);

/// The writers of a run, started on threads of `scope`.
pub(super) struct Writers<'a, 'scope> {
    to_encoders: SyncSender<PngJob>,
    written: Receiver<Written>,
    to_video: Option<SyncSender<Arc<Picture8>>>,
    video: Option<ScopedJoinHandle<'scope, Result<Option<VideoWriter>>>>,
    /// The complete frames a video reads back from disk, in order, not yet fed.
    complete: std::iter::Peekable<std::vec::IntoIter<&'a FramePlan>>,
}

impl<'a, 'scope> Writers<'a, 'scope> {
    /// Starts the encoders, and the video's thread when `job` asks for a video.
    pub(super) fn start<'env>(
        scope: &'scope Scope<'scope, 'env>,
        job: &Job<'env>,
        frames: &'a [FramePlan],
    ) -> Self {
        let (to_encoders, jobs) = sync_channel::<PngJob>(encoder_threads());
        let (report, written) = channel::<Written>();
        // The encoders hold the only handles on the queue's end and on the reports' start: when
        // all have stopped, sending fails, and the reports end when all are done.
        let jobs = Arc::new(Mutex::new(jobs));
        for _ in 0..encoder_threads() {
            let (jobs, report) = (jobs.clone(), report.clone());
            scope.spawn(move || encode_pngs(&jobs, &report));
        }
        let fps = job.animation.fps;
        let (to_video, video) = match job.video {
            Some(path) => {
                let (to_video, pictures) = sync_channel::<Arc<Picture8>>(encoder_threads());
                let thread = scope.spawn(move || feed_video(path, fps, pictures));
                (Some(to_video), Some(thread))
            }
            None => (None, None),
        };
        let complete: Vec<&FramePlan> = match job.video {
            Some(_) => frames.iter().filter(|f| f.complete).collect(),
            None => Vec::new(),
        };
        Self {
            to_encoders,
            written,
            to_video,
            video,
            complete: complete.into_iter().peekable(),
        }
    }

    /// Hands out a rendered frame: its PNG to the encoders (or, with no PNGs, its progress
    /// now), its picture to the video after the complete frames before it; and reports the
    /// frames written meanwhile.
    pub(super) fn frame(
        &mut self,
        plan: &FramePlan,
        frame: &Frame,
        render_seconds: f64,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<()> {
        self.feed_from_disk(plan.frame)?;
        let picture = Arc::new(picture_of(&plan.scene, frame));
        match &plan.png {
            Some(path) => {
                let job = PngJob {
                    frame: plan.frame,
                    scene: plan.scene.clone(),
                    path: path.clone(),
                    picture: picture.clone(),
                    exr: plan.exr.clone().map(|exr| (exr, HdrImage::of(frame))),
                    render_seconds,
                };
                self.to_encoders
                    .send(job)
                    .map_err(|_| stopped("the PNG writers"))?;
            }
            None => progress(Progress::Frame {
                frame: plan.frame,
                path: None,
                render_seconds,
            }),
        }
        self.to_video(picture)?;
        report_written(&self.written, false, progress)
    }

    /// Feeds the video the complete frames after the last rendered one.
    pub(super) fn feed_rest_from_disk(&mut self) -> Result<()> {
        self.feed_from_disk(u32::MAX)
    }

    /// Feeds the video the complete frames numbered below `until`, read back from disk.
    fn feed_from_disk(&mut self, until: u32) -> Result<()> {
        while let Some(plan) = self.complete.next_if(|f| f.frame < until) {
            let (size, rgb) = read_png_rgb(plan.png.as_deref().expect("complete in out"))?;
            self.to_video(Arc::new(Picture8 { size, rgb }))?;
        }
        Ok(())
    }

    fn to_video(&self, picture: Arc<Picture8>) -> Result<()> {
        match &self.to_video {
            Some(queue) => queue.send(picture).map_err(|_| stopped("the video writer")),
            None => Ok(()),
        }
    }

    /// Closes the queues and waits for every PNG to finish (or fail) before the video is kept:
    /// a writer's error is the reason a queue closed, so it comes out before `handed_out`'s.
    /// The video is finished only when `all_rendered` (a stopped run writes none); returns the
    /// frames it holds.
    pub(super) fn finish(
        self,
        handed_out: Result<()>,
        all_rendered: bool,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<u32> {
        let Self {
            to_encoders,
            written,
            to_video,
            video,
            ..
        } = self;
        drop(to_encoders);
        drop(to_video);
        let encoded = report_written(&written, true, progress);
        let video = video.map(|thread| thread.join().expect("the video thread"));
        encoded?;
        let writer = video.transpose()?.flatten();
        handed_out?;
        if !all_rendered {
            // Stopped: an incomplete video is not written (dropped, it leaves nothing).
            return Ok(0);
        }
        let video_frames = writer.as_ref().map_or(0, |w| w.frames() as u32);
        if let Some(writer) = writer {
            writer.finish()?;
        }
        Ok(video_frames)
    }
}

/// Hands the encoders' reports to `progress`: those in already, or (`all`) every one until the
/// encoders are done. The first failed frame's error comes out after the others are reported.
fn report_written(
    written: &Receiver<Written>,
    all: bool,
    progress: &mut dyn FnMut(Progress),
) -> Result<()> {
    let mut first_error = None;
    let mut take = |(frame, path, render_seconds, result): Written| match result {
        Ok(()) => progress(Progress::Frame {
            frame,
            path: Some(&path),
            render_seconds,
        }),
        Err(e) => {
            first_error.get_or_insert(e);
        }
    };
    if all {
        written.iter().for_each(&mut take);
    } else {
        written.try_iter().for_each(&mut take);
    }
    first_error.map_or(Ok(()), Err)
}

/// An encoder thread: writes the PNG of each frame it takes from the queue (then its EXR, where
/// it has one: a frame whose EXR is missing is not complete) until the queue closes, or until a
/// frame fails (then it stops, and with it, once all have, the queue).
fn encode_pngs(jobs: &Mutex<Receiver<PngJob>>, report: &Sender<Written>) {
    loop {
        let next = jobs.lock().expect("the frame queue").recv();
        let Ok(job) = next else { return };
        let result =
            write_png(&job.path, &job.scene, job.picture.size, &job.picture.rgb).and_then(|()| {
                match job.exr {
                    Some((path, image)) => write_hdr(&path, &job.scene, image),
                    None => Ok(()),
                }
            });
        let failed = result.is_err();
        let _ = report.send((job.frame, job.path, job.render_seconds, result));
        if failed {
            return;
        }
    }
}

/// The video thread: starts ffmpeg at the first frame (its size is the video's) and feeds it
/// every frame in order; returns the writer, unfinished, for the caller to keep or drop.
fn feed_video(
    path: &Path,
    fps: f64,
    pictures: Receiver<Arc<Picture8>>,
) -> Result<Option<VideoWriter>> {
    let mut writer: Option<VideoWriter> = None;
    for picture in pictures {
        let w = match &mut writer {
            Some(w) => w,
            None => writer.insert(VideoWriter::start(path, picture.size, fps)?),
        };
        w.push(&picture.rgb)?;
    }
    Ok(writer)
}

/// The error of a queue found closed: the thread at its end stopped on an error of its own,
/// which is the one reported.
fn stopped(writer: &str) -> Error {
    Error::Stopped(format!("{writer} stopped"))
}

/// The picture a frame's PNG shows: the shaded image, or a heat map of `image.view` with its
/// legend.
fn picture_of(scene: &Scene, frame: &Frame) -> Picture8 {
    match scene.image.view {
        View::Shaded => Picture8 {
            size: [frame.width, frame.height],
            rgb: frame.rgb8(),
        },
        view => {
            let (w, h, rgb) = crate::heatmap::view_image(frame, view);
            Picture8 { size: [w, h], rgb }
        }
    }
}
