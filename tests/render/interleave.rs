//! Interleaving (issue 19): the kernels' `INTERLEAVE` 2 traces the camera rays of samples k and
//! k + 1 of a pixel as one fused pair (`sphere_trace_pair`), 1 each alone; the two must give the
//! same bytes: colour, depth, steps, estimates, the AOVs and the path radiance, in f32 and (where
//! the adapter has it) f64. The CPU twin's pair is held to two of its own `sphere_trace`s bit
//! for bit.

use crate::common;

use qjulia::Frame;
use qjulia::cpu::path::PathParams;
use qjulia::gpu::path::GpuPathTracer;
use qjulia::gpu::{GpuContext, GpuReal, GpuTracer, Readback};
use qjulia::params::TraceParams;

/// Phong scenes: odd and even sample counts (an odd one leaves one ray alone), the cut, soft
/// shadows, over-relaxation, the pixel epsilon, the lens, and a sedenion (its z' carried whole).
const PHONG: [&[&str]; 5] = [
    &["image.samples=3", "cut.enabled=true", "light.radius=0.3"],
    &["image.samples=8", "cut.enabled=true", "light.radius=0.3"],
    &[
        "image.samples=8",
        "fractal.step_scale=1.6",
        "fractal.pixel_epsilon=1.0",
        "shading.occlusion=0.5",
        "shading.colouring=\"orbit_trap\"",
    ],
    &[
        "image.samples=5",
        "camera.aperture=0.05",
        "camera.focus_distance=2.5",
    ],
    &[
        "image.samples=4",
        "fractal.algebra=\"sedenion\"",
        "fractal.max_steps=40",
    ],
];

/// Path scenes: odd and even sample counts, the cut, the sphere light, the lens.
const PATH: [&[&str]; 3] = [
    &["image.samples=3", "sun.intensity=3"],
    &[
        "image.samples=8",
        "cut.enabled=true",
        "light.intensity=6",
        "light.radius=0.4",
        "path.bounces=3",
    ],
    &[
        "image.samples=6",
        "camera.aperture=0.05",
        "fractal.step_scale=1.5",
        "fractal.pixel_epsilon=1.0",
    ],
];

fn small(sets: &[&str]) -> qjulia::Scene {
    let mut all = vec!["image.width=32", "image.height=24"];
    all.extend_from_slice(sets);
    common::scene(&all)
}

fn path_scene(sets: &[&str]) -> qjulia::Scene {
    let mut all = vec!["shading.model=\"path\""];
    all.extend_from_slice(sets);
    small(&all)
}

/// The same values, or a panic naming how many differ and the first.
fn assert_same<T: PartialEq + std::fmt::Debug>(what: &str, output: &str, one: &[T], two: &[T]) {
    assert_eq!(one.len(), two.len(), "{what}: {output}: lengths");
    let differ: Vec<usize> = (0..one.len()).filter(|&k| one[k] != two[k]).collect();
    if let Some(&k) = differ.first() {
        panic!(
            "{what}: {output}: {} of {} values differ, the first at {k}: {:?} with INTERLEAVE 1, \
             {:?} with 2",
            differ.len(),
            one.len(),
            one[k],
            two[k]
        );
    }
}

