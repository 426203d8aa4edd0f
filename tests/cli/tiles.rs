//! `render --tile K/N` and `qjulia merge`: N tiles merged are byte for byte one render (the
//! PNG, the `--hdr` EXR, `--stats` but for its times) in phong and path mode, on the GPU and
//! the CPU; bad tiles and bad parts are refused with one line and nothing written.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use crate::common::{assert_refused, assert_same_file, files_in, stderr};

/// 40 x 37: the tiles of 2, 3 and 7 start inside 8-row cone blocks (37 rows: 18, 12, 5, 10,
/// 15, 21, 26, 31), and the last block of the image is cut short.
const SIZE: [&str; 4] = ["--width", "40", "--height", "37"];

/// Runs qjulia in `dir` with bands of 256 pixels (8 rows of 40: five bands, a sample per
/// dispatch), so that the whole render and the tiles run many bands and dispatches.
fn qjulia(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(args)
        .current_dir(dir)
        .env("QJULIA_BAND_PIXELS", "256")
        .output()
        .expect("run qjulia")
}

fn ok(dir: &Path, args: &[&str]) -> Output {
    let out = qjulia(dir, args);
    assert!(out.status.success(), "qjulia {args:?}: {}", stderr(&out));
    out
}

/// The stats as JSON, without the two times (a merge sums its parts', a render has its own).
fn stats_without_times(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let object = v.as_object_mut().expect("an object");
    let seconds = object.remove("render_seconds").expect("render_seconds");
    assert!(seconds.as_f64().is_some_and(|s| s > 0.0), "{seconds}");
    object.remove("gpu_seconds").expect("gpu_seconds");
    // The denoiser's own times, where it ran (both run it once, on the whole image).
    object.remove("denoise_seconds");
    object.remove("denoise_gpu_seconds");
    v
}

/// Renders the scene of `scene` once whole and as each split of `splits`, merges each split
/// (its parts given in reverse order) and checks every output against the whole render's.
fn assert_tiles_merge_to_one_render(name: &str, scene: &[&str], splits: &[u32]) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let whole = [
        &["render"][..],
        scene,
        &SIZE,
        &[
            "-o",
            "whole.png",
            "--hdr",
            "whole.exr",
            "--stats",
            "whole.json",
        ],
    ]
    .concat();
    ok(d, &whole);
    // The picture is not empty: some pixels hit, some miss.
    let stats = stats_without_times(&d.join("whole.json"));
    let hit = stats["hit_fraction"].as_f64().unwrap();
    assert!(hit > 0.05 && hit < 0.95, "{name}: hit fraction {hit}");
    for &n in splits {
        let parts: Vec<String> = (0..n).map(|k| format!("part-{n}-{k}.exr")).collect();
        for (k, part) in parts.iter().enumerate() {
            let tile = format!("{k}/{n}");
            let args = [
                &["render"][..],
                scene,
                &SIZE,
                &["--tile", &tile, "--hdr", part],
            ]
            .concat();
            ok(d, &args);
        }
        let (png, exr, json) = (
            format!("merged-{n}.png"),
            format!("merged-{n}.exr"),
            format!("merged-{n}.json"),
        );
        let mut args = vec!["merge"];
        args.extend(parts.iter().rev().map(String::as_str));
        args.extend(["-o", &png, "--hdr", &exr, "--stats", &json]);
        ok(d, &args);
        let what = format!("{name}-{n}-tiles");
        assert_same_file(&what, &d.join("whole.png"), &d.join(&png));
        assert_same_file(&what, &d.join("whole.exr"), &d.join(&exr));
        assert_eq!(
            stats,
            stats_without_times(&d.join(&json)),
            "{what}: the stats differ"
        );
    }
}

