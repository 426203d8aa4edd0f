//! Adaptive sampling (`path.noise_target`, `path.min_samples`): with the target off nothing
//! changes, and an adaptive render whose pixels all take every sample has the plain one's depth
//! and steps bit for bit; no pixel takes fewer than min(min_samples, samples) (nor 4) or more
//! than the samples; the GPU and the CPU twin stop the same pixels; the rule is unbiased on
//! synthetic rare-bright streams and on the path-traced preset; at equal `samples_total` the
//! adaptive image is closer to a converged reference than the uniform one; any split into
//! dispatches and bands gives the same bytes; and through the binary, `--view samples` and
//! `samples_total`. (Tiles
//! with adaptive sampling: tests/cli/tiles.rs; its keys' bad values: tests/cli/bad_input.rs.)

use crate::common;

use std::path::Path;
use std::process::Command;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::report::monte_carlo::rmse;
use qjulia::scene::PathSampler;
use qjulia::{Frame, Precision, Renderer, Scene};

use crate::common::{cpu_renderer, gpu_renderer, kernels, path_traced, render_hdr};

/// A phong scene with something to average (soft shadows, orbit-trap colour) at `samples`.
fn phong(samples: u32, sets: &[&str]) -> Scene {
    let samples = format!("image.samples={samples}");
    let mut all = vec![
        "image.width=48",
        "image.height=40",
        samples.as_str(),
        "light.radius=0.4",
        "shading.colouring=\"orbit_trap\"",
    ];
    all.extend_from_slice(sets);
    common::scene(&all)
}

/// The path-traced preset, small, at `samples`, with these changes.
fn path(samples: u32, change: impl Fn(&mut Scene)) -> Scene {
    let mut scene = path_traced(40, samples, change);
    scene.image.height = 36;
    scene
}

/// The renderers the tests compare: the GPU's (where GPU tests run) and the CPU twin's.
fn renderers(test: &str, scene: &Scene) -> Vec<(&'static str, Renderer)> {
    let mut out = vec![("cpu", cpu_renderer(scene, Precision::F32))];
    if let Some(kernels) = kernels(test) {
        out.push(("gpu", gpu_renderer(&kernels, scene)));
    }
    out
}

/// The fields in which two frames differ, by name (none: the same bit for bit, NaN depths
/// included), `samples` left out where `samples` is false.
fn differences(a: &Frame, b: &Frame, samples: bool) -> Vec<&'static str> {
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let triples = |v: &[[f32; 3]]| bits(v.as_flattened());
    let fields = [
        ("size", (a.width, a.height) == (b.width, b.height)),
        ("colour", a.colour == b.colour),
        ("depth", bits(&a.depth) == bits(&b.depth)),
        ("steps", a.steps == b.steps),
        ("radiance", triples(&a.radiance) == triples(&b.radiance)),
        ("unclamped", triples(&a.unclamped) == triples(&b.unclamped)),
        ("albedo", triples(&a.albedo) == triples(&b.albedo)),
        ("normal", triples(&a.normal) == triples(&b.normal)),
        (
            "luminance_m2",
            bits(&a.luminance_m2) == bits(&b.luminance_m2),
        ),
        ("samples", !samples || a.samples == b.samples),
        ("estimates", a.estimates == b.estimates),
        ("non_finite", a.non_finite == b.non_finite),
    ];
    fields
        .into_iter()
        .filter(|(_, same)| !same)
        .map(|(name, _)| name)
        .collect()
}

