//! The environment map (issue 38, item 1), against answers known without the renderer: its
//! distribution's density integrates to 1 and its samples follow it (chi-square); rotation
//! turns it about up; a constant map lights the set as the uniform sky of the same radiance
//! does, and a bright cap about up as the sun of the same solid angle and power does, within 3
//! standard errors; phong mode shows it behind the set and takes a constant map's irradiance
//! as its radiance; the GPU agrees with the CPU twin; relative paths resolve as the contract
//! says and the checksum rides in the PNG; bad maps are refused.

use crate::common;

use std::path::Path;
use std::sync::Arc;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::cpu::environment::{environment_pdf, sample_environment};
use qjulia::cpu::path::PathParams;
use qjulia::envmap::EnvironmentData;
use qjulia::{Frame, Picture, Precision, Scene, TraceParams};

/// A small deterministic generator for the tests' u (PCG32, O'Neill 2014).
struct Pcg(u64);

impl Pcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let x = (((self.0 >> 18) ^ self.0) >> 27) as u32;
        let r = (self.0 >> 59) as u32;
        (x.rotate_right(r) >> 8) as f32 / (1u32 << 24) as f32
    }
}

/// A 64 x 32 map: a dim gradient, a bright patch and a black band (its density must be 0 there
/// and positive wherever there is light).
fn test_texels() -> (usize, usize, Vec<[f32; 3]>) {
    let (w, h) = (64, 32);
    let texels = (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            if (20..24).contains(&j) {
                [0.0, 0.0, 0.0]
            } else if (40..44).contains(&i) && (6..9).contains(&j) {
                [50.0, 40.0, 30.0]
            } else {
                [0.1 + 0.01 * i as f32, 0.2, 0.3 + 0.02 * j as f32]
            }
        })
        .collect();
    (w, h, texels)
}

/// A scene with `map` loaded in place of a file, `sky.up` tilted and the map turned.
fn with_map(map: EnvironmentData, sets: &[&str]) -> Scene {
    let mut scene = common::scene(sets);
    scene.loaded.environment = Some(Arc::new(map));
    scene
}

fn test_params(rotation: f64) -> TraceParams<f32> {
    let (w, h, texels) = test_texels();
    let rotation = format!("environment.rotation_degrees={rotation}");
    let scene = with_map(
        EnvironmentData::of_texels(w, h, &texels),
        &["sky.up=[0.3, 1.0, -0.2]", &rotation],
    );
    TraceParams::<f32>::new(&scene)
}

/// The density integrates to 1 over the sphere: its sum over a fine grid of directions in the
/// map's own (u, v), each cell's solid angle 2 pi^2 sin(theta) du dv.
#[test]
fn the_density_integrates_to_one() {
    let p = test_params(30.0);
    let f = p.env_frame();
    let (n, m) = (1024, 512);
    let mut sum = 0.0f64;
    for j in 0..m {
        for i in 0..n {
            let uv = qjulia::algebra::Vec2::new(
                (i as f32 + 0.5) / n as f32,
                (j as f32 + 0.5) / m as f32,
            );
            let d = p.env_uv_direction(f, uv);
            let omega =
                2.0 * std::f64::consts::PI.powi(2) * (std::f64::consts::PI * uv.y as f64).sin()
                    / (n * m) as f64;
            sum += environment_pdf(&p, d) as f64 * omega;
        }
    }
    assert!((sum - 1.0).abs() < 2e-3, "{sum}");
}

