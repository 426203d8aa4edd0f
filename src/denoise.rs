//! The denoiser (`image.denoise`, the `[denoise]` table): an edge-avoiding a-trous wavelet
//! filter (Dammertz et al. 2010) with SVGF's edge-stopping functions and variance (Schied et
//! al. 2017), on the linear image of a whole frame before the display transform, in either
//! model. This module owns the filter's steps around the passes:
//!
//! 1. [`prepare`]: each pixel's linear colour divided by its demodulation, h A + (1 - h) of its
//!    albedo AOV A and hit fraction h (the illumination), the variance of its mean luminance
//!    (from the AOVs' Welford M2), and its guide (the mean normal and the mean depth of its
//!    hits, where most of its samples hit);
//! 2. the passes, on the GPU (src/gpu/denoise.rs over shaders/denoise.wgsl) or on the CPU
//!    (its twin, src/cpu/denoise.rs);
//! 3. [`finish`]: the illumination times the albedo again.
//!
//! The book's chapter "Denoising" (docs/book/denoise.md) gives every formula.

use rayon::prelude::*;

use crate::algebra::Vec3;
use crate::cpu::denoise::{DenoiseParams, Pass, luminance};
use crate::frame::Frame;
#[cfg(feature = "gpu")]
use crate::gpu::GpuKernels;
use crate::scene::Scene;

pub use crate::scene::Denoiser;

/// An albedo channel below this divides the colour as this (a black albedo would give no
/// illumination to filter); the light of the samples that missed is not divided at all.
pub const ALBEDO_FLOOR: f32 = 0.01;

/// The image the passes filter, the guides they follow and the albedo to multiply back.
#[derive(Clone, Debug, PartialEq)]
pub struct Prepared {
    pub width: u32,
    pub height: u32,
    /// Each pixel's illumination (linear colour / albedo) and the variance of its mean
    /// luminance.
    pub image: Vec<[f32; 4]>,
    /// Each pixel's mean normal and the mean depth of its hits, where most of its samples hit
    /// ([`guide_hit`]); 0 and -1 elsewhere.
    pub guide: Vec<[f32; 4]>,
    /// What each pixel was divided by ([`demodulation`]).
    pub albedo: Vec<[f32; 3]>,
}

/// A denoised frame's linear image and what it cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Denoised {
    pub linear: Vec<[f32; 3]>,
    /// Wall seconds, the preparation and the passes (on the GPU: upload, passes, readback).
    pub seconds: f64,
    /// The passes' GPU time, where they ran on a GPU with timestamps.
    pub gpu_seconds: Option<f64>,
    /// "gpu" or "cpu".
    pub backend: &'static str,
}

/// What a pixel's colour is divided by: h A + (1 - h), of its albedo AOV A (the mean over its
/// hits, each channel at least [`ALBEDO_FLOOR`]) and its hit fraction h ([`hit_fraction`]).
/// The mean of its samples' own albedos, a miss's taken as 1: the sky seen past a silhouette
/// is not divided by the surface's colour. 1 where none hit.
pub fn demodulation(albedo: [f32; 3], hit_fraction: f32) -> [f32; 3] {
    let h = hit_fraction;
    albedo.map(|a| h * a.max(ALBEDO_FLOOR) + (1.0 - h))
}

/// The fraction of the samples a pixel took (`samples`; adaptively, its AOVs' hits are taken to
/// those: trace.wgsl's `finish_aovs`) whose primary ray hit, from the AOVs' count of them; in
/// [0, 1], 0 without samples.
pub fn hit_fraction(hits: f32, samples: u32) -> f32 {
    match samples {
        0 => 0.0,
        n => (hits / n as f32).clamp(0.0, 1.0),
    }
}

/// Whether the guide takes a pixel as a hit: where at least half of its samples hit
/// ([`hit_fraction`]); the filter mixes no hit with a miss.
pub fn guide_hit(hit_fraction: f32) -> bool {
    hit_fraction >= 0.5
}

fn vec3(v: [f32; 3]) -> Vec3<f32> {
    Vec3::new(v[0], v[1], v[2])
}

/// The variance of the mean luminance of a pixel of `samples` samples whose luminances' squared
/// deviations sum to `m2`: m2 / (n (n - 1)).
pub fn mean_variance(m2: f32, samples: u32) -> f32 {
    let n = samples as f32;
    (m2 / (n * (n - 1.0))).max(0.0)
}

pub use crate::cpu::trace::NOISE_LUMINANCE_FLOOR;

/// Where a pixel has one sample, its variance is estimated from its neighbours: the variance of
/// the luminances of the pixels within 2 of it (itself included) that the guide takes as it
/// takes it (hit or missed, [`guide_hit`]: with one sample, whether that sample hit).
pub const SPATIAL_RADIUS: i32 = 2;

