//! Adaptive sampling's figures (issue 20), on the GPU:
//!
//! - `lanes [SIZE] [SAMPLES] [TARGET]`: renders the path-traced preset adaptively and, from the
//!   samples each pixel took, counts the SIMD lanes each sample index keeps busy with the
//!   kernels' early-out (a group of W lanes runs while any of its pixels is live) against
//!   compaction within each 8x8 workgroup (its live pixels packed into the first lanes) and
//!   against the live pixels alone, for W = 8 (lavapipe) and 32 (a GPU's warp).
//! - `rmse [SIZE] [REF]`: the time (GPU seconds, the denoiser's included) to the RMSE of 1,024
//!   plain Sobol' samples against a reference of REF samples of the `random` sampler, for plain
//!   Sobol', adaptive sampling (1,024 at most, the noise target swept down), the denoiser
//!   (samples swept up), both, path regularisation (`path.regularize` = 0.5, samples swept up)
//!   and regularisation denoised, and `image.target_error` asked for the goal (relative to the
//!   reference's mean) and a little under it, alone, denoised, regularised and both; each rung
//!   with its bias, the image's mean radiance against the reference's.
//! - `mse REF_A.exr REF_B.exr RUN.exr...`: each run's mean squared error (linear R, G and B, over
//!   every channel and pixel) against the mean of two references of independent seeds, less
//!   that mean's own, a quarter of the squared difference of the two
//!   (scripts/adaptive_efficiency.sh, issue 49's efficiency).
//!
//! Run as:
//!
//!     cargo run --release --example adaptive_study -- lanes 128 256 0.05
//!     cargo run --release --example adaptive_study -- rmse 128 4096
//!     cargo run --release --example adaptive_study -- mse ref-a.exr ref-b.exr run.exr

use std::sync::Arc;

use qjulia::denoise::Denoiser;
use qjulia::gpu::{GpuContext, GpuKernels};
use qjulia::report::monte_carlo::{REGULARIZE, TRIM, image_mean, rmse, rmse_trimmed};
use qjulia::scene::PathSampler;
use qjulia::scene::presets::find;
use qjulia::stats::RenderStats;
use qjulia::{Backend, Frame, Picture, Planner, PrecisionChoice, Readback, Renderer, Scene};

fn main() -> qjulia::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("mse") && args.len() >= 3 {
        return excess_mse(&args[1], &args[2], &args[3..]);
    }
    let arg = |k: usize, d: f64| args.get(k).and_then(|a| a.parse().ok()).unwrap_or(d);
    let kernels = Arc::new(GpuKernels::new(GpuContext::new()?));
    let renderer = Planner::on_device(kernels, Backend::Gpu, PrecisionChoice::F32)
        .plan(&preset(8, 1), Picture::SHADED.into(), &mut |_| {})?
        .renderer;
    match args.first().map(String::as_str) {
        Some("lanes") => lanes(
            &renderer,
            arg(1, 128.0) as u32,
            arg(2, 256.0) as u32,
            arg(3, 0.05),
        ),
        Some("rmse") => time_to_rmse(&renderer, arg(1, 128.0) as u32, arg(2, 4096.0) as u32),
        _ => {
            eprintln!(
                "usage: adaptive_study lanes [SIZE] [SAMPLES] [TARGET] | rmse [SIZE] [REF] | \
                 mse REF_A.exr REF_B.exr RUN.exr..."
            );
            Ok(())
        }
    }
}

/// An EXR's linear R, G and B, row by row.
fn read_rgb(path: &str) -> qjulia::Result<Vec<[f32; 3]>> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| {
                let (w, h) = (resolution.width(), resolution.height());
                (w, vec![[0.0f32; 3]; w * h])
            },
            |(width, texels), position, (r, g, b, _a): (f32, f32, f32, f32)| {
                texels[position.y() * *width + position.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| qjulia::Error::Unsupported(format!("{path}: {e}")))?;
    Ok(image.layer_data.channel_data.pixels.1)
}