/// Samples fall in proportion to the density: a chi-square test over quarters of the map's
/// texels (4 x 2,048 bins, so that where a sample falls within its texel counts too; the black
/// band's bins get none) with 400,000 samples, against the 0.1% critical value. Each sample's
/// stated density is its direction's (but for the few whose f32 direction, rounded at a
/// texel's edge, reads back in the neighbouring texel: at most 1 in 2,000), its radiance its
/// texel's, and no sample lands where the map is black.
#[test]
fn samples_follow_the_density() {
    let p = test_params(-75.0);
    let f = p.env_frame();
    let (w, h) = (64usize, 32usize);
    let mut rng = Pcg(0x853c_49e6_748f_ea9b);
    let n = 400_000;
    let (bw, bh) = (2 * w, 2 * h);
    let mut counts = vec![0u32; bw * bh];
    let mut read_back_elsewhere = 0;
    for _ in 0..n {
        let u = qjulia::algebra::Vec2::new(rng.next(), rng.next());
        let s = sample_environment(&p, u);
        assert!(s.pdf > 0.0);
        if (s.pdf - environment_pdf(&p, s.wi)).abs() > 1e-3 * s.pdf {
            read_back_elsewhere += 1;
        } else {
            assert_eq!(s.radiance, p.env_radiance(s.wi));
        }
        let uv = p.env_direction_uv(f, s.wi);
        let i = ((uv.x * bw as f32) as usize).min(bw - 1);
        let j = ((uv.y * bh as f32) as usize).min(bh - 1);
        counts[j * bw + i] += 1;
    }
    assert!(
        read_back_elsewhere <= n / 2_000,
        "{read_back_elsewhere} of {n}"
    );
    // The density over [0, 1)^2 of each texel, as packed; each of its four bins takes a quarter.
    let (mut chi2, mut bins) = (0.0f64, 0usize);
    for j in 0..bh {
        for i in 0..bw {
            let texel = (j / 2) * w + i / 2;
            let pdf_uv = p.env_word(40 + 4 * texel as u32 + 3) as f64;
            let probability = pdf_uv / (bw * bh) as f64;
            let k = counts[j * bw + i] as f64;
            if probability == 0.0 {
                assert_eq!(k, 0.0, "a sample in a black texel ({i}, {j})");
                continue;
            }
            let expected = probability * n as f64;
            chi2 += (k - expected).powi(2) / expected;
            bins += 1;
        }
    }
    // The 0.1% critical value of chi-square with df degrees of freedom (Wilson-Hilferty).
    let df = (bins - 1) as f64;
    let z = 3.0902;
    let critical = df * (1.0 - 2.0 / (9.0 * df) + z * (2.0 / (9.0 * df)).sqrt()).powi(3);
    eprintln!("chi-square {chi2:.1} over {bins} bins, critical {critical:.1}");
    assert!(
        chi2 < critical,
        "chi-square {chi2:.1} over {bins} bins, critical {critical:.1}"
    );
}

/// Directions and (u, v) are inverses, and the rotation turns the map about up: 360 degrees is
/// 0, and 90 moves every direction's u by a quarter.
#[test]
fn rotation_turns_the_map_about_up() {
    let (a, full, quarter) = (test_params(0.0), test_params(360.0), test_params(90.0));
    let mut rng = Pcg(7);
    for _ in 0..1000 {
        let uv = qjulia::algebra::Vec2::new(rng.next(), 0.02 + 0.96 * rng.next());
        let d = a.env_uv_direction(a.env_frame(), uv);
        let back = a.env_direction_uv(a.env_frame(), d);
        let near = |x: f32, y: f32| (x - y).abs() < 1e-4 || (x - y).abs() > 1.0 - 1e-4;
        assert!(near(back.x, uv.x) && (back.y - uv.y).abs() < 1e-4);
        assert!(near(full.env_direction_uv(full.env_frame(), d).x, uv.x));
        let q = quarter.env_direction_uv(quarter.env_frame(), d);
        let shift = (uv.x - q.x).rem_euclid(1.0);
        assert!((shift - 0.25).abs() < 1e-4, "{shift}");
    }
}

/// The mean and the standard error of the mean of one pixel's samples' radiance (each channel
/// summed), each sample traced by the CPU twin in f64.
fn pixel_estimate(scene: &Scene, (i, j): (u32, u32), n: u32) -> (f64, f64) {
    let params = TraceParams::<f64>::new(scene);
    let path = PathParams::<f64>::new(scene);
    let values: Vec<f64> = (0..n)
        .map(|k| {
            let r = params.trace_path(&path, i, j, k).radiance;
            r.x + r.y + r.z
        })
        .collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    (mean, (variance / n as f64).sqrt())
}

