//! A minimal wgpu program that tells a driver's leak from ours (issue 22, the soak's memory):
//! one tiny compute shader dispatched in a loop, each dispatch submitted and its output read
//! back as `qjulia` does, and the process's resident memory printed as it goes. The shader
//! comes in variants that differ by one construct (a loop, a barrier, an array, a uniform in
//! a loop or a branch; `PROBE_VARY=1` changes the uniform at each dispatch). None of them
//! grows. The `tracer` mode runs qjulia's own renderer on the default scene at 64x64 instead,
//! and prints where the resident memory lies at the end: on Mesa 22.3's lavapipe with the
//! params bound as uniforms (`QJULIA_UNIFORMS_AS_STORAGE=0`) it grows by about 0.6 MB a
//! render, one new JIT-compiled variant of the shader each time
//! ([`qjulia::gpu::GpuContext::uniforms_as_storage`]).
//!
//!     cargo run --release --example driver_leak -- [VARIANT|tracer] [DISPATCHES]

use std::time::Instant;

const PLAIN: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    var x = gid.x * 7u + gid.y;
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + 1013904223u; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const BARRIER: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
var<workgroup> shared_x: array<u32, 64>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    shared_x[lid] = gid.x;
    workgroupBarrier();
    var x = shared_x[63u - lid] * 7u + gid.y;
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + 1013904223u; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const BARRIER_AFTER_RETURN: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
var<workgroup> shared_x: array<u32, 64>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    shared_x[lid] = gid.x;
    workgroupBarrier();
    if gid.x >= 60u { return; }
    var x = shared_x[63u - lid] * 7u + gid.y;
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + 1013904223u; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const BARRIER_NOT_REACHED: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
var<workgroup> shared_x: array<u32, 64>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    var x = gid.x * 7u + gid.y;
    if arrayLength(&out) == 1u {
        shared_x[lid] = gid.x;
        workgroupBarrier();
        x = shared_x[63u - lid];
    }
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + 1013904223u; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const BARRIER_LOCAL_ARRAY: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
var<workgroup> shared_x: array<u32, 64>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    var a = array<u32, 16>();
    for (var k = 0u; k < 16u; k++) { a[k] = gid.x + k; }
    shared_x[lid] = gid.x;
    workgroupBarrier();
    var x = shared_x[63u - lid] * 7u + a[gid.y % 16u];
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + a[(x >> 7u) % 16u]; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const BARRIER_PRIVATE_ARRAY: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
var<workgroup> shared_x: array<u32, 64>;
var<private> TABLE: array<u32, 16> = array<u32, 16>(1u, 3u, 5u, 7u, 9u, 11u, 13u, 15u, 17u, 19u, 21u, 23u, 25u, 27u, 29u, 31u);
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    shared_x[lid] = gid.x;
    workgroupBarrier();
    var x = shared_x[63u - lid] * 7u + gid.y;
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + TABLE[(x >> 7u) % 16u]; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const PRIVATE_ARRAY: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
var<private> TABLE: array<u32, 16> = array<u32, 16>(1u, 3u, 5u, 7u, 9u, 11u, 13u, 15u, 17u, 19u, 21u, 23u, 25u, 27u, 29u, 31u);
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    var x = gid.x * 7u + gid.y;
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + TABLE[(x >> 7u) % 16u]; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const UNIFORM_LOOP: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@group(0) @binding(1) var<uniform> params: vec4<u32>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    var x = gid.x * 7u + gid.y;
    for (var k = params.y % 2u; k < params.x; k++) { x = x * 1664525u + 1013904223u; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const UNIFORM_VALUE: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@group(0) @binding(1) var<uniform> params: vec4<u32>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    var x = gid.x * 7u + gid.y + params.x + params.y;
    for (var k = 0u; k < 64u; k++) { x = x * 1664525u + 1013904223u; }
    out[gid.y * 64u + gid.x] = x;
}
"#;

