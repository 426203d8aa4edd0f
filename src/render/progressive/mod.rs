//! The explorer's live view, rendered progressively through the render module: the schedule's
//! rules (here: how long a tile and a frame's submissions may take, when the view renders a
//! preview at a reduced resolution and at which scale, the device's cost per pixel learned
//! from the tiles' own device time, [`Pace`] and [`TileTimer`]); a session of one kernel in one
//! precision that drives it on that schedule, tile by tile, pass by pass into a running mean,
//! with its readbacks, adaptive counts and the denoiser's hand-off ([`session`]); what a pass
//! reads back and how it decodes ([`readback`]); the views of the slice in either model and
//! precision ([`live`], [`switch`]) and of the 2D set ([`julia2d`]), and the two threads a session uses (pipeline builds, the
//! denoiser). The caller keeps the textures ([`canvas::Canvas`]) and the egui code.

pub mod canvas;
pub mod denoise_worker;
pub mod host_canvas;
pub mod julia2d;
pub mod live;
pub mod pipeline_builder;
pub mod readback;
pub mod session;
pub mod spans;
pub mod switch;
pub mod view_thread;

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::gpu::WORKGROUP_SIZE;

/// Frames per second to hold while the view changes.
pub const INTERACTIVE_FPS: f64 = 15.0;
/// Share of a frame's time the tracer may take while interacting (the rest is the UI's).
const INTERACTIVE_SHARE: f64 = 0.45;
/// Estimated GPU time one tile may take: the longest the UI can wait behind one.
const TILE_SECONDS: f64 = 0.015;
/// Estimated GPU time submitted per UI frame, while the view changes and while it refines
/// alike: at least one tile, and no tile past it. On a CPU adapter (lavapipe) a submission
/// runs on the thread that submits it, so this is the frame's own share of the tracer; one
/// figure for both keeps the frames even, and the UI as quick to answer while the view refines
/// as while it moves. (A refining frame once took 80 ms and more: the soak's 95th percentile.)
pub const FRAME_SECONDS: f64 = 0.03;
/// Submissions in flight at most: one. The view runs on a thread of its own, which waits for
/// its device (`ViewThread`), so more in flight buys no speed, and a new picture waited behind
/// every tile in flight: in the soak on lavapipe, 4 in flight gave a drag's image 835 ms at the
/// 95th percentile, 1 gave 404 ms (docs/book/robustness.md).
pub const MAX_IN_FLIGHT: u32 = 1;
/// How long the scene must stay unchanged before the full-resolution render starts.
pub const IDLE_DELAY: Duration = Duration::from_millis(150);

/// The two images a view keeps: a quick one while things move and the full one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    Preview = 0,
    Full = 1,
}

/// The device's estimated cost per pixel, and what the schedule makes of it: whether the full
/// image fits a frame while things move, the preview's size where it does not, and a tile's
/// rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pace {
    seconds_per_pixel: f64,
}

impl Pace {
    /// A first guess, about lavapipe on 2 cores (the path tracer's pixels cost ten times the
    /// tracer's), corrected after the first tiles.
    pub fn new(path: bool) -> Self {
        Self {
            seconds_per_pixel: if path { 1e-5 } else { 1e-6 },
        }
    }

    /// Learns from `seconds` of device time over `pixels` pixels: half the old estimate and
    /// half the new, so that a slow start-up tile (a shader's compilation) is damped.
    pub fn learn(&mut self, (seconds, pixels): (f64, u64)) {
        if pixels > 0 {
            let measured = (seconds / pixels as f64).clamp(1e-10, 1e-3);
            self.seconds_per_pixel = 0.5 * self.seconds_per_pixel + 0.5 * measured;
        }
    }

    /// The estimated device seconds of `pixels` pixels.
    pub fn seconds(&self, pixels: f64) -> f64 {
        pixels * self.seconds_per_pixel
    }

    /// Whether the whole image at `size` fits the interactive frame budget (no preview needed).
    pub fn interactive(&self, size: [u32; 2]) -> bool {
        self.seconds(pixels(size)) <= INTERACTIVE_SHARE / INTERACTIVE_FPS
    }

    /// The preview's size for a view of `size`: the resolution scale that keeps it within the
    /// interactive frame budget, between 1/16 and 1, each side at least 1 pixel.
    pub fn preview_size(&self, size: [u32; 2]) -> [u32; 2] {
        let budget = INTERACTIVE_SHARE / INTERACTIVE_FPS;
        let scale = (budget / self.seconds(pixels(size)))
            .sqrt()
            .clamp(1.0 / 16.0, 1.0);
        size.map(|side| ((side as f64 * scale).round() as u32).max(1))
    }

