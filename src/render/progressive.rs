//! The progressive schedule's rules and what its passes read back, for the explorer's live
//! view: how long a tile and a frame's submissions may take, when the view renders a preview at
//! a reduced resolution and at which scale, the device's cost per pixel learned from the tiles'
//! own device time ([`Pace`], [`TileTimer`]), and the running mean a pass copies back, decoded
//! into the [`Frame`] the denoiser reads ([`MeanLayout`], [`copy_mean`], [`decode_mean`]), and
//! the depth and steps ([`decode_steps`]).
//!
//! The session that drives the kernels on this schedule (jobs, passes, pipeline builds, the
//! denoiser's hand-off) is still the explorer's `slice_texture.rs`; issue 36 item 2 moves it
//! here, so that the explorer keeps its textures and names no tracer.

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::frame::Frame;
use crate::gpu::{ACCUMULATED_OUTPUT, AOVS_OUTPUT, DEPTH_OUTPUT, GpuReal, WORKGROUP_SIZE};

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
/// Submissions in flight at most.
pub const MAX_IN_FLIGHT: u32 = 4;
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

/// Where the sections of a mean's readback are: bytes per pixel of each, 0 where left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanLayout {
    /// The accumulator (vec4<f32> a pixel): path mode's radiance, and with adaptive sampling
    /// the samples each pixel took.
    pub accumulated: u64,
    /// The AOVs (three vec4<f32>), with a denoiser.
    pub aovs: u64,
    /// The depth (one `F`), with a denoiser.
    pub depth: u64,
}

impl MeanLayout {
    /// What a pass of a view reads back: the accumulator in path mode, with adaptive sampling
    /// under a denoiser, or for the samples view (`counts`); the AOVs and the depth (`depth`
    /// bytes a pixel) with a denoiser (`aovs`).
    pub fn of(path: bool, aovs: bool, adaptive: bool, counts: bool, depth: u64) -> Self {
        Self {
            accumulated: if path || (aovs && adaptive) || counts {
                16
            } else {
                0
            },
            aovs: if aovs { 48 } else { 0 },
            depth: if aovs { depth } else { 0 },
        }
    }

    /// Whether the pass reads anything back (else its colour goes straight to the texture).
    pub fn reads(&self) -> bool {
        self.accumulated + self.aovs > 0
    }
}

