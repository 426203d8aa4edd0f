//! The view against the headless render: interaction changes it, a mode not shown gives its
//! memory back, the 2D mode shows `render2d` (panned and zoomed by mouse), the step views show the
//! heat map of the steps, and the shading panel sets the picture's features.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use qjulia::explore::ExplorerApp;
use qjulia::explore::app::Mode;
use qjulia::scene::View;
use qjulia::{Frame, TraceParams};

use super::{EXACT, WINDOW, changed_fraction, harness, headless, settle, shown_view};
use crate::common;

#[test]
fn the_view_shows_the_headless_render_and_interaction_changes_it() {
    let Some(mut harness) = harness("explorer") else {
        return;
    };
    settle(&mut harness);
    let [w, h] = harness.state().view_pixels();
    assert!(w > 200 && h > 200, "the view is {w}x{h}");
    let shown = shown_view(&mut harness);
    common::assert_agree(
        "explorer_view",
        &headless(&harness),
        &shown,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );

    // A slider: c's real part.
    let before = harness.state().scene.fractal.c.clone();
    harness
        .get_by_role_and_label(egui::Role::Slider, "c real")
        .set_value_accesskit(-0.35);
    settle(&mut harness);
    let after_slider = shown_view(&mut harness);
    assert_ne!(
        harness.state().scene.fractal.c[0],
        before[0],
        "the slider did not move c"
    );
    assert!((harness.state().scene.fractal.c[0] + 0.35).abs() < 1e-9);
    assert!(
        changed_fraction(&shown, &after_slider) > 0.05,
        "a new c left the picture unchanged"
    );
    common::assert_agree(
        "explorer_after_slider",
        &headless(&harness),
        &after_slider,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );

    // A drag across the view orbits the camera.
    let eye = harness.state().scene.camera.eye;
    let centre = harness.state().view_rect().center();
    harness.hover_at(centre);
    harness.drag_at(centre);
    harness.step();
    for k in 1..=6 {
        harness.hover_at(centre + egui::vec2(15.0 * k as f32, 0.0));
        harness.step();
    }
    harness.drop_at(centre + egui::vec2(90.0, 0.0));
    settle(&mut harness);
    let after_drag = shown_view(&mut harness);
    assert_ne!(
        harness.state().scene.camera.eye,
        eye,
        "the drag did not move the camera"
    );
    assert!(
        changed_fraction(&after_slider, &after_drag) > 0.05,
        "orbiting left the picture unchanged"
    );
    common::assert_agree(
        "explorer_after_drag",
        &headless(&harness),
        &after_drag,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
}

/// A mode not shown gives its view's memory back (its texture is gone), and shown again it
/// renders afresh, the same picture.
#[test]
fn the_mode_not_shown_gives_its_memory_back_and_renders_again() {
    let Some(mut harness) = harness("explorer_release") else {
        return;
    };
    settle(&mut harness);
    let first = shown_view(&mut harness);
    assert!(harness.state().slice_texture().unwrap().texture().is_some());

    harness.state_mut().mode = Mode::Julia2d;
    settle(&mut harness);
    assert!(
        harness
            .state()
            .julia2d_texture()
            .unwrap()
            .texture()
            .is_some()
    );
    assert!(
        harness.state().slice_texture().unwrap().texture().is_none(),
        "the 3D view kept its texture in 2D mode"
    );

    harness.state_mut().mode = Mode::Slice3d;
    settle(&mut harness);
    assert!(
        harness
            .state()
            .julia2d_texture()
            .unwrap()
            .texture()
            .is_none(),
        "the 2D view kept its texture in 3D mode"
    );
    let again = shown_view(&mut harness);
    common::assert_agree("explorer_release", &first, &again, &EXACT);
    common::assert_agree(
        "explorer_release_headless",
        &headless(&harness),
        &again,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
}

/// The picture `render2d` draws of the view's scene, on the same kernel (depth zeroed, as the
/// screen has none).
fn headless_2d(harness: &Harness<'static, ExplorerApp>) -> Frame {
    let tracer = common::gpu("headless_2d").expect("GPU");
    let julia = qjulia::gpu::GpuJulia2d::new(tracer.context().clone()).unwrap();
    let scene = harness.state().view_scene();
    let (mut frame, _) = julia
        .render(&qjulia::Julia2dParams::<f32>::new(&scene))
        .unwrap();
    frame.depth.iter_mut().for_each(|d| *d = 0.0);
    frame
}

#[test]
fn the_2d_mode_shows_render2d_and_the_mouse_pans_and_zooms() {
    let Some(mut harness) = harness("explorer_2d") else {
        return;
    };
    harness.state_mut().scene.fractal.c = vec![-0.12, 0.75, 0.0, 0.0];
    harness.state_mut().mode = Mode::Julia2d;
    settle(&mut harness);
    let shown = shown_view(&mut harness);
    common::assert_agree(
        "explorer_2d",
        &headless_2d(&harness),
        &shown,
        &qjulia::compare::JULIA2D_TOLERANCE,
    );
    assert!(
        shown.colour.contains(&0xffff_ffff),
        "no point of the set shown"
    );

    // A drag to the right moves the centre left (the picture follows the pointer).
    let before = harness.state().scene.view2d.clone();
    let centre = harness.state().view_rect().center();
    harness.hover_at(centre);
    harness.drag_at(centre);
    harness.step();
    for k in 1..=4 {
        harness.hover_at(centre + egui::vec2(10.0 * k as f32, -5.0 * k as f32));
        harness.step();
    }
    harness.drop_at(centre + egui::vec2(40.0, -20.0));
    settle(&mut harness);
    let moved = harness.state().scene.view2d.clone();
    assert!(
        moved.center[0] < before.center[0],
        "{before:?} -> {moved:?}"
    );
    assert!(
        moved.center[1] < before.center[1],
        "{before:?} -> {moved:?}"
    );
    assert_eq!(moved.extent, before.extent);
    let after_drag = shown_view(&mut harness);
    common::assert_agree(
        "explorer_2d_after_drag",
        &headless_2d(&harness),
        &after_drag,
        &qjulia::compare::JULIA2D_TOLERANCE,
    );

    // The wheel zooms in about the pointer.
    harness.hover_at(centre);
    for _ in 0..5 {
        harness.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, 60.0),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: egui::Modifiers::NONE,
        });
        harness.step();
    }
    // Smooth scrolling goes on for a few frames: wait until the extent holds still.
    let mut last = harness.state().scene.view2d.extent;
    let mut still = 0;
    while still < 5 {
        harness.step();
        let extent = harness.state().scene.view2d.extent;
        still = if extent == last { still + 1 } else { 0 };
        last = extent;
    }
    // The harness draws the pointer: move it off the view before looking.
    harness.hover_at(egui::pos2(4.0, WINDOW[1] - 4.0));
    settle(&mut harness);
    let zoomed = harness.state().scene.view2d.clone();
    assert!(
        zoomed.extent < 0.9 * moved.extent,
        "{moved:?} -> {zoomed:?}"
    );
    let after_zoom = shown_view(&mut harness);
    assert!(changed_fraction(&after_drag, &after_zoom) > 0.05);
    common::assert_agree(
        "explorer_2d_after_zoom",
        &headless_2d(&harness),
        &after_zoom,
        &qjulia::compare::JULIA2D_TOLERANCE,
    );
}

