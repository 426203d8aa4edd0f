//! The pure-Rust reference tracer: shaders/*.wgsl written again in Rust, generic over f32 and
//! f64, parallel over rows with rayon. The tests hold the GPU to it.

pub mod bsdf;
mod counters;
pub mod denoise;
pub mod environment;
pub mod ggx_albedo;
pub mod ggx_quadrature;
pub mod julia2d;
pub mod light;
pub mod medium;
pub mod path;
pub mod sample;
pub mod sobol;
pub mod trace;

// The counters live in a module of their own: the tracers (trace/, path/) count into them
// and this module, which calls the tracers, reads them.
pub(crate) use counters::{ESTIMATES, ITERATIONS};

/// The cone starts of the blocks in the row of blocks holding pixel row `j` (none for the
/// seed's tracing: every ray starts at the ball).
fn cone_starts<F: Real>(params: &TraceParams<F>, j: u32) -> Vec<F> {
    match params.tracing {
        Tracing::Cone => (0..params.width.div_ceil(trace::CONE_BLOCK))
            .map(|bi| params.cone_start(bi, j / trace::CONE_BLOCK))
            .collect(),
        Tracing::Seed => Vec::new(),
    }
}

/// Work a render does, counted by tracing it once on this thread.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    pub pixels: u64,
    pub estimates: u64,
    pub iterations: u64,
}

/// Counts the distance estimates and quaternion iterations of a render (the GPU does the same
/// work: its kernel is this tracer's twin). Single-threaded; for benchmarks and reports.
pub fn count_work<F: Real>(params: &TraceParams<F>) -> Work {
    ESTIMATES.set(0);
    ITERATIONS.set(0);
    let mut cones: Vec<F> = Vec::new();
    for j in 0..params.height {
        // One cone per block, as on the GPU.
        if j % trace::CONE_BLOCK == 0 {
            cones = cone_starts(params, j);
        }
        for i in 0..params.width {
            let t_min = cones
                .get((i / trace::CONE_BLOCK) as usize)
                .copied()
                .unwrap_or(F::zero());
            params.trace_pixel(i, j, 0, t_min, true);
        }
    }
    Work {
        pixels: params.width as u64 * params.height as u64,
        estimates: ESTIMATES.get(),
        iterations: ITERATIONS.get(),
    }
}

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use crate::algebra::{Real, Vec3};
use crate::frame::Frame;
use crate::params::TraceParams;
use crate::scene::Tracing;

/// Renders every pixel of the scene the parameters describe; returns the frame and the seconds
/// it took.
pub fn render<F: Real>(params: &TraceParams<F>) -> (Frame, f64) {
    let start = Instant::now();
    let frame = render_rows(params, true, false, 0..params.height);
    (frame, start.elapsed().as_secs_f64())
}