/// Records the copy of a pass's mean, the sections of `layout` from the kernel's `outputs`
/// (`items` of each: rows times their stride), into a buffer the host can map: `spare` where
/// it has the size, else a new one.
pub fn copy_mean(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    outputs: &[wgpu::Buffer],
    items: u64,
    spare: Option<wgpu::Buffer>,
    layout: MeanLayout,
) -> wgpu::Buffer {
    let bytes = items * (layout.accumulated + layout.aovs + layout.depth);
    let buffer = spare.filter(|b| b.size() == bytes).unwrap_or_else(|| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("mean readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    });
    let sections = [
        (ACCUMULATED_OUTPUT, layout.accumulated),
        (AOVS_OUTPUT, layout.aovs),
        (DEPTH_OUTPUT, layout.depth),
    ];
    let mut offset = 0;
    for (output, per_item) in sections.into_iter().filter(|(_, b)| *b > 0) {
        encoder.copy_buffer_to_buffer(&outputs[output], 0, &buffer, offset, items * per_item);
        offset += items * per_item;
    }
    buffer
}

/// An image's shape in a readback: width, height and the row stride, in pixels.
pub type Shape = (usize, usize, usize);

/// A pass's mean, decoded.
pub struct Mean {
    /// Path mode: the mean linear radiance, row after row (empty in phong mode).
    pub radiance: Vec<[f32; 3]>,
    /// The samples each pixel has taken, row after row, where the accumulator came back (else
    /// empty).
    pub counts: Vec<u32>,
    /// With adaptive sampling: the mean of `counts`.
    pub samples_taken: Option<f64>,
    /// With a denoiser: the mean with its AOVs and depth, as the denoiser reads it.
    pub frame: Option<Arc<Frame>>,
}

/// Decodes a mapped mean readback of `layout` (`samples` in its running mean; `adaptive`: its
/// pixels stop by themselves, and the accumulator's fourth float is minus the samples of a done
/// one; `path`: the accumulator holds path mode's radiance). The depth is the kernel's `F`; a
/// miss (a negative depth) becomes NaN, as a render's frame has it.
pub fn decode_mean<F: GpuReal + bytemuck::Pod>(
    view: &[u8],
    layout: MeanLayout,
    shape: Shape,
    samples: u32,
    (adaptive, path): (bool, bool),
) -> Mean {
    let items = shape.2 * shape.1;
    let (accumulated, rest) = view.split_at(items * layout.accumulated as usize);
    let (aovs, depth) = rest.split_at(items * layout.aovs as usize);
    // Mapped ranges are aligned to 8 bytes at least, and so is each section.
    let radiance = match path {
        true => unpad::<[f32; 4], _>(accumulated, shape, |a| [a[0], a[1], a[2]]),
        false => Vec::new(),
    };
    // Adaptive sampling: a done pixel's fourth float is minus its samples; the others have
    // taken every pass's.
    let adaptive_counts = match adaptive && !accumulated.is_empty() {
        true => unpad::<[f32; 4], _>(accumulated, shape, move |a| match a[3] < 0.0 {
            true => (-a[3]) as u32,
            false => samples,
        }),
        false => Vec::new(),
    };
    let samples_taken = (!adaptive_counts.is_empty()).then(|| {
        adaptive_counts.iter().map(|&n| n as f64).sum::<f64>() / adaptive_counts.len() as f64
    });
    // Without adaptive sampling every pixel has taken every pass's sample.
    let counts = match (accumulated.is_empty(), adaptive_counts.is_empty()) {
        (true, _) => Vec::new(),
        (false, true) => vec![samples; shape.0 * shape.1],
        (false, false) => adaptive_counts.clone(),
    };
    let frame = (layout.aovs > 0).then(|| {
        let aov =
            |k: usize| unpad::<[[f32; 4]; 3], _>(aovs, shape, move |a| [a[k][0], a[k][1], a[k][2]]);
        let mut frame = Frame::empty(shape.0 as u32);
        frame.height = shape.1 as u32;
        frame.radiance = radiance.clone();
        // Phong mode's linear mean is the AOVs' colour (unclamped).
        if radiance.is_empty() {
            frame.unclamped = aov(0);
        }
        frame.albedo = aov(1);
        frame.normal = aov(2);
        frame.luminance_m2 = unpad::<[[f32; 4]; 3], _>(aovs, shape, |a| a[1][3]);
        frame.hits = unpad::<[[f32; 4]; 3], _>(aovs, shape, |a| a[0][3]);
        frame.hit_depth = unpad::<[[f32; 4]; 3], _>(aovs, shape, |a| a[2][3]);
        frame.depth = unpad::<F, _>(depth, shape, depth_of::<F>);
        frame.samples = adaptive_counts;
        Arc::new(frame)
    });
    Mean {
        radiance,
        counts,
        samples_taken,
        frame,
    }
}

/// Decodes a mapped readback of depth rows (the kernel's `F`) then steps rows (u32) into the
/// depth (a miss NaN) and the steps, row after row.
pub fn decode_steps<F: GpuReal + bytemuck::Pod>(view: &[u8], shape: Shape) -> (Vec<f32>, Vec<u32>) {
    let (depth, steps) = view.split_at(view.len() / (size_of::<F>() + 4) * size_of::<F>());
    (
        unpad::<F, _>(depth, shape, depth_of::<F>),
        unpad::<u32, _>(steps, shape, |&s| s),
    )
}

/// The kernel marks a miss by a negative depth; a frame (and the summary, which counts hits
/// by non-NaN) by NaN.
fn depth_of<F: GpuReal>(d: &F) -> f32 {
    match crate::algebra::Real::to_f64(*d) {
        d if d < 0.0 => f32::NAN,
        d => d as f32,
    }
}

/// The `w` x `h` pixels of an image whose rows are `stride` items of `T` apart, each made into
/// an `R` by `f`, row after row (in parallel).
fn unpad<T: bytemuck::Pod + Sync, R: Send>(
    bytes: &[u8],
    (w, h, stride): Shape,
    f: impl Fn(&T) -> R + Sync + Send,
) -> Vec<R> {
    use rayon::prelude::*;
    let items: &[T] = bytemuck::cast_slice(bytes);
    items
        .par_chunks(stride.max(1))
        .take(h)
        .flat_map_iter(|row| row[..w].iter().map(&f))
        .collect()
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

    #[test]
    fn a_mean_decodes_its_rows_counts_and_misses() {
        // 2 x 2 pixels, rows 3 apart; the accumulator, the AOVs and an f32 depth.
        let shape = (2, 2, 3);
        let layout = MeanLayout::of(true, true, true, false, 4);
        let mut bytes = Vec::new();
        for i in 0..6 {
            let n = if i == 1 { -3.0f32 } else { 0.5 };
            bytes.extend(bytemuck::bytes_of(&[i as f32, 0.0, 0.0, n]));
        }
        for i in 0..6 {
            let aov = [[i as f32, 0.0, 0.0, 1.0], [0.25; 4], [0.0, 0.0, 1.0, 2.0]];
            bytes.extend(bytemuck::bytes_of(&aov));
        }
        for i in 0..6 {
            let d = if i == 3 { -1.0f32 } else { i as f32 };
            bytes.extend(bytemuck::bytes_of(&d));
        }
        let mean = decode_mean::<f32>(&bytes, layout, shape, 4, (true, true));
        let firsts: Vec<f32> = mean.radiance.iter().map(|r| r[0]).collect();
        assert_eq!(firsts, [0.0, 1.0, 3.0, 4.0]);
        assert_eq!(mean.counts, [4, 3, 4, 4]);
        assert_eq!(mean.samples_taken, Some(3.75));
        let frame = mean.frame.expect("AOVs asked for");
        assert_eq!(frame.samples, [4, 3, 4, 4]);
        assert_eq!(frame.albedo[2], [0.25; 3]);
        assert_eq!(frame.hit_depth, [2.0; 4]);
        assert!(frame.depth[2].is_nan());
        assert_eq!(frame.depth[3], 4.0);
    }
}
