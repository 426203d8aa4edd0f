//! The floor's probe (issue 37, item 3): how many of the seed's quaternion iterations this
//! machine's adapter makes a second at best, for `scripts/floor.sh` to compare a render with.
//!
//! The kernel is `iterate_orbit`'s loop for a quaternion in f32 (shaders/estimate.wgsl):
//! z <- z^2 + c, |z|^2, |z'|^2 <- s |z|^2 |z'|^2 and the two tests that end an orbit, with the
//! loop counter. Unlike a render, every lane makes exactly the same number of iterations: no lane
//! waits for another, no ray is traced, nothing but the loop is timed. The scene's values are
//! pipeline constants, as a baked render's are, and are chosen to keep every number normal and
//! nothing foldable: z starts near the attracting fixed point z* of z^2 + c, c = 0.1 + 0.1 (i +
//! j + k), and stays near it, all four parts non-zero; s = 1 / |z*|^2 holds |z'|^2 near 1; no
//! orbit ever ends early (the escape radius and the derivative's limit are never reached).
//!
//! It prints the best of `RUNS` timed dispatches (after an untimed one, which compiles):
//! `peak_iterations_per_second N` and the adapter, one per line.
//!
//!     cargo run --release --example iteration_peak -- [ITERATIONS_PER_LANE] [RUNS]

use std::time::Instant;

const PROBE: &str = r#"
// The scene's values are pipeline constants, as a baked render's are (src/gpu/kernel/bake.rs).
override C_X: f32;
override C_I: f32;
override FIXED_X: f32;
override FIXED_I: f32;
override SCALE: f32;
override ESCAPE_RADIUS_SQUARED: f32;
override DERIVATIVE_LIMIT: f32;
override ITERATIONS: u32;
@group(0) @binding(0) var<storage, read_write> out: array<vec4<f32>>;

fn quat_sq(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(q.x * q.x - dot(q.yzw, q.yzw), 2.0 * q.x * q.yzw);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = gid.y * groups.x * 8u + gid.x;
    // Starts within 1e-3 of the attracting fixed point of z^2 + c, one per lane; its three
    // imaginary parts are equal (as c's are) and stay so, each normal.
    var z = vec4<f32>(FIXED_X - 5e-4 + f32(index % 1024u) * 1e-6, vec3<f32>(FIXED_I));
    var z_norm2 = dot(z, z);
    var dz_norm2 = 1.0;
    var i = 0u;
    for (; i < ITERATIONS; i++) {
        dz_norm2 *= SCALE * z_norm2;
        z = quat_sq(z) + vec4<f32>(C_X, vec3<f32>(C_I));
        z_norm2 = dot(z, z);
        if z_norm2 > ESCAPE_RADIUS_SQUARED || dz_norm2 > DERIVATIVE_LIMIT {
            i++;
            break;
        }
    }
    out[index] = vec4<f32>(z.xy, dz_norm2, f32(i));
}
"#;

fn main() {
    let mut args = std::env::args().skip(1);
    let per_lane: u32 = args
        .next()
        .map_or(4096, |a| a.parse().expect("ITERATIONS_PER_LANE"));
    let runs: u32 = args.next().map_or(5, |a| a.parse().expect("RUNS"));
    qjulia::gpu::give_a_runtime_dir();
    let adapter = pollster::block_on(qjulia::gpu::select_adapter()).expect("an adapter");
    let label = qjulia::gpu::adapter_label(&adapter.get_info());
    let (device, queue) =
        pollster::block_on(adapter.request_device(&Default::default())).expect("a device");
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("iteration peak"),
        source: wgpu::ShaderSource::Wgsl(PROBE.into()),
    });
    // 1024 x 1024 lanes: enough workgroups to fill any adapter.
    let side = 1024u32;
    let lanes = side as u64 * side as u64;
    // c = 0.1 + 0.1 (i + j + k): in the plane of 1 and u = (i + j + k) / sqrt(3), a copy of
    // the complex numbers, c = 0.1 + 0.1 sqrt(3) u, and the fixed point z* = (1 - sqrt(1 - 4c)) / 2
    // (|2 z*| = 0.42 < 1: attracting).
    let (c_x, c_i) = (0.1f64, 0.1f64);
    let (a, b) = (1.0 - 4.0 * c_x, -4.0 * c_i * 3f64.sqrt());
    let r = a.hypot(b);
    let (root_x, root_y) = (((r + a) / 2.0).sqrt(), b.signum() * ((r - a) / 2.0).sqrt());
    let (fixed_x, fixed_u) = ((1.0 - root_x) / 2.0, -root_y / 2.0);
    let constants = [
        ("C_X", c_x),
        ("C_I", c_i),
        ("FIXED_X", fixed_x),
        ("FIXED_I", fixed_u / 3f64.sqrt()),
        ("SCALE", 1.0 / (fixed_x * fixed_x + fixed_u * fixed_u)),
        ("ESCAPE_RADIUS_SQUARED", 10.0),
        ("DERIVATIVE_LIMIT", 1e30),
        ("ITERATIONS", per_lane as f64),
    ];
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("iteration peak"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &constants,
            ..Default::default()
        },
        cache: None,
    });
    let bytes = lanes * 16;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: out.as_entire_binding(),
        }],
    });
    let mut best = f64::INFINITY;
    for run in 0..=runs {
        let start = Instant::now();
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(side / 8, side / 8, 1);
        }
        queue.submit([encoder.finish()]);
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("the device");
        let seconds = start.elapsed().as_secs_f64();
        // The first dispatch compiles the kernel (lavapipe): not timed.
        if run > 0 {
            best = best.min(seconds);
        }
    }
    // Every lane made every iteration: its fourth float is its count.
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(&out, 0, &read, 0, bytes);
    queue.submit([encoder.finish()]);
    read.slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.expect("mapped"));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("the device");
    let outs: Vec<[f32; 4]> =
        bytemuck::cast_slice::<u8, [f32; 4]>(&read.slice(..).get_mapped_range().expect("mapped"))
            .to_vec();
    let short = outs.iter().filter(|v| v[3] as u32 != per_lane).count();
    assert_eq!(short, 0, "{short} lanes ended their orbit early");
    // Each lane ends at the fixed point, its imaginary parts normal.
    let off = outs
        .iter()
        .filter(|v| (v[0] as f64 - fixed_x).abs() > 1e-4 || v[1].abs() < 1e-3)
        .count();
    assert_eq!(off, 0, "{off} lanes left the fixed point");
    let iterations = lanes as f64 * per_lane as f64;
    println!("peak_iterations_per_second {:.0}", iterations / best);
    println!("adapter {label}");
    println!("best_seconds {best:.4} over {runs} runs of {iterations:.0} iterations");
}
