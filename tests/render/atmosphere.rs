//! The atmosphere (issue 38): fog in both models, phong mode's glow and path mode's emission,
//! against answers known without the renderer. An absorbing fog passes exactly the
//! transmittance of the ray's chord through the ball; single scattering under a collimated sun
//! matches its integral (quadrature in f64) within 3 standard errors; a white fog under a uniform
//! sky is the sky; the glow only brightens misses; an emissive ball shows its emission times its
//! albedo; and the GPU agrees with the CPU twin.

use crate::common;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::cpu::path::PathParams;
use qjulia::{Frame, Picture, Precision, Scene, TraceParams};

fn cpu_frame(scene: &Scene, precision: Precision) -> Frame {
    common::cpu_renderer(scene, precision)
        .render_frame(scene, Picture::SHADED)
        .expect("CPU render")
        .0
}

/// The GPU's frame of `scene` (f32), or None where GPU tests are skipped.
fn gpu_frame(test: &str, scene: &Scene) -> Option<Frame> {
    common::gpu_render_frame(test, scene)
}

/// The set cut away (the half-space z <= -10 holds none of the ball), so that every ray misses
/// and crosses the fog alone.
const NO_SET: [&str; 3] = [
    "cut.enabled=true",
    "cut.normal=[0.0, 0.0, 1.0]",
    "cut.offset=-10.0",
];

/// The length of the camera ray of pixel (i, j) (through its centre) inside the bounding ball,
/// from the scene's ball and camera by plain geometry in f64.
fn chord(scene: &Scene, params: &TraceParams<f64>, i: u32, j: u32) -> f64 {
    let d = params.camera_ray(i, j, 0);
    let d = [d.x, d.y, d.z];
    let bounds = scene.slice_bounds();
    let oc: Vec<f64> = (0..3)
        .map(|k| scene.camera.eye[k] - bounds.center[k])
        .collect();
    let b: f64 = (0..3).map(|k| oc[k] * d[k]).sum();
    let foot2: f64 = (0..3).map(|k| (oc[k] - b * d[k]).powi(2)).sum();
    2.0 * (bounds.radius_squared - foot2).max(0.0).sqrt()
}

/// Path mode, an absorbing fog (colour 0) under a uniform sky of radiance 1 with the set cut
/// away: each pixel's radiance is exp(-density chord) exactly (to f32's rounding), on the CPU in
/// both precisions and on the GPU. Phong mode's blend toward black gives the background times
/// the same transmittance, to the 8-bit rounding.
#[test]
fn an_absorbing_fog_passes_exactly_the_transmittance() {
    let density = 0.7;
    let mut sets = vec![
        "image.width=24".to_string(),
        "image.height=24".to_string(),
        format!("fog.density={density}"),
        "fog.colour=[0.0, 0.0, 0.0]".into(),
        "camera.fov_y_degrees=60".into(),
    ];
    sets.extend(NO_SET.iter().map(|s| s.to_string()));
    let mut path_sets = sets.clone();
    path_sets.extend([
        "shading.model=\"path\"".to_string(),
        "sky.zenith=[1.0, 1.0, 1.0]".into(),
        "sky.horizon=[1.0, 1.0, 1.0]".into(),
        "sky.ground=[1.0, 1.0, 1.0]".into(),
    ]);
    let refs: Vec<&str> = path_sets.iter().map(String::as_str).collect();
    let scene = common::scene(&refs);
    let params = TraceParams::<f64>::new(&scene);
    let expected: Vec<f64> = (0..24 * 24)
        .map(|k| (-density * chord(&scene, &params, k % 24, k / 24)).exp())
        .collect();
    assert!(
        expected.iter().any(|&t| t < 0.2) && expected.contains(&1.0),
        "the view holds thick fog and clear sky"
    );
    let mut frames = vec![
        ("CPU f32", cpu_frame(&scene, Precision::F32)),
        ("CPU f64", cpu_frame(&scene, Precision::F64)),
    ];
    if let Some(frame) = gpu_frame("absorbing fog", &scene) {
        frames.push(("GPU", frame));
    }
    for (name, frame) in &frames {
        for (k, (got, want)) in frame.radiance.iter().zip(&expected).enumerate() {
            for c in got {
                assert!(
                    (*c as f64 - want).abs() <= 2e-6 + 1e-5 * want,
                    "{name}, pixel {k}: {c} against exp(-density chord) {want}"
                );
            }
        }
    }

    let mut phong_sets = sets;
    phong_sets.push("shading.background=[0.5, 0.5, 0.5]".into());
    let refs: Vec<&str> = phong_sets.iter().map(String::as_str).collect();
    let scene = common::scene(&refs);
    let mut frames = vec![("CPU f32", cpu_frame(&scene, Precision::F32))];
    if let Some(frame) = gpu_frame("absorbing fog, phong", &scene) {
        frames.push(("GPU", frame));
    }
    for (name, frame) in &frames {
        for (k, (rgb, want)) in frame.rgb8().chunks(3).zip(&expected).enumerate() {
            let want = 255.0 * 0.5 * want;
            for &c in rgb {
                assert!(
                    (c as f64 - want).abs() <= 1.0,
                    "{name} phong, pixel {k}: {c} against {want:.2}"
                );
            }
        }
    }
}

