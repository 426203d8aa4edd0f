//! f64 on the GPU: the f64 kernels against the CPU in f64 on deep zooms (3D and 2D), f32 failing
//! visibly on the same views, and the start-up check of f64 failing loudly on a wrong operation
//! injected through its test hook. On an adapter without f64 (GL llvmpipe) the f64 kernels are
//! refused with the check's reason, and the rest runs: the CPU in f64, f32 failing visibly.

use crate::common::{self, Capability};

use qjulia::compare::{CONTRACT_TOLERANCE, JULIA2D_TOLERANCE, Tolerance};
use qjulia::frame::unpack_rgb;
use qjulia::gpu::{GpuContext, GpuJulia2d, GpuTracer, check_f64};
use qjulia::{Frame, Julia2dParams, Scene, TraceParams};

/// f32 "visibly fails" on a deep view: its colour or mask disagrees with the CPU in f64 on more
/// than this fraction of the pixels.
const F32_FAILS_ABOVE: f64 = 0.20;
/// Colour disagreement for that: more than CONTRACT_TOLERANCE's 2/255 on some channel.
const F32_COLOUR_ABS: u8 = 2;

/// The shared GPU tracer and, where its adapter has f64, the f64 tracer on its device; None
/// where the GPU tests are skipped. Without f64 the f64 tracer must be refused with the reason
/// the adapter's check gives, and the test says that it skipped its f64 part.
fn gpu64(test: &str) -> Option<(Option<GpuTracer<f64>>, &'static GpuTracer)> {
    let tracer = common::gpu(test)?;
    let ctx = tracer.context().clone();
    if !common::has(&ctx, Capability::F64, test, "the GPU's f64 kernels") {
        assert_f64_refused(&ctx);
        return Some((None, tracer));
    }
    let f64_tracer = GpuTracer::new_f64(ctx)
        .unwrap_or_else(|e| panic!("{test}: f64 must run on the test adapter ({e})"));
    Some((Some(f64_tracer), tracer))
}

/// On a device without f64, every f64 kernel is refused with the one line of the start-up
/// check's reason.
fn assert_f64_refused(ctx: &GpuContext) {
    let why = ctx
        .f64_support()
        .expect_err("a device without f64")
        .to_string();
    assert!(
        why.contains("has no f64 (SHADER_F64)") || why.contains("failed the start-up check"),
        "{why}"
    );
    let refusals = [
        GpuTracer::new_f64(ctx.clone()).err().map(|e| e.to_string()),
        GpuJulia2d::new_f64(ctx.clone())
            .err()
            .map(|e| e.to_string()),
        qjulia::gpu::path::GpuPathTracer::new_f64(ctx.clone())
            .err()
            .map(|e| e.to_string()),
    ];
    for refused in refusals {
        let refused = refused.expect("an f64 kernel refused without f64");
        assert!(
            refused.contains(&why) && !refused.contains('\n'),
            "{refused}"
        );
    }
}

/// A deep zoom onto the 30-iteration surface: the point the pixel (i, j) of the view `sets`
/// hits (traced on the CPU in f64 with a tiny epsilon, so that it lies on the surface), seen
/// from back along that ray at the distance where a pixel of a 64 x 64 image spans `footprint`.
/// Epsilon is half a pixel's footprint (`pixel_epsilon`), the normal analytic.
fn deep_scene(sets: &[&str], (i, j): (u32, u32), footprint: f64) -> (Scene, f64) {
    let common_sets = [
        "fractal.max_iterations=30",
        "shading.normal=\"analytic\"",
        "image.width=64",
        "image.height=64",
    ];
    let mut base: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    base.extend(common_sets.iter().map(|s| s.to_string()));
    base.push("fractal.epsilon=1e-13".into());
    let base_refs: Vec<&str> = base.iter().map(|s| s.as_str()).collect();
    let scene = common::scene(&base_refs);
    let p = TraceParams::<f64>::new(&scene);
    let pixel = p.trace_pixel(i, j, 0, 0.0, true);
    assert!(pixel.hit, "the base view's pixel ({i}, {j}) hits the set");
    let dir = p.camera_ray(i, j, 0);
    let hit = p.eye + dir * pixel.depth;
    let fov = scene.camera.fov_y_degrees.to_radians();
    let distance = footprint * 64.0 / (2.0 * (0.5 * fov).tan());
    let eye = hit - dir * distance;
    let v = |v: qjulia::algebra::Vec3<f64>| format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z);
    let mut deep: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    deep.extend(common_sets.iter().map(|s| s.to_string()));
    deep.push(format!("camera.eye={}", v(eye)));
    deep.push(format!("camera.target={}", v(hit)));
    deep.push("fractal.epsilon=1e-300".into());
    deep.push("fractal.pixel_epsilon=0.5".into());
    let deep_refs: Vec<&str> = deep.iter().map(|s| s.as_str()).collect();
    (common::scene(&deep_refs), footprint)
}

