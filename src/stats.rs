//! What a rendered frame holds, in numbers: hit fraction, steps, and the divergence of the work
//! in 8x8 blocks (Crane's Figure 9). One [`Summary`] type, built over a whole frame or band by
//! band; [`RenderStats`] adds how the frame was made. Below the presentation: `views` draws
//! heat maps from these figures, never the other way round.

use rayon::prelude::*;
use serde::Serialize;

use crate::frame::Frame;

/// Pixels a side of the divergence blocks: the tracer's workgroup (`gpu::WORKGROUP_SIZE`, a
/// test checks they agree), the lanes that wait for each other's steps.
pub const DIVERGENCE_BLOCK: u32 = 8;

/// The figures of a frame (docs/CONTRACT.md's `--stats`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub hit_fraction: f64,
    pub steps_mean: f64,
    pub steps_max: u32,
    /// Divergence in 8x8 blocks (README's "Views"): sum of steps over the sum of block pixels
    /// times the block's most steps; 1 where no block works at all.
    pub tile_efficiency: f64,
    /// Mean over pixels of the 8x8 block's most steps minus the pixel's own.
    pub wasted_steps_mean: f64,
    /// Every distance estimate made: all samples, all rays (primary, shadow, occlusion). In the
    /// 2D view, every iteration.
    pub estimates_total: u64,
    /// Every quaternion iteration (z <- z^2 + c) made, counted as `estimates_total` is: in the
    /// distance estimates, the normals and the orbit trap. In the 2D view, every iteration.
    pub iterations_total: u64,
    /// Samples taken, over every pixel: width x height x `image.samples`, or fewer where
    /// adaptive sampling (`path.noise_target`) stopped pixels early ([`Frame::samples`]; one a
    /// pixel where a frame has no counts, as the 2D view).
    pub samples_total: u64,
    /// Path mode: samples dropped because their radiance was not finite or was negative
    /// ([`Frame::nonfinite_samples`]); null in phong mode.
    pub nonfinite_samples: Option<u64>,
    /// Path mode: rays that ran out of `fractal.max_steps` without a hit or an escape, every
    /// ray of every sample ([`Frame::exhausted_rays`]); null in phong mode.
    pub exhausted_rays: Option<u64>,
    /// Path mode: the image's estimated RMSE, from its pixels' halves ([`crate::estimate`]),
    /// of the denoised image where a denoiser ran; null where there is none (phong mode, one
    /// sample a pixel).
    pub estimated_rmse: Option<f64>,
    /// [`Self::estimated_rmse`] over the mean of the image's linear channels.
    pub estimated_relative_rmse: Option<f64>,
}

impl Summary {
    /// The figures of a whole frame.
    pub fn of(frame: &Frame) -> Self {
        let mut builder = SummaryBuilder::new(frame.width);
        builder.add(frame);
        builder.finish()
    }
}

/// What `--stats` writes (docs/CONTRACT.md): how a frame was made and what it holds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RenderStats {
    /// "gpu" or "cpu".
    pub backend: String,
    /// Adapter name and wgpu backend, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) / Vulkan"; "cpu".
    pub adapter: String,
    /// "f32" or "f64".
    pub precision: String,
    /// Why that precision ran: "asked for (--precision f32)", "auto: f32 resolves the scene",
    /// or (auto) what f32 could not resolve.
    pub precision_reason: String,
    pub width: u32,
    pub height: u32,
    /// From the first dispatch to the image in host memory, after an untimed warm-up.
    pub render_seconds: f64,
    /// GPU time from timestamp queries; None where unsupported (and on the CPU).
    pub gpu_seconds: Option<f64>,
    /// Seconds to read the environment map, decode it and pack it with its distribution (the
    /// scene's load, before the render); absent where the scene has no map.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub environment_seconds: Option<f64>,
    /// The denoiser's figures, where it ran (`image.denoise`); nothing where it did not.
    #[serde(flatten)]
    pub denoise: Option<DenoiseStats>,
    /// How a render to `image.target_error` went (src/render/target.rs), where it did.
    #[serde(flatten)]
    pub target: Option<TargetStats>,
    /// The GPU kernel that drew the picture, as `qjulia kernel` composes it; nothing on the CPU.
    #[serde(flatten)]
    pub kernel: Option<KernelStats>,
    #[serde(flatten)]
    pub summary: Summary,
}

/// The kernel a GPU render ran (`--stats`' `kernel*` keys): its name in shaders/kernels.json,
/// and its composed text's size in bytes and 64-bit FNV-1a fingerprint (16 hex digits), before
/// the host's override constants.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KernelStats {
    #[serde(rename = "kernel")]
    pub name: String,
    #[serde(rename = "kernel_bytes")]
    pub bytes: usize,
    #[serde(rename = "kernel_fingerprint")]
    pub fingerprint: String,
}