/// The mean and the standard error of the mean of one pixel's samples' red radiance, each
/// sample traced by the CPU twin in f64.
fn pixel_estimate(
    params: &TraceParams<f64>,
    path: &PathParams<f64>,
    (i, j): (u32, u32),
    n: u32,
) -> (f64, f64) {
    let values: Vec<f64> = (0..n)
        .map(|k| params.trace_path(path, i, j, k).radiance.x)
        .collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    (mean, (variance / n as f64).sqrt())
}

/// The Henyey-Greenstein phase function, written out here.
fn henyey_greenstein(g: f64, c: f64) -> f64 {
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * c).powf(1.5))
}

/// Where the ray x + t w (w unit) leaves the ball of centre `c` and radius^2 `r2`, x inside.
fn exit_distance(x: [f64; 3], w: [f64; 3], c: [f64; 3], r2: f64) -> f64 {
    let oc: Vec<f64> = (0..3).map(|k| x[k] - c[k]).collect();
    let b: f64 = (0..3).map(|k| oc[k] * w[k]).sum();
    let cc: f64 = oc.iter().map(|v| v * v).sum::<f64>() - r2;
    -b + (b * b - cc).max(0.0).sqrt()
}

/// Single scattering under a collimated sun, the closed form: along a camera ray that crosses
/// the ball over [t0, t1], the light the fog scatters toward the camera is
/// integral over s of sigma_s exp(-sigma_t (s - t0)) p(cos) E exp(-sigma_t l(x(s))) ds, with p
/// the phase function at the angle between the sun's light and the ray, E the sun's
/// irradiance and l the distance from x(s) to the ball's rim toward the sun. With one bounce and
/// a black sky the path tracer estimates exactly that (the sun's disc is 0.05 degrees, so the
/// phase function and l vary across it by parts in 10^5). Checked at three pixels, each within 3
/// standard errors of its 4,096 samples, for an optically thin fog (0.05 per unit, 0.17 across
/// the ball) and a thick one (0.5, 1.7).
#[test]
fn single_scattering_matches_the_closed_form() {
    let (g, albedo, irradiance) = (0.4, 0.8, 2.0);
    let sun = unit([0.3, 1.0, -0.4]);
    for density in [0.05, 0.5] {
        let mut sets = single_scattering_scene(sun, density, albedo, g, irradiance);
        sets.extend(NO_SET.iter().map(|s| s.to_string()));
        let medium = Medium {
            sun,
            density,
            albedo,
            g,
            irradiance,
        };
        let pixels = [(512, 512), (300, 700), (700, 420)];
        check_single_scattering(&sets, &medium, &pixels, |_| true);
    }
}