#[test]
fn phong_tiles_merge_to_one_gpu_render() {
    if common::gpu("phong tiles").is_none() {
        return;
    }
    // Cone tracing (one march per 8x8 block: the tiles of 2, 3 and 7 start inside blocks),
    // several samples a pixel (a mean over dispatches), a soft light: every part of phong
    // mode's colour. Then the seed's tracing, which the default scene uses.
    let scene = [
        "--backend",
        "gpu",
        "--set",
        "fractal.tracing=\"cone\"",
        "--set",
        "image.samples=3",
        "--set",
        "light.radius=0.3",
    ];
    assert_tiles_merge_to_one_render("phong-gpu-cone", &scene, &[1, 2, 3, 7]);
    assert_tiles_merge_to_one_render("phong-gpu-seed", &["--backend", "gpu"], &[3]);
}

#[test]
fn path_tiles_merge_to_one_gpu_render() {
    if common::gpu("path tiles").is_none() {
        return;
    }
    let scene = [
        "--backend",
        "gpu",
        "--set",
        "shading.model=\"path\"",
        "--set",
        "image.samples=4",
        "--set",
        "image.tone_map=\"aces\"",
    ];
    assert_tiles_merge_to_one_render("path-gpu", &scene, &[1, 2, 3, 7]);
    // Rays that run out of steps (30 a ray: thousands of them), counted in each part and summed
    // by merge to the whole render's `exhausted_rays`.
    let crevice = [&scene[..], &["--set", "fractal.max_steps=30"]].concat();
    assert_tiles_merge_to_one_render("path-gpu-crevice", &crevice, &[3]);
}

/// With the denoiser, which sees the whole image: merge runs it over the merged frame, on the
/// parts' backend, and gives one render's bytes.
#[test]
fn denoised_tiles_merge_to_one_render() {
    let denoised = [
        "--set",
        "image.denoise=\"atrous\"",
        "--set",
        "denoise.iterations=3",
    ];
    if common::gpu("denoised tiles").is_some() {
        let path = [
            &["--backend", "gpu", "--set", "shading.model=\"path\""][..],
            &["--set", "image.samples=4"],
            &denoised,
        ]
        .concat();
        assert_tiles_merge_to_one_render("path-gpu-denoised", &path, &[1, 2, 3, 7]);
        let phong = [
            &["--backend", "gpu", "--set", "image.samples=3"][..],
            &["--set", "light.radius=0.3"],
            &denoised,
        ]
        .concat();
        assert_tiles_merge_to_one_render("phong-gpu-denoised", &phong, &[3]);
    }
    let cpu = [
        &["--backend", "cpu", "--set", "shading.model=\"path\""][..],
        &["--set", "image.samples=2"],
        &denoised,
    ]
    .concat();
    assert_tiles_merge_to_one_render("path-cpu-denoised", &cpu, &[3]);
}

/// With adaptive sampling: each pixel stops on its own samples alone, so the tiles' counts are
/// the whole render's (no halo), and the merge, denoiser and all, is one render.
#[test]
fn adaptive_tiles_merge_to_one_render() {
    let adaptive = [
        "--set",
        "path.noise_target=0.05",
        "--set",
        "path.min_samples=3",
    ];
    if common::gpu("adaptive tiles").is_some() {
        let path = [
            &["--backend", "gpu", "--set", "shading.model=\"path\""][..],
            &["--set", "image.samples=12"],
            &adaptive,
            &["--set", "image.denoise=\"atrous\""],
        ]
        .concat();
        assert_tiles_merge_to_one_render("path-gpu-adaptive", &path, &[2, 7]);
        let phong = [
            &["--backend", "gpu", "--set", "image.samples=12"][..],
            &["--set", "light.radius=0.3"],
            &adaptive,
        ]
        .concat();
        assert_tiles_merge_to_one_render("phong-gpu-adaptive", &phong, &[3]);
    }
    let cpu = [
        &["--backend", "cpu", "--set", "shading.model=\"path\""][..],
        &["--set", "image.samples=6"],
        &adaptive,
    ]
    .concat();
    assert_tiles_merge_to_one_render("path-cpu-adaptive", &cpu, &[3]);
}

