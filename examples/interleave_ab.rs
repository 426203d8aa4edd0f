//! An experiment (issue 19, "interleaving"): does one invocation that traces two samples of its
//! pixel interleaved, step for step and iteration for iteration, run faster than one that traces
//! them one after the other? Two readings of lavapipe disagree: docs/PERFORMANCE.md found it
//! bound by the iterations' arithmetic (interleaving would not help), an earlier estimate a
//! latency chain (about 114 lane-cycles an iteration: two independent chains would overlap).
//! It paid, and the kernels now pair their camera rays (`sphere_trace_pair` in
//! shaders/march.wgsl, the `INTERLEAVE` override); this stays as the isolated measurement of the
//! fused loops alone, without the cut, over-relaxation or shading.
//!
//! Both entry points sphere-trace the camera rays of samples 0..S of every pixel (quaternions,
//! the tracer's own estimate and step rule, no cut, no over-relaxation) and write the sum of the
//! t reached, so that nothing is optimised away: `seq_main` one ray after the other with the
//! tracer's `sphere_trace`; `pair_main` two rays at once, each estimate of the one fused with
//! the other's in one iteration loop; and `single_main` the pair's code with the second ray
//! never live, one ray at a time (so that the A/B is of the interleaving alone, not of the code). They are timed on the GPU, alternating, 9 times each, and
//! the medians printed; the sums are compared (the same rays, the same steps: they must agree).
//!
//!     cargo run --release --example interleave_ab [SIZE] [SAMPLES]

use qjulia::gpu::kernel::{Band, Kernel, KernelSpec, Run};
use qjulia::gpu::shaders::ShaderModuleSource;
use qjulia::gpu::{GpuContext, GpuParams, TRACE_OUTPUTS};
use qjulia::params::TraceParams;

const EXPERIMENT_WGSL: &str = r#"#import trace
// The estimate at two points at once: both orbits in one loop, each stopping on its own.
fn estimate_pair(p1: vec3<f32>, p2: vec3<f32>, live: vec2<bool>) -> vec2<f32> {
    var z1 = slice_point(p1);
    var z2 = slice_point(p2);
    var n1 = hyper_dot(z1, z1, 1u);
    var n2 = hyper_dot(z2, z2, 1u);
    var dz1: f32 = 1.0;
    var dz2: f32 = 1.0;
    var a1 = live.x;
    var a2 = live.y;
    for (var i = 0u; i < params.max_iterations; i++) {
        if !(a1 || a2) {
            break;
        }
        if a1 {
            dz1 *= 4.0 * n1;
            z1 = hyper_add(hyper_sq(z1, 1u), params.c);
            n1 = hyper_dot(z1, z1, 1u);
            a1 = !(n1 > params.escape_radius_squared || dz1 > DERIVATIVE_LIMIT);
        }
        if a2 {
            dz2 *= 4.0 * n2;
            z2 = hyper_add(hyper_sq(z2, 1u), params.c);
            n2 = hyper_dot(z2, z2, 1u);
            a2 = !(n2 > params.escape_radius_squared || dz2 > DERIVATIVE_LIMIT);
        }
    }
    let d1 = select(0.0, 0.25 * sqrt(n1 / dz1) * log(n1), n1 >= MIN_NORMAL && dz1 <= DERIVATIVE_LIMIT && dz1 > n1 * TINY);
    let d2 = select(0.0, 0.25 * sqrt(n2 / dz2) * log(n2), n2 >= MIN_NORMAL && dz2 <= DERIVATIVE_LIMIT && dz2 > n2 * TINY);
    return vec2<f32>(d1, d2);
}

// Two sphere traces from the eye at once (the tracer's step rule without over-relaxation or
// pixel epsilon): the sum of the t each reaches.
// With `both` false the second ray is never traced: the same code, one ray at a time.
fn trace_pair(d1: vec3<f32>, d2: vec3<f32>, both: bool) -> f32 {
    let b1 = intersect_bounds(params.eye, d1);
    let b2 = intersect_bounds(params.eye, d2);
    var t = vec2<f32>(b1.t_enter, b2.t_enter);
    var live = vec2<bool>(b1.hit, b2.hit && both);
    var done = vec2<f32>(0.0, 0.0);
    for (var steps = 1u; steps <= params.max_steps; steps++) {
        if !(live.x || live.y) {
            break;
        }
        let d = estimate_pair(params.eye + t.x * d1, params.eye + t.y * d2, live);
        let r = max(d, vec2<f32>(0.0));
        let t_plain = t + r;
        let threshold = max(vec2<f32>(params.epsilon), t_plain * RELATIVE_EPSILON);
        let hit = d < threshold;
        let out = t_plain > vec2<f32>(b1.t_exit, b2.t_exit);
        let stop = live & (hit | out);
        done = select(done, t_plain, stop);
        live = live & !stop;
        t = t_plain;
    }
    return done.x + done.y;
}

fn trace_one(dir: vec3<f32>) -> f32 {
    let b = intersect_bounds(params.eye, dir);
    if !b.hit {
        return 0.0;
    }
    let r = sphere_trace(params.eye, dir, b.t_enter, b.t_exit, 0.0);
    return r.t;
}