/// What `--stats` says of a render to a target.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TargetStats {
    /// "target_error" where the last pass's estimate met the target, "samples" where the
    /// passes reached `image.samples` without it.
    pub stopped_by: &'static str,
    /// Every pass, in order: its samples and its estimate.
    pub target_passes: Vec<TargetPass>,
}

impl TargetStats {
    /// The last pass's samples: the image's.
    pub fn samples(&self) -> u32 {
        self.target_passes.last().map_or(0, |p| p.samples)
    }
}

/// One pass of a render to a target.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TargetPass {
    pub samples: u32,
    pub estimated_relative_rmse: Option<f64>,
}

/// What the denoiser cost (`--stats`' `denoise_*` keys).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DenoiseStats {
    /// Wall seconds: the preparation and the passes, not in `render_seconds`.
    #[serde(rename = "denoise_seconds")]
    pub seconds: f64,
    /// The passes' GPU time, where they ran on a GPU with timestamps.
    #[serde(
        rename = "denoise_gpu_seconds",
        skip_serializing_if = "Option::is_none"
    )]
    pub gpu_seconds: Option<f64>,
    /// Where the denoiser ran, "gpu" or "cpu" (a GPU whose buffers cannot hold the image
    /// leaves it to the CPU).
    #[serde(rename = "denoise_backend")]
    pub backend: String,
}

/// A [`Summary`] accumulated over bands of whole rows, top to bottom, so that a streamed render
/// of any size can report it.
#[derive(Clone, Debug)]
pub struct SummaryBuilder {
    pixels: u64,
    hits: u64,
    steps: u64,
    steps_max: u32,
    estimates: u64,
    iterations: u64,
    samples: u64,
    /// Path mode's counts, where a band was path-traced.
    path_counts: Option<(u64, u64)>,
    /// The raw error estimate's sums ([`crate::estimate::HalvesSums`]).
    halves: crate::estimate::HalvesSums,
    blocks: BlockWork,
}

impl SummaryBuilder {
    pub fn new(width: u32) -> Self {
        Self {
            pixels: 0,
            hits: 0,
            steps: 0,
            steps_max: 0,
            estimates: 0,
            iterations: 0,
            samples: 0,
            path_counts: None,
            halves: Default::default(),
            blocks: BlockWork::new(width, DIVERGENCE_BLOCK),
        }
    }

    /// Adds the rows of a band (of the frame's width).
    pub fn add(&mut self, band: &Frame) {
        self.add_arrays(&band.depth, &band.steps);
        self.estimates += band.estimates;
        self.iterations += band.iterations;
        if !band.radiance.is_empty() {
            let (dropped, exhausted) = self.path_counts.unwrap_or_default();
            let counts = (
                dropped + band.nonfinite_samples,
                exhausted + band.exhausted_rays,
            );
            self.path_counts = Some(counts);
        }
        self.halves.add(band);
        self.samples += match band.samples.is_empty() {
            true => band.pixel_count() as u64,
            false => band.samples.par_iter().map(|&n| n as u64).sum::<u64>(),
        };
    }

    /// Adds whole rows given as their depth (NaN: no hit) and steps. The sums run in parallel
    /// (a 4K frame is 8.3 Mpixel).
    pub fn add_arrays(&mut self, depth: &[f32], steps: &[u32]) {
        self.blocks.add_rows(steps);
        self.pixels += steps.len() as u64;
        self.hits += depth.par_iter().filter(|d| !d.is_nan()).count() as u64;
        self.steps += steps.par_iter().map(|&s| s as u64).sum::<u64>();
        let most = steps.par_iter().copied().max().unwrap_or(0);
        self.steps_max = self.steps_max.max(most);
    }

    pub fn finish(self) -> Summary {
        let n = self.pixels.max(1) as f64;
        let (tile_efficiency, wasted_steps_mean) = self.blocks.finish();
        let estimate = self.halves.finish();
        Summary {
            hit_fraction: self.hits as f64 / n,
            steps_mean: self.steps as f64 / n,
            steps_max: self.steps_max,
            tile_efficiency,
            wasted_steps_mean,
            estimates_total: self.estimates,
            iterations_total: self.iterations,
            samples_total: self.samples,
            nonfinite_samples: self.path_counts.map(|c| c.0),
            exhausted_rays: self.path_counts.map(|c| c.1),
            estimated_rmse: estimate.map(|e| e.rmse),
            estimated_relative_rmse: estimate.map(|e| e.relative),
        }
    }
}

