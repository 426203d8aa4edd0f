//! Path mode (`shading.model = "path"`) through the renderer and the binary: the GPU against
//! the CPU twin on the 8-bit display image, the white furnace and a background-only view from
//! the scene's keys alone, phong untouched by the path keys, bad values refused, and the PNG's
//! scene read back.

use crate::common;

use std::sync::{Arc, OnceLock};

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::gpu::GpuKernels;
use qjulia::{Backend, Frame, Picture, Planner, Precision, PrecisionChoice, Scene};

/// The renderer of `scene` on the tests' GPU (f32), or None where GPU tests are skipped.
fn gpu_renderer(test: &str, scene: &Scene) -> Option<qjulia::Renderer> {
    let tracer = common::gpu(test)?;
    static KERNELS: OnceLock<Arc<GpuKernels>> = OnceLock::new();
    let kernels = KERNELS.get_or_init(|| Arc::new(GpuKernels::new(tracer.context().clone())));
    let plan = Planner::on_device(kernels.clone(), Backend::Gpu, PrecisionChoice::F32)
        .plan(scene, Picture::SHADED.into(), &mut |_| {})
        .expect("a GPU plan");
    Some(plan.renderer)
}

fn cpu_frame(scene: &Scene, precision: Precision) -> Frame {
    common::cpu_renderer(scene, precision)
        .render_frame(scene, Picture::SHADED)
        .expect("CPU render")
        .0
}

fn path_scene(extra: &[&str]) -> Scene {
    let mut sets = vec!["shading.model=\"path\""];
    sets.extend_from_slice(extra);
    common::scene(&sets)
}

/// The sRGB transfer function (IEC 61966-2-1), written out here, and 8-bit rounding.
fn srgb8(linear: f64) -> u8 {
    let v = linear.clamp(0.0, 1.0);
    let encoded = if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (255.0 * encoded + 0.5).floor() as u8
}

/// Path traced, the GPU agrees with the CPU twin in f32 on the display image within
/// CONTRACT_TOLERANCE at equal samples: the same sampler bits, the same estimator. Paths part
/// where a branch (a hit, a lobe choice, roulette) falls the other way on one rounding; the
/// share of pixels whose linear radiance differs by more than 1% says how often.
#[test]
fn gpu_and_cpu_agree_on_the_display_image() {
    let scenes: [&[&str]; 3] = [
        &["sun.intensity=3", "image.tone_map=\"aces\""],
        &[
            "shading.colouring=\"orbit_trap\"",
            "cut.enabled=true",
            "material.metallic=1",
            "material.roughness=0.25",
            "light.intensity=6",
            "light.radius=0.4",
            "path.bounces=5",
            "image.exposure=0.5",
            "image.tone_map=\"reinhard\"",
        ],
        &[
            "path.sampler=\"random\"",
            "sun.intensity=2",
            "path.clamp=4",
            "light.intensity=4",
        ],
    ];
    for sets in scenes {
        let mut all = vec!["image.width=64", "image.height=64", "image.samples=8"];
        all.extend_from_slice(sets);
        let scene = path_scene(&all);
        let name = format!("path {}", sets.join(" "));
        let Some(gpu) = gpu_renderer(&name, &scene) else {
            return;
        };
        let (actual, _) = gpu
            .render_frame(&scene, Picture::SHADED)
            .expect("GPU render");
        let expected = cpu_frame(&scene, Precision::F32);
        assert_eq!(actual.radiance.len(), actual.pixel_count());
        common::assert_agree(&name, &expected, &actual, &CONTRACT_TOLERANCE);
        let parted = expected
            .radiance
            .iter()
            .zip(&actual.radiance)
            .filter(|(e, a)| {
                (0..3).any(|c| (e[c] - a[c]).abs() > 0.01 * e[c].abs().max(a[c].abs()).max(1e-3))
            })
            .count();
        eprintln!(
            "{name}: {parted} of {} pixels' radiance differ by over 1% ({:.2}%)",
            expected.pixel_count(),
            100.0 * parted as f64 / expected.pixel_count() as f64
        );
        // Sample 0 is the pinhole's camera ray: its depth and steps are the tracer's.
        common::assert_steps_mostly_agree(&name, &expected, &actual);
    }
}

