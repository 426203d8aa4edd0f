//! The denoiser (`image.denoise = "atrous"`): a flat, noise-free image comes out unchanged; an
//! edge in the albedo or the normal survives while the noise on either side falls; on the
//! path-traced preset 16 denoised samples beat 64 plain ones against a converged reference; the
//! GPU's passes agree with the CPU twin's; and through the binary, `--hdr` carries the noisy
//! layer, phong mode denoises, and bad values are refused.

use crate::common;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::cpu::denoise::DenoiseParams;
use qjulia::denoise::{self, Denoiser, Prepared};
use qjulia::display::Display;
use qjulia::report::monte_carlo::{TRIM, rmse, rmse_trimmed};
use qjulia::scene::PathSampler;
use qjulia::{Frame, Picture, Readback, Scene};

use crate::common::{gpu_renderer, kernels, path_traced, render_hdr};

/// A uniform number in [-1, 1) of pixel k (a fixed integer hash, so the noise is the same on
/// every run).
fn noise(k: usize, salt: u32) -> f32 {
    let mut x = (k as u32).wrapping_mul(0x9E37_79B9) ^ salt.wrapping_mul(0x85EB_CA6B);
    x ^= x >> 16;
    x = x.wrapping_mul(0x7FEB_352D);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846C_A68B);
    x ^= x >> 16;
    (x >> 8) as f32 / (1u32 << 23) as f32 - 1.0
}

/// The share of a pixel's noise variance that a uniform number in [-a, a) has: a^2 / 3.
fn uniform_variance(a: f32) -> f32 {
    a * a / 3.0
}

/// A synthetic frame of `w` x `h` as a render with its AOVs would give it, each pixel made by
/// `pixel(i, j)`: (linear colour, albedo, normal, depth or NaN, the variance of its mean
/// luminance), at `samples` samples (the M2 is what gives that variance).
fn frame(
    (w, h): (u32, u32),
    samples: u32,
    pixel: impl Fn(u32, u32) -> ([f32; 3], [f32; 3], [f32; 3], f32, f32),
) -> Frame {
    let mut f = Frame::empty(w);
    f.height = h;
    let n = samples as f32;
    for j in 0..h {
        for i in 0..w {
            let (linear, albedo, normal, depth, variance) = pixel(i, j);
            f.colour.push(0);
            f.depth.push(depth);
            f.steps.push(0);
            f.unclamped.push(linear);
            f.albedo.push(albedo);
            f.normal.push(normal);
            f.luminance_m2.push(variance * n * (n - 1.0));
            // Every sample hit where the depth is a number, none elsewhere.
            let hit = !depth.is_nan();
            f.hits.push(if hit { n } else { 0.0 });
            f.hit_depth.push(if hit { depth } else { 0.0 });
        }
    }
    f
}

fn scene(sets: &[&str]) -> Scene {
    let mut all = vec!["image.denoise=\"atrous\""];
    all.extend_from_slice(sets);
    common::scene(&all)
}

type Both = (Vec<[f32; 3]>, Option<Vec<[f32; 3]>>);

/// The passes of `scene` over `prepared` on the CPU, and on the GPU where there is one.
fn both(test: &str, scene: &Scene, prepared: &Prepared) -> Both {
    let passes: Vec<DenoiseParams> = denoise::passes(scene, prepared.width, prepared.height);
    both_of(test, &passes, prepared)
}

/// The frame's signals (`denoise::prepare_split`), each through its passes on the CPU and on
/// the GPU where there is one, added: what the renderer's denoiser makes.
fn both_signals(test: &str, scene: &Scene, noisy: &Frame) -> Both {
    let split = denoise::prepare_split(noisy, scene, scene.image.samples);
    let (w, h) = (noisy.width, noisy.height);
    let (mut cpu, mut gpu) = both_of(test, &denoise::passes(scene, w, h), &split.diffuse);
    if let Some(specular) = &split.specular {
        let (c, g) = both_of(test, &denoise::specular_passes(scene, w, h), specular);
        let add = |a: &mut Vec<[f32; 3]>, b: &[[f32; 3]]| {
            a.iter_mut()
                .zip(b)
                .for_each(|(a, b)| (0..3).for_each(|k| a[k] += b[k]))
        };
        add(&mut cpu, &c);
        if let (Some(gpu), Some(g)) = (gpu.as_mut(), g) {
            add(gpu, &g);
        }
    }
    (cpu, gpu)
}