const UNIFORM_BRANCH: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@group(0) @binding(1) var<uniform> params: vec4<u32>;
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    var x = gid.x * 7u + gid.y;
    if params.z == 1u {
        x = (x ^ (x >> 1u)) * 1664525u + 0u;
        x = (x ^ (x >> 2u)) * 1664527u + 1u;
        x = (x ^ (x >> 3u)) * 1664529u + 2u;
        x = (x ^ (x >> 4u)) * 1664531u + 3u;
        x = (x ^ (x >> 5u)) * 1664533u + 4u;
        x = (x ^ (x >> 6u)) * 1664535u + 5u;
        x = (x ^ (x >> 7u)) * 1664537u + 6u;
        x = (x ^ (x >> 8u)) * 1664539u + 7u;
        x = (x ^ (x >> 9u)) * 1664541u + 8u;
        x = (x ^ (x >> 10u)) * 1664543u + 9u;
        x = (x ^ (x >> 11u)) * 1664545u + 10u;
        x = (x ^ (x >> 12u)) * 1664547u + 11u;
        x = (x ^ (x >> 13u)) * 1664549u + 12u;
        x = (x ^ (x >> 1u)) * 1664551u + 13u;
        x = (x ^ (x >> 2u)) * 1664553u + 14u;
        x = (x ^ (x >> 3u)) * 1664555u + 15u;
        x = (x ^ (x >> 4u)) * 1664557u + 16u;
        x = (x ^ (x >> 5u)) * 1664559u + 17u;
        x = (x ^ (x >> 6u)) * 1664561u + 18u;
        x = (x ^ (x >> 7u)) * 1664563u + 19u;
        x = (x ^ (x >> 8u)) * 1664565u + 20u;
        x = (x ^ (x >> 9u)) * 1664567u + 21u;
        x = (x ^ (x >> 10u)) * 1664569u + 22u;
        x = (x ^ (x >> 11u)) * 1664571u + 23u;
        x = (x ^ (x >> 12u)) * 1664573u + 24u;
        x = (x ^ (x >> 13u)) * 1664575u + 25u;
        x = (x ^ (x >> 1u)) * 1664577u + 26u;
        x = (x ^ (x >> 2u)) * 1664579u + 27u;
        x = (x ^ (x >> 3u)) * 1664581u + 28u;
        x = (x ^ (x >> 4u)) * 1664583u + 29u;
        x = (x ^ (x >> 5u)) * 1664585u + 30u;
        x = (x ^ (x >> 6u)) * 1664587u + 31u;
        x = (x ^ (x >> 7u)) * 1664589u + 32u;
        x = (x ^ (x >> 8u)) * 1664591u + 33u;
        x = (x ^ (x >> 9u)) * 1664593u + 34u;
        x = (x ^ (x >> 10u)) * 1664595u + 35u;
        x = (x ^ (x >> 11u)) * 1664597u + 36u;
        x = (x ^ (x >> 12u)) * 1664599u + 37u;
        x = (x ^ (x >> 13u)) * 1664601u + 38u;
        x = (x ^ (x >> 1u)) * 1664603u + 39u;
        x = (x ^ (x >> 2u)) * 1664605u + 40u;
        x = (x ^ (x >> 3u)) * 1664607u + 41u;
        x = (x ^ (x >> 4u)) * 1664609u + 42u;
        x = (x ^ (x >> 5u)) * 1664611u + 43u;
        x = (x ^ (x >> 6u)) * 1664613u + 44u;
        x = (x ^ (x >> 7u)) * 1664615u + 45u;
        x = (x ^ (x >> 8u)) * 1664617u + 46u;
        x = (x ^ (x >> 9u)) * 1664619u + 47u;
        x = (x ^ (x >> 10u)) * 1664621u + 48u;
        x = (x ^ (x >> 11u)) * 1664623u + 49u;
        x = (x ^ (x >> 12u)) * 1664625u + 50u;
        x = (x ^ (x >> 13u)) * 1664627u + 51u;
        x = (x ^ (x >> 1u)) * 1664629u + 52u;
        x = (x ^ (x >> 2u)) * 1664631u + 53u;
        x = (x ^ (x >> 3u)) * 1664633u + 54u;
        x = (x ^ (x >> 4u)) * 1664635u + 55u;
        x = (x ^ (x >> 5u)) * 1664637u + 56u;
        x = (x ^ (x >> 6u)) * 1664639u + 57u;
        x = (x ^ (x >> 7u)) * 1664641u + 58u;
        x = (x ^ (x >> 8u)) * 1664643u + 59u;
        x = (x ^ (x >> 9u)) * 1664645u + 60u;
        x = (x ^ (x >> 10u)) * 1664647u + 61u;
        x = (x ^ (x >> 11u)) * 1664649u + 62u;
        x = (x ^ (x >> 12u)) * 1664651u + 63u;
        x = (x ^ (x >> 13u)) * 1664653u + 64u;
        x = (x ^ (x >> 1u)) * 1664655u + 65u;
        x = (x ^ (x >> 2u)) * 1664657u + 66u;
        x = (x ^ (x >> 3u)) * 1664659u + 67u;
        x = (x ^ (x >> 4u)) * 1664661u + 68u;
        x = (x ^ (x >> 5u)) * 1664663u + 69u;
        x = (x ^ (x >> 6u)) * 1664665u + 70u;
        x = (x ^ (x >> 7u)) * 1664667u + 71u;
        x = (x ^ (x >> 8u)) * 1664669u + 72u;
        x = (x ^ (x >> 9u)) * 1664671u + 73u;
        x = (x ^ (x >> 10u)) * 1664673u + 74u;
        x = (x ^ (x >> 11u)) * 1664675u + 75u;
        x = (x ^ (x >> 12u)) * 1664677u + 76u;
        x = (x ^ (x >> 13u)) * 1664679u + 77u;
        x = (x ^ (x >> 1u)) * 1664681u + 78u;
        x = (x ^ (x >> 2u)) * 1664683u + 79u;
        x = (x ^ (x >> 3u)) * 1664685u + 80u;
        x = (x ^ (x >> 4u)) * 1664687u + 81u;
        x = (x ^ (x >> 5u)) * 1664689u + 82u;
        x = (x ^ (x >> 6u)) * 1664691u + 83u;
        x = (x ^ (x >> 7u)) * 1664693u + 84u;
        x = (x ^ (x >> 8u)) * 1664695u + 85u;
        x = (x ^ (x >> 9u)) * 1664697u + 86u;
        x = (x ^ (x >> 10u)) * 1664699u + 87u;
        x = (x ^ (x >> 11u)) * 1664701u + 88u;
        x = (x ^ (x >> 12u)) * 1664703u + 89u;
        x = (x ^ (x >> 13u)) * 1664705u + 90u;
        x = (x ^ (x >> 1u)) * 1664707u + 91u;
        x = (x ^ (x >> 2u)) * 1664709u + 92u;
        x = (x ^ (x >> 3u)) * 1664711u + 93u;
        x = (x ^ (x >> 4u)) * 1664713u + 94u;
        x = (x ^ (x >> 5u)) * 1664715u + 95u;
        x = (x ^ (x >> 6u)) * 1664717u + 96u;
        x = (x ^ (x >> 7u)) * 1664719u + 97u;
        x = (x ^ (x >> 8u)) * 1664721u + 98u;
        x = (x ^ (x >> 9u)) * 1664723u + 99u;
        x = (x ^ (x >> 10u)) * 1664725u + 100u;
        x = (x ^ (x >> 11u)) * 1664727u + 101u;
        x = (x ^ (x >> 12u)) * 1664729u + 102u;
        x = (x ^ (x >> 13u)) * 1664731u + 103u;
        x = (x ^ (x >> 1u)) * 1664733u + 104u;
        x = (x ^ (x >> 2u)) * 1664735u + 105u;
        x = (x ^ (x >> 3u)) * 1664737u + 106u;
        x = (x ^ (x >> 4u)) * 1664739u + 107u;
        x = (x ^ (x >> 5u)) * 1664741u + 108u;
        x = (x ^ (x >> 6u)) * 1664743u + 109u;
        x = (x ^ (x >> 7u)) * 1664745u + 110u;
        x = (x ^ (x >> 8u)) * 1664747u + 111u;
        x = (x ^ (x >> 9u)) * 1664749u + 112u;
        x = (x ^ (x >> 10u)) * 1664751u + 113u;
        x = (x ^ (x >> 11u)) * 1664753u + 114u;
        x = (x ^ (x >> 12u)) * 1664755u + 115u;
        x = (x ^ (x >> 13u)) * 1664757u + 116u;
        x = (x ^ (x >> 1u)) * 1664759u + 117u;
        x = (x ^ (x >> 2u)) * 1664761u + 118u;
        x = (x ^ (x >> 3u)) * 1664763u + 119u;
    }
    out[gid.y * 64u + gid.x] = x;
}
"#;