/// Prints each run's excess mean squared error (the module's `mse`), one line each: the file and
/// the figure.
fn excess_mse(reference_a: &str, reference_b: &str, runs: &[String]) -> qjulia::Result<()> {
    let (a, b) = (read_rgb(reference_a)?, read_rgb(reference_b)?);
    let n = (a.len() * 3) as f64;
    let channels = |p: &[[f32; 3]]| p.iter().flatten().map(|&v| v as f64).collect::<Vec<_>>();
    let (a, b) = (channels(&a), channels(&b));
    let reference: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 0.5 * (x + y)).collect();
    let own = a.iter().zip(&b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n / 4.0;
    println!("reference {reference_a} {reference_b}: its own mse {own:.6e}");
    for run in runs {
        let values = channels(&read_rgb(run)?);
        assert_eq!(
            values.len(),
            reference.len(),
            "{run}: not the references' size"
        );
        let mse = values
            .iter()
            .zip(&reference)
            .map(|(v, r)| (v - r).powi(2))
            .sum::<f64>()
            / n;
        println!("{run} {:.6e}", mse - own);
    }
    Ok(())
}

/// The path-traced preset at `size` x `size` and `samples`.
fn preset(size: u32, samples: u32) -> Scene {
    let mut s = find("path-traced").expect("the preset").scene();
    s.image.width = size;
    s.image.height = size;
    s.image.samples = samples;
    s
}

/// The whole frame of `scene` with its AOVs, its stats, and its seconds: GPU time where the
/// device has timestamps, the denoiser's added.
fn render(renderer: &Renderer, scene: &Scene) -> qjulia::Result<(Frame, RenderStats, f64)> {
    let mut frame = Frame::empty(scene.image.width);
    let stats = renderer.render_with(scene, Picture::SHADED, Readback::Hdr, &mut |band| {
        frame.append(band);
        Ok(())
    })?;
    let denoise = stats
        .denoise
        .as_ref()
        .map_or(0.0, |d| d.gpu_seconds.unwrap_or(d.seconds));
    let seconds = stats.gpu_seconds.unwrap_or(stats.render_seconds) + denoise;
    Ok((frame, stats, seconds))
}

fn lanes(renderer: &Renderer, size: u32, samples: u32, target: f64) -> qjulia::Result<()> {
    let mut scene = preset(size, samples);
    scene.path.noise_target = target;
    let (frame, stats, seconds) = render(renderer, &scene)?;
    let (w, h) = (size as usize, size as usize);
    let total = stats.summary.samples_total;
    println!(
        "path-traced {size}x{size}, at most {samples} samples, target {target}: {total} samples \
         ({:.1}% of {}), {seconds:.3} s",
        100.0 * total as f64 / (w * h) as f64 / samples as f64,
        w * h * samples as usize
    );
    for width in [8usize, 32] {
        // Lane-samples paid: the early-out runs a group of `width` lanes (consecutive
        // invocations of an 8x8 workgroup, row by row) at sample k while any of its pixels is
        // live; compaction packs a workgroup's live pixels into its first lanes.
        let (mut early, mut compact, mut live) = (0u64, 0u64, 0u64);
        for k in 0..samples {
            for by in (0..h).step_by(8) {
                for bx in (0..w).step_by(8) {
                    let mut in_group = [0u64; 64];
                    let mut count = 0;
                    for l in 0..64 {
                        let (x, y) = (bx + l % 8, by + l / 8);
                        if x < w && y < h && frame.samples[y * w + x] > k {
                            in_group[l / width] += 1;
                            count += 1;
                        }
                    }
                    early += in_group.iter().filter(|&&n| n > 0).count() as u64 * width as u64;
                    compact += (count as u64).div_ceil(width as u64) * width as u64;
                    live += count as u64;
                }
            }
        }
        println!(
            "{width} lanes: early-out pays {early} lane-samples, compaction within the \
             workgroup {compact} ({:.3}x), the live pixels alone {live} ({:.3}x)",
            compact as f64 / early as f64,
            live as f64 / early as f64
        );
    }
    Ok(())
}