#[test]
fn with_the_target_off_nothing_changes_bit_for_bit() {
    for (model, off, inert, never_stops) in [
        (
            "phong",
            phong(12, &[]),
            phong(12, &["path.min_samples=3"]),
            phong(12, &["path.noise_target=1e-30", "path.min_samples=12"]),
        ),
        (
            "path",
            path(12, |_| {}),
            path(12, |s| s.path.min_samples = 3),
            path(12, |s| {
                s.path.noise_target = 1e-30;
                s.path.min_samples = 12;
            }),
        ),
    ] {
        for (backend, renderer) in renderers("adaptive off", &off) {
            let context = format!("{model} on the {backend}");
            let plain = render_hdr(&renderer, &off);
            let pixels = plain.pixel_count();
            assert_eq!(plain.samples, vec![12; pixels], "{context}: the counts");
            // min_samples alone does nothing.
            let changed = differences(&render_hdr(&renderer, &inert), &plain, true);
            assert!(
                changed.is_empty(),
                "{context}: min_samples changes {changed:?}"
            );
            // Adaptive, with a floor of every sample: every pixel takes them all, and its depth
            // and steps are the plain render's bit for bit (sample 0 is stream 0's first, through
            // the pixel's centre). In phong mode its picture is stream 1's alone, so it differs;
            // in path mode a plain render has the two streams too (issue 49, item 3), both rules
            // fire at their cap, and the picture is the plain one's bit for bit.
            assert!(never_stops.adaptive());
            let adaptive = render_hdr(&renderer, &never_stops);
            assert_eq!(adaptive.samples, plain.samples, "{context}: the counts");
            let changed = differences(&adaptive, &plain, false);
            let same = ["size", "depth", "steps", "non_finite"];
            let picture_same = model == "path";
            assert!(
                same.iter().all(|field| !changed.contains(field))
                    && changed.contains(&"colour") != picture_same
                    && (!picture_same || !changed.contains(&"radiance")),
                "{context}: an adaptive render whose pixels take every sample differs in \
                 {changed:?}"
            );
        }
    }
}

/// How many of the pixels took each count from 0 to `samples`.
fn histogram(samples: &[u32], most: u32) -> Vec<usize> {
    let mut h = vec![0; most as usize + 1];
    for &n in samples {
        h[n as usize] += 1;
    }
    h
}

#[test]
fn no_pixel_takes_fewer_than_the_floor_or_more_than_the_samples() {
    let cases = [
        // (scene, the floor: max(min(min_samples, samples), 4))
        (
            "phong, floor 5",
            phong(24, &["path.noise_target=0.02", "path.min_samples=5"]),
            5,
        ),
        (
            "path, floor 5",
            path(24, |s| {
                s.path.noise_target = 0.05;
                s.path.min_samples = 5;
            }),
            5,
        ),
        (
            "path, min_samples 1: floor 4 (two samples of each stream)",
            path(24, |s| {
                s.path.noise_target = 0.05;
                s.path.min_samples = 1;
            }),
            4,
        ),
        (
            "path, min_samples above the samples: every pixel takes them all",
            path(24, |s| {
                s.path.noise_target = 0.05;
                s.path.min_samples = 40;
            }),
            24,
        ),
    ];
    for (name, scene, floor) in cases {
        let mut counts = Vec::new();
        for (backend, renderer) in renderers("adaptive floor", &scene) {
            let frame = render_hdr(&renderer, &scene);
            let h = histogram(&frame.samples, 24);
            eprintln!("{name} on the {backend}: pixels by samples taken {h:?}");
            assert_eq!(frame.samples.len(), frame.pixel_count());
            let (fewest, most) = (
                *frame.samples.iter().min().unwrap(),
                *frame.samples.iter().max().unwrap(),
            );
            assert!(
                fewest >= floor && most <= 24,
                "{name} on the {backend}: samples {fewest}..={most}, outside {floor}..=24"
            );
            if floor < 24 {
                // The target is met somewhere and not everywhere.
                assert!(
                    fewest < 24 && h[24] > 0,
                    "{name} on the {backend}: no pixel stopped early, or every pixel did: {h:?}"
                );
            }
            counts.push((backend, frame));
        }
        // The GPU stops the same pixels as the CPU twin (f32 on both; a pixel whose noise
        // lands within rounding of the target may go either way), and their pictures agree
        // within CONTRACT_TOLERANCE.
        if let [(_, cpu), (_, gpu)] = &counts[..] {
            let same = (0..cpu.pixel_count())
                .filter(|&k| cpu.samples[k] == gpu.samples[k])
                .collect::<Vec<_>>();
            let share = same.len() as f64 / cpu.pixel_count() as f64;
            eprintln!(
                "{name}: the GPU and the CPU agree on {:.2}% of counts",
                100.0 * share
            );
            assert!(
                share >= 0.97,
                "{name}: the counts agree on {share:.4} of the pixels"
            );
            let what = format!("adaptive {name}").replace([' ', ',', ':'], "-");
            common::assert_agree(&what, cpu, gpu, &CONTRACT_TOLERANCE);
        }
    }
}

fn random_sampler(scene: &mut Scene) {
    scene.path.sampler = PathSampler::Random;
}

/// Independent renders (`path.seed` 0..SEEDS) that the allocation test looks at.
const SEEDS: u32 = 4;