/// The white furnace from scene keys alone: the unit ball (c = 0), a Lambert albedo of 0.5
/// under a uniform sky of radiance 1, no sun and no sphere light. Every path that hits leaves
/// after one bounce with radiance 0.5, every miss has 1, at any number of bounces: at one
/// sample the PNG holds exactly sRGB(0.5) and 255, on both backends and in both precisions.
#[test]
fn the_white_furnace_from_scene_keys() {
    let scene = path_scene(&[
        "fractal.c=[0.0, 0.0, 0.0, 0.0]",
        "sky.zenith=[1.0, 1.0, 1.0]",
        "sky.horizon=[1.0, 1.0, 1.0]",
        "sky.ground=[1.0, 1.0, 1.0]",
        "shading.diffuse=[0.5, 0.5, 0.5]",
        "material.specular=0",
        "material.metallic=0",
        "path.bounces=4",
        "image.width=32",
        "image.height=32",
    ]);
    let grey = srgb8(0.5) as u32;
    let hit = 0xff00_0000 | grey << 16 | grey << 8 | grey;
    let check = |name: &str, frame: &Frame| {
        let mut hits = 0;
        for (k, (&c, d)) in frame.colour.iter().zip(&frame.depth).enumerate() {
            let expected = if d.is_nan() { 0xffff_ffff } else { hit };
            hits += usize::from(!d.is_nan());
            assert_eq!(c, expected, "{name}: pixel {k} is {c:08x}");
        }
        assert!(
            hits > 100,
            "{name}: the ball fills the middle ({hits} hits)"
        );
    };
    check("CPU f64", &cpu_frame(&scene, Precision::F64));
    check("CPU f32", &cpu_frame(&scene, Precision::F32));
    if let Some(gpu) = gpu_renderer("white furnace from scene keys", &scene) {
        check("GPU", &gpu.render_frame(&scene, Picture::SHADED).unwrap().0);
    }
}

/// Tone map "none" at exposure 0 on a view of the background alone gives the sky's sRGB
/// colour; exposure 1 doubles it before the curve.
#[test]
fn a_background_only_view_is_the_skys_srgb_colour() {
    let sky = [0.2, 0.4, 0.05];
    let colour = format!("[{}, {}, {}]", sky[0], sky[1], sky[2]);
    let sets = |exposure: &str| {
        vec![
            "camera.target=[0.0, 0.0, 6.0]".to_string(),
            format!("sky.zenith={colour}"),
            format!("sky.horizon={colour}"),
            format!("sky.ground={colour}"),
            format!("image.exposure={exposure}"),
            "image.width=16".into(),
            "image.height=16".into(),
        ]
    };
    for (exposure, scale) in [("0", 1.0), ("1", 2.0)] {
        let owned = sets(exposure);
        let refs: Vec<&str> = owned.iter().map(String::as_str).collect();
        let scene = path_scene(&refs);
        let [r, g, b] = sky.map(|c| srgb8(c * scale) as u32);
        let expected = 0xff00_0000 | b << 16 | g << 8 | r;
        let frame = cpu_frame(&scene, Precision::F64);
        assert!(frame.depth.iter().all(|d| d.is_nan()), "nothing is hit");
        assert!(
            frame.colour.iter().all(|&c| c == expected),
            "exposure {exposure}: {:08x} != {expected:08x}",
            frame.colour[0]
        );
    }
}

