//! `cargo bench`: the GPU path (whatever adapter wgpu finds: lavapipe on a machine without a
//! GPU) against the CPU reference in f32 and f64, on the same scenes in one run, throughput in
//! pixels. Criterion measures every render; a summary table at the end gives Mpixel/s, distance
//! estimates and quaternion iterations per second, the GPU/CPU ratio and the gain of per-scene
//! specialisation (the generic pipeline against the scene's own). GPU time is taken by timestamp
//! queries where the adapter has them; every pipeline is compiled and warmed up before timing.

use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput};

use qjulia::gpu::{GpuContext, GpuKernels, GpuTracer};
use qjulia::scene::SceneLoader;
use qjulia::{
    Backend, Picture, Planner, Precision, PrecisionChoice, Renderer, Scene, TraceParams, cpu,
};

/// The renderer of a plan on `backend` in `precision` (a GPU one on `kernels`), as the
/// command line plans it.
fn planned(kernels: Option<GpuKernels>, backend: Backend, precision: Precision) -> Renderer {
    let choice = match precision {
        Precision::F32 => PrecisionChoice::F32,
        Precision::F64 => PrecisionChoice::F64,
    };
    let mut planner = match kernels {
        Some(kernels) => Planner::on_device(Arc::new(kernels), backend, choice),
        None => Planner::new(backend, choice),
    };
    planner
        .plan(&Scene::default(), Picture::SHADED.into(), &mut |_| {})
        .expect("a plan")
        .renderer
}

/// The CPU renderer in `precision`.
fn cpu_renderer(precision: Precision) -> Renderer {
    planned(None, Backend::Cpu, precision)
}

fn scene(sets: &[&str]) -> Scene {
    let mut loader = SceneLoader::new();
    for s in sets {
        loader.set(s).expect("bench scene");
    }
    loader.build().expect("bench scene")
}

/// The benchmark scenes: the seed's look with and without shadows, many iterations, a wide
/// view that mostly misses, and a close-up where every pixel hits.
fn scenes() -> Vec<(&'static str, Scene)> {
    vec![
        ("seed 512 shadows", scene(&[])),
        ("seed 512 no shadows", scene(&["shading.shadows=false"])),
        (
            "40 iterations 256",
            scene(&[
                "fractal.max_iterations=40",
                "image.width=256",
                "image.height=256",
            ]),
        ),
        (
            "wide view 512",
            scene(&[
                "camera.fov_y_degrees=120",
                "camera.eye=[0.8, 1.0, 2.0]",
                "light.position=[-2, 3, 2]",
            ]),
        ),
        (
            "close-up 512",
            scene(&["camera.eye=[0.2, 0.1, 1.6]", "camera.fov_y_degrees=12"]),
        ),
    ]
}

/// The tracers compared.
struct Gpus {
    specialised: Renderer,
    generic: Renderer,
    adapter: String,
}

fn gpus() -> Option<Gpus> {
    let make = || GpuContext::new().and_then(GpuTracer::new);
    match (make(), make()) {
        (Ok(specialised), Ok(mut generic)) => {
            generic.set_specialise(false);
            Some(Gpus {
                adapter: specialised.context().adapter_label(),
                specialised: planned(
                    Some(GpuKernels::with_tracer(Arc::new(specialised))),
                    Backend::Gpu,
                    Precision::F32,
                ),
                generic: planned(
                    Some(GpuKernels::with_tracer(Arc::new(generic))),
                    Backend::Gpu,
                    Precision::F32,
                ),
            })
        }
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("no GPU benchmarks: {e}");
            None
        }
    }
}

fn criterion_benches(c: &mut Criterion, gpus: Option<&Gpus>) {
    for (name, scene) in scenes() {
        let mut group = c.benchmark_group(name);
        group
            .sample_size(10)
            .measurement_time(Duration::from_secs(4));
        group.throughput(Throughput::Elements(
            scene.image.width as u64 * scene.image.height as u64,
        ));
        let render = |r: &Renderer| r.render_frame(&scene, Picture::SHADED).expect("render");
        if let Some(g) = gpus {
            for (label, renderer) in [
                ("gpu specialised", &g.specialised),
                ("gpu generic", &g.generic),
            ] {
                render(renderer);
                group.bench_function(label, |b| b.iter(|| render(renderer)));
            }
        }
        for (label, precision) in [("cpu f32", Precision::F32), ("cpu f64", Precision::F64)] {
            let cpu = cpu_renderer(precision);
            group.bench_function(label, |b| b.iter(|| render(&cpu)));
        }
        group.finish();
    }
}

