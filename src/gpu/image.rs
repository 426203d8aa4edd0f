//! What comes back of an image kernel (the tracer, the path tracer and the 2D view): which
//! outputs ([`Readback`]), where each lies among the kernel's outputs, and the bands read back
//! decoded into [`Frame`]s, band by band or a stream of frames.

use super::kernel::{self, BandOutput, Kernel, OutputSpec};
use crate::error::Result;
use crate::frame::Frame;

/// Which outputs of a render come back to the host.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Readback {
    /// Colour, depth and steps, and the stats' [`Summary`](crate::stats::Summary) of them.
    All,
    /// The colour only (a picture that is only written as an image: an animation's frames):
    /// the bands' depth and steps are empty and the stats' summary is left at zero. The GPU
    /// reads back a quarter of the bytes.
    Colour,
    /// What `All` reads, and the AOVs `--hdr` writes ([`Frame::unclamped`],
    /// [`Frame::albedo`], [`Frame::normal`]). The kernels compute the AOVs only for this (the
    /// tracers' AOVS override): a shaded picture only.
    Hdr,
}

impl Readback {
    /// Whether depth and steps come back (and the stats' summary is made of them).
    pub fn maps(self) -> bool {
        matches!(self, Readback::All | Readback::Hdr)
    }

    /// Whether the AOVs come back.
    pub fn aovs(self) -> bool {
        self == Readback::Hdr
    }

    /// The override constants that go with this readback: AOVS where the AOVs come back.
    pub fn constants(self) -> &'static [(&'static str, f64)] {
        match self.aovs() {
            true => &[("AOVS", 1.0)],
            false => &[],
        }
    }
}

