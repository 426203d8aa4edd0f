//! What a pass of the live view reads back, and how it decodes: the running mean's sections
//! ([`MeanLayout`]), copied into a buffer the host maps ([`copy_mean`]) and decoded into the
//! [`Frame`] the denoiser reads ([`decode_mean`]); the depth and steps ([`decode_steps`]).

use std::sync::Arc;

use crate::frame::Frame;
use crate::gpu::{ACCUMULATED_OUTPUT, AOVS_OUTPUT, DEPTH_OUTPUT, GpuReal};

/// Where the sections of a mean's readback are: bytes per pixel of each, 0 where left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanLayout {
    /// The accumulator (vec4<f32> a pixel): path mode's radiance, and with adaptive sampling
    /// the samples each pixel took.
    pub accumulated: u64,
    /// Path mode: the pixels' halves, the accumulator's second and third planes (a vec4<f32>
    /// each), of which the view's error estimate is made ([`crate::estimate`]).
    pub halves: u64,
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
            halves: if path { 32 } else { 0 },
            aovs: if aovs { 64 } else { 0 },
            depth: if aovs { depth } else { 0 },
        }
    }

    /// Whether the pass reads anything back (else its colour goes straight to the texture).
    pub fn reads(&self) -> bool {
        self.accumulated + self.aovs > 0
    }
}