#[test]
fn tiles_merge_to_one_cpu_render_in_both_models_and_precisions() {
    let phong = [
        "--backend",
        "cpu",
        "--set",
        "image.samples=2",
        "--set",
        "fractal.tracing=\"cone\"",
    ];
    assert_tiles_merge_to_one_render("phong-cpu", &phong, &[3]);
    let f64 = ["--backend", "cpu", "--precision", "f64"];
    assert_tiles_merge_to_one_render("phong-cpu-f64", &f64, &[2]);
    let path = [
        "--backend",
        "cpu",
        "--set",
        "shading.model=\"path\"",
        "--set",
        "image.samples=2",
    ];
    assert_tiles_merge_to_one_render("path-cpu", &path, &[3]);
}

#[test]
fn the_tiles_rows_are_k_h_over_n() {
    // 37 rows in 7 tiles: floor(k * 37 / 7) for k = 0..=7, worked by hand.
    let starts = [0, 5, 10, 15, 21, 26, 31, 37];
    for k in 0..7 {
        let tile = qjulia::tile::Tile::parse(&format!("{k}/7"), 37).unwrap();
        assert_eq!(tile.rows(37), starts[k]..starts[k + 1], "tile {k}/7");
    }
    // One tile per row.
    let last = qjulia::tile::Tile::parse("36/37", 37).unwrap();
    assert_eq!(last.rows(37), 36..37);
}

#[test]
fn bad_tiles_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fn render<'a>(extra: &[&'a str]) -> Vec<&'a str> {
        [
            &["render", "--backend", "cpu"][..],
            &SIZE,
            &["--hdr", "part.exr"],
            extra,
        ]
        .concat()
    }
    for tile in ["3/3", "0/0", "0/38", "x", "1", "-1/3", "a/b"] {
        assert_refused(d, &render(&["--tile", tile]), "error: --tile", tile);
    }
    for flag in [
        &["-o", "a.png"][..],
        &["--depth", "d.npy"],
        &["--steps", "s.npy"],
    ] {
        let args = render(&[&["--tile", "0/2"][..], flag].concat());
        assert_refused(d, &args, "error: --tile 0/2", flag[0]);
    }
    let no_hdr = ["render", "--backend", "cpu", "--tile", "0/2"];
    assert_refused(d, &no_hdr, "error: --tile 0/2", "--hdr");
    // A render to an error stops on the whole image's estimate, which a tile cannot see.
    let target = [
        "--tile",
        "0/2",
        "--set",
        "shading.model=\"path\"",
        "--set",
        "image.samples=8",
        "--set",
        "image.target_error=0.05",
    ];
    assert_refused(
        d,
        &render(&target),
        "error: --tile 0/2",
        "image.target_error",
    );
}