/// Pixels of the default view on the set (lit from many sides) and one off it.
const PIXELS: [(u32, u32); 4] = [(16, 16), (10, 20), (22, 12), (2, 2)];

/// Two scenes' estimates at [`PIXELS`] agree within 3 standard errors of their difference.
fn assert_same_light(what: &str, a: &Scene, b: &Scene, n: u32) {
    for &pixel in &PIXELS {
        let (ma, sa) = pixel_estimate(a, pixel, n);
        let (mb, sb) = pixel_estimate(b, pixel, n);
        let se = (sa * sa + sb * sb).sqrt();
        eprintln!(
            "{what}, pixel {pixel:?}: {ma:.5} +- {sa:.5} against {mb:.5} +- {sb:.5} ({:.2} SE)",
            (ma - mb) / se.max(1e-300)
        );
        assert!(
            (ma - mb).abs() <= 3.0 * se + 1e-6 * ma.abs(),
            "{what}, pixel {pixel:?}: {ma} +- {sa} against {mb} +- {sb}"
        );
    }
}

const PATH_VIEW: [&str; 4] = [
    "shading.model=\"path\"",
    "image.width=32",
    "image.height=32",
    "path.bounces=3",
];

/// A constant map of radiance L lights the set as the uniform gradient sky of radiance L does
/// (zenith, horizon and ground L): the same integral, one estimated with the map's light
/// sampling and the other by the BSDF's alone. Unbiased, so equal within 3 standard errors,
/// not per sample.
#[test]
fn a_constant_map_is_the_uniform_sky() {
    let l = [0.6f32, 0.5, 0.4];
    let map = EnvironmentData::of_texels(32, 16, &vec![l; 32 * 16]);
    let mut sets = PATH_VIEW.to_vec();
    let mapped = with_map(map, &sets);
    let sky = format!("[{}, {}, {}]", l[0], l[1], l[2]);
    let (z, h, g) = (
        format!("sky.zenith={sky}"),
        format!("sky.horizon={sky}"),
        format!("sky.ground={sky}"),
    );
    sets.extend([z.as_str(), h.as_str(), g.as_str()]);
    let uniform = common::scene(&sets);
    assert_same_light("constant map against uniform sky", &mapped, &uniform, 4096);
}

/// A black map with one cap about up of angular radius theta_c (two whole rows of a 128 x 64
/// map: theta_c = pi / 32) and radiance L is the sun along up of the same angular radius with
/// `sun.intensity` = L Omega, Omega = 2 pi (1 - cos theta_c) (docs/book/atmosphere.md): the
/// sun's disc then has radiance L over the same cone. Equal within 3 standard errors.
#[test]
fn a_cap_is_the_sun() {
    let (w, h, rows) = (128usize, 64usize, 2usize);
    let radiance = 40.0f32;
    let texels: Vec<[f32; 3]> = (0..w * h)
        .map(|k| match k / w < rows {
            true => [radiance; 3],
            false => [0.0; 3],
        })
        .collect();
    let theta = std::f64::consts::PI * rows as f64 / h as f64;
    let omega = 2.0 * std::f64::consts::PI * (1.0 - theta.cos());
    let mapped = with_map(EnvironmentData::of_texels(w, h, &texels), &PATH_VIEW);
    let mut sets = PATH_VIEW.to_vec();
    let (radius, intensity) = (
        format!("sun.angular_radius_degrees={}", theta.to_degrees()),
        format!("sun.intensity={}", radiance as f64 * omega),
    );
    sets.extend([
        "sun.direction=[0.0, 1.0, 0.0]",
        "sky.intensity=0",
        radius.as_str(),
        intensity.as_str(),
    ]);
    let sun = common::scene(&sets);
    assert_same_light("cap against sun", &mapped, &sun, 4096);
}

fn cpu_frame(scene: &Scene, precision: Precision) -> Frame {
    common::cpu_renderer(scene, precision)
        .render_frame(scene, Picture::SHADED)
        .expect("CPU render")
        .0
}