/// On the path-traced preset at 64x64 (flat sky and fractal detail), adaptive sampling (target
/// 0.08, 16 to 256 samples) spends no more samples than uniform sampling of its mean (rounded
/// up), and spends them where the noise is: for every seed, the quarter of the pixels that a
/// converged reference (1,024 samples of the `random` sampler) shows to be noisiest (its
/// per-pixel variance of the luminance) takes at least twice the samples a pixel of the
/// quietest quarter takes. It also prints each seed's root mean squared error against the
/// reference, adaptive and uniform, which docs/book/adaptive.md reports: which of the two is
/// lower turns on whether a rare glint lands in a render (over 12 seeds, uniform sampling's
/// was the lower), so no test asserts it.
#[test]
fn adaptive_sampling_spends_its_samples_where_the_noise_is() {
    let Some(kernels) = kernels("adaptive allocation") else {
        return;
    };
    let size = 64;
    let pixels = (size * size) as u64;
    let reference_scene = path_traced(size, 1024, random_sampler);
    let renderer = gpu_renderer(&kernels, &reference_scene);
    let reference = render_hdr(&renderer, &reference_scene);
    // The pixels by the reference's variance of the luminance, quietest first.
    let mut order: Vec<usize> = (0..reference.luminance_m2.len()).collect();
    order.sort_by(|&a, &b| reference.luminance_m2[a].total_cmp(&reference.luminance_m2[b]));
    let quarter = order.len() / 4;
    let (quietest, noisiest) = (&order[..quarter], &order[order.len() - quarter..]);
    let (mut a2, mut u2, mut total, mut uniform_total) = (0.0, 0.0, 0u64, 0u64);
    for seed in 0..SEEDS {
        let adaptive_scene = path_traced(size, 256, |s| {
            s.path.noise_target = 0.08;
            s.path.min_samples = 16;
            s.path.seed = seed;
        });
        let adaptive = render_hdr(&renderer, &adaptive_scene);
        let taken: u64 = adaptive.samples.iter().map(|&n| n as u64).sum();
        let per_pixel = taken.div_ceil(pixels) as u32;
        let uniform_scene = path_traced(size, per_pixel, |s| s.path.seed = seed);
        let uniform = render_hdr(&renderer, &uniform_scene);
        let (a, u) = (
            rmse(&adaptive.radiance, &reference.radiance),
            rmse(&uniform.radiance, &reference.radiance),
        );
        let mean = |set: &[usize]| {
            set.iter().map(|&k| adaptive.samples[k] as f64).sum::<f64>() / set.len() as f64
        };
        let (quiet, noisy) = (mean(quietest), mean(noisiest));
        eprintln!(
            "seed {seed}: adaptive {taken} samples ({quiet:.1} a pixel in the quietest quarter, \
             {noisy:.1} in the noisiest), RMSE {a:.5}; uniform {per_pixel} a pixel, RMSE {u:.5}"
        );
        assert!(
            noisy >= 2.0 * quiet,
            "seed {seed}: {noisy:.1} samples a pixel in the noisiest quarter, {quiet:.1} in the \
             quietest"
        );
        (a2, u2) = (a2 + a * a, u2 + u * u);
        total += taken;
        uniform_total += per_pixel as u64 * pixels;
    }
    let (a, u) = ((a2 / SEEDS as f64).sqrt(), (u2 / SEEDS as f64).sqrt());
    eprintln!(
        "path-traced {size}x{size} against 1024 random samples, {SEEDS} seeds: adaptive (target \
         0.08, 16..256) {total} samples, RMSE {a:.5}; uniform {uniform_total} samples, RMSE {u:.5}"
    );
    assert!(total <= uniform_total);
}

/// Runs qjulia in `dir` with `args` and these environment variables.
fn run(dir: &Path, args: &[&str], env: &[(&str, &str)]) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_qjulia"));
    command
        .args(args)
        .current_dir(dir)
        .envs(env.iter().copied());
    let out = command.output().expect("run qjulia");
    assert!(
        out.status.success(),
        "qjulia {args:?}: {}",
        common::stderr(&out)
    );
}

/// `samples_total` of a `--stats` file.
fn samples_total(path: &Path) -> u64 {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["samples_total"].as_u64().expect("samples_total")
}