/// Renders the rows `rows` (0 at the top) of the image, in parallel over rows: a frame of
/// `rows.len()` rows. With several samples a pixel's colour is the mean of its samples' clamped
/// colours; depth and steps are sample 0's. `shade` false traces depth and steps only, as the
/// GPU's pipelines without the shading code: the colour is the background. `aovs` (with
/// `shade`) adds the AOVs (`add_pixel_aovs`, as the kernel's AOVS override does).
pub fn render_rows<F: Real>(
    params: &TraceParams<F>,
    shade: bool,
    aovs: bool,
    rows: std::ops::Range<u32>,
) -> Frame {
    assert!(shade || !aovs, "the AOVs are made of a shaded picture");
    let keep = Keep {
        f64: is_f64::<F>(),
        radiance: false,
        aovs,
        samples: params.adaptive(),
    };
    fill_rows(params.width, rows, keep, |j| {
        // Each row computes its blocks' cones again: the CPU has no shared workgroup memory to
        // hand them over in. Their estimates are not the pixels' (the GPU counts them apart).
        let cones = cone_starts(params, j);
        move |i| {
            let t_min = cones
                .get((i / trace::CONE_BLOCK) as usize)
                .copied()
                .unwrap_or(F::zero());
            let before = (ESTIMATES.get(), ITERATIONS.get());
            // Where the lens is open, the depth and the steps are the pinhole ray's, traced for
            // them alone (the kernel's `main`).
            let pinhole = params
                .lens_open()
                .then(|| params.trace_primary(&params.pinhole_ray(i, j, 0, t_min)));
            let clamp = |c: Vec3<F>| {
                let unit = |v: F| v.max(F::zero()).min(F::one());
                Vec3::new(unit(c.x), unit(c.y), unit(c.z))
            };
            let samples = params.samples.max(1);
            let mut first = None;
            let mut non_finite = 0;
            let mut made = trace::Aovs::default();
            let mut mean = Vec3::zero();
            // Adaptive sampling's state, as the kernel keeps it: the pixel's streams
            // (`add_to_streams`), and the samples taken.
            let (mut streams, mut taken) = (trace::Streams::default(), samples);
            // As the kernel's `main` with INTERLEAVE 2: samples k and k + 1 traced as a pair at
            // k (`trace_primary_pair`), k + 1's trace kept for it; an odd one left traced alone.
            let mut second = None;
            for k in 0..samples {
                let ray = params.primary_ray(i, j, k, t_min);
                let trace = match second.take() {
                    Some(trace) => trace,
                    None if k + 1 < samples => {
                        let next = params.primary_ray(i, j, k + 1, t_min);
                        let [a, b] = params.trace_primary_pair(&ray, &next);
                        second = Some(b);
                        a
                    }
                    None => params.trace_primary(&ray),
                };
                let pixel = params.shade_pixel(&ray, trace, shade);
                non_finite += non_finite_values(&pixel);
                let c = clamp(pixel.colour);
                if params.adaptive() {
                    // The samples the pixel's colours hold, and whether this one joined them.
                    let before = streams.rule_a[3] + streams.b[3];
                    streams = params.add_to_streams(streams, k, true, c.to_f32());
                    let n = streams.rule_a[3] + streams.b[3];
                    if aovs && n > before {
                        made = params.add_pixel_aovs(made, n as u32 - 1, &pixel);
                    }
                    first.get_or_insert(pixel);
                    if params.sampling_done(&streams, k + 1) {
                        taken = k + 1;
                        break;
                    }
                    continue;
                }
                // The running mean, as the kernel keeps it: exact where all samples agree.
                mean = match k {
                    0 => c,
                    _ => mean + (c - mean) / F::lit((k + 1) as f64),
                };
                if aovs {
                    made = params.add_pixel_aovs(made, k, &pixel);
                }
                first.get_or_insert(pixel);
            }
            if params.adaptive() {
                // Every pixel is done by its last sample (`sampling_done`).
                if aovs {
                    made = trace::finish_aovs(made, &streams, taken);
                }
                mean = Vec3::from_f32(trace::streams_mean(&streams));
            }
            let first = first.expect("at least one sample");
            let colour = if params.samples <= 1 {
                trace::pack_colour(first.colour)
            } else {
                trace::pack_colour(mean)
            };
            let (hit, depth, steps) = match pinhole {
                Some(t) => (t.hit, t.t, t.steps),
                None => (first.hit, first.depth, first.steps),
            };
            PixelOut {
                colour,
                depth: if hit { depth.to_f64() } else { f64::NAN },
                steps,
                non_finite,
                estimates: ESTIMATES.get() - before.0,
                iterations: ITERATIONS.get() - before.1,
                radiance: [0.0; 3],
                halves: Default::default(),
                aovs: made,
                samples: taken,
            }
        }
    })
}

/// How many of a pixel's colour channels and depth are NaN or infinite.
fn non_finite_values<F: Real>(pixel: &trace::Pixel<F>) -> u64 {
    let c = pixel.colour;
    [c.x, c.y, c.z, pixel.depth]
        .iter()
        .filter(|v| !v.is_finite())
        .count() as u64
}

/// What a CPU kernel makes of one pixel: the frame's three values, and how many values came
/// out NaN or infinite on the way.
pub struct PixelOut {
    pub colour: u32,
    /// NaN where nothing was hit.
    pub depth: f64,
    pub steps: u32,
    pub non_finite: u64,
    /// Distance estimates made for the pixel.
    pub estimates: u64,
    /// Quaternion iterations made for the pixel (cpu::counters' ITERATIONS).
    pub iterations: u64,
    /// Path mode: the mean linear radiance (kept where [`fill_rows`] is asked to).
    pub radiance: [f32; 3],
    /// Path mode: the pixel's halves ([`Frame::halves`]; kept with the radiance).
    pub halves: [[f32; 3]; 2],
    /// The AOVs (kept where [`fill_rows`] is asked to).
    pub aovs: trace::Aovs,
    /// The samples the pixel took (kept where [`fill_rows`] is asked to).
    pub samples: u32,
}

/// What [`fill_rows`] keeps beyond colour, depth and steps.
#[derive(Clone, Copy, Debug, Default)]
pub struct Keep {
    /// The depth in f64 too.
    pub f64: bool,
    /// Each pixel's radiance (path mode).
    pub radiance: bool,
    /// Each pixel's AOVs: [`Frame::unclamped`] (phong mode: where the radiance is not kept),
    /// [`Frame::albedo`] and [`Frame::normal`].
    pub aovs: bool,
    /// Each pixel's samples ([`Frame::samples`]: adaptive sampling).
    pub samples: bool,
}

/// Whether `F` is f64: its frames keep their depth in f64 too ([`Frame::depth_f64`]).
pub fn is_f64<F: Real>() -> bool {
    size_of::<F>() == size_of::<f64>()
}