/// Phong mode: a miss shows the map (a constant map of 0.25: 64 of 255 in every channel), and
/// with `shading.environment_light` a constant map of radiance 1 gives the ambient term its
/// irradiance over pi, 1: the picture of `ambient` with a white ambient light, to the 8-bit
/// rounding.
#[test]
fn phong_shows_the_map_and_takes_its_irradiance() {
    let quarter = EnvironmentData::of_texels(16, 8, &vec![[0.25; 3]; 16 * 8]);
    let sets = ["image.width=24", "image.height=24", "shading.ambient=0.4"];
    let frame = cpu_frame(&with_map(quarter, &sets), Precision::F32);
    let miss = frame.colour[0];
    assert_eq!(miss & 0xff_ffff, 0x40_4040, "{miss:08x}");
    let one = EnvironmentData::of_texels(16, 8, &vec![[1.0; 3]; 16 * 8]);
    let mut lit_sets = sets.to_vec();
    lit_sets.push("shading.environment_light=true");
    let lit = cpu_frame(&with_map(one, &lit_sets), Precision::F32);
    let plain = cpu_frame(&common::scene(&sets), Precision::F32);
    let mut hits = 0;
    for (k, (a, b)) in lit.colour.iter().zip(&plain.colour).enumerate() {
        if plain.depth[k].is_nan() || plain.depth[k] < 0.0 {
            continue;
        }
        hits += 1;
        for c in 0..3 {
            let (x, y) = ((a >> (8 * c)) & 0xff, (b >> (8 * c)) & 0xff);
            assert!(x.abs_diff(y) <= 1, "pixel {k}: {a:08x} against {b:08x}");
        }
    }
    assert!(hits > 100, "{hits} hits");
}

/// The GPU and the CPU twin (f32) agree within the contract's tolerance on the built-in map:
/// path mode with a sun and fog, and phong mode with the map's ambient light, turned.
#[test]
fn gpu_and_cpu_agree_on_the_environment() {
    let scenes: [&[&str]; 2] = [
        &[
            "shading.model=\"path\"",
            "image.samples=8",
            "environment.file=\"qjulia:dusk.hdr\"",
            "environment.rotation_degrees=40",
            "sun.intensity=2",
            "fog.density=0.3",
            "path.bounces=4",
        ],
        &[
            "environment.file=\"qjulia:dusk.hdr\"",
            "environment.rotation_degrees=-120",
            "environment.intensity=0.7",
            "shading.environment_light=true",
            "shading.ambient=0.6",
            "image.samples=2",
        ],
    ];
    for sets in scenes {
        let mut all = vec!["image.width=48", "image.height=48"];
        all.extend_from_slice(sets);
        let scene = common::scene(&all);
        let name = format!("environment {}", sets.join(" "));
        let Some(actual) = common::gpu_render_frame(&name, &scene) else {
            return;
        };
        let expected = cpu_frame(&scene, Precision::F32);
        common::assert_agree(&name, &expected, &actual, &CONTRACT_TOLERANCE);
        common::assert_steps_mostly_agree(&name, &expected, &actual);
    }
}

/// Writes a Radiance map of `width` x `height` texels of `value` at `path`.
fn write_hdr(path: &Path, width: usize, height: usize, value: f32) {
    let pixels = vec![image::Rgb([value, value * 0.8, value * 0.6]); width * height];
    let file = std::fs::File::create(path).unwrap();
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&pixels, width, height)
        .unwrap();
}

/// The scene a PNG carries, as text.
fn png_scene(path: &Path) -> String {
    qjulia::scene::scene_from_png(path).unwrap()
}

