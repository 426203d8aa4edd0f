//! The browser's fixtures (web/), made by the binary and checked in so that the TypeScript
//! tests (vitest) need no Rust build, are held fresh here: `qjulia schema --json` is
//! web/src/generated/schema.json byte for byte, and each case of web/test/fixtures/scenes.json
//! (a preset, a scene file of web/test/corpus and `--set`s) has the scene `qjulia gpu-params` resolves,
//! its uniform's bytes and its override constants, or the one line it refuses it with; and
//! web/src/generated/layout.json is the uniforms' layout `gpu-params` prints; and
//! web/test/fixtures/heatmap.json holds a render's steps and samples with the heat maps the
//! binary drew of them (`--view steps|divergence|samples`); web/e2e/fixtures/render-128.json
//! the default scene at 128x128 as the CPU twin renders it, for the page's end-to-end test. `QJULIA_BLESS=1 cargo test --release --test architecture web::` writes
//! them again from the binary.
//!
//! Why it passes 600 lines: it is the one place that makes every fixture the browser's tests
//! read (scenes, layouts, heat maps, the page's render, the environment maps), each a few lines
//! of making and one `check_file`, sharing the blessing.

use std::path::{Path, PathBuf};
use std::process::Command;

pub(crate) fn web() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("web")
}

fn bless() -> bool {
    std::env::var("QJULIA_BLESS").is_ok_and(|v| v == "1")
}

/// Compares `path`'s bytes with `made` (or writes them, blessing); a stale file fails with how
/// to make it again.
pub(crate) fn check_file(path: &Path, made: &str) {
    if bless() {
        std::fs::write(path, made).unwrap();
        return;
    }
    let held = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        held == made,
        "{} is stale: run `QJULIA_BLESS=1 cargo test --release --test architecture web::` and check in the \
         result",
        path.display()
    );
}

