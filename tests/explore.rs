//! The explorer driven offscreen (egui_kittest with its wgpu renderer, no display server): the
//! image it shows is the headless render of the same scene, and scripted interaction (a slider,
//! a drag) changes the picture.

mod common;

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use qjulia::explore::ExplorerApp;
use qjulia::{Frame, TraceParams};

const WINDOW: [f32; 2] = [760.0, 420.0];

/// The explorer on the GPU, or None where the GPU tests are opted out.
fn harness(test: &str) -> Option<Harness<'static, ExplorerApp>> {
    common::gpu(test)?;
    let render_state = egui_kittest::wgpu::create_render_state(
        qjulia::explore::wgpu_setup(),
        egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let mut app = ExplorerApp::with_scene(common::scene(&["fractal.max_iterations=8"]));
    app.attach_gpu(&render_state);
    assert!(app.view.is_some(), "the explorer found no GPU tracer");
    let harness = Harness::builder()
        .with_size(WINDOW)
        .with_pixels_per_point(1.0)
        .renderer(egui_kittest::wgpu::WgpuTestRenderer::from_render_state(
            render_state,
        ))
        .build_ui_state(|ui, app: &mut ExplorerApp| app.frame(ui), app);
    Some(harness)
}

/// Steps frames until the view shows the full-resolution image of the current scene.
fn settle(harness: &mut Harness<'static, ExplorerApp>) {
    let start = Instant::now();
    loop {
        harness.step();
        if harness.state().view_refined() {
            harness.step();
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the view never refined"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The view's pixels as the harness renders the whole window.
fn shown_view(harness: &mut Harness<'static, ExplorerApp>) -> Frame {
    let image = harness.render().expect("render the window");
    let rect = harness.state().view_rect;
    let [w, h] = harness.state().view_pixels;
    let (x0, y0) = (rect.min.x.round() as u32, rect.min.y.round() as u32);
    let colour = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| {
            let p = image.get_pixel(x0 + i, y0 + j).0;
            u32::from_le_bytes([p[0], p[1], p[2], 255])
        })
        .collect();
    // The screen has no depth: agree on colour only (depth NaN-free zeros on both sides).
    let n = (w * h) as usize;
    Frame {
        width: w,
        height: h,
        colour,
        depth: vec![0.0; n],
        steps: vec![0; n],
        non_finite: 0,
    }
}

fn headless(harness: &Harness<'static, ExplorerApp>) -> Frame {
    let tracer = common::gpu("headless").expect("GPU");
    let mut frame = tracer
        .render(&TraceParams::<f32>::new(&harness.state().view_scene()))
        .unwrap()
        .frame;
    frame.depth.iter_mut().for_each(|d| *d = 0.0);
    frame
}

fn changed_fraction(a: &Frame, b: &Frame) -> f64 {
    let n = a
        .colour
        .iter()
        .zip(&b.colour)
        .filter(|(x, y)| x != y)
        .count();
    n as f64 / a.colour.len() as f64
}

#[test]
fn the_view_shows_the_headless_render_and_interaction_changes_it() {
    let Some(mut harness) = harness("explorer") else {
        return;
    };
    settle(&mut harness);
    let [w, h] = harness.state().view_pixels;
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
    let centre = harness.state().view_rect.center();
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