/// Every output of two frames, byte for byte (floats by their bits), and both made some hits
/// (so that the comparison is of traced pixels, not of a background).
fn assert_same_bytes(what: &str, one: &Frame, two: &Frame) {
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let bits3 = |v: &[[f32; 3]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    let bits64 = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_same(what, "colour", &one.colour, &two.colour);
    assert_same(what, "depth", &bits(&one.depth), &bits(&two.depth));
    let (d1, d2) = (bits64(&one.depth_f64), bits64(&two.depth_f64));
    assert_same(what, "f64 depth", &d1, &d2);
    assert_same(what, "steps", &one.steps, &two.steps);
    assert_same(what, "estimates", &[one.estimates], &[two.estimates]);
    let (r1, r2) = (bits3(&one.radiance), bits3(&two.radiance));
    assert_same(what, "radiance", &r1, &r2);
    let (u1, u2) = (bits3(&one.unclamped), bits3(&two.unclamped));
    assert_same(what, "AOV colour", &u1, &u2);
    let (a1, a2) = (bits3(&one.albedo), bits3(&two.albedo));
    assert_same(what, "AOV albedo", &a1, &a2);
    let (n1, n2) = (bits3(&one.normal), bits3(&two.normal));
    assert_same(what, "AOV normal", &n1, &n2);
    let hits = one.depth.iter().filter(|d| !d.is_nan()).count();
    assert!(hits > 0, "{what}: no pixel hit");
    assert!(one.estimates > 0, "{what}: no estimates");
}

fn phong_frame<F: GpuReal>(tracer: &GpuTracer<F>, scene: &qjulia::Scene) -> Frame {
    let params = TraceParams::<F>::new(scene);
    let mut frame = Frame::empty(params.width);
    tracer
        .render_bands(&params, true, Readback::Hdr, &mut |band| {
            frame.append(&band);
            Ok(())
        })
        .expect("a render");
    frame
}

fn path_frame<F: GpuReal>(tracer: &GpuPathTracer<F>, scene: &qjulia::Scene) -> Frame {
    let params = TraceParams::<F>::new(scene);
    let mut frame = Frame::empty(params.width);
    tracer
        .render_bands(
            &params,
            &PathParams::new(scene),
            Readback::Hdr,
            &mut |band| {
                frame.append(&band);
                Ok(())
            },
        )
        .expect("a render");
    frame
}

/// Phong and path mode with INTERLEAVE 1 and 2 on the specialised and the generic pipelines,
/// in one precision.
fn check_precision<F: GpuReal>(
    name: &str,
    make: fn(GpuContext) -> qjulia::Result<GpuTracer<F>>,
    make_path: fn(GpuContext) -> qjulia::Result<GpuPathTracer<F>>,
    ctx: &GpuContext,
) {
    let mut one = make(ctx.clone()).unwrap_or_else(|e| panic!("{name}: the tracer ({e})"));
    let mut two = make(ctx.clone()).expect("a second tracer");
    one.set_interleave(1);
    two.set_interleave(2);
    for specialise in [true, false] {
        one.set_specialise(specialise);
        two.set_specialise(specialise);
        // The two are different pipelines (the override reaches the shader).
        let variant = one.variant_for(&TraceParams::<F>::new(&small(PHONG[0])), true);
        assert!(
            one.pipeline(variant).unwrap() != two.pipeline(variant).unwrap(),
            "{name}: INTERLEAVE 1 and 2 built one pipeline"
        );
        // The generic pipeline (compiled once per INTERLEAVE, slowly) on the first scene only.
        for sets in PHONG.iter().take(if specialise { PHONG.len() } else { 1 }) {
            let scene = small(sets);
            let what = format!("{name} phong {sets:?} (specialised {specialise})");
            assert_same_bytes(
                &what,
                &phong_frame(&one, &scene),
                &phong_frame(&two, &scene),
            );
        }
    }
    let mut one = make_path(ctx.clone()).expect("the path tracer");
    let mut two = make_path(ctx.clone()).expect("a second path tracer");
    one.set_interleave(1);
    two.set_interleave(2);
    for sets in PATH {
        let scene = path_scene(sets);
        let what = format!("{name} path {sets:?}");
        assert_same_bytes(&what, &path_frame(&one, &scene), &path_frame(&two, &scene));
    }
}

#[test]
fn interleaved_and_single_rays_give_the_same_bytes_f32() {
    let Some(gpu) = common::gpu("interleave_f32") else {
        return;
    };
    check_precision::<f32>("f32", GpuTracer::new, GpuPathTracer::new, gpu.context());
}

#[test]
fn interleaved_and_single_rays_give_the_same_bytes_f64() {
    let test = "interleaved_and_single_rays_give_the_same_bytes_f64";
    let Some(gpu) = common::gpu(test) else {
        return;
    };
    if !common::has(
        gpu.context(),
        common::Capability::F64,
        test,
        "the f64 tracers",
    ) {
        return;
    }
    check_precision::<f64>(
        "f64",
        GpuTracer::new_f64,
        GpuPathTracer::new_f64,
        gpu.context(),
    );
}

/// The CPU twin: `trace_primary_pair` of samples k and k + 1 is `trace_primary` of each, bit for
/// bit, over every pixel of scenes where rays hit and miss, run out of steps, are over-relaxed
/// and meet the cut.
#[test]
fn the_cpu_pair_is_two_single_traces() {
    fn check<F: qjulia::algebra::Real>(sets: &[&str]) {
        let scene = small(sets);
        let p = TraceParams::<F>::new(&scene);
        let (mut hits, mut misses, mut stalled) = (0, 0, 0);
        for j in 0..p.height {
            for i in 0..p.width {
                for k in 0..p.samples.max(2) - 1 {
                    let a = p.primary_ray(i, j, k, F::zero());
                    let b = p.primary_ray(i, j, k + 1, F::zero());
                    let pair = p.trace_primary_pair(&a, &b);
                    for (ray, got) in [(a, pair[0]), (b, pair[1])] {
                        let want = p.trace_primary(&ray);
                        assert_eq!(got.hit, want.hit, "{sets:?} ({i}, {j}) sample {k}");
                        assert_eq!(got.steps, want.steps, "{sets:?} ({i}, {j}) sample {k}");
                        assert_eq!(
                            got.t.to_f64().to_bits(),
                            want.t.to_f64().to_bits(),
                            "{sets:?} ({i}, {j}) sample {k}"
                        );
                        hits += want.hit as u32;
                        misses += (!want.hit) as u32;
                        stalled += (want.steps == p.max_steps) as u32;
                    }
                }
            }
        }
        assert!(
            hits > 0 && misses > 0,
            "{sets:?}: {hits} hits, {misses} misses"
        );
        if sets.contains(&"fractal.max_steps=12") {
            assert!(stalled > 0, "{sets:?}: no ray ran out of steps");
        }
    }
    let scenes: [&[&str]; 4] = [
        &["image.samples=4", "cut.enabled=true"],
        &[
            "image.samples=3",
            "fractal.step_scale=1.8",
            "fractal.pixel_epsilon=1.0",
        ],
        &["image.samples=2", "fractal.max_steps=12"],
        &[
            "image.samples=2",
            "fractal.algebra=\"octonion\"",
            "camera.aperture=0.05",
        ],
    ];
    for sets in scenes {
        check::<f32>(sets);
        check::<f64>(sets);
    }
}
