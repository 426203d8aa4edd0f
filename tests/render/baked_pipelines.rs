//! Renders whose values change at every render, as a drag in the explorer changes them, hold
//! their memory where each bakes its values into a pipeline of its own
//! (`qjulia::gpu::variant::Bake`): the kernel keeps at most `MAX_PIPELINES`, the least recently
//! used dropped, and the driver frees a dropped pipeline's code. The test runs in a process of
//! its own (`common::own_process`), so that the resident memory it measures is its own. It runs on the GPU: without an adapter it
//! fails, unless `QJULIA_SKIP_GPU_TESTS=1`.

use crate::common;

use qjulia::gpu::kernel::MAX_PIPELINES;

/// Warmed up past the cap, 32 more renders, each of a new c and so of a new baked pipeline,
/// grow the resident memory by under 24 MB, and the tracer holds at most `MAX_PIPELINES`.
/// Unbounded (the cap raised to 16,000), 96 new pipelines grew it by 469 MB on lavapipe
/// (276 to 745 MB), about 4.9 MB each; held by the cap, by 0.2 MB.
#[test]
fn renders_of_changing_values_are_held_by_the_pipeline_cap() {
    let name = "renders_of_changing_values_are_held_by_the_pipeline_cap";
    if !common::own_process(module_path!(), name, &[]) {
        return;
    }
    let Some(kernels) = common::kernels("baked pipelines") else {
        return;
    };
    let mut tracer = qjulia::gpu::GpuTracer::new(kernels.context().clone()).expect("a tracer");
    tracer.set_bake(qjulia::gpu::variant::Bake::Always);
    let render = |k: u32| {
        let c = format!("fractal.c=[-0.2, {:.6}, 0.3, 0.1]", 0.6 + k as f64 * 1e-4);
        let scene = common::scene(&["image.width=32", "image.height=32", &c]);
        let params = qjulia::params::TraceParams::<f32>::new(&scene);
        tracer.render(&params).expect("a render");
    };
    for k in 0..MAX_PIPELINES as u32 + 8 {
        render(k);
    }
    let Some(before) = qjulia::memory::resident_bytes() else {
        common::say_skipped(name, "the memory check", "no /proc/self/statm here");
        return;
    };
    let more = 32;
    for k in 0..more {
        render(1000 + k);
    }
    let after = qjulia::memory::resident_bytes().expect("statm read once");
    let growth_mb = (after as f64 - before as f64) / 1e6;
    eprintln!(
        "baked pipelines: resident {:.1} MB -> {:.1} MB over {more} new pipelines, {} held",
        before as f64 / 1e6,
        after as f64 / 1e6,
        tracer.pipelines_held()
    );
    assert!(tracer.pipelines_held() <= MAX_PIPELINES);
    assert!(
        growth_mb < 24.0,
        "{more} renders of new values grew the resident memory by {growth_mb:.1} MB (from \
         {:.1} MB): something keeps a dropped pipeline's memory",
        before as f64 / 1e6
    );
}