/// A relative `environment.file` resolves against the scene file's folder, whatever the
/// current directory; the PNG rendered records the path as written and the map's CRC-32; a
/// scene carried by a PNG resolves against the PNG's folder, then the current directory; and
/// where neither holds the file, the error names both places.
#[test]
fn relative_maps_resolve_as_the_contract_says() {
    let root = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        root.path().join("a"),
        root.path().join("b"),
        root.path().join("c"),
    );
    for d in [&a, &b, &c] {
        std::fs::create_dir(d).unwrap();
    }
    write_hdr(&a.join("sky.hdr"), 16, 8, 0.5);
    let crc = crc32fast::hash(&std::fs::read(a.join("sky.hdr")).unwrap());
    std::fs::write(
        a.join("scene.toml"),
        "[environment]\nfile = \"sky.hdr\"\n[image]\nwidth = 8\nheight = 8\n",
    )
    .unwrap();
    // From another folder: against the scene file's.
    let scene_path = a.join("scene.toml");
    let out = b.join("x.png");
    let args = [
        "render",
        "--scene",
        scene_path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    let run = common::qjulia(&b, &args);
    assert!(run.status.success(), "{}", common::stderr(&run));
    let text = png_scene(&out);
    assert!(text.contains("file = \"sky.hdr\""), "{text}");
    assert!(text.contains(&format!("checksum = {crc}")), "{text}");
    // The PNG in b, run from a: not beside the PNG, found in the current directory.
    let again = c.join("y.png");
    let args = [
        "render",
        "--scene",
        out.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ];
    let run = common::qjulia(&a, &args);
    assert!(run.status.success(), "{}", common::stderr(&run));
    // From c: in neither place.
    let run = common::qjulia(
        &c,
        &["render", "--scene", out.to_str().unwrap(), "-o", "z.png"],
    );
    let err = common::stderr(&run);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(
        err.contains("environment.file") && err.contains("b/sky.hdr"),
        "{err}"
    );
    assert!(!c.join("z.png").exists());
    // A changed map under the recorded checksum is refused, naming the checksum.
    write_hdr(&a.join("sky.hdr"), 16, 8, 0.25);
    let run = common::qjulia(
        &a,
        &["render", "--scene", out.to_str().unwrap(), "-o", "w.png"],
    );
    let err = common::stderr(&run);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(err.contains("environment.checksum"), "{err}");
    // ... unless the file is given again by a later layer, which records its own.
    let set = format!("environment.file=\"{}\"", a.join("sky.hdr").display());
    let run = common::qjulia(
        &b,
        &[
            "render",
            "--scene",
            out.to_str().unwrap(),
            "--set",
            &set,
            "-o",
            "w.png",
        ],
    );
    assert!(run.status.success(), "{}", common::stderr(&run));
}

/// Bad maps and bad values exit 2 with one line naming the key, and write nothing: a missing
/// file, one of another format, one not 2:1, a corrupt and a truncated one, a NaN intensity,
/// and a map over the memory budget.
#[test]
fn bad_maps_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_hdr(&d.join("square.hdr"), 8, 8, 1.0);
    write_hdr(&d.join("good.hdr"), 64, 32, 1.0);
    std::fs::write(d.join("corrupt.exr"), b"this is not an OpenEXR file at all").unwrap();
    let good = std::fs::read(d.join("good.hdr")).unwrap();
    std::fs::write(d.join("cut.hdr"), &good[..good.len() / 2]).unwrap();
    std::fs::write(d.join("sky.png"), b"png").unwrap();
    for (set, key) in [
        ("environment.file=\"missing.hdr\"", "environment.file"),
        ("environment.file=\"sky.png\"", "environment.file"),
        ("environment.file=\"square.hdr\"", "environment.file"),
        ("environment.file=\"corrupt.exr\"", "environment.file"),
        ("environment.file=\"cut.hdr\"", "environment.file"),
        (
            "environment.file=\"qjulia:nothing.hdr\"",
            "environment.file",
        ),
        ("environment.intensity=nan", "environment.intensity"),
        ("environment.intensity=-1", "environment.intensity"),
    ] {
        common::assert_refused(
            d,
            &[
                "render", "--width", "8", "--height", "8", "--set", set, "-o", "x.png",
            ],
            "error: --set",
            key,
        );
    }
    // 64 x 32 texels need 64 KiB to load; a limit of 32 KiB refuses the map.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .current_dir(d)
        .env("QJULIA_MEMORY_LIMIT", "32768")
        .args(["render", "--width", "8", "--height", "8", "-o", "y.png"])
        .args(["--set", "environment.file=\"good.hdr\""])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("environment.file") && err.contains("memory"),
        "{err}"
    );
    assert!(!d.join("y.png").exists());
}