/// The outputs of the image kernels (the tracer and the 2D view), 4 bytes a pixel each:
/// colour (packed RGBA8), depth (negative: no hit) and steps. The tracer adds
/// [`TRACE_OUTPUTS`]'s two.
pub const IMAGE_OUTPUTS: [OutputSpec; 3] = [
    OutputSpec {
        name: "colour",
        bytes_per_item: 4,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "depth",
        bytes_per_item: 4,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "steps",
        bytes_per_item: 4,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
];

/// Where the colour, depth and steps are among the image kernels' outputs.
const COLOUR_OUTPUT: usize = 0;
/// (The depth's index is public: the explorer's denoised view reads it back.)
pub const DEPTH_OUTPUT: usize = 1;
const STEPS_OUTPUT: usize = 2;

/// Where the tracer's work counts are among its outputs (after the image's three); the
/// accumulator after it stays on the device in phong mode, the AOVs after that come back only
/// for [`Readback::Hdr`].
const WORK_OUTPUT: usize = IMAGE_OUTPUTS.len();
/// Where the running mean of the samples (`accumulated`) is among the tracer's outputs.
pub const ACCUMULATED_OUTPUT: usize = WORK_OUTPUT + 1;
/// Where the AOVs (four `vec4<f32>` a pixel, accumulate.wgsl's `store_aovs`) are among the
/// tracer's outputs.
pub const AOVS_OUTPUT: usize = ACCUMULATED_OUTPUT + 1;

/// [`IMAGE_OUTPUTS`] of an f64 kernel: the depth is f64.
pub const IMAGE64_OUTPUTS: [OutputSpec; 3] = [
    IMAGE_OUTPUTS[0],
    OutputSpec {
        name: "depth",
        bytes_per_item: 8,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    IMAGE_OUTPUTS[2],
];

/// [`TRACE_OUTPUTS`] of the f64 tracer: the depth is f64.
pub const TRACE64_OUTPUTS: [OutputSpec; 6] = [
    IMAGE64_OUTPUTS[0],
    IMAGE64_OUTPUTS[1],
    IMAGE64_OUTPUTS[2],
    TRACE_OUTPUTS[3],
    TRACE_OUTPUTS[4],
    TRACE_OUTPUTS[5],
];

/// The tracer's outputs: the image's three, the work made per pixel (trace.wgsl's `out_work`:
/// the distance estimates and the quaternion iterations, each a u64 as two u32s), the running
/// mean of the samples' colours (`vec4<f32>`, then three more planes for adaptive sampling's
/// streams, accumulate.wgsl's `Streams`, which stay on the device), and on demand the AOVs
/// (four `vec4<f32>` a pixel: accumulate.wgsl's `store_aovs`). Six storage buffers, within
/// WebGPU's default of eight a stage.
pub const TRACE_OUTPUTS: [OutputSpec; 6] = [
    IMAGE_OUTPUTS[0],
    IMAGE_OUTPUTS[1],
    IMAGE_OUTPUTS[2],
    OutputSpec {
        name: "work",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "accumulated",
        bytes_per_item: 16,
        on_demand: false,
        planes: 4,
        planes_back: 3,
    },
    OutputSpec {
        name: "aovs",
        bytes_per_item: 64,
        on_demand: true,
        planes: 1,
        planes_back: 1,
    },
];

/// What a frame keeps of the tracer's accumulator (`accumulated`, a `vec4<f32>` a pixel),
/// which then comes back: its rgb as the mean linear radiance (the path kernel's; phong mode's
/// is the clamped colours' mean, whose packed colour comes back instead), its fourth float as
/// the samples each pixel took (adaptive sampling's state once a pixel is done: minus its
/// samples). Nothing by default (the 2D view has no accumulator).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Accumulated {
    pub radiance: bool,
    pub samples: bool,
}

/// Runs an image kernel over a `width` x `height` image with these override constants and
/// per-dispatch uniform, `dispatches` a band, handing each band to `sink` as a [`Frame`] of the
/// outputs `read` asks for (by index; [`image_readback`] gives a [`Readback`]'s) and of the
/// accumulator what `kept` says, binding the scene's `input` array (the environment map).
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_image_bands(
    kernel: &Kernel,
    constants: &[(&'static str, f64)],
    ((width, height), dispatches): ((u32, u32), u32),
    read: &[bool],
    kept: Accumulated,
    uniform: &dyn Fn(kernel::Band) -> Vec<u8>,
    rows: std::ops::Range<u32>,
    input: kernel::InputData,
    sink: &mut dyn FnMut(Frame) -> Result<()>,
) -> Result<kernel::RunTimes> {
    let mut read = read.to_vec();
    if kept.radiance || kept.samples {
        read[ACCUMULATED_OUTPUT] = true;
    }
    let run = kernel::Run {
        constants,
        size: (width, height),
        read: &read,
        dispatches_per_band: dispatches,
        params: uniform,
        input,
    };
    // A band must start on a multiple of the kernel's rows (a cone block's): rendered from the
    // block row at or above `rows.start`, and the rows above it cropped off.
    let multiple = kernel.spec().band_row_multiple.max(1);
    let start = rows.start / multiple * multiple;
    let keep = rows.clone();
    let planes: Vec<u64> = kernel
        .spec()
        .outputs
        .iter()
        .map(|o| o.planes_back)
        .collect();
    let decode = |out: BandOutput<'_>| match crop_band(&out, &keep, &planes) {
        None => decode_frame(width, &out, kept),
        Some((row, rows, cropped)) => {
            let outputs: Vec<Option<&[u8]>> = cropped.iter().map(|o| o.as_deref()).collect();
            let band = BandOutput {
                row,
                rows,
                outputs: &outputs,
            };
            decode_frame(width, &band, kept)
        }
    };
    kernel.run_rows(&run, start..rows.end, decode, sink)
}

/// The rows of `band` that lie in `keep`, as the first row, the rows and the outputs of a band
/// of their own (each output's `planes` cropped one by one); None where the band lies in `keep`
/// whole.
#[allow(clippy::type_complexity)]
fn crop_band(
    band: &BandOutput<'_>,
    keep: &std::ops::Range<u32>,
    planes: &[u64],
) -> Option<(u32, u32, Vec<Option<Vec<u8>>>)> {
    let first = keep.start.max(band.row);
    let last = keep.end.min(band.row + band.rows).max(first);
    if (first, last) == (band.row, band.row + band.rows) {
        return None;
    }
    let (skip, rows) = ((first - band.row) as usize, (last - first) as usize);
    let cropped = band
        .outputs
        .iter()
        .zip(planes)
        .map(|(o, &planes)| {
            o.map(|bytes| {
                let plane = bytes.len() / planes.max(1) as usize;
                let per_row = plane / band.rows.max(1) as usize;
                bytes
                    .chunks(plane.max(1))
                    .flat_map(|p| &p[skip * per_row..(skip + rows) * per_row])
                    .copied()
                    .collect()
            })
        })
        .collect();
    Some((first, rows as u32, cropped))
}

/// Which outputs of an image kernel come back for `readback`. All: colour, depth, steps and
/// (where the kernel has it) the work counts, not the accumulator. Colour: the colour alone.
/// Hdr: All's and (where the kernel has them) the AOVs.
pub(crate) fn image_readback(kernel: &Kernel, readback: Readback) -> Vec<bool> {
    let last = match readback {
        Readback::All | Readback::Hdr => WORK_OUTPUT,
        Readback::Colour => COLOUR_OUTPUT,
    };
    (0..kernel.spec().outputs.len())
        .map(|k| k <= last || (k == AOVS_OUTPUT && readback.aovs()))
        .collect()
}

/// Runs the bands of many frames of an image kernel as one stream, handing each frame whole to
/// `sink`, in order, with its times: from its first band's submission to its last band decoded,
/// and the GPU time of its bands.
pub(crate) fn stream_frames(
    kernel: &Kernel,
    steps: &mut dyn Iterator<Item = kernel::Step>,
    sink: &mut dyn FnMut(Frame, kernel::RunTimes) -> Result<()>,
) -> Result<()> {
    // The frame being put together: its bands so far, its first submission, its GPU time.
    let mut frame: Option<(Frame, std::time::Instant, Option<f64>)> = None;
    kernel.run_stream(
        steps,
        |step, out| decode_frame(step.width, &out, Accumulated::default()),
        |step, done| {
            let (whole, submitted, gpu) =
                frame.get_or_insert_with(|| (Frame::empty(step.width), done.submitted, Some(0.0)));
            whole.append(&done.made);
            *gpu = gpu.zip(done.gpu_seconds).map(|(a, b)| a + b);
            if step.row + step.rows == step.height {
                let times = kernel::RunTimes {
                    seconds: (done.decoded - *submitted).as_secs_f64(),
                    gpu_seconds: *gpu,
                };
                let (whole, _, _) = frame.take().expect("a frame");
                sink(whole, times)?;
            }
            Ok(())
        },
    )
}

/// A band of an image kernel's outputs as a [`Frame`]: a negative depth (no hit) becomes NaN,
/// and depths that came out NaN or infinite are counted. The estimates and the iterations are
/// the kernel's fourth output where it has one (the tracer's work), else both the steps (the 2D
/// view's iterations). Outputs not
/// read back stay empty, and of the accumulator what `kept` says. The arrays are converted in
/// parallel: at 3840x2160 each is 33 MB.
pub(crate) fn decode_frame(width: u32, band: &BandOutput<'_>, kept: Accumulated) -> Frame {
    use rayon::prelude::*;
    // An output not read back is an empty array of its type.
    fn output<'a, T: bytemuck::Pod>(band: &BandOutput<'a>, k: usize) -> &'a [T] {
        band.outputs
            .get(k)
            .copied()
            .flatten()
            .map_or(&[], bytemuck::cast_slice)
    }
    let colour: &[u32] = output(band, COLOUR_OUTPUT);
    let pixels = band.rows as usize * width as usize;
    // An f64 kernel's depth is 8 bytes a pixel: kept whole in `depth_f64`, rounded in `depth`.
    let depth_bytes = band
        .outputs
        .get(DEPTH_OUTPUT)
        .copied()
        .flatten()
        .unwrap_or(&[]);
    let depths_f64: Vec<f64> = if pixels > 0 && depth_bytes.len() == 8 * pixels {
        bytemuck::pod_collect_to_vec::<u8, f64>(depth_bytes)
    } else {
        Vec::new()
    };
    let depths_f32: Vec<f32>;
    let depths: &[f32] = if depths_f64.is_empty() {
        output(band, DEPTH_OUTPUT)
    } else {
        depths_f32 = depths_f64.par_iter().map(|&d| d as f32).collect();
        &depths_f32
    };
    let steps: &[u32] = output(band, STEPS_OUTPUT);
    // A count's two words, low then high.
    let wide = |low: u32, high: u32| low as u64 | (high as u64) << 32;
    let (estimates, iterations) = match output::<[u32; 4]>(band, WORK_OUTPUT) {
        [] => {
            let n = steps.par_iter().map(|&n| n as u64).sum::<u64>();
            (n, n)
        }
        work => work
            .par_iter()
            .map(|w| (wide(w[0], w[1]), wide(w[2], w[3])))
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1)),
    };
    // The accumulator where it was read back, its planes one after another: path mode's mean
    // linear radiance, adaptive sampling's samples (a done pixel's fourth float is minus its
    // samples), then the pixels' halves (accumulate.wgsl's store_halves).
    let planes: &[[f32; 4]] = output(band, ACCUMULATED_OUTPUT);
    let (accumulated, halves) = planes.split_at(planes.len().min(pixels));
    let radiance: &[[f32; 4]] = if kept.radiance { accumulated } else { &[] };
    let half = crate::estimate::half_colour;
    // The AOVs where they were read back: four vec4s a pixel (colour and hits, albedo and M2,
    // normal and the hits' depth, specular light and view cosine). The colour is phong mode's
    // linear mean; path mode's is the accumulator's.
    let aovs: &[[[f32; 4]; 4]] = output(band, AOVS_OUTPUT);
    let aov = |k: usize| -> Vec<[f32; 3]> {
        aovs.par_iter()
            .map(|a| [a[k][0], a[k][1], a[k][2]])
            .collect()
    };
    assert_eq!(
        colour.len(),
        band.rows as usize * width as usize,
        "an image band reads back its colour"
    );
    Frame {
        width,
        height: band.rows,
        colour: colour.par_iter().copied().collect(),
        depth: depths
            .par_iter()
            .map(|&d| if d < 0.0 { f32::NAN } else { d })
            .collect(),
        depth_f64: depths_f64
            .par_iter()
            .map(|&d| if d < 0.0 { f64::NAN } else { d })
            .collect(),
        steps: steps.par_iter().copied().collect(),
        radiance: radiance.par_iter().map(|a| [a[0], a[1], a[2]]).collect(),
        unclamped: if radiance.is_empty() {
            aov(0)
        } else {
            Vec::new()
        },
        albedo: aov(1),
        normal: aov(2),
        luminance_m2: aovs.par_iter().map(|a| a[1][3]).collect(),
        hits: aovs.par_iter().map(|a| a[0][3]).collect(),
        hit_depth: aovs.par_iter().map(|a| a[2][3]).collect(),
        // Path mode's alone: phong mode has no specular signal.
        specular: if radiance.is_empty() {
            Vec::new()
        } else {
            aov(3)
        },
        view_cosine: match radiance.is_empty() {
            true => Vec::new(),
            false => aovs.par_iter().map(|a| a[3][3]).collect(),
        },
        noisy: Vec::new(),
        halves: match kept.radiance && halves.len() == 2 * pixels {
            true => (0..pixels)
                .into_par_iter()
                .map(|k| [half(&halves[k]), half(&halves[pixels + k])])
                .collect(),
            false => Vec::new(),
        },
        samples: match kept.samples {
            true => accumulated.par_iter().map(|a| (-a[3]) as u32).collect(),
            false => Vec::new(),
        },
        non_finite: depths.par_iter().filter(|d| !d.is_finite()).count() as u64
            + radiance
                .par_iter()
                .map(|a| a[..3].iter().filter(|c| !c.is_finite()).count() as u64)
                .sum::<u64>(),
        estimates,
        iterations,
        // Path mode's counters are in the colour words until the renderer takes them
        // (Frame::take_path_counters).
        nonfinite_samples: 0,
        exhausted_rays: 0,
    }
}