/// Records the copy of a pass's mean, the sections of `layout` from the kernel's `outputs`
/// (`items` of each: rows times their stride; the halves from the accumulator's second and
/// third planes, a quarter of its buffer apart), into a buffer the host can map: `spare` where
/// it has the size, else a new one.
pub fn copy_mean(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    outputs: &[wgpu::Buffer],
    items: u64,
    spare: Option<wgpu::Buffer>,
    layout: MeanLayout,
) -> wgpu::Buffer {
    let bytes = items * (layout.accumulated + layout.halves + layout.aovs + layout.depth);
    let buffer = spare.filter(|b| b.size() == bytes).unwrap_or_else(|| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("mean readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    });
    let plane = outputs[ACCUMULATED_OUTPUT].size() / 4;
    let half = layout.halves / 2;
    let sections = [
        (ACCUMULATED_OUTPUT, 0, layout.accumulated),
        (ACCUMULATED_OUTPUT, plane, half),
        (ACCUMULATED_OUTPUT, 2 * plane, half),
        (AOVS_OUTPUT, 0, layout.aovs),
        (DEPTH_OUTPUT, 0, layout.depth),
    ];
    let mut offset = 0;
    for (output, from, per_item) in sections.into_iter().filter(|(_, _, b)| *b > 0) {
        encoder.copy_buffer_to_buffer(&outputs[output], from, &buffer, offset, items * per_item);
        offset += items * per_item;
    }
    buffer
}

/// An image's shape in a readback: width, height and the row stride, in pixels.
pub type Shape = (usize, usize, usize);

/// The shape of an image of `size` pixels whose rows are `row_stride` pixels apart.
pub fn shape(size: [u32; 2], row_stride: u32) -> Shape {
    (size[0] as usize, size[1] as usize, row_stride as usize)
}

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
    /// Path mode: the mean's estimated error ([`crate::estimate::raw`]); None below two
    /// samples.
    pub estimate: Option<crate::estimate::ErrorEstimate>,
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
    let (halves, rest) = rest.split_at(items * layout.halves as usize);
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
    let half = crate::estimate::half_colour;
    // An adaptive pixel keeps its halves there only once it is done (before, its streams'
    // state): a mean some of whose pixels still sample has no halves, and no estimate.
    let still = adaptive
        && !accumulated.is_empty()
        && unpad::<[f32; 4], _>(accumulated, shape, |a| a[3] >= 0.0)
            .into_iter()
            .any(|sampling| sampling);
    let halves: Vec<[[f32; 3]; 2]> = match halves.is_empty() || still {
        true => Vec::new(),
        false => {
            let (a, b) = halves.split_at(halves.len() / 2);
            let a = unpad::<[f32; 4], _>(a, shape, half);
            let b = unpad::<[f32; 4], _>(b, shape, half);
            a.into_iter().zip(b).map(|(a, b)| [a, b]).collect()
        }
    };
    let mut sums = crate::estimate::HalvesSums::default();
    sums.add_pixels(shape.0 as u32, &halves, &radiance);
    let estimate = sums.finish();
    let frame = (layout.aovs > 0).then(|| {
        let aov =
            |k: usize| unpad::<[[f32; 4]; 4], _>(aovs, shape, move |a| [a[k][0], a[k][1], a[k][2]]);
        let mut frame = Frame::empty(shape.0 as u32);
        frame.height = shape.1 as u32;
        frame.radiance = radiance.clone();
        // Phong mode's linear mean is the AOVs' colour (unclamped).
        if radiance.is_empty() {
            frame.unclamped = aov(0);
        }
        frame.albedo = aov(1);
        frame.normal = aov(2);
        frame.luminance_m2 = unpad::<[[f32; 4]; 4], _>(aovs, shape, |a| a[1][3]);
        frame.hits = unpad::<[[f32; 4]; 4], _>(aovs, shape, |a| a[0][3]);
        frame.hit_depth = unpad::<[[f32; 4]; 4], _>(aovs, shape, |a| a[2][3]);
        // Path mode's alone: phong mode has no specular signal.
        if !radiance.is_empty() {
            frame.specular = aov(3);
            frame.view_cosine = unpad::<[[f32; 4]; 4], _>(aovs, shape, |a| a[3][3]);
        }
        frame.depth = unpad::<F, _>(depth, shape, depth_of::<F>);
        frame.samples = adaptive_counts;
        frame.halves = halves;
        Arc::new(frame)
    });
    Mean {
        radiance,
        counts,
        samples_taken,
        frame,
        estimate,
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
    fn a_mean_decodes_its_rows_counts_and_misses() {
        // 2 x 2 pixels, rows 3 apart; the accumulator, the AOVs and an f32 depth.
        let shape = (2, 2, 3);
        let layout = MeanLayout::of(true, true, true, false, 4);
        let mut bytes = Vec::new();
        for i in 0..6 {
            let n = if i == 1 { -3.0f32 } else { 0.5 };
            bytes.extend(bytemuck::bytes_of(&[i as f32, 0.0, 0.0, n]));
        }
        // The halves: A's means i + 0.5 (none in pixel 0), B's i - 0.5, two samples each.
        for i in 0..6 {
            let n = if i == 0 { 0.0f32 } else { 2.0 };
            bytes.extend(bytemuck::bytes_of(&[i as f32 + 0.5, 0.0, 0.0, n]));
        }
        for i in 0..6 {
            bytes.extend(bytemuck::bytes_of(&[i as f32 - 0.5, 0.0, 0.0, 2.0f32]));
        }
        for i in 0..6 {
            let aov = [
                [i as f32, 0.0, 0.0, 1.0],
                [0.25; 4],
                [0.0, 0.0, 1.0, 2.0],
                [0.125, 0.0, 0.0, 0.75],
            ];
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
        // Adaptively, three pixels still sample: their planes hold their streams, not halves,
        // so the mean has no halves and no estimate.
        assert_eq!(mean.estimate, None);
        // Without adaptive sampling pixels 1, 3 and 4 (of the four kept) have both halves, 1
        // apart in the red channel: (1^2 / 4 + 0 + 0) / 3 channels a pixel, an MSE of 1 / 12.
        let plain = decode_mean::<f32>(&bytes, layout, shape, 4, (false, true));
        let estimate = plain.estimate.expect("the halves' estimate");
        assert!(
            (estimate.rmse - (1.0f64 / 12.0).sqrt()).abs() < 1e-9,
            "{estimate:?}"
        );
        let halves = &plain.frame.as_ref().expect("AOVs asked for").halves;
        assert!(halves[0][0][0].is_nan());
        assert_eq!(halves[1], [[1.5, 0.0, 0.0], [0.5, 0.0, 0.0]]);
        let frame = mean.frame.expect("AOVs asked for");
        assert!(frame.halves.is_empty());
        assert_eq!(frame.samples, [4, 3, 4, 4]);
        assert_eq!(frame.albedo[2], [0.25; 3]);
        assert_eq!(frame.hit_depth, [2.0; 4]);
        assert_eq!(frame.specular[1], [0.125, 0.0, 0.0]);
        assert_eq!(frame.view_cosine, [0.75; 4]);
        assert!(frame.depth[2].is_nan());
        assert_eq!(frame.depth[3], 4.0);
    }
}
