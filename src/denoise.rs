//! The denoiser (`image.denoise`, the `[denoise]` table): an edge-avoiding a-trous wavelet
//! filter (Dammertz et al. 2010) with SVGF's edge-stopping functions and variance (Schied et
//! al. 2017), on the linear image of a whole frame before the display transform, in either
//! model. This module owns the filter's steps around the passes:
//!
//! 1. [`prepare`]: each pixel's linear colour divided by its demodulation, h A + (1 - h) of its
//!    albedo AOV A and hit fraction h (the illumination), the variance of its mean luminance
//!    (from the AOVs' Welford M2), and its guide (the mean normal and the mean depth of its
//!    hits, where most of its samples hit); in path mode with a specular lobe, [`prepare_split`]
//!    makes two signals of it, the first hits' specular direct light over the lobes'
//!    reflectance ([`specular_reflectance`]) and the rest over the albedo;
//! 2. the passes, on the GPU (src/gpu/denoise.rs over shaders/denoise.wgsl) or on the CPU
//!    (its twin, src/cpu/denoise.rs), each signal its own ([`passes`], [`specular_passes`]);
//! 3. [`finish`]: the illumination times the albedo (the reflectance) again, the signals
//!    added.
//!
//! The book's chapter "Denoising" (docs/book/denoise.md) gives every formula.

use rayon::prelude::*;

use crate::algebra::Vec3;
use crate::cpu::bsdf::{
    Material, fresnel_schlick, has_specular_lobe, material_f0, multiscatter_average,
    multiscatter_fresnel,
};
use crate::cpu::denoise::{DenoiseParams, Pass, luminance};
use crate::cpu::ggx_albedo::ggx_albedo;
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
/// those: accumulate.wgsl's `finish_aovs`) whose primary ray hit, from the AOVs' count of them; in
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
/// ready for the passes as one signal (what [`prepare_split`] gives where the frame has no
/// specular signal).
pub fn prepare(frame: &Frame, samples: u32) -> Prepared {
    prepare_signals(frame, samples, None).diffuse
}

/// The frame's two signals, each ready for its own passes: the diffuse one (the linear colour
/// less the specular signal, over its albedo, as [`prepare`] makes it) and, where the frame
/// has a specular signal ([`Frame::specular`], path mode) and `scene`'s material a specular
/// lobe, the specular one ([`specular_reflectance`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    pub diffuse: Prepared,
    pub specular: Option<Prepared>,
}

/// `scene`'s material of the first hit, its albedo black (each pixel's is its AOV's).
pub fn scene_material(scene: &Scene) -> Material<f32> {
    let m = &scene.material;
    Material {
        albedo: Vec3::new(0.0, 0.0, 0.0),
        roughness: m.roughness as f32,
        metallic: m.metallic as f32,
        specular: m.specular as f32,
        multiscatter: m.multiscatter,
    }
}

/// [`prepare`], split in two signals where `frame` and `scene` have two ([`Split`]).
pub fn prepare_split(frame: &Frame, scene: &Scene, samples: u32) -> Split {
    let material = scene_material(scene);
    let split = frame.specular.len() == frame.pixel_count()
        && frame.view_cosine.len() == frame.pixel_count()
        && has_specular_lobe(material);
    prepare_signals(frame, samples, split.then_some(material))
}

/// A reflectance channel below this divides the specular signal as this.
pub const REFLECTANCE_FLOOR: f32 = 1e-3;

/// The pre-integrated reflectance of `material`'s specular lobes (its albedo the pixel's) seen
/// at a cosine `mu` to the normal: Schlick's Fresnel at mu times the white GGX lobe's
/// directional albedo E(mu) ([`ggx_albedo`], shaders/ggx_albedo.wgsl's table), plus, with the
/// multiple-scattering lobe, its directional albedo F_ms (1 - E(mu)). The denoiser divides the
/// specular signal by it (times the hit fraction), as it divides the diffuse one by the albedo.
pub fn specular_reflectance(material: Material<f32>, mu: f32) -> [f32; 3] {
    if !has_specular_lobe(material) {
        return [0.0; 3];
    }
    let mu = mu.clamp(0.0, 1.0);
    let e = ggx_albedo(mu, material.roughness);
    let mut r = fresnel_schlick(material_f0(material), mu) * e;
    let e_avg = multiscatter_average(material);
    if e_avg < 1.0 {
        r += multiscatter_fresnel(material, e_avg) * (1.0 - e);
    }
    [r.x, r.y, r.z]
}

/// The samples from which the specular passes' normal weight is the lobe's
/// ([`specular_passes`]).
pub const SPECULAR_LOBE_SAMPLES: u32 = 16;