/// `passes` over `prepared` on the CPU, and on the GPU where there is one.
fn both_of(test: &str, passes: &[DenoiseParams], prepared: &Prepared) -> Both {
    let cpu = denoise::run_cpu(passes, prepared.image.clone(), &prepared.guide);
    let gpu = kernels(test).map(|k| {
        k.denoiser()
            .expect("the denoiser's kernel")
            .run(passes, &prepared.image, &prepared.guide)
            .expect("the GPU passes")
            .image
    });
    let finish = |image: &[[f32; 4]]| denoise::finish(image, &prepared.albedo);
    (finish(&cpu), gpu.as_deref().map(finish))
}

#[test]
fn a_flat_noise_free_image_is_unchanged() {
    let scene = scene(&["image.samples=16"]);
    let (w, h) = (48, 40);
    // A tilted plane of one colour, and a disc of sky where the rays miss.
    let input = frame((w, h), 16, |i, j| {
        let (x, y) = (i as f32 - 12.0, j as f32 - 12.0);
        if x * x + y * y < 64.0 {
            ([0.3, 0.45, 0.6], [0.0; 3], [0.0; 3], f32::NAN, 0.0)
        } else {
            let albedo = [0.8, 0.5, 0.3];
            let linear = albedo.map(|a| 0.7 * a);
            (linear, albedo, [0.0, 0.6, 0.8], 3.0 + 0.01 * i as f32, 0.0)
        }
    });
    let prepared = denoise::prepare(&input, 16);
    let (cpu, gpu) = both("a flat image", &scene, &prepared);
    for (name, out) in [("cpu", Some(cpu)), ("gpu", gpu)] {
        let Some(out) = out else { continue };
        for (k, (a, b)) in input.unclamped.iter().zip(&out).enumerate() {
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= 1e-6 * a[c].abs().max(1e-3),
                    "{name}: pixel {k} channel {c}: {} became {}",
                    a[c],
                    b[c]
                );
            }
        }
    }
}

/// Per half of a `w`-wide image split at column `w / 2`: the standard deviation of the values'
/// luminance about their half's mean, over the columns at least `margin` from the edge.
fn half_deviation(image: &[[f32; 3]], w: usize, margin: usize) -> [f64; 2] {
    let l = |c: &[f32; 3]| (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) as f64;
    let half = w / 2;
    [0..half - margin, half + margin..w].map(|cols| {
        let values: Vec<f64> = image
            .chunks(w)
            .flat_map(|row| row[cols.clone()].iter().map(l))
            .collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
    })
}

/// The mean luminance of column `i` (over every row).
fn column_mean(image: &[[f32; 3]], w: usize, i: usize) -> f64 {
    let rows: Vec<_> = image.chunks(w).collect();
    rows.iter()
        .map(|row| {
            let c = row[i];
            (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) as f64
        })
        .sum::<f64>()
        / rows.len() as f64
}

