//! Where a process's start-up goes (issue 22, "a start-up that does not recompile"): the phases
//! of a 16x16 render on the GPU, timed one by one in one process, as `qjulia render` goes
//! through them: the instance and its adapters, the device, the tracer's module (naga's WGSL
//! front end and validation), the scene's pipeline (its constants applied and the branches they
//! decide cut, src/gpu/kernel/specialise.rs, then naga's back end and the driver), the first
//! render (the first dispatch: lavapipe compiles the rest here), and a second render of the same
//! scene (what is left once all is built).
//! Run it with Mesa's shader cache on and off (`MESA_SHADER_CACHE_DISABLE=1`):
//!
//!     cargo run --release --example startup

use std::time::Instant;

use qjulia::gpu::{GpuContext, GpuKernels};
use qjulia::params::TraceParams;
use qjulia::{Backend, Picture, Planner, PrecisionChoice, Scene};

fn main() -> qjulia::Result<()> {
    let process = Instant::now();
    let mut last = Instant::now();
    let mut phase = |name: &str| {
        let now = Instant::now();
        println!("{name:<44} {:>8.1} ms", (now - last).as_secs_f64() * 1e3);
        last = now;
    };
    qjulia::gpu::give_a_runtime_dir();
    let adapters = pollster::block_on(qjulia::gpu::available_adapters());
    phase("instance and adapters");
    let adapter = qjulia::gpu::choose_adapter(adapters)?;
    let ctx = GpuContext::from_adapter(adapter)?;
    phase(&format!("device ({})", ctx.adapter_label()));
    println!(
        "  PIPELINE_CACHE: {}; key {:?}",
        ctx.adapter
            .features()
            .contains(wgpu::Features::PIPELINE_CACHE),
        wgpu::util::pipeline_cache_key(&ctx.info)
    );
    let kernels = std::sync::Arc::new(GpuKernels::new(ctx));
    let tracer = kernels.tracer()?;
    phase("tracer module (naga front end)");
    let mut scene = Scene::default();
    scene.image.width = 16;
    scene.image.height = 16;
    let variant = tracer.variant_for(&TraceParams::<f32>::new(&scene), true);
    tracer.pipeline(variant)?;
    phase("the scene's pipeline (specialised, driver)");
    let mut planner = Planner::on_device(kernels, Backend::Gpu, PrecisionChoice::F32);
    for run in ["first render (first dispatch)", "second render"] {
        let plan = planner.plan(&scene, Picture::SHADED.into(), &mut |_| {})?;
        plan.renderer
            .render(&scene, Picture::SHADED, &mut |_| Ok(()))?;
        phase(run);
    }
    println!(
        "{:<44} {:>8.1} ms",
        "in all",
        process.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}