/// Divergence over square blocks of `block` pixels a side, aligned to pixel (0, 0), accumulated
/// band by band (bands of whole rows, any number of rows each).
#[derive(Clone, Debug)]
struct BlockWork {
    width: u32,
    block: u32,
    /// Rows added so far.
    rows: u32,
    /// Per block of the current block row: pixels, sum of steps, most steps.
    open: Vec<(u64, u64, u32)>,
    /// Over closed blocks: steps taken, and steps paid (pixels times the block's most).
    useful: u64,
    paid: u64,
}

impl BlockWork {
    fn new(width: u32, block: u32) -> Self {
        Self {
            width,
            block,
            rows: 0,
            open: vec![(0, 0, 0); width.div_ceil(block) as usize],
            useful: 0,
            paid: 0,
        }
    }

    /// Adds whole rows of steps (a multiple of the width). Whole block rows, once the rows so
    /// far end on one, are summed in parallel, one block row each; the rest row by row.
    fn add_rows(&mut self, mut steps: &[u32]) {
        let width = self.width as usize;
        let block_row = width * self.block as usize;
        if self.rows.is_multiple_of(self.block) && steps.len() >= block_row {
            let whole = steps.len() / block_row * block_row;
            let (useful, paid) = steps[..whole]
                .par_chunks(block_row)
                .map(|rows| {
                    let mut blocks = BlockWork::new(self.width, self.block);
                    blocks.add_rows_one_by_one(rows);
                    (blocks.useful, blocks.paid)
                })
                .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
            self.useful += useful;
            self.paid += paid;
            self.rows += (whole / width) as u32;
            steps = &steps[whole..];
        }
        self.add_rows_one_by_one(steps);
    }

    /// Adds whole rows of steps one row at a time, closing each block row as it ends.
    fn add_rows_one_by_one(&mut self, steps: &[u32]) {
        for row in steps.chunks(self.width as usize) {
            for (i, &s) in row.iter().enumerate() {
                let b = &mut self.open[i / self.block as usize];
                b.0 += 1;
                b.1 += s as u64;
                b.2 = b.2.max(s);
            }
            self.rows += 1;
            if self.rows.is_multiple_of(self.block) {
                self.close();
            }
        }
    }

    fn close(&mut self) {
        for b in &mut self.open {
            self.useful += b.1;
            self.paid += b.0 * b.2 as u64;
            *b = (0, 0, 0);
        }
    }

    /// Over every row added: the share of the paid work that is useful (sum of steps over the
    /// sum of block pixels times the block's most steps; 1 where no block works at all), and
    /// the mean over pixels of the block's most steps minus the pixel's own.
    fn finish(mut self) -> (f64, f64) {
        self.close();
        let pixels = self.rows as u64 * self.width as u64;
        let efficiency = if self.paid == 0 {
            1.0
        } else {
            self.useful as f64 / self.paid as f64
        };
        let wasted_steps_mean = (self.paid - self.useful) as f64 / pixels.max(1) as f64;
        (efficiency, wasted_steps_mean)
    }
}

/// The most steps in each [`DIVERGENCE_BLOCK`] block, blocks row by row.
pub fn block_maxima(steps: &[u32], width: u32, height: u32) -> Vec<u32> {
    let columns = width.div_ceil(DIVERGENCE_BLOCK) as usize;
    let mut max = vec![0u32; columns * height.div_ceil(DIVERGENCE_BLOCK) as usize];
    for (k, &s) in steps.iter().enumerate() {
        let b = &mut max[block_of(k, width)];
        *b = (*b).max(s);
    }
    max
}

/// The index, in [`block_maxima`], of the block holding pixel `k` of an image `width` wide.
pub fn block_of(k: usize, width: u32) -> usize {
    let columns = width.div_ceil(DIVERGENCE_BLOCK) as usize;
    let (i, j) = (k % width as usize, k / width as usize);
    (j / DIVERGENCE_BLOCK as usize) * columns + i / DIVERGENCE_BLOCK as usize
}

