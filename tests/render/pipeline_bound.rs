//! A kernel holds a bounded number of pipelines: an explorer session that visits scene after
//! scene meets a new variant at each, and every pipeline held keeps the driver's compiled code.
//! Past `MAX_PIPELINES` the one used longest ago is dropped, and a scene whose pipeline was
//! dropped renders the same bytes when it comes back. It runs on the GPU: without an adapter
//! it fails, unless `QJULIA_SKIP_GPU_TESTS=1`.

use crate::common;

use qjulia::Picture;
use qjulia::gpu::kernel::MAX_PIPELINES;

/// Scenes of distinct variants: every combination of five features.
fn scenes() -> Vec<qjulia::Scene> {
    let features = [
        "shading.shadows=false",
        "shading.occlusion=0.5",
        "shading.colouring=\"orbit_trap\"",
        "cut.enabled=true",
        "light.radius=0.2",
    ];
    (0..1u32 << features.len())
        .map(|mask| {
            let mut sets = vec!["image.width=16", "image.height=16"];
            sets.extend(
                features
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| mask & (1 << k) != 0)
                    .map(|(_, s)| *s),
            );
            common::scene(&sets)
        })
        .collect()
}

#[test]
fn the_tracer_holds_at_most_max_pipelines_and_a_dropped_one_renders_the_same_bytes() {
    let Some(kernels) = common::kernels("pipeline bound") else {
        return;
    };
    let tracer = kernels.tracer().expect("the tracer");
    let scenes = scenes();
    let render = |scene: &qjulia::Scene| {
        common::gpu_renderer(&kernels, scene)
            .render_frame(scene, Picture::SHADED)
            .expect("a render")
            .0
    };
    let first = render(&scenes[0]);
    let mut most = 0;
    for scene in &scenes[1..] {
        render(scene);
        most = most.max(tracer.pipelines_held());
    }
    assert!(
        most > MAX_PIPELINES / 2,
        "{} scenes made only {most} pipelines: the scenes do not differ in variant",
        scenes.len()
    );
    assert!(
        most <= MAX_PIPELINES,
        "the tracer held {most} pipelines, over its bound of {MAX_PIPELINES}"
    );
    // The first scene's pipeline was the least recently used: gone, and built again.
    let again = render(&scenes[0]);
    let bits = |f: &qjulia::Frame| f.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
    assert_eq!(first.colour, again.colour, "the rebuilt pipeline's colours");
    assert_eq!(bits(&first), bits(&again), "the rebuilt pipeline's depths");
    assert_eq!(first.steps, again.steps, "the rebuilt pipeline's steps");
}

/// What the explorer's frame asks of a kernel: a pipeline not built is None, and nothing is
/// built by asking; once built (on another thread, as the explorer's builder does), it is held.
#[test]
fn a_held_pipeline_is_only_looked_up_and_a_build_on_another_thread_is_held() {
    let Some(kernels) = common::kernels("held pipeline") else {
        return;
    };
    let tracer = kernels.tracer().expect("the tracer");
    let scene = common::scene(&["image.width=16", "image.height=16", "cut.enabled=true"]);
    let params = qjulia::TraceParams::<f32>::new(&scene);
    // Unshaded (a step view's variant): the test beside this one renders shaded scenes only.
    let variant = tracer.variant_for(&params, false);
    let readback = qjulia::gpu::Readback::All;
    // The kernels are shared with the test beside this one: counts of pipelines race, so
    // asking twice stands for "asking built nothing".
    assert!(tracer.held_pipeline_reading(variant, readback).is_none());
    assert!(
        tracer.held_pipeline_reading(variant, readback).is_none(),
        "asking built the pipeline"
    );
    let builder = tracer.clone();
    std::thread::spawn(move || builder.pipeline_reading(variant, readback).map(|_| ()))
        .join()
        .expect("the build's thread")
        .expect("the build");
    assert!(tracer.held_pipeline_reading(variant, readback).is_some());
}