#[test]
fn edges_in_the_albedo_and_the_normal_survive() {
    let scene = scene(&["image.samples=16"]);
    let (w, h) = (64u32, 32u32);
    let amplitude = 0.2;
    let variance = uniform_variance(amplitude);
    // An albedo edge: one illumination, noisy, over an albedo of 0.2 left and 0.8 right.
    let albedo_edge = frame((w, h), 16, |i, j| {
        let a = if i < w / 2 { 0.2 } else { 0.8 };
        let e = 1.0 + amplitude * noise((j * w + i) as usize, 1);
        let albedo = [a; 3];
        (
            albedo.map(|a| a * e),
            albedo,
            [0.0, 0.0, 1.0],
            3.0,
            a * a * variance,
        )
    });
    // A normal edge: a crease, the left face lit 0.3 and the right 0.9, one albedo.
    let normal_edge = frame((w, h), 16, |i, j| {
        let (level, normal) = match i < w / 2 {
            true => (0.3, [0.0, 0.0, 1.0]),
            false => (0.9, [1.0, 0.0, 0.0]),
        };
        let e = level * (1.0 + amplitude * noise((j * w + i) as usize, 2));
        let a = 0.5;
        (
            [a * e; 3],
            [a; 3],
            normal,
            3.0,
            (a * level).powi(2) * variance,
        )
    });
    for (name, input, step) in [
        ("albedo edge", albedo_edge, 0.8 - 0.2),
        ("normal edge", normal_edge, 0.5 * (0.9 - 0.3)),
    ] {
        let prepared = denoise::prepare(&input, 16);
        let (cpu, gpu) = both(name, &scene, &prepared);
        let before = half_deviation(&input.unclamped, w as usize, 2);
        for (side, out) in [("cpu", Some(cpu)), ("gpu", gpu)] {
            let Some(out) = out else { continue };
            let half = w as usize / 2;
            let measured =
                column_mean(&out, w as usize, half) - column_mean(&out, w as usize, half - 1);
            let after = half_deviation(&out, w as usize, 2);
            eprintln!(
                "{name} ({side}): step {measured:.4} of {step:.4}; noise {:.4} -> {:.4}, {:.4} -> {:.4}",
                before[0], after[0], before[1], after[1]
            );
            assert!(
                (measured - step).abs() <= 0.05 * step,
                "{name} ({side}): the step across the edge is {measured:.4}, not {step:.4} within 5%"
            );
            for k in 0..2 {
                assert!(
                    after[k] <= 0.5 * before[k],
                    "{name} ({side}): the noise of half {k} only fell from {:.4} to {:.4}",
                    before[k],
                    after[k]
                );
            }
        }
    }
}

fn random_sampler(scene: &mut Scene) {
    scene.path.sampler = PathSampler::Random;
}

fn denoised(scene: &mut Scene) {
    scene.image.denoise = Denoiser::Atrous;
}

/// On the path-traced preset at 64x64, the denoised image of 16 samples is closer to a
/// converged reference (1,024 samples of the `random` sampler, independent of the Sobol'
/// estimates) than the plain mean of the same 16 samples, both in the root of the mean squared
/// error over 4 seeds (`path.seed`) and in the trimmed one (the worst 0.5% of pixels left out,
/// the glints). It prints the plain mean of 64 samples beside them, which docs/book/denoise.md
/// reports: whether 16 denoised samples beat 64 plain ones turns on whether rare glints land in
/// the 64-sample renders (over seeds 0 to 11 they did, 0.0240 against 0.0253; over seeds 0 to 3
/// alone they did not, 0.0237 against 0.0166), so no test asserts it.
#[test]
fn sixteen_denoised_samples_beat_sixteen_plain_ones() {
    let Some(kernels) = kernels("16 denoised samples") else {
        return;
    };
    let size = 64;
    let seeds = 4;
    let reference_scene = path_traced(size, 1024, random_sampler);
    let renderer = gpu_renderer(&kernels, &reference_scene);
    let reference = render_hdr(&renderer, &reference_scene).radiance;
    // Squared errors summed over the seeds, plain and trimmed: 16 plain, 64 plain, 16 denoised.
    let (mut squared, mut trimmed) = ([0.0f64; 3], [0.0f64; 3]);
    for seed in 0..seeds {
        let render = |samples, denoise: bool| {
            let scene = path_traced(size, samples, |s| {
                s.path.seed = seed;
                if denoise {
                    denoised(s);
                }
            });
            render_hdr(&renderer, &scene).radiance
        };
        let images = [render(16, false), render(64, false), render(16, true)];
        for (k, image) in images.iter().enumerate() {
            squared[k] += rmse(image, &reference).powi(2);
            trimmed[k] += rmse_trimmed(image, &reference, TRIM).powi(2);
        }
    }
    let root = |v: [f64; 3]| v.map(|x| (x / seeds as f64).sqrt());
    let (figures, trimmed) = (root(squared), root(trimmed));
    eprintln!(
        "path-traced {size}x{size}, RMSE against 1024 random samples over {seeds} seeds: 16 \
         plain {:.5}, 64 plain {:.5}, 16 denoised {:.5}",
        figures[0], figures[1], figures[2]
    );
    eprintln!(
        "trimmed: 16 plain {:.5}, 64 plain {:.5}, 16 denoised {:.5}",
        trimmed[0], trimmed[1], trimmed[2]
    );
    for (what, v) in [("RMSE", figures), ("trimmed RMSE", trimmed)] {
        assert!(
            v[2] < v[0],
            "16 denoised samples have {what} {:.5}, 16 plain ones {:.5}",
            v[2],
            v[0]
        );
    }
}

