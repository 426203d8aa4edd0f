//! The error on request (issue 49, item 3): each render's `estimated_rmse` (src/estimate.rs)
//! against its error measured from a reference of independent `random` samples, the
//! reference's own variance taken out (qjulia::report::error_estimate), raw and denoised, on
//! the path-traced, path-gallery and fog-shafts presets; the GPU's halves against the CPU
//! twin's; no estimate where there is nothing to estimate it from.

use qjulia::report::error_estimate::{check, reference};
use qjulia::scene::presets::find;
use qjulia::{Backend, Picture, Planner, PrecisionChoice, Scene};

use crate::common::{gpu_renderer, kernels, render_hdr};

/// A preset at `size` x `size`, `samples` a pixel, without its denoiser.
fn preset(slug: &str, size: u32, samples: u32) -> Scene {
    let mut scene = find(slug).expect("a preset").scene();
    scene.image.width = size;
    scene.image.height = size;
    scene.image.samples = samples;
    scene.image.denoise = qjulia::denoise::Denoiser::None;
    scene
}

/// On three presets at 32x32, 64 Sobol' samples, raw and denoised, over 4 seeds against 4,096
/// `random` samples: the root mean square of the estimates is within 20% of the measured RMSE.
/// (Measured at issue 49: ratios 0.91 to 1.10 with a 1,024-sample reference.) The estimate of
/// the denoised image sees the filter's bias too: on the first two presets at these counts the
/// denoised image's error is larger than the raw one's, and so is its estimate.
#[test]
fn the_estimate_is_within_20_percent_of_the_measured_error() {
    let mut planner = Planner::new(Backend::Cpu, PrecisionChoice::F32);
    let seeds = [1, 2, 3, 4];
    let mut failures = Vec::new();
    for slug in ["path-traced", "path-gallery", "fog-shafts"] {
        let scene = preset(slug, 32, 64);
        let truth = reference(&mut planner, &scene, 4096).expect("a reference");
        for denoise in [false, true] {
            let mut s = scene.clone();
            if denoise {
                s.image.denoise = qjulia::denoise::Denoiser::Atrous;
            }
            let c = check(&mut planner, &s, &seeds, &truth).expect("the renders");
            let ratio = c.estimated / c.measured;
            let line = format!(
                "{slug}, denoised {denoise}: estimated {:.5}, measured {:.5}, ratio {ratio:.3}",
                c.estimated, c.measured
            );
            eprintln!("{line}");
            if (ratio - 1.0).abs() > 0.2 {
                failures.push(line);
            }
        }
    }
    assert!(
        failures.is_empty(),
        "off by over 20%:\n{}",
        failures.join("\n")
    );
}

/// The GPU keeps the same halves as the CPU twin (the same sampler bits, the same streams), so
/// its estimate agrees with the twin's within 5%, and what each pixel shows is its halves' mean.
#[test]
fn the_gpus_halves_agree_with_the_cpu_twins() {
    let Some(kernels) = kernels("the GPU's halves") else {
        return;
    };
    let scene = preset("path-traced", 32, 16);
    let gpu = render_hdr(&gpu_renderer(&kernels, &scene), &scene);
    let cpu = render_hdr(
        &Planner::new(Backend::Cpu, PrecisionChoice::F32)
            .plan(&scene, Picture::SHADED.into(), &mut |_| {})
            .expect("a CPU plan")
            .renderer,
        &scene,
    );
    let (g, c) = (
        qjulia::estimate::raw(&gpu).expect("the GPU's estimate"),
        qjulia::estimate::raw(&cpu).expect("the CPU's estimate"),
    );
    assert!(
        (g.rmse / c.rmse - 1.0).abs() < 0.05,
        "GPU {g:?} against CPU {c:?}"
    );
    for frame in [&gpu, &cpu] {
        for (h, m) in frame.halves.iter().zip(&frame.radiance) {
            for k in 0..3 {
                let mean = (h[0][k] + h[1][k]) / 2.0;
                assert!(
                    (mean - m[k]).abs() <= 1e-6 * m[k].abs().max(1.0),
                    "{h:?} {m:?}"
                );
            }
        }
    }
}

/// Nothing to estimate from: phong mode, and path mode at one sample a pixel (one half only),
/// give no estimate (`estimated_rmse` null).
#[test]
fn one_sample_or_phong_mode_gives_no_estimate() {
    let mut planner = Planner::new(Backend::Cpu, PrecisionChoice::F32);
    let one = preset("path-traced", 16, 1);
    let (_, estimate) =
        qjulia::report::error_estimate::render_estimated(&mut planner, &one).expect("a render");
    assert_eq!(estimate, None);
    let mut phong = crate::common::scene(&["image.width=16", "image.height=16"]);
    phong.image.samples = 4;
    let (frame, estimate) =
        qjulia::report::error_estimate::render_estimated(&mut planner, &phong).expect("a render");
    assert_eq!(estimate, None);
    assert!(frame.halves.is_empty());
}

/// A render to `image.target_error` (at most 4,096 samples) on three presets at 32x32, raw and
/// denoised, over 4 seeds: every render stops because its estimate met the target, and the root
/// mean square of the measured relative RMSE (against 4,096 `random` samples, their variance
/// taken out, over the reference's mean) is within 20% of the target or under it. The targets
/// ask for some 100 to 250 samples a pixel.
#[test]
fn a_render_to_a_target_reaches_it_as_measured() {
    let mut planner = Planner::new(Backend::Cpu, PrecisionChoice::F32);
    let seeds = [1, 2, 3, 4];
    let mut failures = Vec::new();
    for (slug, target) in [
        ("path-traced", 0.03),
        ("path-gallery", 0.02),
        ("fog-shafts", 0.1),
    ] {
        let scene = preset(slug, 32, 4096);
        let truth = reference(&mut planner, &scene, 4096).expect("a reference");
        for denoise in [false, true] {
            let mut s = scene.clone();
            s.image.target_error = target;
            if denoise {
                s.image.denoise = qjulia::denoise::Denoiser::Atrous;
            }
            let t = qjulia::report::error_estimate::check_target(&mut planner, &s, &seeds, &truth)
                .expect("the renders");
            let line = format!(
                "{slug}, denoised {denoise}, target {target}: measured {:.4}, {:.1} samples a \
                 pixel, passes {:?}",
                t.measured(),
                t.mean_samples(),
                t.renders
            );
            eprintln!("{line}");
            if t.measured() > 1.2 * target || t.renders.iter().any(|r| !r.1) {
                failures.push(line);
            }
        }
    }
    assert!(
        failures.is_empty(),
        "targets missed:\n{}",
        failures.join("\n")
    );
}