#[test]
fn bad_parts_are_refused_with_one_line_naming_the_part() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tile = |sets: &[&str], tile: &str, out: &str| {
        ok(
            d,
            &[
                &["render", "--backend", "cpu"][..],
                &SIZE,
                sets,
                &["--tile", tile, "--hdr", out],
            ]
            .concat(),
        );
    };
    for k in 0..3 {
        tile(&[], &format!("{k}/3"), &format!("p{k}.exr"));
    }
    tile(&["--set", "fractal.max_iterations=9"], "1/3", "foreign.exr");
    tile(&[], "1/2", "half.exr");
    ok(
        d,
        &[
            &["render", "--backend", "cpu"][..],
            &SIZE,
            &["--hdr", "whole.exr"],
        ]
        .concat(),
    );
    // A part cut short, and one with its pixels damaged.
    let bytes = std::fs::read(d.join("p1.exr")).unwrap();
    std::fs::write(d.join("short.exr"), &bytes[..bytes.len() / 2]).unwrap();
    let mut damaged = bytes.clone();
    let n = damaged.len();
    for b in &mut damaged[n - 200..n - 100] {
        *b ^= 0x5a;
    }
    std::fs::write(d.join("damaged.exr"), damaged).unwrap();
    std::fs::write(d.join("text.exr"), "not an EXR").unwrap();
    // The good parts merge.
    ok(
        d,
        &["merge", "p0.exr", "p1.exr", "p2.exr", "-o", "good.png"],
    );
    std::fs::remove_file(d.join("good.png")).unwrap();
    let files = files_in(d);
    fn merge<'a>(parts: &[&'a str]) -> Vec<&'a str> {
        let outputs = ["-o", "m.png", "--hdr", "m.exr", "--stats", "m.json"];
        [&["merge"][..], parts, &outputs].concat()
    }
    let cases: [(&[&str], &str, &str); 9] = [
        (
            &["p0.exr", "p2.exr"],
            "error: merge: rows 12..24",
            "tile 1/3",
        ),
        (
            &["p0.exr", "p1.exr", "p1.exr", "p2.exr"],
            "error: p1.exr",
            "overlap",
        ),
        (
            &["p0.exr", "half.exr", "p1.exr"],
            "error: half.exr",
            "overlap",
        ),
        (
            &["p0.exr", "foreign.exr", "p2.exr"],
            "error: foreign.exr",
            "another scene",
        ),
        (
            &["p0.exr", "short.exr", "p2.exr"],
            "error: short.exr",
            "short.exr",
        ),
        (
            &["p0.exr", "damaged.exr", "p2.exr"],
            "error: damaged.exr",
            "damaged.exr",
        ),
        (
            &["p0.exr", "text.exr", "p2.exr"],
            "error: text.exr",
            "OpenEXR",
        ),
        (
            &["p0.exr", "whole.exr", "p2.exr"],
            "error: whole.exr",
            "not a partial",
        ),
        (
            &["p0.exr", "gone.exr", "p2.exr"],
            "error: gone.exr",
            "cannot read",
        ),
    ];
    for (parts, prefix, key) in cases {
        assert_refused(d, &merge(parts), prefix, key);
    }
    assert_eq!(files_in(d), files, "a refused merge wrote a file");
}

#[test]
fn a_part_carries_its_scene_and_its_rows() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        &["render", "--backend", "cpu"][..],
        &SIZE,
        &["--tile", "2/3", "--hdr", "part.exr"],
    ]
    .concat();
    let out = ok(d, &args);
    assert!(stderr(&out).contains("rows 24..37"), "{}", stderr(&out));
    // Its scene renders again: `--scene PART.exr` is the whole image's scene.
    ok(
        d,
        &[
            "render",
            "--backend",
            "cpu",
            "--scene",
            "part.exr",
            "-o",
            "again.png",
        ],
    );
    let ([w, h], _) = qjulia::output::read_png_rgb(&d.join("again.png")).unwrap();
    assert_eq!([w, h], [40, 37]);
    // Read by an EXR reader of its own: the data window is the tile's rows of the whole
    // image, and the channels are there with their types.
    let image = exr::prelude::read_first_flat_layer_from_file(d.join("part.exr")).unwrap();
    let layer = &image.layer_data;
    assert_eq!(
        image.attributes.display_window.size,
        exr::prelude::Vec2(40, 37)
    );
    assert_eq!(layer.attributes.layer_position, exr::prelude::Vec2(0, 24));
    assert_eq!(layer.size, exr::prelude::Vec2(40, 13));
    let channels: Vec<(String, &str)> = layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let kind = match c.sample_data {
                exr::prelude::FlatSamples::F32(_) => "f32",
                exr::prelude::FlatSamples::U32(_) => "u32",
                exr::prelude::FlatSamples::F16(_) => "f16",
            };
            (c.name.to_string(), kind)
        })
        .collect();
    let want = [
        ("B", "f32"),
        ("G", "f32"),
        ("N.X", "f32"),
        ("N.Y", "f32"),
        ("N.Z", "f32"),
        ("R", "f32"),
        ("Z", "f32"),
        ("Z.mean", "f32"),
        ("albedo.B", "f32"),
        ("albedo.G", "f32"),
        ("albedo.R", "f32"),
        ("colour8", "u32"),
        ("hits", "f32"),
        ("luminance.M2", "f32"),
        ("samples", "u32"),
        ("steps", "u32"),
    ];
    let want: Vec<(String, &str)> = want.iter().map(|(n, k)| (n.to_string(), *k)).collect();
    assert_eq!(channels, want);
}