#[test]
fn the_schema_file_is_the_binarys() {
    let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(["schema", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let made = String::from_utf8(out.stdout).unwrap();
    let parsed: serde_json::Value = serde_json::from_str(&made).unwrap();
    assert_eq!(parsed["format"], 1);
    assert_eq!(
        parsed["keys"].as_array().unwrap().len(),
        qjulia::scene::SCHEMA.len()
    );
    check_file(&web().join("src/generated/schema.json"), &made);
}

#[test]
fn the_scene_fixtures_are_the_binarys() {
    let path = web().join("test/fixtures/scenes.json");
    let mut cases: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert!(cases.len() >= 20, "a corpus of {} scenes", cases.len());
    let (mut good, mut bad) = (0, 0);
    for case in &mut cases {
        let mut args = vec!["gpu-params".to_string(), "--json".into()];
        if let Some(preset) = case.get("preset").and_then(|p| p.as_str()) {
            args.extend(["--preset".into(), preset.into()]);
        }
        if let Some(file) = case["file"].as_str() {
            args.extend(["--scene".into(), file.into()]);
        }
        for set in case["sets"].as_array().unwrap() {
            args.extend(["--set".into(), set.as_str().unwrap().into()]);
        }
        let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
            .args(&args)
            .current_dir(web().join("test"))
            .output()
            .unwrap();
        let object = case.as_object_mut().unwrap();
        if out.status.success() {
            let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            object.insert("message".into(), serde_json::Value::Null);
            for field in ["scene", "bytes", "samples_per_dispatch"] {
                object.insert(field.into(), json[field].clone());
            }
            object.insert("path_bytes".into(), json["path"]["bytes"].clone());
            object.insert("julia2d_bytes".into(), json["julia2d"]["bytes"].clone());
            object.insert("warnings".into(), json["warnings"].clone());
            object.insert("julia2d_warnings".into(), json["julia2d_warnings"].clone());
            let text = String::from_utf8(out.stdout.clone()).unwrap();
            object.insert("overrides".into(), overrides_in_order(&text));
            good += 1;
        } else {
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            let stderr = String::from_utf8(out.stderr).unwrap();
            let lines: Vec<&str> = stderr.lines().collect();
            assert_eq!(lines.len(), 1, "{args:?}: {stderr}");
            let message = lines[0].strip_prefix("error: ").expect("error: ...");
            object.insert("message".into(), message.into());
            for field in [
                "scene",
                "bytes",
                "overrides",
                "samples_per_dispatch",
                "path_bytes",
                "julia2d_bytes",
                "warnings",
                "julia2d_warnings",
            ] {
                object.remove(field);
            }
            bad += 1;
        }
    }
    assert!(good >= 5 && bad >= 15, "{good} good and {bad} bad scenes");
    let mut made = serde_json::to_string_pretty(&cases).unwrap();
    made.push('\n');
    check_file(&path, &made);
}

/// The `overrides` object of `gpu-params`' pretty JSON as `[name, value]` pairs in the order
/// it prints them (the pipeline's constants in order; a JSON object's order is not kept).
fn overrides_in_order(text: &str) -> serde_json::Value {
    let start = text.find("\"overrides\": {").expect("an overrides object");
    let body = &text[start..];
    let end = body.find('}').expect("its end");
    let pairs: Vec<serde_json::Value> = body[..end]
        .lines()
        .skip(1)
        .filter_map(|line| {
            let (name, value) = line.trim().trim_end_matches(',').split_once(": ")?;
            let name: String = serde_json::from_str(name).ok()?;
            let value: f64 = value.parse().ok()?;
            Some(serde_json::json!([name, value]))
        })
        .collect();
    assert!(!pairs.is_empty(), "no constants in {text}");
    serde_json::Value::Array(pairs)
}

#[test]
fn the_layout_file_is_the_binarys() {
    let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(["gpu-params", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let layouts = serde_json::json!({
        "params": json["layout"],
        "julia2d": json["julia2d"]["layout"],
        "path": json["path"]["layout"],
    });
    let mut made = serde_json::to_string_pretty(&layouts).unwrap();
    made.push('\n');
    check_file(&web().join("src/generated/layout.json"), &made);
}

/// The values of a uint32 `.npy` (the `--steps` file): after its header, little-endian.
fn npy_u32(path: &Path) -> Vec<u32> {
    let bytes = std::fs::read(path).unwrap();
    let header = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    bytes[10 + header..]
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

/// The image rows of a heat-map PNG (the legend strip below them left out), as hex.
fn view_rows(path: &Path, height: u32) -> String {
    let ([w, _], rgb) = qjulia::output::read_png_rgb(path).unwrap();
    rgb[..(w * height * 3) as usize]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

#[test]
fn the_heat_map_fixture_is_the_binarys() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (w, h) = (40u32, 28u32);
    let size = ["--width", "40", "--height", "28", "--backend", "cpu"];
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
            .args(args)
            .args(size)
            .current_dir(d)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run(&[
        "render",
        "--view",
        "steps",
        "-o",
        "steps.png",
        "--steps",
        "steps.npy",
    ]);
    run(&["render", "--view", "divergence", "-o", "divergence.png"]);
    let adaptive = [
        "--set",
        "image.samples=12",
        "--set",
        "light.radius=0.4",
        "--set",
        "path.min_samples=4",
        "--set",
    ];
    let target = "path.noise_target=0.02";
    run(&[
        &["render", "--view", "samples", "-o", "samples.png"][..],
        &adaptive,
        &[target],
    ]
    .concat());
    run(&[
        &["render", "--tile", "0/1", "--hdr", "part.exr"][..],
        &adaptive,
        &[target],
    ]
    .concat());
    let (_, frame, _) = qjulia::tile::merge(&[d.join("part.exr")]).unwrap();
    let steps = npy_u32(&d.join("steps.npy"));
    assert_eq!(steps.len(), (w * h) as usize);
    let fixture = serde_json::json!({
        "width": w,
        "height": h,
        "steps": steps,
        "samples": frame.samples,
        "views": {
            "steps": view_rows(&d.join("steps.png"), h),
            "divergence": view_rows(&d.join("divergence.png"), h),
            "samples": view_rows(&d.join("samples.png"), h),
        },
    });
    let mut made = serde_json::to_string(&fixture).unwrap();
    made.push('\n');
    check_file(&web().join("test/fixtures/heatmap.json"), &made);
}

/// Standard base64 (RFC 4648, with padding) of `bytes`.
pub(crate) fn b64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (k, &b)| n | (b as u32) << (16 - 8 * k));
        for k in 0..4 {
            out.push(match k <= chunk.len() {
                true => ALPHABET[(n >> (18 - 6 * k)) as usize & 63] as char,
                false => '=',
            });
        }
    }
    out
}

/// The float32 values of a `.npy` (the `--depth` file).
fn npy_f32(path: &Path) -> Vec<f32> {
    npy_u32(path).into_iter().map(f32::from_bits).collect()
}

#[test]
fn the_page_reference_is_the_binarys() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args([
            "render",
            "--backend",
            "cpu",
            "--width",
            "128",
            "--height",
            "128",
        ])
        .args(["-o", "r.png", "--depth", "d.npy", "--steps", "s.npy"])
        .current_dir(d)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ([w, h], rgb) = qjulia::output::read_png_rgb(&d.join("r.png")).unwrap();
    let hit: Vec<u8> = npy_f32(&d.join("d.npy"))
        .iter()
        .map(|z| u8::from(!z.is_nan()))
        .collect();
    let steps: Vec<u8> = npy_u32(&d.join("s.npy"))
        .iter()
        .flat_map(|s| s.to_le_bytes())
        .collect();
    let fixture = serde_json::json!({
        "command": "qjulia render --backend cpu --width 128 --height 128",
        "width": w,
        "height": h,
        "rgb": b64(&rgb),
        "hit": b64(&hit),
        "steps": b64(&steps),
    });
    let mut made = serde_json::to_string_pretty(&fixture).unwrap();
    made.push('\n');
    std::fs::create_dir_all(web().join("e2e/fixtures")).unwrap();
    check_file(&web().join("e2e/fixtures/render-128.json"), &made);
}

/// A small deterministic generator for the camera fixture's moves (the moves are stored, so the
/// TypeScript replays them without it).
struct Moves(u64);

impl Moves {
    /// A value in [-span, span], in quarter points (as a pointer's deltas are).
    fn next(&mut self, span: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let unit = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        ((unit * 2.0 - 1.0) * span * 4.0).round() / 4.0
    }
}

fn camera_json(c: &qjulia::scene::Camera) -> serde_json::Value {
    serde_json::json!({ "eye": c.eye, "target": c.target, "fov_y_degrees": c.fov_y_degrees })
}

#[test]
fn the_camera_fixture_is_the_librarys() {
    use qjulia::explore::camera;
    use qjulia::scene::{Camera, View2d};
    let mut moves = Moves(21);
    let mut starts = vec![("the default camera", Camera::default())];
    for slug in ["rabbit", "deep-zoom"] {
        let p = qjulia::scene::presets::find(slug).expect("a preset");
        starts.push((p.name, p.scene().camera));
    }
    let tilted = Camera {
        up: [0.3, 1.0, -0.2],
        eye: [1.0, 2.9, 0.5],
        ..Default::default()
    };
    starts.push(("a tilted up", tilted));
    let mut scripts = Vec::new();
    for (name, start) in starts {
        let mut cam = start.clone();
        let mut steps = Vec::new();
        for k in 0..60 {
            let op = match k % 5 {
                0 | 1 => serde_json::json!(["orbit", moves.next(40.0), moves.next(40.0)]),
                2 => serde_json::json!(["pan", moves.next(30.0), moves.next(30.0), 256.0]),
                // Long runs of the wheel reach the closest distance and the narrowing field.
                _ => serde_json::json!(["wheel", moves.next(300.0) + 200.0]),
            };
            match op[0].as_str().unwrap() {
                "orbit" => {
                    camera::drag_orbit(&mut cam, op[1].as_f64().unwrap(), op[2].as_f64().unwrap())
                }
                "pan" => camera::drag_pan(
                    &mut cam,
                    op[1].as_f64().unwrap(),
                    op[2].as_f64().unwrap(),
                    op[3].as_f64().unwrap(),
                ),
                _ => camera::wheel_zoom(&mut cam, op[1].as_f64().unwrap()),
            }
            steps.push(serde_json::json!({ "op": op, "camera": camera_json(&cam) }));
        }
        scripts.push(serde_json::json!({
            "name": name,
            "start": { "up": start.up, "camera": camera_json(&start) },
            "steps": steps,
        }));
    }
    let mut view = View2d::default();
    let mut steps_2d = Vec::new();
    for k in 0..80 {
        let op = match k % 3 {
            0 => serde_json::json!(["drag", moves.next(50.0), moves.next(50.0), 300.0]),
            1 => serde_json::json!([
                "wheel",
                moves.next(200.0) + 150.0,
                300.0,
                [moves.next(150.0), moves.next(150.0)]
            ]),
            _ => serde_json::json!(["wheel", moves.next(400.0), 300.0, null]),
        };
        let f = |k: usize| op[k].as_f64().unwrap();
        match (op[0].as_str().unwrap(), op[3].as_array()) {
            ("drag", _) => camera::drag_2d(&mut view, f(1), f(2), f(3)),
            (_, Some(at)) => {
                let at = [at[0].as_f64().unwrap(), at[1].as_f64().unwrap()];
                camera::wheel_zoom_2d(&mut view, f(1), f(2), Some(at))
            }
            _ => camera::wheel_zoom_2d(&mut view, f(1), f(2), None),
        }
        steps_2d
            .push(serde_json::json!({ "op": op, "center": view.center, "extent": view.extent }));
    }
    let fixture = serde_json::json!({
        "constants": {
            "ORBIT_PER_POINT": camera::ORBIT_PER_POINT,
            "ZOOM_PER_POINT": camera::ZOOM_PER_POINT,
            "MIN_DISTANCE": camera::MIN_DISTANCE,
            "MAX_DISTANCE": camera::MAX_DISTANCE,
            "WIDE_FOV_DEGREES": camera::WIDE_FOV_DEGREES,
            "MIN_FOV_DEGREES": camera::MIN_FOV_DEGREES,
            "MIN_EXTENT": camera::MIN_EXTENT,
        },
        "scripts": scripts,
        "view2d": { "start": { "center": View2d::default().center, "extent": View2d::default().extent }, "steps": steps_2d },
    });
    let mut made = serde_json::to_string_pretty(&fixture).unwrap();
    made.push('\n');
    check_file(&web().join("test/fixtures/camera.json"), &made);
}

#[test]
fn the_display_fixture_is_the_librarys() {
    use qjulia::display::{Display, ToneMap};
    // f32 radiances: 0, negatives, a geometric sweep over 1e-6..1e3, the sRGB knee's
    // neighbours, and the f32s whose 8-bit value is about to change under no tone map.
    let mut values: Vec<f32> = vec![0.0, -0.5, -1e-9, 0.003_130_8, 0.003_130_7, 1.0, 2.0];
    values.extend((0..1200).map(|k| 1e-6f32 * 10f32.powf(k as f32 / 133.0)));
    let plain = Display::default();
    for k in 1..255u32 {
        // The smallest f32 that encodes to k, by bisection, and the one just below it.
        let (mut lo, mut hi) = (0.0f32, 1.0f32);
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if u32::from(plain.encode(mid)) >= k {
                hi = mid
            } else {
                lo = mid
            }
        }
        values.extend([hi, f32::from_bits(hi.to_bits() - 1)]);
    }
    let mut cases = Vec::new();
    for tone_map in ToneMap::ALL {
        for exposure in [0.0, -1.5, 2.25, 7.0] {
            let d = Display { exposure, tone_map };
            let bytes: String = values
                .iter()
                .map(|&v| format!("{:02x}", d.encode(v)))
                .collect();
            cases.push(serde_json::json!({
                "tone_map": tone_map.name(), "exposure": exposure, "bytes": bytes
            }));
        }
    }
    let fixture = serde_json::json!({
        "values": values.iter().map(|&v| v as f64).collect::<Vec<_>>(),
        "cases": cases,
    });
    let mut made = serde_json::to_string_pretty(&fixture).unwrap();
    made.push('\n');
    check_file(&web().join("test/fixtures/display.json"), &made);
}