fn time_to_rmse(renderer: &Renderer, size: u32, reference_samples: u32) -> qjulia::Result<()> {
    let mut reference_scene = preset(size, reference_samples);
    reference_scene.path.sampler = PathSampler::Random;
    let (reference, _, reference_seconds) = render(renderer, &reference_scene)?;
    let reference = reference.radiance;
    let reference_mean = image_mean(&reference);
    println!(
        "reference: {reference_samples} random samples, {reference_seconds:.2} s, mean \
         {reference_mean:.5}"
    );
    // RMSE, trimmed RMSE, seconds, samples taken (the last pass's, to a target), the mean's
    // bias in percent, and to a target its passes' samples.
    type Measured = (f64, f64, f64, u64, f64, String);
    let measure = |scene: &Scene| -> qjulia::Result<Measured> {
        let (frame, stats, seconds) = render(renderer, scene)?;
        let error = rmse(&frame.radiance, &reference);
        let trimmed = rmse_trimmed(&frame.radiance, &reference, TRIM);
        let bias = 100.0 * (image_mean(&frame.radiance) / reference_mean - 1.0);
        let passes = stats.target.as_ref().map_or(String::new(), |t| {
            let samples: Vec<String> = t
                .target_passes
                .iter()
                .map(|p| p.samples.to_string())
                .collect();
            format!(
                ", passes {} (stopped by {})",
                samples.join(" "),
                t.stopped_by
            )
        });
        Ok((
            error,
            trimmed,
            seconds,
            stats.summary.samples_total,
            bias,
            passes,
        ))
    };
    let (goal, goal_trimmed, plain_seconds, _, plain_bias, _) = measure(&preset(size, 1024))?;
    println!(
        "plain Sobol', 1024 samples: RMSE {goal:.5} (trimmed {goal_trimmed:.5}), \
         {plain_seconds:.2} s, mean {plain_bias:+.3}%"
    );
    // Each way's ladder, cheapest first; its time is that of the first rung at the goal.
    let targets = [
        0.2, 0.14, 0.1, 0.07, 0.05, 0.035, 0.025, 0.018, 0.0125, 0.009, 0.0064,
    ];
    let ladder_samples = [16, 32, 64, 128, 256, 512, 1024];
    type Rung = (String, Scene);
    let adaptive = |denoise: bool| -> Vec<Rung> {
        targets
            .iter()
            .map(|&t| {
                let mut s = preset(size, 1024);
                s.path.noise_target = t;
                if denoise {
                    s.image.denoise = Denoiser::Atrous;
                }
                (format!("target {t}"), s)
            })
            .collect()
    };
    let swept = |denoise: bool, regularize: f64| -> Vec<Rung> {
        ladder_samples
            .iter()
            .map(|&n| {
                let mut s = preset(size, n);
                if denoise {
                    s.image.denoise = Denoiser::Atrous;
                }
                s.path.regularize = regularize;
                (format!("{n} samples"), s)
            })
            .collect()
    };
    // `image.target_error` asked for the goal itself, relative to the reference's mean (what a
    // user who knows the error they want would ask), then a little under it: each rung one
    // render of passes, its seconds all of them, at most 4,096 samples.
    let relative_goal = goal / reference_mean;
    let to_target = |denoise: bool, regularize: f64| -> Vec<Rung> {
        [1.0, 0.9, 0.8, 0.7]
            .iter()
            .map(|&f| {
                let mut s = preset(size, 4096);
                s.image.target_error = relative_goal * f;
                if denoise {
                    s.image.denoise = Denoiser::Atrous;
                }
                s.path.regularize = regularize;
                (format!("target_error {:.5}", relative_goal * f), s)
            })
            .collect()
    };
    for (way, ladder) in [
        ("adaptive", adaptive(false)),
        ("denoised", swept(true, 0.0)),
        ("adaptive + denoised", adaptive(true)),
        ("regularized", swept(false, REGULARIZE)),
        ("regularized + denoised", swept(true, REGULARIZE)),
        ("to a target", to_target(false, 0.0)),
        ("to a target, denoised", to_target(true, 0.0)),
        ("to a target, regularized", to_target(false, REGULARIZE)),
        (
            "to a target, regularized + denoised",
            to_target(true, REGULARIZE),
        ),
    ] {
        let mut reached = None;
        for (rung, scene) in &ladder {
            let (error, trimmed, seconds, total, bias, passes) = measure(scene)?;
            println!(
                "  {way}, {rung}: RMSE {error:.5} (trimmed {trimmed:.5}), {seconds:.3} s, \
                 {:.1} samples a pixel, mean {bias:+.3}%{passes}",
                total as f64 / (size * size) as f64
            );
            if error <= goal {
                reached = Some((rung.clone(), seconds));
                break;
            }
        }
        match reached {
            Some((rung, seconds)) => println!(
                "{way}: reaches {goal:.5} at {rung} in {seconds:.3} s: {:.1}x less time than \
                 plain",
                plain_seconds / seconds
            ),
            None => println!("{way}: does not reach {goal:.5} on its ladder"),
        }
    }
    Ok(())
}