#[test]
fn step_views_show_the_heat_map_of_the_steps() {
    let Some(mut harness) = harness("explorer_steps") else {
        return;
    };
    for view in [View::Steps, View::Divergence] {
        harness.state_mut().scene.image.view = view;
        settle(&mut harness);
        let shown = shown_view(&mut harness);
        let tracer = common::gpu("headless_steps").expect("GPU");
        let scene = harness.state().view_scene();
        let frame = tracer
            .render_outputs(&TraceParams::<f32>::new(&scene), false)
            .unwrap()
            .frame;
        let map = qjulia::heatmap::heat_map_of(view, &frame.steps, &[], frame.width, frame.height)
            .unwrap();
        assert_eq!(harness.state().heat_legend(), Some(&map.legend));
        // Above the legend strip at the bottom, the screen holds the heat map.
        let rows = frame.height - qjulia::heatmap::LEGEND_HEIGHT - 4;
        let crop = |rgb: Vec<u8>| -> Frame {
            let n = (frame.width * rows) as usize;
            Frame {
                width: frame.width,
                height: rows,
                colour: rgb[..n * 3]
                    .chunks(3)
                    .map(|p| u32::from_le_bytes([p[0], p[1], p[2], 255]))
                    .collect(),
                depth: vec![0.0; n],
                depth_f64: Vec::new(),
                steps: vec![0; n],
                radiance: Vec::new(),
                unclamped: Vec::new(),
                albedo: Vec::new(),
                normal: Vec::new(),
                luminance_m2: Vec::new(),
                hits: Vec::new(),
                hit_depth: Vec::new(),
                specular: Vec::new(),
                view_cosine: Vec::new(),
                noisy: Vec::new(),
                halves: Vec::new(),
                samples: Vec::new(),
                non_finite: 0,
                estimates: 0,
                iterations: 0,
                nonfinite_samples: 0,
                exhausted_rays: 0,
            }
        };
        common::assert_agree(
            &format!("explorer_{}", view.name()),
            &crop(map.rgb),
            &crop(shown.rgb8()),
            &qjulia::compare::CONTRACT_TOLERANCE,
        );
    }
}

/// The shading panel holds the picture's features (issue 11): its sliders set the scene keys and
/// the view shows the headless render of the result.
#[test]
fn the_shading_panel_sets_the_picture_features() {
    let Some(mut harness) = harness("explorer_shading") else {
        return;
    };
    settle(&mut harness);
    let before = shown_view(&mut harness);
    harness.get_by_label("Light and shading").click_accesskit();
    for _ in 0..10 {
        harness.step();
    }
    for label in [
        "trap radius",
        "trap scale",
        "phase red",
        "phase green",
        "phase blue",
    ] {
        harness.get_by_role_and_label(egui::Role::Slider, label);
    }
    harness.get_by_label("colouring");
    for (label, value) in [("light radius", 0.4), ("ambient", 0.3), ("occlusion", 1.0)] {
        harness
            .get_by_role_and_label(egui::Role::Slider, label)
            .set_value_accesskit(value);
        harness.step();
    }
    let scene = &harness.state().scene;
    assert!(
        (scene.light.radius - 0.4).abs() < 1e-9,
        "{}",
        scene.light.radius
    );
    assert!((scene.shading.ambient - 0.3).abs() < 1e-9);
    assert!((scene.shading.occlusion - 1.0).abs() < 1e-9);
    settle(&mut harness);
    let after = shown_view(&mut harness);
    assert!(
        changed_fraction(&before, &after) > 0.05,
        "the features left the picture unchanged"
    );
    common::assert_agree(
        "explorer_features",
        &headless(&harness),
        &after,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
}