/// Light shafts: the unit ball (c = 0) in a fog ball of radius 3, the sun straight above. Rays
/// below the ball cross its shadow, a cylinder of radius 1 about the vertical axis, where the
/// fog gets no sunlight: single scattering with that shadow (the closed form's visibility, by
/// plain geometry) matches the path tracer's within 3 standard errors, at pixels whose rays pass
/// through the shadow and beside it; and those through it are darker than those beside.
#[test]
fn the_sets_shadow_in_the_fog_matches_the_closed_form() {
    let (g, albedo, irradiance, density) = (0.3, 0.8, 2.0, 0.2);
    let sun = [0.0, 1.0, 0.0];
    let mut sets = single_scattering_scene(sun, density, albedo, g, irradiance);
    sets.extend([
        "fractal.c=[0, 0, 0, 0]".to_string(),
        "fractal.bounding_radius_squared=9".into(),
        "camera.eye=[0.0, 0.0, 4.0]".into(),
        "camera.fov_y_degrees=70".into(),
    ]);
    let medium = Medium {
        sun,
        density,
        albedo,
        g,
        irradiance,
    };
    // The unit ball's shadow: the sun's ray from x meets the ball (x below its centre's
    // height, within the cylinder of radius 1; the set's surface is at 1 + O(epsilon)).
    let lit = |x: [f64; 3]| x[1] >= 0.0 || x[0] * x[0] + x[2] * x[2] >= 1.0;
    // Rows below the ball: the rays pass under it, through the shadow's cylinder at the
    // middle column and beside it at the edge.
    let shadowed = [(512, 820), (540, 900)];
    let beside = [(900, 820), (130, 900)];
    let through = check_single_scattering(&sets, &medium, &shadowed, lit);
    let outside = check_single_scattering(&sets, &medium, &beside, lit);
    for (a, b) in through.iter().zip(&outside) {
        assert!(a < b, "the shadow is darker: {a} against {b}");
    }
}

/// The unit vector along v.
fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.map(|x| x / n)
}

/// A fog lit by a collimated sun alone (black sky, one bounce): the `--set`s.
fn single_scattering_scene(
    sun: [f64; 3],
    density: f64,
    albedo: f64,
    g: f64,
    irradiance: f64,
) -> Vec<String> {
    vec![
        "shading.model=\"path\"".to_string(),
        "image.width=1024".into(),
        "image.height=1024".into(),
        "image.samples=4096".into(),
        "path.bounces=1".into(),
        "sky.intensity=0".into(),
        format!("sun.direction=[{}, {}, {}]", sun[0], sun[1], sun[2]),
        "sun.angular_radius_degrees=0.05".into(),
        format!("sun.intensity={irradiance}"),
        format!("fog.density={density}"),
        format!("fog.colour=[{albedo}, {albedo}, {albedo}]"),
        format!("fog.anisotropy={g}"),
    ]
}

/// The fog and its sun, for the closed form.
struct Medium {
    sun: [f64; 3],
    density: f64,
    albedo: f64,
    g: f64,
    irradiance: f64,
}

