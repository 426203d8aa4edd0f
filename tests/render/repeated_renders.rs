//! Many renders in one process hold their memory: the explorer and `animate` render the same
//! pipelines thousands of times, and on Mesa 22.3's lavapipe a uniform the tracer tests in an
//! `if` made the driver compile (and keep) a new variant of the shader at every render, about
//! 0.6 MB each (docs/book/robustness.md). The test runs in a process of its own
//! (`common::own_process`), so that the resident memory it measures is its own. It runs on the GPU: without an adapter it fails, unless
//! `QJULIA_SKIP_GPU_TESTS=1`. `QJULIA_UNIFORMS_AS_STORAGE=0` brings the leak back on
//! lavapipe, and the test then fails.

use crate::common;

use qjulia::Picture;

/// Warmed up, 300 more renders of each of two scenes (the default, shaded; the path-traced
/// preset, with its sample kernel) grow the resident memory by under 24 MB: the leak grew it
/// by 732 MB here (220 to 952 MB), and with the params bound as storage it grows by 0.0 MB.
#[test]
fn three_hundred_renders_grow_resident_memory_by_under_24_mb() {
    let name = "three_hundred_renders_grow_resident_memory_by_under_24_mb";
    if !common::own_process(module_path!(), name, &[]) {
        return;
    }
    let Some(kernels) = common::kernels("repeated renders") else {
        return;
    };
    let shaded = common::scene(&["image.width=64", "image.height=64"]);
    let path = common::path_traced(32, 1, |_| {});
    let renderers = [
        (common::gpu_renderer(&kernels, &shaded), &shaded),
        (common::gpu_renderer(&kernels, &path), &path),
    ];
    let render_all = |times: u32| {
        for _ in 0..times {
            for (renderer, scene) in &renderers {
                renderer
                    .render(scene, Picture::SHADED, &mut |_| Ok(()))
                    .expect("a render");
            }
        }
    };
    render_all(30);
    let Some(before) = qjulia::memory::resident_bytes() else {
        common::say_skipped(name, "the memory check", "no /proc/self/statm here");
        return;
    };
    render_all(300);
    let after = qjulia::memory::resident_bytes().expect("statm read once");
    let growth_mb = (after as f64 - before as f64) / 1e6;
    eprintln!(
        "repeated renders: resident {:.1} MB -> {:.1} MB over 600 renders",
        before as f64 / 1e6,
        after as f64 / 1e6
    );
    assert!(
        growth_mb < 24.0,
        "600 renders grew the resident memory by {growth_mb:.1} MB (from {:.1} MB): \
         something keeps memory per render",
        before as f64 / 1e6
    );
}