/// The rows `rows` of a `width`-wide image, in parallel over rows: `row(j)` prepares row j and
/// gives the function of its pixels, called for i = 0 to width - 1. With `keep.f64` the frame
/// keeps the depth in f64 as well, with `keep.radiance` the pixels' radiance, with `keep.aovs`
/// their AOVs.
pub fn fill_rows<R, P>(width: u32, rows: std::ops::Range<u32>, keep: Keep, row: R) -> Frame
where
    R: Fn(u32) -> P + Sync,
    P: Fn(u32) -> PixelOut,
{
    let (w, h) = (width as usize, rows.len());
    let mut colour = vec![0u32; w * h];
    let mut depth = vec![0f64; w * h];
    let mut steps = vec![0u32; w * h];
    let mut radiance = vec![[0f32; 3]; if keep.radiance { w * h } else { 0 }];
    let mut halves = vec![[[0f32; 3]; 2]; if keep.radiance { w * h } else { 0 }];
    let mut aovs = vec![trace::Aovs::default(); if keep.aovs { w * h } else { 0 }];
    let mut samples = vec![0u32; if keep.samples { w * h } else { 0 }];
    let non_finite = AtomicU64::new(0);
    let estimates = AtomicU64::new(0);
    let iterations = AtomicU64::new(0);
    // A row of radiance (of AOVs) where it is kept; none (an empty slice) where not.
    fn rows_of<T>(values: &mut [T], kept: bool, (w, h): (usize, usize)) -> Vec<&mut [T]> {
        match kept {
            true => values.chunks_mut(w).collect(),
            false => (0..h).map(|_| Default::default()).collect(),
        }
    }
    let mut radiance_rows = rows_of(&mut radiance, keep.radiance, (w, h));
    let mut halves_rows = rows_of(&mut halves, keep.radiance, (w, h));
    let mut aov_rows = rows_of(&mut aovs, keep.aovs, (w, h));
    let mut sample_rows = rows_of(&mut samples, keep.samples, (w, h));
    colour
        .par_chunks_mut(w)
        .zip(depth.par_chunks_mut(w))
        .zip(steps.par_chunks_mut(w))
        .zip(radiance_rows.par_iter_mut().zip(aov_rows.par_iter_mut()))
        .zip(sample_rows.par_iter_mut().zip(halves_rows.par_iter_mut()))
        .enumerate()
        .for_each(
            |(r, ((((colour_row, depth_row), steps_row), (radiance_row, aov_row)), rest))| {
                let (sample_row, halves_row) = rest;
                let pixel = row(rows.start + r as u32);
                let (mut bad, mut made, mut iterated) = (0, 0, 0);
                for i in 0..w {
                    let out = pixel(i as u32);
                    colour_row[i] = out.colour;
                    depth_row[i] = out.depth;
                    steps_row[i] = out.steps;
                    if let Some(slot) = radiance_row.get_mut(i) {
                        *slot = out.radiance;
                    }
                    if let Some(slot) = halves_row.get_mut(i) {
                        *slot = out.halves;
                    }
                    if let Some(slot) = aov_row.get_mut(i) {
                        *slot = out.aovs;
                    }
                    if let Some(slot) = sample_row.get_mut(i) {
                        *slot = out.samples;
                    }
                    bad += out.non_finite;
                    made += out.estimates;
                    iterated += out.iterations;
                }
                non_finite.fetch_add(bad, Ordering::Relaxed);
                estimates.fetch_add(made, Ordering::Relaxed);
                iterations.fetch_add(iterated, Ordering::Relaxed);
            },
        );
    let aov = |take: fn(&trace::Aovs) -> Vec3<f32>| -> Vec<[f32; 3]> {
        aovs.par_iter()
            .map(|a| {
                let v = take(a);
                [v.x, v.y, v.z]
            })
            .collect()
    };
    // Path mode's linear mean is its radiance: the unclamped colour is phong mode's.
    let unclamped = match keep.radiance {
        true => Vec::new(),
        false => aov(|a| a.colour),
    };
    Frame {
        width,
        height: h as u32,
        colour,
        depth: depth.par_iter().map(|&d| d as f32).collect(),
        depth_f64: if keep.f64 { depth } else { Vec::new() },
        steps,
        radiance,
        unclamped,
        albedo: aov(|a| a.albedo),
        normal: aov(|a| a.normal),
        luminance_m2: aovs.par_iter().map(|a| a.m2).collect(),
        hits: aovs.par_iter().map(|a| a.hits).collect(),
        hit_depth: aovs.par_iter().map(|a| a.depth).collect(),
        // Path mode's alone: phong mode has no specular signal.
        specular: match keep.radiance {
            true => aov(|a| a.specular),
            false => Vec::new(),
        },
        view_cosine: match keep.radiance && keep.aovs {
            true => aovs.par_iter().map(|a| a.cosine).collect(),
            false => Vec::new(),
        },
        noisy: Vec::new(),
        halves,
        samples,
        non_finite: non_finite.into_inner(),
        estimates: estimates.into_inner(),
        iterations: iterations.into_inner(),
        nonfinite_samples: 0,
        exhausted_rays: 0,
    }
}
