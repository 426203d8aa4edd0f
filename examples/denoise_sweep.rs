//! Tuning the denoiser (issue 20): renders the path-traced preset once at SIZE and SAMPLES with
//! its AOVs on the GPU, and a reference of REF samples (the `random` sampler), then runs the
//! CPU twin's passes over the one prepared image for a grid of `[denoise]` settings and prints
//! each one's RMSE (plain and trimmed, as the Monte Carlo page) against the reference.
//!
//!     cargo run --release --example denoise_sweep [SIZE] [SAMPLES] [REF]

use std::sync::Arc;

use qjulia::denoise;
use qjulia::gpu::{GpuContext, GpuKernels};
use qjulia::report::monte_carlo::{TRIM, rmse, rmse_trimmed};
use qjulia::scene::PathSampler;
use qjulia::scene::presets::find;
use qjulia::{Backend, Frame, Picture, Planner, PrecisionChoice, Readback, Scene};

fn main() -> qjulia::Result<()> {
    let arg = |k: usize, d: u32| {
        std::env::args()
            .nth(k)
            .and_then(|a| a.parse().ok())
            .unwrap_or(d)
    };
    let (size, samples, reference_samples) = (arg(1, 64), arg(2, 16), arg(3, 1024));
    let kernels = Arc::new(GpuKernels::new(GpuContext::new()?));
    let scene = |samples: u32, sampler: PathSampler| -> Scene {
        let mut s = find("path-traced").expect("the preset").scene();
        s.image.width = size;
        s.image.height = size;
        s.image.samples = samples;
        s.path.sampler = sampler;
        s
    };
    let base = scene(samples, PathSampler::Sobol);
    let renderer = Planner::on_device(kernels, Backend::Gpu, PrecisionChoice::F32)
        .plan(&base, Picture::SHADED.into(), &mut |_| {})?
        .renderer;
    let render = |scene: &Scene| -> qjulia::Result<Frame> {
        let mut frame = Frame::empty(scene.image.width);
        renderer.render_with(scene, Picture::SHADED, Readback::Hdr, &mut |band| {
            frame.append(band);
            Ok(())
        })?;
        Ok(frame)
    };
    let reference_frame = render(&scene(reference_samples, PathSampler::Random))?;
    let reference = reference_frame.radiance.clone();
    let noisy = render(&base)?;
    let plain4 = render(&scene(4 * samples, PathSampler::Sobol))?.radiance;
    let figures = |image: &[[f32; 3]]| {
        format!(
            "{:.5} {:.5}",
            rmse(image, &reference),
            rmse_trimmed(image, &reference, TRIM)
        )
    };
    println!("plain {samples}: {}", figures(&noisy.radiance));
    println!("plain {}: {}", 4 * samples, figures(&plain4));
    // The denoiser's bias: the reference itself denoised (its noise is small).
    let mut reference_scene = base.clone();
    reference_scene.image.samples = reference_samples;
    let bias = denoise::denoise(&reference_frame, &reference_scene, None)?.linear;
    println!(
        "reference denoised (bias at the defaults): {}",
        figures(&bias)
    );
    if let Ok(dir) = std::env::var("PICTURES") {
        let display = qjulia::display::Display::of(&base);
        let denoised = denoise::denoise(&noisy, &base, None)?.linear;
        let error = |image: &[[f32; 3]]| -> Vec<[f32; 3]> {
            image
                .iter()
                .zip(&reference)
                .map(|(a, b)| [(0..3).map(|c| (a[c] - b[c]).abs()).sum::<f32>() * 4.0; 3])
                .collect()
        };
        let none = qjulia::display::Display::default();
        let pictures: [(&str, Vec<[f32; 3]>, qjulia::display::Display); 7] = [
            ("noisy", noisy.radiance.clone(), display),
            ("denoised", denoised.clone(), display),
            ("plain4x", plain4.clone(), display),
            ("reference", reference.clone(), display),
            ("error-noisy", error(&noisy.radiance), none),
            ("error-denoised", error(&denoised), none),
            ("error-plain4x", error(&plain4), none),
        ];
        for (name, image, display) in pictures {
            let path = format!("{dir}/sweep-{name}.png");
            image::save_buffer(
                &path,
                &display.rgb8(&image),
                size,
                size,
                image::ColorType::Rgb8,
            )
            .expect("a PNG");
        }
    }
    if std::env::var("SWEEP").is_err() {
        return Ok(());
    }
    let prepared = denoise::prepare(&noisy, samples);
    for iterations in [3, 5] {
        for sigma_luminance in [1.0, 2.0, 4.0] {
            for sigma_normal in [0.0, 4.0, 16.0, 32.0] {
                for sigma_depth in [0.0, 1.0, 4.0, 16.0] {
                    let mut s = base.clone();
                    s.denoise.iterations = iterations;
                    s.denoise.sigma_luminance = sigma_luminance;
                    s.denoise.sigma_normal = sigma_normal;
                    s.denoise.sigma_depth = sigma_depth;
                    let passes = denoise::passes(&s, size, size);
                    let image = denoise::run_cpu(&passes, prepared.image.clone(), &prepared.guide);
                    let linear = denoise::finish(&image, &prepared.albedo);
                    println!(
                        "it {iterations} l {sigma_luminance} n {sigma_normal} z {sigma_depth}: {}",
                        figures(&linear)
                    );
                }
            }
        }
    }
    Ok(())
}