/// The GPU's passes and the CPU twin's, over one render's prepared image, give display images
/// within CONTRACT_TOLERANCE, in both models.
#[test]
fn gpu_and_cpu_passes_agree() {
    let Some(kernels) = kernels("denoiser GPU against CPU") else {
        return;
    };
    let path = path_traced(64, 8, denoised);
    let phong = scene(&[
        "image.width=64",
        "image.height=64",
        "image.samples=4",
        "light.radius=0.3",
    ]);
    for (name, scene) in [("path", path), ("phong", phong)] {
        let renderer = gpu_renderer(&kernels, &scene);
        let mut noisy = Frame::empty(scene.image.width);
        // The noisy render (no denoiser), with its AOVs.
        let mut plain = scene.clone();
        plain.image.denoise = Denoiser::None;
        renderer
            .render_with(&plain, Picture::SHADED, Readback::Hdr, &mut |band| {
                noisy.append(band);
                Ok(())
            })
            .expect("a render");
        let (cpu, gpu) = both_signals(name, &scene, &noisy);
        assert_eq!(
            denoise::prepare_split(&noisy, &scene, scene.image.samples)
                .specular
                .is_some(),
            name == "path",
            "{name}: path mode's glossy material has a specular signal"
        );
        let gpu = gpu.expect("a GPU");
        let pack = |linear: &[[f32; 3]]| match name {
            "path" => Display::of(&scene).pack_all(linear),
            _ => denoise::pack_phong(linear),
        };
        let mut expected = noisy.clone();
        expected.set_denoised(cpu.clone(), pack(&cpu));
        let mut actual = noisy.clone();
        actual.set_denoised(gpu.clone(), pack(&gpu));
        common::assert_agree(
            &format!("denoised {name}"),
            &expected,
            &actual,
            &CONTRACT_TOLERANCE,
        );
        // And the renderer's own denoised render is the GPU passes' image.
        let mut rendered = Frame::empty(scene.image.width);
        renderer
            .render(&scene, Picture::SHADED, &mut |band| {
                rendered.append(band);
                Ok(())
            })
            .expect("a denoised render");
        assert_eq!(
            rendered.colour, actual.colour,
            "{name}: the render's colour"
        );
        assert_eq!(
            rendered.noisy,
            noisy.linear(),
            "{name}: the noisy image kept"
        );
    }
}