/// Per pixel, the wasted steps of its block: the most steps of any pixel in its block (those
/// at the right and bottom edges may be partial) minus its own.
pub fn divergence(steps: &[u32], width: u32, height: u32) -> Vec<u32> {
    let block_max = block_maxima(steps, width, height);
    steps
        .iter()
        .enumerate()
        .map(|(k, &s)| block_max[block_of(k, width)] - s)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32, height: u32, steps: Vec<u32>) -> Frame {
        let n = (width * height) as usize;
        Frame {
            width,
            height,
            colour: vec![0; n],
            depth: vec![0.0; n],
            depth_f64: Vec::new(),
            steps,
            radiance: Vec::new(),
            unclamped: Vec::new(),
            albedo: Vec::new(),
            normal: Vec::new(),
            luminance_m2: Vec::new(),
            hits: Vec::new(),
            hit_depth: Vec::new(),
            specular: Vec::new(),
            view_cosine: Vec::new(),
            noisy: Vec::new(),
            halves: Vec::new(),
            samples: Vec::new(),
            non_finite: 0,
            estimates: 0,
            iterations: 0,
            nonfinite_samples: 0,
            exhausted_rays: 0,
        }
    }

    #[test]
    fn block_efficiency_counts_idle_lanes() {
        let efficiency = |steps: Vec<u32>, block| {
            let mut work = BlockWork::new(2, block);
            work.add_rows(&steps);
            work.finish().0
        };
        assert_eq!(efficiency(vec![5, 5, 5, 5], 2), 1.0);
        assert_eq!(efficiency(vec![4, 0, 0, 0], 2), 0.25);
        assert_eq!(efficiency(vec![4, 0, 0, 0], 1), 1.0);
    }

    #[test]
    fn divergence_is_the_block_maximum_minus_the_pixel() {
        // 10x9: blocks of 8x8, 2x8, 8x1 and 2x1 pixels.
        let (w, h) = (10u32, 9u32);
        let mut steps = vec![1u32; (w * h) as usize];
        steps[3 * 10 + 4] = 7; // in the top-left 8x8 block
        steps[2 * 10 + 9] = 5; // in the top-right 2x8 block
        steps[8 * 10] = 0; // the bottom-left 8x1 block: max 1
        steps[8 * 10 + 9] = 4; // the bottom-right 2x1 block
        let d = divergence(&steps, w, h);
        let at = |i: usize, j: usize| d[j * 10 + i];
        assert_eq!(at(4, 3), 0);
        assert_eq!(at(0, 0), 6);
        assert_eq!(at(7, 7), 6);
        assert_eq!(at(8, 0), 4);
        assert_eq!(at(9, 2), 0);
        assert_eq!(at(8, 7), 4);
        assert_eq!(at(0, 8), 1);
        assert_eq!(at(1, 8), 0);
        assert_eq!(at(8, 8), 3);
        assert_eq!(at(9, 8), 0);
    }

    #[test]
    fn block_work_agrees_with_the_divergence_and_with_itself_in_bands() {
        let (w, h) = (13u32, 11u32);
        let steps: Vec<u32> = (0..w * h).map(|k| (k * 7919) % 23).collect();
        let whole = Summary::of(&frame(w, h, steps.clone()));
        let wasted: u64 = divergence(&steps, w, h).iter().map(|&v| v as u64).sum();
        assert!((whole.wasted_steps_mean - wasted as f64 / (w * h) as f64).abs() < 1e-12);
        let maxima = block_maxima(&steps, w, h);
        let paid: u64 = (0..steps.len())
            .map(|k| maxima[block_of(k, w)] as u64)
            .sum();
        let useful: u64 = steps.iter().map(|&s| s as u64).sum();
        assert!((whole.tile_efficiency - useful as f64 / paid as f64).abs() < 1e-15);
        // Bands of 3 rows (not a multiple of the block) give the same.
        let mut banded = SummaryBuilder::new(w);
        for band in steps.chunks(3 * w as usize) {
            banded.add(&frame(w, band.len() as u32 / w, band.to_vec()));
        }
        assert_eq!(banded.finish(), whole);
        // No work at all: efficiency 1, nothing wasted.
        let mut idle = BlockWork::new(4, DIVERGENCE_BLOCK);
        idle.add_rows(&[0; 8]);
        assert_eq!(idle.finish(), (1.0, 0.0));
    }

    #[test]
    fn block_rows_summed_in_parallel_match_row_by_row() {
        // 37x45: five whole block rows and five rows over, in bands of several sizes.
        let (w, h) = (37u32, 45u32);
        let steps: Vec<u32> = (0..w * h).map(|k| (k * 104_729) % 97).collect();
        let mut serial = BlockWork::new(w, DIVERGENCE_BLOCK);
        serial.add_rows_one_by_one(&steps);
        let serial = serial.finish();
        for band_rows in [1, 3, 8, 16, 20, 45] {
            let mut banded = BlockWork::new(w, DIVERGENCE_BLOCK);
            for band in steps.chunks((band_rows * w) as usize) {
                banded.add_rows(band);
            }
            assert_eq!(banded.finish(), serial, "bands of {band_rows} rows");
        }
    }

    #[test]
    fn the_divergence_block_is_the_workgroup() {
        assert_eq!(
            (DIVERGENCE_BLOCK, DIVERGENCE_BLOCK),
            crate::gpu::WORKGROUP_SIZE
        );
    }
}