/// The path keys change nothing in phong mode: its pixels, depth and steps are those of the
/// defaults.
#[test]
fn phong_mode_ignores_the_path_keys() {
    let base = common::scene(&["image.width=48", "image.height=48", "image.samples=2"]);
    let with_path_keys = common::scene(&[
        "image.width=48",
        "image.height=48",
        "image.samples=2",
        "material.roughness=0.9",
        "material.metallic=1",
        "sky.intensity=3",
        "sun.intensity=5",
        "light.intensity=9",
        "path.bounces=7",
        "image.exposure=2",
        "image.tone_map=\"aces\"",
    ]);
    let a = cpu_frame(&base, Precision::F32);
    let b = cpu_frame(&with_path_keys, Precision::F32);
    assert_eq!(a.colour, b.colour);
    assert_eq!(a.steps, b.steps);
    assert!(a.radiance.is_empty() && b.radiance.is_empty());
}

/// Bad path values exit 2 with one line naming the key, and write nothing.
#[test]
fn bad_path_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (set, key) in [
        ("shading.model=\"pbr\"", "shading.model"),
        ("material.roughness=2", "material.roughness"),
        ("material.metallic=-0.5", "material.metallic"),
        ("material.specular=1.5", "material.specular"),
        ("path.bounces=0", "path.bounces"),
        ("path.bounces=17", "path.bounces"),
        ("path.clamp=-1", "path.clamp"),
        ("path.sampler=\"halton\"", "path.sampler"),
        ("image.tone_map=\"filmic\"", "image.tone_map"),
        ("image.exposure=inf", "image.exposure"),
        ("camera.aperture=-0.1", "camera.aperture"),
        ("camera.blades=2", "camera.blades"),
        ("sun.angular_radius_degrees=0", "sun.angular_radius_degrees"),
        (
            "sun.angular_radius_degrees=91",
            "sun.angular_radius_degrees",
        ),
        ("sun.intensity=nan", "sun.intensity"),
        ("sun.direction=[0.0, 0.0, 0.0]", "sun.direction"),
        ("sky.up=[0.0, 0.0, 0.0]", "sky.up"),
        ("sky.zenith=[0.5, -0.1, 0.5]", "sky.zenith"),
        ("light.intensity=nan", "light.intensity"),
        ("light.intensity=-2", "light.intensity"),
    ] {
        common::assert_refused(
            dir.path(),
            &[
                "render",
                "--width",
                "8",
                "--height",
                "8",
                "--set",
                "shading.model=\"path\"",
                "--set",
                set,
                "-o",
                "x.png",
            ],
            "error: --set",
            key,
        );
    }
    // From a file, the error names the file.
    std::fs::write(
        dir.path().join("scene.toml"),
        "[shading]\nmodel = \"path\"\n[path]\nbounces = 17\n",
    )
    .unwrap();
    let out = common::qjulia(
        dir.path(),
        &["render", "--scene", "scene.toml", "-o", "x.png"],
    );
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("scene.toml") && stderr.contains("path.bounces"));
    assert!(!dir.path().join("x.png").exists());
}

/// A path-traced PNG carries its scene, path keys and all: `--scene out.png` renders the same
/// bytes again.
#[test]
fn a_path_traced_png_renders_again_from_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--backend",
        "cpu",
        "--width",
        "24",
        "--height",
        "16",
        "--set",
        "shading.model=\"path\"",
        "--set",
        "sun.intensity=2.5",
        "--set",
        "material.roughness=0.55",
        "--set",
        "image.tone_map=\"aces\"",
        "--set",
        "image.samples=3",
        "-o",
        "a.png",
    ];
    let out = common::qjulia(dir.path(), &args);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let out = common::qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--scene",
            "a.png",
            "-o",
            "b.png",
        ],
    );
    assert!(out.status.success(), "{}", common::stderr(&out));
    let text = qjulia::scene::scene_from_png(&dir.path().join("a.png")).unwrap();
    for line in [
        "model = \"path\"",
        "roughness = 0.55",
        "tone_map = \"aces\"",
    ] {
        assert!(text.contains(line), "the PNG's scene has {line}:\n{text}");
    }
    let pixels = |name: &str| {
        let img = image::open(dir.path().join(name)).unwrap().to_rgb8();
        img.into_raw()
    };
    assert_eq!(pixels("a.png"), pixels("b.png"));
}