#[test]
fn the_png_fixture_is_the_binarys() {
    // A qjulia PNG (an 8x6 render of the rabbit), for the page's reader of the scene chunk.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rabbit.png");
    let status = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args([
            "render", "--preset", "rabbit", "--width", "8", "--height", "6",
        ])
        .args(["--backend", "cpu", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(status.status.success());
    let made = std::fs::read(&out).unwrap();
    let path = web().join("test/fixtures/rabbit.png");
    if bless() {
        std::fs::write(&path, &made).unwrap();
    }
    assert!(
        std::fs::read(&path).unwrap_or_default() == made,
        "{} is stale: run `QJULIA_BLESS=1 cargo test --release --test architecture web::`",
        path.display()
    );
}

/// The numbers of a `const NAME = [a, b, ...];` line of a TypeScript file.
fn ts_numbers(text: &str, name: &str) -> Vec<u64> {
    let start = text
        .find(&format!("const {name} = ["))
        .unwrap_or_else(|| panic!("no {name} in the file"));
    let list = &text[start..];
    let list = &list[list.find('[').unwrap() + 1..list.find(']').unwrap()];
    list.split(',').map(|n| n.trim().parse().unwrap()).collect()
}

/// The page binds its kernels' outputs as the Rust runner does: web/src/gpu.ts's bytes a pixel
/// of each output are the kernel specs' (bytes an item times planes), so that a kernel that
/// widens an output cannot write past a buffer the page made for the old width.
#[test]
fn the_pages_output_sizes_are_the_runners() {
    let gpu_ts = std::fs::read_to_string(web().join("src/gpu.ts")).unwrap();
    let bytes = |outputs: &[qjulia::gpu::OutputSpec]| -> Vec<u64> {
        outputs
            .iter()
            .map(|o| o.bytes_per_item * o.planes)
            .collect()
    };
    assert_eq!(
        ts_numbers(&gpu_ts, "OUTPUT_BYTES"),
        bytes(&qjulia::gpu::TRACE_OUTPUTS)
    );
    assert_eq!(
        ts_numbers(&gpu_ts, "JULIA2D_OUTPUT_BYTES"),
        bytes(qjulia::gpu::JULIA2D_KERNEL.outputs)
    );
}

/// A map's texels, made up: varied colours over many exponents, with runs of equal texels (the
/// RLE's runs) and zeros.
fn map_texel(i: usize, j: usize) -> [f32; 3] {
    if (i / 4 + j).is_multiple_of(5) {
        return [0.25, 0.5, 1.0];
    }
    let x = (i as f32 + 1.0) * 0.37 + j as f32 * 1.9;
    [
        x.sin().abs() * 3.0,
        (x * 0.5).cos().abs() * 0.01,
        x * x * 0.125 % 40.0,
    ]
}

fn map_texels(width: usize, height: usize) -> Vec<[f32; 3]> {
    (0..height)
        .flat_map(|j| (0..width).map(move |i| map_texel(i, j)))
        .collect()
}

/// A Radiance file of the made-up texels (new-style RLE from 8 wide, flat scanlines below).
fn map_hdr(width: usize, height: usize) -> Vec<u8> {
    let pixels: Vec<image::Rgb<f32>> = map_texels(width, height)
        .into_iter()
        .map(image::Rgb)
        .collect();
    let mut out = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut out)
        .encode(&pixels, width, height)
        .unwrap();
    out
}

/// A Radiance file whose scanlines use the old run-length scheme (a pixel of 1, 1, 1 repeats
/// the one before, 256 times more for each such pixel in a row).
fn map_hdr_old_rle() -> Vec<u8> {
    let mut out = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n".to_vec();
    // Row 0: a pixel and a run of three; row 1: four pixels as they are.
    out.extend([100, 50, 25, 130, 1, 1, 1, 3]);
    out.extend([
        10, 20, 30, 129, 200, 0, 7, 120, 0, 0, 0, 0, 255, 255, 255, 140,
    ]);
    out
}

/// An OpenEXR file of the made-up texels: RGB(A) in `f16` or `f32`, compressed so, in scan
/// lines of the given order.
fn map_exr(
    width: usize,
    height: usize,
    half: bool,
    compression: exr::prelude::Compression,
    line_order: exr::prelude::LineOrder,
    texel: impl Fn(usize, usize) -> [f32; 3] + Sync,
) -> Vec<u8> {
    use exr::prelude::*;
    let encoding = Encoding {
        compression,
        blocks: Blocks::ScanLines,
        line_order,
    };
    let mut out = std::io::Cursor::new(Vec::new());
    let attributes = LayerAttributes::named("sky");
    if half {
        let channels = SpecificChannels::rgba(|p: Vec2<usize>| {
            let [r, g, b] = texel(p.x(), p.y());
            (
                f16::from_f32(r),
                f16::from_f32(g),
                f16::from_f32(b),
                f16::ONE,
            )
        });
        Image::from_layer(Layer::new((width, height), attributes, encoding, channels))
            .write()
            .to_buffered(&mut out)
            .unwrap();
    } else {
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
            let [r, g, b] = texel(p.x(), p.y());
            (r, g, b)
        });
        Image::from_layer(Layer::new((width, height), attributes, encoding, channels))
            .write()
            .to_buffered(&mut out)
            .unwrap();
    }
    out.into_inner()
}