/// Bands of one row of 40 pixels and one sample a dispatch (`QJULIA_BAND_PIXELS=64`) give the
/// bytes of the default bands (the whole image, up to 8 samples a dispatch): a pixel's stop
/// depends on its own samples alone, and a done pixel stays done across dispatches. So does the
/// early-out alone, without compaction (`QJULIA_COMPACT=0`).
#[test]
fn any_split_into_dispatches_and_bands_gives_the_same_bytes() {
    let mut cases = vec![(
        "cpu-phong",
        vec![
            "--backend",
            "cpu",
            "--set",
            "image.samples=12",
            "--set",
            "light.radius=0.4",
        ],
    )];
    if common::gpu("adaptive dispatch splits").is_some() {
        cases.push((
            "gpu-path",
            vec![
                "--backend",
                "gpu",
                "--preset",
                "path-traced",
                "--set",
                "image.samples=20",
            ],
        ));
        cases.push((
            "gpu-phong",
            vec![
                "--backend",
                "gpu",
                "--set",
                "image.samples=20",
                "--set",
                "light.radius=0.4",
            ],
        ));
    }
    for (name, scene) in cases {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let adaptive = [
            "--set",
            "path.noise_target=0.05",
            "--set",
            "path.min_samples=3",
        ];
        let size = ["--width", "40", "--height", "36"];
        let args = |out: &'static str, stats: &'static str| {
            [
                &["render"][..],
                &scene,
                &adaptive,
                &size,
                &["-o", out, "--stats", stats],
            ]
            .concat()
        };
        run(d, &args("whole.png", "whole.json"), &[]);
        run(
            d,
            &args("split.png", "split.json"),
            &[("QJULIA_BAND_PIXELS", "64")],
        );
        let no_compaction = [("QJULIA_BAND_PIXELS", "64"), ("QJULIA_COMPACT", "0")];
        run(d, &args("early.png", "early.json"), &no_compaction);
        let total = samples_total(&d.join("whole.json"));
        for other in ["split", "early"] {
            common::assert_same_file(
                &format!("adaptive-{other}-{name}"),
                &d.join("whole.png"),
                &d.join(format!("{other}.png")),
            );
            let stats = d.join(format!("{other}.json"));
            assert_eq!(total, samples_total(&stats), "{name}: {other}");
        }
        let most = if name == "cpu-phong" { 12 } else { 20 };
        assert!(
            total < 40 * 36 * most,
            "{name}: no pixel stopped early ({total} samples)"
        );
    }
}

/// `--view samples` draws the counts the tile carries (the same render, whole, as `--tile 0/1`)
/// as `heatmap::samples_view` draws them, with the legend below; `samples_total` is their sum,
/// and with the target off, width x height x samples.
#[test]
fn the_samples_view_and_samples_total() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = [
        "--preset",
        "path-traced",
        "--width",
        "40",
        "--height",
        "36",
        "--set",
        "image.samples=24",
    ];
    let on = [&scene[..], &["--set", "path.noise_target=0.05"]].concat();
    run(
        d,
        &[
            &["render"][..],
            &on,
            &[
                "--view",
                "samples",
                "-o",
                "view.png",
                "--stats",
                "view.json",
            ],
        ]
        .concat(),
        &[],
    );
    run(
        d,
        &[
            &["render"][..],
            &on,
            &["--tile", "0/1", "--hdr", "part.exr"],
        ]
        .concat(),
        &[],
    );
    let (_, frame, stats) = qjulia::tile::merge(&[d.join("part.exr")]).expect("the part");
    let total: u64 = frame.samples.iter().map(|&n| n as u64).sum();
    assert_eq!(stats.summary.samples_total, total);
    assert_eq!(samples_total(&d.join("view.json")), total);
    assert!(total < 40 * 36 * 24, "no pixel stopped early");
    let map = qjulia::heatmap::samples_view(&frame.samples, 40, 36);
    assert!(
        map.legend.min >= 16 && map.legend.max == 24,
        "{:?}",
        map.legend
    );
    let ([w, h], rgb) = qjulia::output::read_png_rgb(&d.join("view.png")).unwrap();
    assert_eq!([w, h], [40, 36 + qjulia::heatmap::LEGEND_HEIGHT]);
    assert!(
        rgb[..map.rgb.len()] == map.rgb[..],
        "the view is not the heat map of the counts"
    );
    // Off: every pixel takes every sample.
    run(
        d,
        &[
            &["render"][..],
            &scene,
            &["-o", "off.png", "--stats", "off.json"],
        ]
        .concat(),
        &[],
    );
    assert_eq!(samples_total(&d.join("off.json")), 40 * 36 * 24);
}