@compute @workgroup_size(8, 8, 1)
fn seq_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.row_count {
        return;
    }
    let j = params.row_offset + gid.y;
    var sum: f32 = 0.0;
    for (var k = params.sample_start; k < params.sample_end; k++) {
        sum += trace_one(camera_ray(gid.x, j, k));
    }
    out_depth[gid.y * params.row_stride + gid.x] = sum;
}

@compute @workgroup_size(8, 8, 1)
fn single_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.row_count {
        return;
    }
    let j = params.row_offset + gid.y;
    var sum: f32 = 0.0;
    for (var k = params.sample_start; k < params.sample_end; k++) {
        let d = camera_ray(gid.x, j, k);
        sum += trace_pair(d, d, false);
    }
    out_depth[gid.y * params.row_stride + gid.x] = sum;
}

@compute @workgroup_size(8, 8, 1)
fn pair_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.row_count {
        return;
    }
    let j = params.row_offset + gid.y;
    var sum: f32 = 0.0;
    for (var k = params.sample_start; k < params.sample_end; k += 2u) {
        sum += trace_pair(camera_ray(gid.x, j, k), camera_ray(gid.x, j, k + 1u), true);
    }
    out_depth[gid.y * params.row_stride + gid.x] = sum;
}
"#;

const MODULE: ShaderModuleSource = ShaderModuleSource::text("interleave", EXPERIMENT_WGSL);

fn spec(entry_point: &'static str) -> KernelSpec {
    KernelSpec {
        name: entry_point,
        module: MODULE,
        entry_point,
        uniform_bytes: size_of::<GpuParams>() as u64,
        outputs: &TRACE_OUTPUTS,
        band_row_multiple: 1,
        trusted: true,
        second_uniform: None,
        input: Some(8),
        bake_keeps: None,
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let size: u32 = args.next().map_or(256, |a| a.parse().expect("SIZE"));
    let samples: u32 = args.next().map_or(8, |a| a.parse().expect("SAMPLES"));
    assert!(
        samples.is_multiple_of(2) && samples <= 8,
        "an even number of samples, at most 8"
    );
    let mut scene = qjulia::Scene::default();
    scene.image.width = size;
    scene.image.height = size;
    scene.image.samples = samples;
    let params = TraceParams::<f32>::new(&scene);
    let ctx = GpuContext::new().expect("a GPU adapter");
    eprintln!("on {}", ctx.adapter_label());
    let kernels = [
        Kernel::new(ctx.clone(), spec("seq_main")).expect("seq"),
        Kernel::new(ctx.clone(), spec("single_main")).expect("single"),
        Kernel::new(ctx, spec("pair_main")).expect("pair"),
    ];
    let uniform = |band: Band| {
        bytemuck::bytes_of(&GpuParams::new(&params, band.row, band.rows).with_samples(0, samples))
            .to_vec()
    };
    let constants = [
        ("SPECIALISED", 1.0),
        ("STANDARD_SLICE", 1.0),
        ("OVER_RELAXED", 0.0),
        ("PIXEL_EPSILON", 0.0),
        ("CUT", 0.0),
    ];
    // The depth output alone comes back.
    let read: Vec<bool> = (0..TRACE_OUTPUTS.len()).map(|k| k == 1).collect();
    let run = |kernel: &Kernel| {
        let r = Run {
            constants: &constants,
            size: (size, size),
            read: &read,
            dispatches_per_band: 1,
            params: &uniform,
            input: None,
        };
        let mut sums: Vec<f32> = Vec::new();
        let times = kernel
            .run(
                &r,
                |out| bytemuck::cast_slice::<u8, f32>(out.outputs[1].expect("depth")).to_vec(),
                |band| {
                    sums.extend(band);
                    Ok(())
                },
            )
            .expect("a run");
        (times.gpu_seconds.unwrap_or(times.seconds), sums)
    };
    // Warm both up (lavapipe compiles at the first dispatch), and compare their answers.
    let (_, seq_sums) = run(&kernels[0]);
    let (_, single_sums) = run(&kernels[1]);
    let (_, pair_sums) = run(&kernels[2]);
    // The same rays by the same code, summed in another order: equal to rounding.
    let same = single_sums
        .iter()
        .zip(&pair_sums)
        .all(|(a, b)| (a - b).abs() <= 1e-5 * a.abs().max(1.0));
    assert!(same, "the pair code gives the same sums, paired or not");
    let agree = seq_sums
        .iter()
        .zip(&pair_sums)
        .filter(|(a, b)| (*a - *b).abs() <= 1e-4 * a.abs().max(1.0))
        .count();
    eprintln!(
        "sums agree on {agree} of {} pixels (the pair's step rule is the tracer's without its \
         fallbacks)",
        seq_sums.len()
    );
    let mut times = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..9 {
        for (k, kernel) in kernels.iter().enumerate() {
            times[k].push(run(kernel).0);
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (seq, single, pair) = (
        median(&mut times[0]),
        median(&mut times[1]),
        median(&mut times[2]),
    );
    println!(
        "{size}x{size}, {samples} samples a pixel, 9 runs each alternating (median gpu_seconds): \
         the tracer's sphere_trace one ray after the other {seq:.4} s; the pair code one ray \
         at a time {single:.4} s; interleaved in pairs {pair:.4} s; pairs / one at a time {:.3}",
        pair / single
    );
}