/// Little-endian bytes of f32s.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A packed map as the fixture holds it: its size and checksum, the CRC-32 of each part of the
/// buffer (header and irradiance, texels, marginal CDF, rows' CDFs), and the whole buffer where
/// it is small (else its head, the size and the irradiance).
fn packed_json(width: usize, height: usize, checksum: u32, packed: &[f32]) -> serde_json::Value {
    let texels = 40 + 4 * width * height;
    let marginal = texels + height + 1;
    let parts = [
        &packed[..40],
        &packed[40..texels],
        &packed[texels..marginal],
        &packed[marginal..],
    ];
    let crcs: Vec<u32> = parts
        .iter()
        .map(|p| crc32fast::hash(&f32_bytes(p)))
        .collect();
    let mut json = serde_json::json!({
        "width": width, "height": height, "checksum": checksum, "floats": packed.len(),
        "part_crcs": crcs,
    });
    if packed.len() <= 4096 {
        json["packed"] = b64(&f32_bytes(packed)).into();
    } else {
        json["head"] = b64(&f32_bytes(&packed[..40])).into();
    }
    json
}

/// The page's reader and packer of environment maps (web/src/envmap.ts) against the library's:
/// map files in each format the page reads (web/test/fixtures/envmap/, written here), the
/// built-in dusk.hdr, and a map halved to fit a binding, each with the buffer
/// `qjulia::envmap` packs of it; and the library's words for the maps it refuses.
#[test]
fn the_environment_map_fixture_is_the_librarys() {
    use exr::prelude::{Compression, LineOrder};
    use qjulia::envmap::{MapFormat, from_bytes, pack};
    let dir = web().join("test/fixtures/envmap");
    std::fs::create_dir_all(&dir).unwrap();
    let files: Vec<(&str, Vec<u8>)> = vec![
        ("rle.hdr", map_hdr(32, 16)),
        ("flat.hdr", map_hdr(4, 2)),
        ("old-rle.hdr", map_hdr_old_rle()),
        (
            "half-zip.exr",
            map_exr(
                32,
                16,
                true,
                Compression::ZIP16,
                LineOrder::Increasing,
                map_texel,
            ),
        ),
        (
            "float-zips.exr",
            map_exr(
                32,
                16,
                false,
                Compression::ZIP1,
                LineOrder::Decreasing,
                map_texel,
            ),
        ),
        (
            "float-raw.exr",
            map_exr(
                16,
                8,
                false,
                Compression::Uncompressed,
                LineOrder::Increasing,
                map_texel,
            ),
        ),
        (
            "half-rle.exr",
            map_exr(
                16,
                8,
                true,
                Compression::RLE,
                LineOrder::Increasing,
                map_texel,
            ),
        ),
        ("square.hdr", map_hdr(8, 8)),
        (
            "negative.exr",
            map_exr(
                8,
                4,
                false,
                Compression::Uncompressed,
                LineOrder::Increasing,
                |i, j| [0.5, if (i, j) == (5, 2) { -2.0 } else { 0.25 }, 1.0],
            ),
        ),
    ];
    let mut maps = Vec::new();
    for (name, bytes) in &files {
        let path = dir.join(name);
        if bless() {
            std::fs::write(&path, bytes).unwrap();
        }
        assert!(
            std::fs::read(&path).unwrap_or_default() == *bytes,
            "{} is stale: run `QJULIA_BLESS=1 cargo test --release --test architecture web::`",
            path.display()
        );
        let format = MapFormat::of(Path::new(name)).unwrap();
        let mut json = serde_json::json!({ "file": format!("envmap/{name}") });
        match from_bytes(bytes, format, None) {
            Ok(map) => {
                let packed = pack(map.width, map.height, &map.texels);
                let packed = packed_json(map.width, map.height, map.checksum, &packed);
                json.as_object_mut()
                    .unwrap()
                    .extend(packed.as_object().unwrap().clone());
            }
            Err(message) => json["message"] = message.into(),
        }
        maps.push(json);
    }
    let dusk =
        qjulia::envmap::load_source(&qjulia::envmap::MapSource::Builtin("dusk.hdr")).unwrap();
    let mut dusk_json = packed_json(dusk.width, dusk.height, dusk.checksum, &dusk.packed);
    dusk_json["file"] = "../../../assets/environment/dusk.hdr".into();
    maps.push(dusk_json);
    // 4096 x 2048 packs to more than 128 MiB: halved once, to 2048 x 1024. Its texels are
    // `halving_texel` (web/test/envmap.test.ts makes the same), written as an EXR of f32.
    let halving_texel = |i: usize, j: usize| {
        [
            (i % 7) as f32 * 0.5,
            (j % 5) as f32 * 0.25,
            ((i + j) % 3) as f32,
        ]
    };
    let tmp = tempfile::tempdir().unwrap();
    let big = tmp.path().join("big.exr");
    let exr = map_exr(
        4096,
        2048,
        false,
        Compression::Uncompressed,
        LineOrder::Increasing,
        halving_texel,
    );
    std::fs::write(&big, exr).unwrap();
    let halved = qjulia::envmap::load_source(&qjulia::envmap::MapSource::File(big)).unwrap();
    assert_eq!(halved.downsampled_from, Some((4096, 2048)));
    let mut halved_json = packed_json(halved.width, halved.height, halved.checksum, &halved.packed);
    halved_json["file"] = serde_json::Value::Null;
    halved_json["texels"] = "halving".into();
    halved_json["downsampled_from"] = serde_json::json!([4096, 2048]);
    maps.push(halved_json);
    let mut made = serde_json::to_string_pretty(&serde_json::json!({ "maps": maps })).unwrap();
    made.push('\n');
    check_file(&web().join("test/fixtures/envmap.json"), &made);
}
