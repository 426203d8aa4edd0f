//! `cargo bench`: the GPU path (whatever adapter wgpu finds) against the CPU reference in f32
//! and f64 on the same scenes, throughput in pixels.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use qjulia::gpu::{GpuContext, GpuTracer};
use qjulia::scene::SceneLoader;
use qjulia::{Scene, TraceParams, cpu};

fn scene(sets: &[&str]) -> Scene {
    let mut loader = SceneLoader::new();
    for s in sets {
        loader.set(s).expect("bench scene");
    }
    loader.build().expect("bench scene")
}

fn bench(c: &mut Criterion) {
    let scenes = [
        ("seed_look_512", scene(&[])),
        (
            "seed_look_no_shadows_512",
            scene(&["shading.shadows=false"]),
        ),
    ];
    let gpu = match GpuContext::new().and_then(GpuTracer::new) {
        Ok(t) => Some(t),
        Err(e) => {
            eprintln!("no GPU benchmarks: {e}");
            None
        }
    };
    for (name, scene) in &scenes {
        let mut group = c.benchmark_group(*name);
        group.sample_size(10);
        group.throughput(Throughput::Elements(
            scene.image.width as u64 * scene.image.height as u64,
        ));
        if let Some(tracer) = &gpu {
            let params = TraceParams::<f32>::new(scene);
            tracer.render(&params).expect("GPU warm-up");
            let label = format!("gpu {}", tracer.context().adapter_label());
            group.bench_function(label, |b| {
                b.iter(|| tracer.render(&params).expect("GPU render"))
            });
        }
        let p32 = TraceParams::<f32>::new(scene);
        group.bench_function("cpu f32", |b| b.iter(|| cpu::render(&p32)));
        let p64 = TraceParams::<f64>::new(scene);
        group.bench_function("cpu f64", |b| b.iter(|| cpu::render(&p64)));
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