/// A deep view: its name, the base view's `--set`s, the pixel whose hit it zooms onto, and the
/// pixel footprint.
type DeepView = (&'static str, &'static [&'static str], (u32, u32), f64);

/// The deep 3D views: three surfaces, pixel footprints 1e-8 to 1e-10.
fn deep_scenes() -> Vec<(&'static str, Scene, f64)> {
    let views: [DeepView; 3] = [
        ("deep_default_1e-8", &[], (32, 32), 1e-8),
        ("deep_default_side_1e-9", &[], (40, 24), 1e-9),
        (
            "deep_other_c_1e-10",
            &["fractal.c=[-0.291, -0.399, 0.339, 0.437]"],
            (30, 28),
            1e-10,
        ),
    ];
    views
        .into_iter()
        .map(|(name, sets, pixel, footprint)| {
            let (scene, footprint) = deep_scene(sets, pixel, footprint);
            (name, scene, footprint)
        })
        .collect()
}

/// Fraction of pixels where colour (beyond `colour_abs` on a channel) or mask differ.
fn disagreement(expected: &Frame, actual: &Frame, colour_abs: u8) -> f64 {
    let n = expected.pixel_count();
    let differ = (0..n)
        .filter(|&k| {
            let (e, a) = (unpack_rgb(expected.colour[k]), unpack_rgb(actual.colour[k]));
            let colour = e.iter().zip(&a).any(|(x, y)| x.abs_diff(*y) > colour_abs);
            colour || expected.depth[k].is_nan() != actual.depth[k].is_nan()
        })
        .count();
    differ as f64 / n as f64
}

/// Within CONTRACT_TOLERANCE in masks and colour, and depth within one pixel footprint.
fn deep_tolerance(footprint: f64) -> Tolerance {
    Tolerance {
        depth_abs: footprint,
        ..CONTRACT_TOLERANCE
    }
}

#[test]
fn gpu_f64_matches_cpu_f64_on_deep_zooms_where_f32_fails() {
    let Some((gpu, gpu32)) = gpu64("gpu_f64_matches_cpu_f64_on_deep_zooms_where_f32_fails") else {
        return;
    };
    for (name, scene, footprint) in deep_scenes() {
        let c = &scene.camera;
        eprintln!(
            "{name}: camera.eye={:?} camera.target={:?}",
            c.eye, c.target
        );
        let (expected, _) = qjulia::cpu::render(&TraceParams::<f64>::new(&scene));
        let hits = expected.hit_mask().iter().filter(|&&h| h).count();
        assert!(
            hits * 2 > expected.pixel_count(),
            "{name}: the view looks at the surface ({hits} hits)"
        );
        if let Some(gpu) = &gpu {
            let actual = gpu
                .render(&TraceParams::<f64>::new(&scene))
                .expect("GPU f64 render")
                .frame;
            assert_eq!(
                actual.depth_f64.len(),
                actual.pixel_count(),
                "{name}: f64 depth"
            );
            common::assert_agree(name, &expected, &actual, &deep_tolerance(footprint));
        }
        let f32_frame = common::gpu_frame(gpu32, &scene);
        let wrong = disagreement(&expected, &f32_frame, F32_COLOUR_ABS);
        eprintln!(
            "{name}: GPU f32 disagrees with CPU f64 on {:.1}% of pixels",
            wrong * 100.0
        );
        assert!(
            wrong > F32_FAILS_ABOVE,
            "{name}: GPU f32 disagrees with CPU f64 on only {:.1}% of pixels (f32 should fail \
             visibly here: > {:.0}%)",
            wrong * 100.0,
            F32_FAILS_ABOVE * 100.0
        );
    }
}

/// A point of the rabbit's boundary (c = -0.12 + 0.75i): bisection in f64 between 0 (in the
/// set) and 0.5 + 0.9i (outside) with 1000 iterations, to 1e-15.
fn rabbit_boundary_point() -> (f64, f64) {
    let inside = |t: f64| {
        let (mut x, mut y) = (0.5 * t, 0.9 * t);
        for _ in 0..1000 {
            if x * x + y * y > 256.0 {
                return false;
            }
            (x, y) = (x * x - y * y - 0.12, 2.0 * x * y + 0.75);
        }
        true
    };
    assert!(inside(0.0) && !inside(1.0));
    let (mut lo, mut hi) = (0.0, 1.0);
    while hi - lo > 1e-15 {
        let mid = 0.5 * (lo + hi);
        if inside(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * lo, 0.9 * lo)
}

/// The rabbit's boundary at an extent of 1e-9: lace in f64, nothing in f32.
#[test]
fn gpu_f64_matches_cpu_f64_on_a_deep_2d_zoom_where_f32_fails() {
    let Some((f64_tracer, gpu32)) =
        gpu64("gpu_f64_matches_cpu_f64_on_a_deep_2d_zoom_where_f32_fails")
    else {
        return;
    };
    let ctx = gpu32.context().clone();
    let (x, y) = rabbit_boundary_point();
    let center = format!("view2d.center=[{x:e}, {y:e}]");
    let scene = common::scene(&[
        "fractal.c=[-0.12, 0.75, 0.0, 0.0]",
        "image.width=96",
        "image.height=96",
        &center,
        "view2d.extent=1e-9",
        "view2d.max_iterations=1000",
    ]);
    let expected = {
        let p = Julia2dParams::<f64>::new(&scene);
        qjulia::cpu::julia2d::render_rows(&p, 0..p.height)
    };
    let inside = expected.hit_mask().iter().filter(|&&h| h).count();
    let n = expected.pixel_count();
    assert!(
        inside > n / 20 && inside < n * 19 / 20,
        "the view straddles the boundary ({inside} of {n} inside)"
    );
    if f64_tracer.is_some() {
        let gpu = GpuJulia2d::new_f64(ctx.clone()).expect("the f64 2D view");
        let (actual, _) = gpu
            .render(&Julia2dParams::<f64>::new(&scene))
            .expect("GPU f64 render");
        common::assert_agree("deep_rabbit_1e-9", &expected, &actual, &JULIA2D_TOLERANCE);
    }
    let (f32_frame, _) = GpuJulia2d::new(ctx)
        .expect("the f32 2D view")
        .render(&Julia2dParams::<f32>::new(&scene))
        .expect("GPU f32 render");
    let wrong = disagreement(&expected, &f32_frame, F32_COLOUR_ABS);
    eprintln!(
        "deep_rabbit_1e-9: GPU f32 disagrees with CPU f64 on {:.1}%",
        wrong * 100.0
    );
    assert!(
        wrong > F32_FAILS_ABOVE,
        "deep_rabbit_1e-9: GPU f32 disagrees on only {:.1}% of pixels",
        wrong * 100.0
    );
}

/// The start-up check passes on the test adapter and fails, naming the operation, when one is
/// made wrong through the test hook; a wrong sqrt is repaired instead. Where the adapter has no
/// f64, the check gives the same one-line reason every time it runs.
#[test]
fn the_f64_check_fails_loudly_on_an_injected_wrong_operation() {
    let test = "the_f64_check_fails_loudly_on_an_injected_wrong_operation";
    let Some(tracer) = common::gpu(test) else {
        return;
    };
    // A device of its own: the check's outcome is cached per device.
    let ctx = GpuContext::from_adapter(tracer.context().adapter.clone()).expect("a device");
    if !common::has(&ctx, Capability::F64, test, "the check's operations") {
        // The check's reason is the same each time it runs.
        let why = ctx.f64_support().expect_err("no f64").to_string();
        let again = check_f64(&ctx, None).expect_err("no f64").to_string();
        assert_eq!(again, why);
        return;
    }
    let support = check_f64(&ctx, None).expect("f64 passes on the test adapter");
    eprintln!("f64 check: {support:?}");
    for op in ["div", "mul", "real_log", "to_f32", "split_exponent"] {
        let e = check_f64(&ctx, Some(op)).expect_err(op).to_string();
        assert!(
            e.contains("failed the start-up check") && e.contains(&format!("{op} of (")),
            "{op}: {e}"
        );
    }
    let repaired = check_f64(&ctx, Some("sqrt")).expect("a wrong sqrt is repaired");
    assert_eq!(repaired.repaired, ["sqrt"]);
    assert_eq!(repaired.constants, [("SQRT_NEWTON", 1.0)]);
}