#[test]
fn the_binary_denoises_writes_the_noisy_layer_and_refuses_bad_values() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let common_args = [
        "--preset",
        "path-traced",
        "--width",
        "32",
        "--height",
        "32",
        "--set",
        "image.samples=4",
    ];
    let mut args: Vec<&str> = vec!["render"];
    args.extend_from_slice(&common_args);
    args.extend_from_slice(&[
        "--set",
        "image.denoise=\"atrous\"",
        "-o",
        "d.png",
        "--hdr",
        "d.exr",
        "--stats",
        "d.json",
    ]);
    if std::env::var(common::SKIP_GPU_ENV).is_ok_and(|v| v == "1") {
        args.extend_from_slice(&["--backend", "cpu"]);
    }
    let out = common::qjulia(dir.path(), &args);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("d.json")).expect("the stats"))
            .expect("JSON stats");
    assert!(stats["denoise_seconds"].as_f64().is_some(), "{stats}");
    assert!(stats["denoise_backend"].is_string(), "{stats}");
    let image =
        exr::prelude::read_all_flat_layers_from_file(dir.path().join("d.exr")).expect("an EXR");
    let layer = &image.layer_data[0];
    let channel = |name: &str| -> Vec<f32> {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .unwrap_or_else(|| panic!("no channel {name}"));
        c.sample_data.values_as_f32().collect()
    };
    let (r, noisy_r) = (channel("R"), channel("noisy.R"));
    assert_eq!(r.len(), 32 * 32);
    assert_ne!(r, noisy_r, "the denoised R is the noisy one");
    // Bad values: one line naming the key, exit 2, nothing written.
    for (set, key) in [
        ("denoise.iterations=0", "denoise.iterations"),
        ("denoise.iterations=11", "denoise.iterations"),
        ("denoise.sigma_luminance=-1", "denoise.sigma_luminance"),
        ("denoise.sigma_normal=nan", "denoise.sigma_normal"),
        ("denoise.sigma_depth=-0.5", "denoise.sigma_depth"),
        ("image.denoise=\"oidn\"", "image.denoise"),
    ] {
        let bad = tempfile::tempdir().expect("a temporary folder");
        common::assert_refused(
            bad.path(),
            &["render", "--set", set, "-o", "x.png", "--hdr", "x.exr"],
            "error: --set",
            key,
        );
    }
}

/// An animation's frames are denoised as `render` denoises: frame 0 of the default animation
/// is the scene itself, byte for byte, on the GPU (where frames otherwise stream) and the CPU.
#[test]
fn animate_denoises_its_frames_as_render_does() {
    let gpu = common::gpu("denoised animation").is_some();
    for backend in ["cpu", "gpu"] {
        if backend == "gpu" && !gpu {
            continue;
        }
        let dir = tempfile::tempdir().expect("a temporary folder");
        let scene = [
            "--width",
            "48",
            "--height",
            "32",
            "--backend",
            backend,
            "--set",
            "image.samples=4",
            "--set",
            "light.radius=0.3",
            "--set",
            "image.denoise=\"atrous\"",
        ];
        let out = common::qjulia(
            dir.path(),
            &[&["animate", "--frames", "0..1"], &scene[..]].concat(),
        );
        assert!(out.status.success(), "{}", common::stderr(&out));
        let out = common::qjulia(
            dir.path(),
            &[&["render", "-o", "r.png"], &scene[..]].concat(),
        );
        assert!(out.status.success(), "{}", common::stderr(&out));
        let render = std::fs::read(dir.path().join("r.png")).expect("the render");
        let frame =
            std::fs::read(dir.path().join("qjulia-frames/frame-00000.png")).expect("frame 0");
        assert!(
            frame == render,
            "{backend}: frame 0 is not the denoised render"
        );
        // And the denoiser did something: the noisy render differs.
        let mut noisy = scene.to_vec();
        noisy.truncate(noisy.len() - 2);
        let out = common::qjulia(
            dir.path(),
            &[&["render", "-o", "n.png"], &noisy[..]].concat(),
        );
        assert!(out.status.success(), "{}", common::stderr(&out));
        assert!(std::fs::read(dir.path().join("n.png")).expect("noisy") != render);
    }
}