    /// Rows a tile of an image `width` wide takes: about [`TILE_SECONDS`] of device time, in
    /// whole workgroups of rows, at least one.
    pub fn tile_rows(&self, width: u32) -> u32 {
        let row_seconds = self.seconds(width as f64);
        ((TILE_SECONDS / row_seconds) as u32 / WORKGROUP_SIZE.1 * WORKGROUP_SIZE.1)
            .max(WORKGROUP_SIZE.1)
    }
}

fn pixels(size: [u32; 2]) -> f64 {
    size[0] as f64 * size[1] as f64
}

/// Times the view's tiles on the device: a thread that waits for each tile's submission in
/// turn and notes when it finished, so that a tile's device time (from its submission, or the
/// end of the tile before, to its end) is known to the millisecond. The UI thread sees a tile
/// finish only at its next frame's poll: timing tiles by that, as the view once did, counts
/// the frames between, and where a frame took longer than its budget of tiles the estimate fed
/// on itself and submitted ever less per frame (on lavapipe with the CPU shared, a
/// path-traced pass took ten times the device's time).
pub struct TileTimer {
    send: mpsc::Sender<(wgpu::SubmissionIndex, Instant, u64)>,
    /// Device seconds and pixels of the tiles finished since the last [`Self::take`].
    done: Arc<Mutex<(f64, u64)>>,
}

impl TileTimer {
    pub fn new(device: wgpu::Device) -> Self {
        let (send, receive) = mpsc::channel::<(wgpu::SubmissionIndex, Instant, u64)>();
        let done = Arc::new(Mutex::new((0.0, 0)));
        let shared = done.clone();
        let spawned = std::thread::Builder::new()
            .name("qjulia view timer".into())
            .spawn(move || {
                let mut last_end: Option<Instant> = None;
                // Ends when the view (the sender) is dropped.
                while let Ok((index, submitted, pixels)) = receive.recv() {
                    let wait = wgpu::PollType::Wait {
                        submission_index: Some(index),
                        timeout: Some(Duration::from_secs(10)),
                    };
                    if device.poll(wait).is_err() {
                        continue;
                    }
                    let end = Instant::now();
                    let start = last_end.map_or(submitted, |t| t.max(submitted));
                    last_end = Some(end);
                    let mut done = shared.lock().unwrap();
                    done.0 += end.duration_since(start).as_secs_f64();
                    done.1 += pixels;
                }
            });
        if let Err(e) = spawned {
            eprintln!("qjulia: the view's timer did not start ({e}); its cost stays a guess");
        }
        Self { send, done }
    }

    /// Times the tile of `pixels` submitted at `submitted` as `index`.
    pub fn time(&self, index: wgpu::SubmissionIndex, submitted: Instant, pixels: u64) {
        self.send.send((index, submitted, pixels)).ok();
    }

    /// Device seconds and pixels of the tiles finished since the last call.
    pub fn take(&self) -> (f64, u64) {
        std::mem::take(&mut *self.done.lock().unwrap())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_preview_keeps_the_frame_budget_and_the_aspect() {
        // About 5e-7 s a pixel: the full view takes 0.72 s, its preview about a fifth a side.
        let mut pace = Pace::new(false);
        pace.learn((0.0, 1));
        let size = [1600, 900];
        assert!(!pace.interactive(size));
        let preview = pace.preview_size(size);
        let seconds = pace.seconds(pixels(preview));
        let budget = INTERACTIVE_SHARE / INTERACTIVE_FPS;
        // Within the rounding of each side to a whole pixel.
        assert!(
            (seconds / budget - 1.0).abs() < 0.02,
            "{seconds} for {preview:?}"
        );
        let aspect = preview[0] as f64 / preview[1] as f64;
        assert!((aspect - 16.0 / 9.0).abs() < 0.02, "{preview:?}");
        // A fast device renders the whole image while things move.
        assert!(Pace::new(false).interactive([64, 64]));
        // At most 16 times smaller, each side at least a pixel.
        let mut slow = Pace::new(true);
        for _ in 0..4 {
            slow.learn((1.0, 1));
        }
        assert_eq!(slow.preview_size([3200, 4]), [200, 1]);
    }

    #[test]
    fn a_tile_is_whole_workgroups_of_rows_of_bounded_cost() {
        let mut pace = Pace::new(false);
        pace.learn((1e-6 * 1000.0, 1000));
        for width in [1, 64, 1000, 8192] {
            let rows = pace.tile_rows(width);
            assert_eq!(rows % WORKGROUP_SIZE.1, 0);
            assert!(rows >= WORKGROUP_SIZE.1);
            let cost = pace.seconds(rows as f64 * width as f64);
            assert!(
                rows == WORKGROUP_SIZE.1 || cost <= TILE_SECONDS,
                "{width}: {cost}"
            );
        }
    }
}