/// Single scattering under a collimated sun, the closed form, at each pixel of the scene of
/// `sets`, checked against the path tracer's mean within 3 standard errors (4,096 samples);
/// `lit(x)` is whether the sun reaches x past the set. Returns the means.
fn check_single_scattering(
    sets: &[String],
    m: &Medium,
    pixels: &[(u32, u32)],
    lit: impl Fn([f64; 3]) -> bool,
) -> Vec<f64> {
    let refs: Vec<&str> = sets.iter().map(String::as_str).collect();
    let scene = common::scene(&refs);
    let params = TraceParams::<f64>::new(&scene);
    let path = PathParams::<f64>::new(&scene);
    let bounds = scene.slice_bounds();
    let eye = scene.camera.eye;
    let mut means = Vec::new();
    for &(i, j) in pixels {
        let d = params.camera_ray(i, j, 0);
        let d = [d.x, d.y, d.z];
        let oc: Vec<f64> = (0..3).map(|k| eye[k] - bounds.center[k]).collect();
        let b: f64 = (0..3).map(|k| oc[k] * d[k]).sum();
        let cc: f64 = oc.iter().map(|v| v * v).sum::<f64>() - bounds.radius_squared;
        let root = (b * b - cc).sqrt();
        let (t0, t1) = (-b - root, -b + root);
        // The light travels from the sun, -sun, and scatters into -d toward the camera.
        let cos: f64 = (0..3).map(|k| m.sun[k] * d[k]).sum();
        let phase = henyey_greenstein(m.g, cos);
        let f = |s: f64| {
            let x = [0, 1, 2].map(|k| eye[k] + s * d[k]);
            if !lit(x) {
                return 0.0;
            }
            let l = exit_distance(x, m.sun, bounds.center, bounds.radius_squared);
            let towards_camera = (-m.density * (s - t0)).exp();
            m.density * m.albedo * towards_camera * phase * m.irradiance * (-m.density * l).exp()
        };
        // Simpson's rule.
        let n = 40_000;
        let h = (t1 - t0) / n as f64;
        let mut sum = f(t0) + f(t1);
        for k in 1..n {
            sum += f(t0 + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        let want = sum * h / 3.0;
        let (mean, se) = pixel_estimate(&params, &path, (i, j), 4096);
        eprintln!(
            "density {}, pixel ({i}, {j}): {mean:.6} +- {se:.6} against {want:.6} \
             ({:.2} standard errors)",
            m.density,
            (mean - want) / se
        );
        assert!(se > 0.0 && se < 0.1 * want, "a useful standard error");
        assert!(
            (mean - want).abs() <= 3.0 * se,
            "density {}, pixel ({i}, {j}): {mean} +- {se} against {want}",
            m.density
        );
        means.push(mean);
    }
    means
}

/// A white fog (albedo 1) under a uniform sky of radiance 1, at an optical depth of 1 across the
/// ball, with 16 bounces and the set cut away, conserves energy: every pixel is the sky, 1.
///
/// - Without Russian roulette (the path parameters' `roulette_start` past the bounces) each
///   path's weight stays exactly 1 through every scattering event, so each sample is exactly 1
///   (it left the ball) or 0 (it reached the bounce cap): over a 6 x 6 grid of pixels (each
///   ray crossing an optical depth over 0.5), 4,096 samples each, every pixel is 1 within 3
///   standard errors, and the share of capped paths is what the cap loses, under its bound
///   (1 - e^-1)^17 = 4.1e-4 (docs/book/atmosphere.md; none of these 147,456 paths).
/// - With roulette (the scene's own paths), the 64 x 64 view's mean over 16 samples a pixel is
///   1 within 3 standard errors.
#[test]
fn a_white_fog_under_a_uniform_sky_is_the_sky() {
    let radius = 3f64.sqrt();
    let density = 1.0 / (2.0 * radius);
    let mut sets = vec![
        "shading.model=\"path\"".to_string(),
        "image.width=64".into(),
        "image.height=64".into(),
        "image.samples=4096".into(),
        "path.bounces=16".into(),
        "camera.fov_y_degrees=60".into(),
        "sky.zenith=[1.0, 1.0, 1.0]".into(),
        "sky.horizon=[1.0, 1.0, 1.0]".into(),
        "sky.ground=[1.0, 1.0, 1.0]".into(),
        format!("fog.density={density}"),
        "fog.colour=[1.0, 1.0, 1.0]".into(),
        "fog.anisotropy=0.3".into(),
    ];
    sets.extend(NO_SET.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = sets.iter().map(String::as_str).collect();
    let scene = common::scene(&refs);
    let params = TraceParams::<f64>::new(&scene);
    let path = PathParams::<f64>::new(&scene);
    let no_roulette = PathParams {
        roulette_start: 17,
        ..path
    };
    let (mut capped, mut paths) = (0, 0);
    for j in (12..=52).step_by(8) {
        for i in (12..=52).step_by(8) {
            let depth = density * chord(&scene, &params, i, j);
            assert!(depth > 0.5, "({i}, {j}): {depth}");
            let n = 4096;
            let values: Vec<f64> = (0..n)
                .map(|k| params.trace_path(&no_roulette, i, j, k).radiance.x)
                .collect();
            assert!(
                values.iter().all(|&v| v == 0.0 || v == 1.0),
                "pixel ({i}, {j}): a path's weight changed"
            );
            let zeros = values.iter().filter(|&&v| v == 0.0).count();
            let mean = 1.0 - zeros as f64 / n as f64;
            let se = (mean * (1.0 - mean) / (n - 1) as f64).sqrt();
            assert!(
                (mean - 1.0).abs() <= 3.0 * se,
                "pixel ({i}, {j}): {mean} +- {se}"
            );
            (capped, paths) = (capped + zeros, paths + n);
        }
    }
    let lost = capped as f64 / paths as f64;
    eprintln!("the bounce cap ended {capped} of {paths} paths ({lost:.2e})");
    assert!(lost <= (1.0 - (-1.0f64).exp()).powi(17));
    // The whole view with roulette, 16 samples a pixel, each sample one value of the mean.
    let (mut n, mut sum, mut sum2) = (0.0, 0.0, 0.0);
    for j in 0..64 {
        for i in 0..64 {
            for k in 0..16 {
                let v = params.trace_path(&path, i, j, k).radiance.x;
                (n, sum, sum2) = (n + 1.0, sum + v, sum2 + v * v);
            }
        }
    }
    let mean = sum / n;
    let se = ((sum2 / n - mean * mean) / (n - 1.0)).sqrt();
    eprintln!("the view's mean with roulette: {mean:.5} +- {se:.5}");
    assert!(se > 0.0 && (mean - 1.0).abs() <= 3.0 * se, "{mean} +- {se}");
}

/// Phong mode's glow: a larger strength never darkens a miss and never touches a hit (pixels
/// whose ray hit keep their bytes), and it does brighten misses near the set.
#[test]
fn glow_brightens_misses_alone() {
    let frame = |strength: f64| {
        let scene = common::scene(&[
            "image.width=64",
            "image.height=64",
            &format!("glow.strength={strength}"),
            "glow.radius=0.1",
        ]);
        cpu_frame(&scene, Precision::F32)
    };
    let frames = [frame(0.0), frame(0.5), frame(2.0)];
    let rgb: Vec<Vec<u8>> = frames.iter().map(Frame::rgb8).collect();
    let mut brightened = 0;
    for k in 0..frames[0].pixel_count() {
        let hit = frames[0].depth[k].is_finite();
        assert_eq!(
            hit,
            frames[2].depth[k].is_finite(),
            "pixel {k}: the same hits"
        );
        for c in 0..3 {
            let v = [rgb[0][3 * k + c], rgb[1][3 * k + c], rgb[2][3 * k + c]];
            if hit {
                assert!(v[0] == v[1] && v[1] == v[2], "hit {k} changed: {v:?}");
            } else {
                assert!(v[0] <= v[1] && v[1] <= v[2], "miss {k} darkened: {v:?}");
            }
        }
        brightened += usize::from(!hit && rgb[2][3 * k] > rgb[0][3 * k] + 20);
    }
    assert!(brightened > 100, "the halo shows: {brightened} misses");
}

/// An emissive unit ball (c = 0, convex: nothing it scatters comes back to it) under a black sky
/// with no lights: every pixel whose ray hits shows its emission times its albedo, exactly;
/// misses are black.
#[test]
fn an_emissive_ball_shows_emission_times_albedo() {
    let scene = common::scene(&[
        "shading.model=\"path\"",
        "fractal.c=[0, 0, 0, 0]",
        "image.width=32",
        "image.height=32",
        "camera.fov_y_degrees=50",
        "sky.intensity=0",
        "shading.diffuse=[0.5, 0.25, 1.0]",
        "material.emission=[2.0, 1.0, 0.5]",
        "path.bounces=3",
    ]);
    let want = [1.0f32, 0.25, 0.5];
    let mut frames = vec![("CPU f32", cpu_frame(&scene, Precision::F32))];
    if let Some(frame) = gpu_frame("emissive ball", &scene) {
        frames.push(("GPU", frame));
    }
    for (name, frame) in &frames {
        let (mut inside, mut outside) = (0, 0);
        for (k, rgb) in frame.radiance.iter().enumerate() {
            if frame.depth[k].is_finite() {
                inside += 1;
                for c in 0..3 {
                    assert!((rgb[c] - want[c]).abs() <= 1e-6, "{name} {k}: {rgb:?}");
                }
            } else {
                outside += 1;
                assert_eq!(*rgb, [0.0; 3], "{name} {k}");
            }
        }
        assert!(inside > 100 && outside > 100, "{name}: {inside}, {outside}");
    }
    // One number is all three channels.
    let grey = common::scene(&["material.emission=1.5"]);
    assert_eq!(grey.material.emission, [1.5; 3]);
}

/// The GPU agrees with the CPU twin (f32) within CONTRACT_TOLERANCE on the atmosphere: path mode
/// with fog, light shafts from the sun through the set, a sphere light and emission; phong mode
/// with fog and glow.
#[test]
fn gpu_and_cpu_agree_on_the_atmosphere() {
    let scenes: [&[&str]; 3] = [
        &[
            "shading.model=\"path\"",
            "image.samples=8",
            "sun.intensity=3",
            "fog.density=0.6",
            "fog.anisotropy=0.5",
            "fog.colour=[0.9, 0.8, 0.7]",
            "path.bounces=4",
        ],
        &[
            "shading.model=\"path\"",
            "image.samples=8",
            "shading.colouring=\"orbit_trap\"",
            "material.emission=2",
            "light.intensity=5",
            "light.radius=0.3",
            "sky.intensity=0.1",
            "fog.density=0.3",
            "fog.anisotropy=-0.3",
        ],
        &[
            "fog.density=0.4",
            "fog.colour=[0.6, 0.7, 0.9]",
            "glow.strength=1.5",
            "image.samples=2",
        ],
    ];
    for sets in scenes {
        let mut all = vec!["image.width=48", "image.height=48"];
        all.extend_from_slice(sets);
        let scene = common::scene(&all);
        let name = format!("atmosphere {}", sets.join(" "));
        let Some(actual) = gpu_frame(&name, &scene) else {
            return;
        };
        let expected = cpu_frame(&scene, Precision::F32);
        common::assert_agree(&name, &expected, &actual, &CONTRACT_TOLERANCE);
        common::assert_steps_mostly_agree(&name, &expected, &actual);
    }
}

/// Bad atmosphere values exit 2 with one line naming the key, and write nothing.
#[test]
fn bad_atmosphere_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (set, key) in [
        ("fog.density=-0.1", "fog.density"),
        ("fog.density=nan", "fog.density"),
        ("fog.anisotropy=1", "fog.anisotropy"),
        ("fog.anisotropy=-1.5", "fog.anisotropy"),
        ("fog.colour=[0.5, 1.2, 0.5]", "fog.colour"),
        ("glow.strength=-1", "glow.strength"),
        ("glow.radius=0", "glow.radius"),
        ("material.emission=-1", "material.emission"),
        ("material.emission=[1.0, 2.0]", "material.emission"),
        ("material.emission=inf", "material.emission"),
    ] {
        common::assert_refused(
            dir.path(),
            &[
                "render", "--width", "8", "--height", "8", "--set", set, "-o", "x.png",
            ],
            "error: --set",
            key,
        );
    }
}