fn spatial_variance(luma: &[f32], hit: &[bool], (w, h): (usize, usize), i: usize, j: usize) -> f32 {
    let (mut sum, mut squares, mut n) = (0.0f64, 0.0f64, 0.0f64);
    let centre = hit[j * w + i];
    for dy in -SPATIAL_RADIUS..=SPATIAL_RADIUS {
        for dx in -SPATIAL_RADIUS..=SPATIAL_RADIUS {
            let (x, y) = (i as i32 + dx, j as i32 + dy);
            if x < 0 || y < 0 || x >= w as i32 || y >= h as i32 {
                continue;
            }
            let k = y as usize * w + x as usize;
            if hit[k] != centre {
                continue;
            }
            let l = luma[k] as f64;
            sum += l;
            squares += l * l;
            n += 1.0;
        }
    }
    let mean = sum / n;
    (squares / n - mean * mean).max(0.0) as f32
}

/// A whole frame (rendered with its AOVs, [`crate::Readback::Hdr`]) of `samples` samples a
/// pixel (`image.samples`; [`Frame::samples`] where adaptive sampling took fewer),
/// ready for the passes.
pub fn prepare(frame: &Frame, samples: u32) -> Prepared {
    let pixels = frame.pixel_count();
    let linear = frame.linear();
    assert!(
        linear.len() == pixels
            && frame.albedo.len() == pixels
            && frame.normal.len() == pixels
            && frame.luminance_m2.len() == pixels
            && frame.hits.len() == pixels
            && frame.hit_depth.len() == pixels,
        "the denoiser needs the AOVs (Readback::Hdr)"
    );
    let (w, h) = (frame.width as usize, frame.height as usize);
    // Each pixel's hit fraction, of the samples it took (an adaptive pixel's hits are taken to
    // those: trace.wgsl's `finish_aovs`).
    let fraction: Vec<f32> = (0..pixels)
        .into_par_iter()
        .map(|k| hit_fraction(frame.hits[k], frame.samples_of(k, samples)))
        .collect();
    let albedo: Vec<[f32; 3]> = (0..pixels)
        .into_par_iter()
        .map(|k| demodulation(frame.albedo[k], fraction[k]))
        .collect();
    let hit: Vec<bool> = fraction.par_iter().map(|&f| guide_hit(f)).collect();
    let variance: Vec<f32> = if samples >= 2 {
        // Each pixel's own count: adaptive sampling stops pixels at different ones (and takes
        // its M2 to the count it took: trace.wgsl's `finish_aovs`).
        frame
            .luminance_m2
            .par_iter()
            .enumerate()
            .map(|(k, &m2)| mean_variance(m2, frame.samples_of(k, samples)))
            .collect()
    } else {
        let luma: Vec<f32> = linear.par_iter().map(|&c| luminance(vec3(c))).collect();
        (0..pixels)
            .into_par_iter()
            .map(|k| spatial_variance(&luma, &hit, (w, h), k % w, k / w))
            .collect()
    };
    let image = (0..pixels)
        .into_par_iter()
        .map(|k| {
            let (c, a) = (linear[k], albedo[k]);
            // The illumination's luminance varies as the colour's over the albedo's squared.
            let scale = luminance(vec3(a));
            [
                c[0] / a[0],
                c[1] / a[1],
                c[2] / a[2],
                variance[k] / (scale * scale),
            ]
        })
        .collect();
    let guide = (0..pixels)
        .into_par_iter()
        .map(|k| match hit[k] {
            true => {
                let n = frame.normal[k];
                [n[0], n[1], n[2], frame.hit_depth[k]]
            }
            false => [0.0, 0.0, 0.0, -1.0],
        })
        .collect();
    Prepared {
        width: frame.width,
        height: frame.height,
        image,
        guide,
        albedo,
    }
}

/// The passes of `scene`'s `[denoise]` over an image of `width` x `height`: pass k's taps lie
/// 2^k pixels apart.
pub fn passes(scene: &Scene, width: u32, height: u32) -> Vec<DenoiseParams> {
    let d = &scene.denoise;
    (0..d.iterations)
        .map(|k| DenoiseParams {
            width,
            height,
            step: 1 << k,
            sigma_luminance: d.sigma_luminance as f32,
            sigma_normal: d.sigma_normal as f32,
            sigma_depth: d.sigma_depth as f32,
        })
        .collect()
}

/// The passes on the CPU twin, one after another.
pub fn run_cpu(
    passes: &[DenoiseParams],
    image: Vec<[f32; 4]>,
    guide: &[[f32; 4]],
) -> Vec<[f32; 4]> {
    passes.iter().fold(image, |source, &params| {
        Pass {
            params,
            source: &source,
            guide,
        }
        .atrous_pass()
    })
}