/// The passes of the specular signal: `scene`'s `[denoise]` passes ([`passes`]), fewer where
/// the lobe is narrow, ceil(iterations min(1, 2 roughness)) and at least 1; from
/// [`SPECULAR_LOBE_SAMPLES`] samples (`image.samples`) on, each with a normal weight from the
/// lobe's width, sigma_normal at least 4 / alpha^2 (alpha = GGX's, roughness squared, held at
/// ROUGHNESS_MIN at least). A reflected direction turns twice as fast as the normal and the
/// lobe is about alpha wide, so 4 / alpha^2 keeps apart the pixels that reflect different
/// light. With fewer samples a pixel's own specular mean is too noisy to keep so apart: on the
/// path-traced preset at 4 samples the lobe's weight cost 10% in RMSE, at 16 it saved 3%
/// (docs/book/denoise.md).
pub fn specular_passes(scene: &Scene, width: u32, height: u32) -> Vec<DenoiseParams> {
    let roughness = scene
        .material
        .roughness
        .max(crate::cpu::bsdf::ROUGHNESS_MIN);
    let alpha = roughness * roughness;
    let keep =
        ((scene.denoise.iterations as f64 * (2.0 * roughness).min(1.0)).ceil() as usize).max(1);
    let lobe = match scene.image.samples >= SPECULAR_LOBE_SAMPLES {
        true => (4.0 / (alpha * alpha)) as f32,
        false => 0.0,
    };
    let mut passes = passes(scene, width, height);
    passes.truncate(keep);
    for p in &mut passes {
        p.sigma_normal = p.sigma_normal.max(lobe);
    }
    passes
}