/// The median of `n` timings.
fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(|a, b| a.total_cmp(b));
    times[times.len() / 2]
}

/// GPU seconds (timestamps, else render seconds) of a render, median of 7 after a warm-up.
fn gpu_seconds(renderer: &Renderer, scene: &Scene) -> f64 {
    let seconds = || {
        let (_, s) = renderer
            .render_frame(scene, Picture::SHADED)
            .expect("GPU render");
        s.gpu_seconds.unwrap_or(s.render_seconds)
    };
    seconds();
    median((0..7).map(|_| seconds()).collect())
}

/// Render seconds on the CPU, median of 3.
fn cpu_seconds(scene: &Scene, precision: Precision) -> f64 {
    let renderer = cpu_renderer(precision);
    let seconds = || {
        let (_, s) = renderer
            .render_frame(scene, Picture::SHADED)
            .expect("CPU render");
        s.render_seconds
    };
    median((0..3).map(|_| seconds()).collect())
}

/// The summary table, printed and written to target/criterion/qjulia-summary.md.
fn summary(gpus: Option<&Gpus>) {
    let adapter = gpus.map_or("none".to_string(), |g| g.adapter.clone());
    let mut out = format!(
        "# qjulia bench summary\n\nGPU adapter: {adapter}. GPU seconds by timestamp queries (median of 7 after a \
         warm-up); CPU seconds wall-clock (median of 3), {} threads.\n\n\
         | scene | tracer | seconds | Mpixel/s | M estimates/s | M iterations/s | x CPU f32 |\n\
         |---|---|---|---|---|---|---|\n",
        rayon::current_num_threads()
    );
    let mut gains = String::from(
        "\n| scene | generic pipeline s | specialised s | specialisation gain |\n|---|---|---|---|\n",
    );
    for (name, scene) in scenes() {
        let work = cpu::count_work(&TraceParams::<f32>::new(&scene));
        let cpu32 = cpu_seconds(&scene, Precision::F32);
        let cpu64 = cpu_seconds(&scene, Precision::F64);
        let mut rows = vec![("cpu f32", cpu32), ("cpu f64", cpu64)];
        if let Some(g) = gpus {
            let spec = gpu_seconds(&g.specialised, &scene);
            let generic = gpu_seconds(&g.generic, &scene);
            rows.insert(0, ("gpu specialised", spec));
            rows.insert(1, ("gpu generic", generic));
            gains += &format!(
                "| {name} | {generic:.4} | {spec:.4} | {:.0}% less time |\n",
                100.0 * (1.0 - spec / generic)
            );
        }
        for (tracer, s) in rows {
            out += &format!(
                "| {name} | {tracer} | {s:.4} | {:.2} | {:.1} | {:.1} | {:.2} |\n",
                work.pixels as f64 / s / 1e6,
                work.estimates as f64 / s / 1e6,
                work.iterations as f64 / s / 1e6,
                cpu32 / s
            );
        }
        let (_, stats) = cpu_renderer(Precision::F32)
            .render_frame(&scene, Picture::SHADED)
            .expect("CPU render");
        out += &format!(
            "| {name} | work | {} px | | {} estimates | {} iterations | primary steps useful in 8x8 blocks: {:.0}% |\n",
            work.pixels,
            work.estimates,
            work.iterations,
            100.0 * stats.summary.tile_efficiency
        );
    }
    out += &gains;
    println!("\n{out}");
    let path =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("../criterion/qjulia-summary.md");
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    match std::fs::write(&path, &out) {
        Ok(()) => println!("summary written to {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
}

fn main() {
    let start = Instant::now();
    let gpus = gpus();
    let mut c = Criterion::default().configure_from_args();
    criterion_benches(&mut c, gpus.as_ref());
    summary(gpus.as_ref());
    c.final_summary();
    eprintln!("bench took {:.0} s", start.elapsed().as_secs_f64());
}