/// The filtered illumination times the albedo it was divided by.
pub fn finish(image: &[[f32; 4]], albedo: &[[f32; 3]]) -> Vec<[f32; 3]> {
    image
        .par_iter()
        .zip(albedo)
        .map(|(v, a)| [v[0] * a[0], v[1] * a[1], v[2] * a[2]])
        .collect()
}

/// Phong mode's packed colours of a denoised linear image: each channel clamped to [0, 1],
/// times 255, rounded half up, as the tracer packs its mean (no curve).
pub fn pack_phong(linear: &[[f32; 3]]) -> Vec<u32> {
    linear
        .par_iter()
        .map(|&c| crate::cpu::trace::pack_colour(vec3(c)))
        .collect()
}

/// `scene`'s denoiser over a whole `frame` (with its AOVs): on `gpu` where there is one and the
/// image fits its buffers, else on the CPU.
#[cfg(feature = "gpu")]
pub fn denoise(
    frame: &Frame,
    scene: &Scene,
    gpu: Option<&GpuKernels>,
) -> crate::error::Result<Denoised> {
    let start = std::time::Instant::now();
    let prepared = prepare(frame, scene.image.samples);
    let passes = passes(scene, frame.width, frame.height);
    let (image, gpu_seconds, backend) = match gpu {
        Some(kernels) => {
            let denoiser = kernels.denoiser()?;
            match denoiser.fits(prepared.image.len() as u64) {
                true => {
                    let run = denoiser.run(&passes, &prepared.image, &prepared.guide)?;
                    (run.image, run.gpu_seconds, "gpu")
                }
                false => (
                    run_cpu(&passes, prepared.image, &prepared.guide),
                    None,
                    "cpu",
                ),
            }
        }
        None => (
            run_cpu(&passes, prepared.image, &prepared.guide),
            None,
            "cpu",
        ),
    };
    Ok(Denoised {
        linear: finish(&image, &prepared.albedo),
        seconds: start.elapsed().as_secs_f64(),
        gpu_seconds,
        backend,
    })
}

/// [`denoise`], and where `frame` has its halves (path mode) the denoised image's estimated
/// error: each half denoised alone too ([`crate::estimate::denoised`]). The seconds are the
/// three runs' wall time; the GPU seconds, the whole image's run's.
#[cfg(feature = "gpu")]
pub fn denoise_estimated(
    frame: &Frame,
    scene: &Scene,
    gpu: Option<&GpuKernels>,
) -> crate::error::Result<(Denoised, Option<crate::estimate::ErrorEstimate>)> {
    let start = std::time::Instant::now();
    let mut denoised = denoise(frame, scene, gpu)?;
    let estimate = match crate::estimate::half_frames(frame) {
        Some([a, b]) => {
            let da = denoise(&a, scene, gpu)?.linear;
            let db = denoise(&b, scene, gpu)?.linear;
            crate::estimate::denoised(&frame.halves, [&da, &db], &denoised.linear)
        }
        None => None,
    };
    denoised.seconds = start.elapsed().as_secs_f64();
    Ok((denoised, estimate))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_demodulation_is_the_mean_albedo_of_the_samples_a_miss_counting_1() {
        // Half the samples hit an orange surface: the sky's half is not divided by its colour.
        let d = demodulation([0.9, 0.3, 0.0], 0.5);
        assert_eq!(d, [0.95, 0.65, 0.5 * ALBEDO_FLOOR + 0.5]);
        assert_eq!(demodulation([0.9, 0.3, 0.0], 1.0), [0.9, 0.3, ALBEDO_FLOOR]);
        assert_eq!(demodulation([0.0; 3], 0.0), [1.0; 3]);
        assert_eq!(hit_fraction(3.0, 4), 0.75);
        assert_eq!(hit_fraction(0.0, 0), 0.0);
    }

    #[test]
    fn the_guide_is_the_mean_depth_of_the_hits_where_most_samples_hit() {
        let mut frame = Frame::empty(3);
        frame.height = 1;
        frame.radiance = vec![[0.5; 3]; 3];
        frame.albedo = vec![[0.5; 3]; 3];
        frame.normal = vec![[0.0, 0.0, 1.0]; 3];
        frame.luminance_m2 = vec![0.0; 3];
        // 4 of 4 samples hit at a mean depth of 2.5 (the pinhole ray's is 2), 2 of 4 at 3, 1 of 4.
        frame.depth = vec![2.0, f32::NAN, 3.0];
        frame.hits = vec![4.0, 2.0, 1.0];
        frame.hit_depth = vec![2.5, 3.0, 3.5];
        let prepared = prepare(&frame, 4);
        let depths: Vec<f32> = prepared.guide.iter().map(|g| g[3]).collect();
        assert_eq!(depths, [2.5, 3.0, -1.0]);
        assert_eq!(prepared.albedo[1], [0.75; 3]);
        assert_eq!(prepared.albedo[2], [0.875; 3]);
    }
}