fn prepare_signals(frame: &Frame, samples: u32, split: Option<Material<f32>>) -> Split {
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
    // those: accumulate.wgsl's `finish_aovs`).
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
        // its M2 to the count it took: accumulate.wgsl's `finish_aovs`).
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
    // Each pixel's specular light, where the signals split and the guide takes it as a hit (a
    // missed pixel's light is all diffuse), at most its colour.
    let specular: Vec<[f32; 3]> = match split {
        Some(_) => (0..pixels)
            .into_par_iter()
            .map(|k| match hit[k] {
                true => std::array::from_fn(|c| frame.specular[k][c].clamp(0.0, linear[k][c])),
                false => [0.0; 3],
            })
            .collect(),
        None => Vec::new(),
    };
    // A signal's illumination (its light over its demodulation) and variance: the colour's,
    // times the signal's share of the colour's luminance (a half where the colour is black),
    // over the demodulation's luminance squared.
    let signal = |c: [f32; 3], a: [f32; 3], share: f32, variance: f32| {
        let scale = luminance(vec3(a));
        [
            c[0] / a[0],
            c[1] / a[1],
            c[2] / a[2],
            variance * share / (scale * scale),
        ]
    };
    let share = |part: [f32; 3], k: usize| {
        let total = luminance(vec3(linear[k]));
        match total > 0.0 {
            true => (luminance(vec3(part)) / total).clamp(0.0, 1.0),
            false => 0.5,
        }
    };
    let image = (0..pixels)
        .into_par_iter()
        .map(|k| {
            let c = match specular.get(k) {
                Some(s) => std::array::from_fn(|i| linear[k][i] - s[i]),
                None => linear[k],
            };
            let share = if specular.is_empty() {
                1.0
            } else {
                share(c, k)
            };
            signal(c, albedo[k], share, variance[k])
        })
        .collect();
    let guide: Vec<[f32; 4]> = (0..pixels)
        .into_par_iter()
        .map(|k| match hit[k] {
            true => {
                let n = frame.normal[k];
                [n[0], n[1], n[2], frame.hit_depth[k]]
            }
            false => [0.0, 0.0, 0.0, -1.0],
        })
        .collect();
    let specular = split.map(|material| {
        let reflectance: Vec<[f32; 3]> = (0..pixels)
            .into_par_iter()
            .map(|k| {
                let albedo = vec3(frame.albedo[k]);
                let r = specular_reflectance(Material { albedo, ..material }, frame.view_cosine[k]);
                r.map(|r| (fraction[k] * r).max(REFLECTANCE_FLOOR))
            })
            .collect();
        let image = (0..pixels)
            .into_par_iter()
            .map(|k| {
                signal(
                    specular[k],
                    reflectance[k],
                    share(specular[k], k),
                    variance[k],
                )
            })
            .collect();
        Prepared {
            width: frame.width,
            height: frame.height,
            image,
            guide: guide.clone(),
            albedo: reflectance,
        }
    });
    Split {
        diffuse: Prepared {
            width: frame.width,
            height: frame.height,
            image,
            guide,
            albedo,
        },
        specular,
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
    let split = prepare_split(frame, scene, scene.image.samples);
    let (width, height) = (frame.width, frame.height);
    let mut signals = vec![(passes(scene, width, height), split.diffuse)];
    if let Some(specular) = split.specular {
        signals.push((specular_passes(scene, width, height), specular));
    }
    let mut linear: Vec<[f32; 3]> = Vec::new();
    let (mut gpu_seconds, mut backend) = (None, "cpu");
    for (passes, prepared) in signals {
        let denoiser = gpu
            .map(|kernels| kernels.denoiser())
            .transpose()?
            .filter(|d| d.fits(prepared.image.len() as u64));
        let image = match denoiser {
            Some(denoiser) => {
                let run = denoiser.run(&passes, &prepared.image, &prepared.guide)?;
                if let Some(s) = run.gpu_seconds {
                    gpu_seconds = Some(gpu_seconds.unwrap_or(0.0) + s);
                }
                backend = "gpu";
                run.image
            }
            None => run_cpu(&passes, prepared.image, &prepared.guide),
        };
        let signal = finish(&image, &prepared.albedo);
        linear = match linear.is_empty() {
            true => signal,
            false => linear
                .par_iter()
                .zip(&signal)
                .map(|(a, b)| std::array::from_fn(|c| a[c] + b[c]))
                .collect(),
        };
    }
    Ok(Denoised {
        linear,
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
    fn the_specular_reflectance_is_the_lobes_directional_albedo() {
        let m = |metallic: f32, specular: f32, multiscatter: bool| Material {
            albedo: Vec3::new(0.9, 0.6, 0.3),
            roughness: 0.25,
            metallic,
            specular,
            multiscatter,
        };
        // No specular lobe: nothing to divide by.
        assert_eq!(specular_reflectance(m(0.0, 0.0, true), 0.7), [0.0; 3]);
        // A metal seen face on, single scattering: F0 = its albedo, times E(1).
        let e = ggx_albedo(1.0f32, 0.25);
        let r = specular_reflectance(m(1.0, 0.5, false), 1.0);
        for (c, a) in r.iter().zip([0.9f32, 0.6, 0.3]) {
            assert!((c - a * e).abs() < 1e-6, "{r:?}");
        }
        // The multiple-scattering lobe only adds light; a dielectric reflects more at grazing.
        let with = specular_reflectance(m(1.0, 0.5, true), 0.5);
        let without = specular_reflectance(m(1.0, 0.5, false), 0.5);
        assert!((0..3).all(|c| with[c] > without[c]), "{with:?} {without:?}");
        let face_on = specular_reflectance(m(0.0, 0.5, false), 1.0)[1];
        assert!(specular_reflectance(m(0.0, 0.5, false), 0.1)[1] > face_on);
        assert!(face_on > 0.0 && face_on < 0.04 + 1e-6, "{face_on}");
    }

    #[test]
    fn the_two_signals_add_back_to_the_colour() {
        let mut frame = Frame::empty(4);
        frame.height = 1;
        frame.radiance = vec![[0.5, 0.4, 0.3], [0.2; 3], [0.0; 3], [0.6, 0.2, 0.1]];
        frame.albedo = vec![[0.8, 0.5, 0.2]; 4];
        frame.normal = vec![[0.0, 0.0, 1.0]; 4];
        frame.luminance_m2 = vec![0.3; 4];
        frame.hits = vec![4.0, 4.0, 4.0, 1.0];
        frame.hit_depth = vec![2.0; 4];
        // Pixel 1's specular light is more than its colour (an adaptive mean's halves can
        // leave it so): it is held at the colour. Pixel 3 is a miss to the guide: all diffuse.
        frame.specular = vec![[0.1, 0.05, 0.02], [0.3; 3], [0.0; 3], [0.1; 3]];
        frame.view_cosine = vec![0.8, 0.3, 0.5, 0.9];
        let scene = crate::scene::presets::find("path-traced").unwrap().scene();
        let split = prepare_split(&frame, &scene, 4);
        let specular = split.specular.expect("a glossy material splits");
        let d = finish(&split.diffuse.image, &split.diffuse.albedo);
        let s = finish(&specular.image, &specular.albedo);
        let expected_specular = [[0.1, 0.05, 0.02], [0.2; 3], [0.0; 3], [0.0; 3]];
        for k in 0..4 {
            for c in 0..3 {
                let sum = d[k][c] + s[k][c];
                assert!(
                    (sum - frame.radiance[k][c]).abs() < 1e-6,
                    "pixel {k}: {sum}"
                );
                assert!(
                    (s[k][c] - expected_specular[k][c]).abs() < 1e-6,
                    "pixel {k}"
                );
            }
        }
        // The variance splits by the signals' shares of the luminance (before demodulation).
        let share = luminance(vec3(expected_specular[0])) / luminance(vec3(frame.radiance[0]));
        let scale = luminance(vec3(specular.albedo[0]));
        let v = mean_variance(0.3, 4) * share / (scale * scale);
        assert!(
            (specular.image[0][3] - v).abs() <= 1e-6 * v,
            "{}",
            specular.image[0][3]
        );
        // Phong mode (no specular light) and a material without a specular lobe do not split.
        let mut lambert = scene.clone();
        lambert.material.specular = 0.0;
        assert!(prepare_split(&frame, &lambert, 4).specular.is_none());
        frame.specular.clear();
        assert!(prepare_split(&frame, &scene, 4).specular.is_none());
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