/// The process's resident memory in MB (Linux: /proc/self/statm).
fn resident_mb() -> f64 {
    qjulia::memory::resident_bytes().unwrap_or(0) as f64 / 1e6
}

fn main() {
    let mut args = std::env::args().skip(1);
    let variant = args.next().unwrap_or_else(|| "plain".into());
    let dispatches: u32 = args.next().and_then(|n| n.parse().ok()).unwrap_or(4000);
    let source = match variant.as_str() {
        "plain" => PLAIN,
        "barrier" => BARRIER,
        "barrier-after-return" => BARRIER_AFTER_RETURN,
        "barrier-not-reached" => BARRIER_NOT_REACHED,
        "barrier-local-array" => BARRIER_LOCAL_ARRAY,
        "barrier-private-array" => BARRIER_PRIVATE_ARRAY,
        "private-array" => PRIVATE_ARRAY,
        "uniform-loop" => UNIFORM_LOOP,
        "uniform-value" => UNIFORM_VALUE,
        "uniform-branch" => UNIFORM_BRANCH,
        "tracer" => return tracer(dispatches),
        "variants" => return variants(dispatches),
        other => {
            eprintln!("error: no variant {other:?} (see the file's opening comment)");
            std::process::exit(2);
        }
    };
    qjulia::gpu::give_a_runtime_dir();
    let adapter = pollster::block_on(qjulia::gpu::select_adapter()).expect("an adapter");
    println!(
        "adapter: {}",
        qjulia::gpu::adapter_label(&adapter.get_info())
    );
    let (device, queue) =
        pollster::block_on(adapter.request_device(&Default::default())).expect("a device");
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(&variant),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(&variant),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let (side, bytes) = (64u32, 64 * 64 * 4);
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
    let uniform = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("params"),
        size: 16,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let has_uniform = source.contains("var<uniform>");
    let mut entries = vec![wgpu::BindGroupEntry {
        binding: 0,
        resource: out.as_entire_binding(),
    }];
    if has_uniform {
        entries.push(wgpu::BindGroupEntry {
            binding: 1,
            resource: uniform.as_entire_binding(),
        });
    }
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let start = Instant::now();
    let mut checksum = 0u64;
    for n in 0..=dispatches {
        if n % (dispatches / 10).max(1) == 0 {
            println!(
                "{variant:<22} dispatch {n:>6}  resident {:>8.1} MB  {:>6.1} s",
                resident_mb(),
                start.elapsed().as_secs_f64()
            );
        }
        if has_uniform {
            // Written as qjulia writes each dispatch's params: the same value, or a new one
            // each time under PROBE_VARY.
            queue.write_buffer(
                &uniform,
                0,
                bytemuck::cast_slice(&[64u32, std::env::var("PROBE_VARY").map_or(0, |_| n), 0, 0]),
            );
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(side / 8, side / 8, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &read, 0, bytes);
        queue.submit([encoder.finish()]);
        read.slice(..)
            .map_async(wgpu::MapMode::Read, |r| r.expect("mapped"));
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("the device");
        checksum += read.slice(..).get_mapped_range().expect("mapped")[0] as u64;
        read.unmap();
    }
    println!("checksum {checksum}");
}

/// The same loop through qjulia's own renderer: the default scene at 64x64, `renders` times.
fn tracer(renders: u32) {
    use qjulia::{Backend, Picture, Planner, PrecisionChoice, Scene};
    qjulia::gpu::give_a_runtime_dir();
    let ctx = qjulia::gpu::GpuContext::new().expect("a device");
    println!("adapter: {}", ctx.adapter_label());
    let kernels = std::sync::Arc::new(qjulia::gpu::GpuKernels::new(ctx));
    let mut planner = Planner::on_device(kernels, Backend::Gpu, PrecisionChoice::F32);
    let mut scene = Scene::default();
    scene.image.width = 64;
    scene.image.height = 64;
    let plan = planner
        .plan(&scene, Picture::SHADED.into(), &mut |_| {})
        .expect("a plan");
    let start = Instant::now();
    for n in 0..=renders {
        if n % (renders / 10).max(1) == 0 {
            println!(
                "tracer                 render {n:>6}  resident {:>8.1} MB  {:>6.1} s",
                resident_mb(),
                start.elapsed().as_secs_f64()
            );
        }
        plan.renderer
            .render(&scene, Picture::SHADED, &mut |_| Ok(()))
            .expect("a render");
    }
    mappings();
}

/// Scenes of 24 distinct variants (five features on and off; a light's radius matters only
/// with shadows), each rendered once in turn, `rounds` times: the resident memory after each
/// scene, and the pipelines the tracer holds. Past [`qjulia::gpu::kernel::MAX_PIPELINES`] the
/// tracer drops the one used longest ago: whether the driver then gives its memory back.
fn variants(rounds: u32) {
    use qjulia::{Backend, Picture, Planner, PrecisionChoice, scene::SceneLoader};
    qjulia::gpu::give_a_runtime_dir();
    let ctx = qjulia::gpu::GpuContext::new().expect("a device");
    println!("adapter: {}", ctx.adapter_label());
    let kernels = std::sync::Arc::new(qjulia::gpu::GpuKernels::new(ctx));
    let tracer = kernels.tracer().expect("the tracer");
    let features = [
        "shading.shadows=false",
        "shading.occlusion=0.5",
        "shading.colouring=\"orbit_trap\"",
        "cut.enabled=true",
        "light.radius=0.2",
    ];
    let scenes: Vec<_> = (0..1u32 << features.len())
        .filter(|mask| mask & 1 == 0 || mask & 16 == 0)
        .map(|mask| {
            let mut loader = SceneLoader::new();
            for set in ["image.width=16", "image.height=16"].into_iter().chain(
                (0..features.len())
                    .filter(|k| mask & (1 << k) != 0)
                    .map(|k| features[k]),
            ) {
                loader.set(set).expect("a set");
            }
            loader.build().expect("a scene")
        })
        .collect();
    println!(
        "{} scenes, at most {} pipelines held",
        scenes.len(),
        qjulia::gpu::kernel::MAX_PIPELINES
    );
    for round in 0..rounds.max(1) {
        for (n, scene) in scenes.iter().enumerate() {
            let plan = Planner::on_device(kernels.clone(), Backend::Gpu, PrecisionChoice::F32)
                .plan(scene, Picture::SHADED.into(), &mut |_| {})
                .expect("a plan");
            plan.renderer
                .render(scene, Picture::SHADED, &mut |_| Ok(()))
                .expect("a render");
            println!(
                "variants  round {round} scene {n:>2}  pipelines {:>2}  resident {:>8.1} MB",
                tracer.pipelines_held(),
                resident_mb()
            );
        }
    }
}

/// The process's anonymous mappings, summed by permissions (where the growth lies: heap,
/// executable JIT code, or a driver's own maps).
fn mappings() {
    let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap_or_default();
    let mut by: std::collections::BTreeMap<String, (u64, u64)> = Default::default();
    let mut key = String::new();
    for line in smaps.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields
            .first()
            .is_some_and(|f| f.contains('-') && !f.ends_with(':'))
        {
            let name = fields.get(5).copied().unwrap_or("[anon]");
            key = format!("{} {}", fields[1], name);
        } else if fields.first() == Some(&"Rss:") {
            let kb: u64 = fields[1].parse().unwrap_or(0);
            let e = by.entry(key.clone()).or_default();
            e.0 += kb;
            e.1 += 1;
        }
    }
    let mut rows: Vec<_> = by.into_iter().collect();
    rows.sort_by_key(|(_, (kb, _))| std::cmp::Reverse(*kb));
    for (key, (kb, n)) in rows.iter().take(8) {
        println!("  {:>9.1} MB in {n:>6} mappings  {key}", *kb as f64 / 1e3);
    }
}
