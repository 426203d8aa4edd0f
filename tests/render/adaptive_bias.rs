//! Adaptive sampling is unbiased (issue 35, item 3; cross-fitted since issue 49): the rule itself
//! (the twins' `add_to_streams`, `sampling_done` and `streams_mean`) on synthetic rare-bright
//! streams, and
//! the path-traced preset against a 4,096-sample `random` reference, each within 3 standard
//! errors. (The rest of adaptive sampling: tests/render/adaptive.rs.)

use qjulia::scene::PathSampler;
use qjulia::{Frame, Scene};

use crate::common::{gpu_renderer, kernels, path_traced, render_hdr};

/// The path-traced preset, small, at `samples`, with these changes.
fn path(samples: u32, change: impl Fn(&mut Scene)) -> Scene {
    let mut scene = path_traced(40, samples, change);
    scene.image.height = 36;
    scene
}

fn random_sampler(scene: &mut Scene) {
    scene.path.sampler = PathSampler::Random;
}

/// The mean and its standard error of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Issue 35, item 3, and issue 49 (cross-fitting): the rule itself (the twins'
/// `add_to_streams`, `sampling_done` and `streams_mean`, driven as the kernels drive them) on
/// synthetic rare-bright streams, where each sample is 1, or `bright` with probability `p` (the
/// truth is 1 + p (bright - 1)): over 20,000 pixels at the settings (target 0.05, 16 to
/// 256 samples), the mean of what the pixels show is within 3 standard errors of the truth. What
/// stream A shows of itself at its own stop, the mean of the samples that decided (the rule
/// before issue 35), lands more than 10 standard errors low: the test can tell a biased rule.
/// Both streams reach the output: the samples a pixel took and the samples its two halves hold
/// differ by |tau_A - tau_B| a pixel.
#[test]
fn the_rule_is_unbiased_on_rare_bright_streams() {
    use qjulia::algebra::Vec3;
    use qjulia::cpu::sobol::{random_sample, to_unit};
    use qjulia::cpu::trace::{Streams, streams_mean};
    let scene = path(256, |s| {
        s.path.noise_target = 0.05;
        s.path.min_samples = 16;
    });
    let params = qjulia::params::TraceParams::<f32>::new(&scene);
    assert!(params.adaptive());
    for (case, (bright, p)) in [(100.0f32, 0.02f32), (20.0, 0.05)].into_iter().enumerate() {
        let truth = 1.0 + p as f64 * (bright as f64 - 1.0);
        let (mut shown, mut deciding) = (Vec::new(), Vec::new());
        let (mut taken, mut held) = (0u64, 0u64);
        for pixel in 0..20_000u32 {
            let mut streams = Streams::default();
            let mut took = 0;
            for k in 0..params.samples {
                let u = to_unit(random_sample(pixel, k, case as u32));
                let x = if u < p { bright } else { 1.0 };
                streams = params.add_to_streams(streams, k, true, Vec3::splat(x));
                if params.sampling_done(&streams, k + 1) {
                    took = k + 1;
                    break;
                }
            }
            // A's colour holds A's first tau_B samples, B's B's first tau_A, and the pixel took
            // 2 max(tau_A, tau_B).
            let (tau_a, tau_b) = (streams.a[3], streams.rule_b[3]);
            assert_eq!(
                (streams.rule_a[3], streams.b[3]),
                (tau_b, tau_a),
                "pixel {pixel}"
            );
            assert_eq!(took as f32, 2.0 * tau_a.max(tau_b), "pixel {pixel}");
            taken += took as u64;
            held += (streams.rule_a[3] + streams.b[3]) as u64;
            shown.push(streams_mean(&streams).x as f64);
            // Stream A's luminances stop being counted at its own stop.
            deciding.push(streams.rule_a[0] as f64);
        }
        let (m, se) = mean_and_error(&shown);
        let (d, d_se) = mean_and_error(&deciding);
        eprintln!(
            "1 or {bright} with p {p}, truth {truth:.4}: shown {m:.4} +- {se:.4} ({:+.2} SE), \
             the deciding stream's own mean {d:.4} +- {d_se:.4} ({:+.1} SE); {:.1} samples a \
             pixel, {:.1} of them in what it shows",
            (m - truth) / se,
            (d - truth) / d_se,
            taken as f64 / 20_000.0,
            held as f64 / 20_000.0
        );
        assert!(
            (m - truth).abs() <= 3.0 * se,
            "1 or {bright} with p {p}: shown {m} +- {se}, truth {truth}"
        );
        assert!(
            truth - d > 10.0 * d_se,
            "1 or {bright} with p {p}: the deciding stream {d} +- {d_se} is not biased low"
        );
    }
}

/// The mean luminance of a frame's radiance and its standard error, from each pixel's variance
/// of its mean (the AOVs' M2 over the samples its mean holds, `denoise::mean_variance`).
fn image_mean(frame: &Frame, samples: u32) -> (f64, f64) {
    use qjulia::denoise::mean_variance;
    let pixels = frame.pixel_count();
    let (mut sum, mut variance) = (0.0f64, 0.0f64);
    for k in 0..pixels {
        let [r, g, b] = frame.radiance[k];
        sum += 0.2126 * r as f64 + 0.7152 * g as f64 + 0.0722 * b as f64;
        let n = frame.samples_of(k, samples);
        variance += mean_variance(frame.luminance_m2[k], n) as f64;
    }
    let p = pixels as f64;
    (sum / p, variance.sqrt() / p)
}

/// Issue 35, item 3: the path-traced preset at 32x32, adaptively (Sobol', target 0.05, 16 to
/// 256 samples), has the image mean luminance of a 4,096-sample `random` reference, within 3
/// standard errors (both renders', from each pixel's M2).
#[test]
fn the_adaptive_path_traced_preset_is_unbiased() {
    let Some(kernels) = kernels("adaptive bias") else {
        return;
    };
    let size = 32;
    let reference_scene = path_traced(size, 4096, random_sampler);
    let renderer = gpu_renderer(&kernels, &reference_scene);
    let reference = render_hdr(&renderer, &reference_scene);
    let (truth, truth_se) = image_mean(&reference, 4096);
    let scene = path_traced(size, 256, |s| {
        s.path.noise_target = 0.05;
        s.path.min_samples = 16;
    });
    let adaptive = render_hdr(&renderer, &scene);
    let (m, se) = image_mean(&adaptive, 256);
    let total: u64 = adaptive.samples.iter().map(|&n| n as u64).sum();
    let error = (se * se + truth_se * truth_se).sqrt();
    eprintln!(
        "path-traced {size}x{size}: adaptive {m:.5} +- {se:.5} ({total} samples), reference \
         {truth:.5} +- {truth_se:.5}: {:+.2} standard errors",
        (m - truth) / error
    );
    assert!(
        (m - truth).abs() <= 3.0 * error,
        "adaptive {m} +- {se}, reference {truth} +- {truth_se}"
    );
}
