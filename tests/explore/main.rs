//! The explorer driven offscreen (egui_kittest with its wgpu renderer, no display server): the
//! image it shows is the headless render of the same scene, and scripted interaction (a slider,
//! a drag) changes the picture; the step views show the heat map of the headless render's steps,
//! and the 2D mode shows what `render2d` draws, panned and zoomed by mouse.
//!
//! The tests are in `view.rs` (the view against the headless render, the 2D mode, the step
//! views, the shading panel), `session.rs` (the timeline, the f64 switch, exports, closing, the
//! scene file) and `path_traced.rs` (path mode, adaptive sampling, the denoiser); the harness
//! and the comparisons they share are here.

#[path = "../common/mod.rs"]
mod common;
mod path_traced;
mod session;
mod view;

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use qjulia::explore::ExplorerApp;
use qjulia::{Frame, TraceParams};

const WINDOW: [f32; 2] = [760.0, 420.0];

/// The explorer on the GPU, or None where the GPU tests are opted out.
fn harness(test: &str) -> Option<Harness<'static, ExplorerApp>> {
    harness_of(test, common::scene(&["fractal.max_iterations=8"]), WINDOW)
}

/// The explorer on the GPU showing `scene` in a window of `window` points.
fn harness_of(
    test: &str,
    scene: qjulia::Scene,
    window: [f32; 2],
) -> Option<Harness<'static, ExplorerApp>> {
    harness_sampling(test, scene, window, 3)
}

/// [`harness_of`] with the view's `samples` (adaptive sampling's pixels stop at 4 or more).
fn harness_sampling(
    test: &str,
    scene: qjulia::Scene,
    window: [f32; 2],
    samples: u32,
) -> Option<Harness<'static, ExplorerApp>> {
    common::gpu(test)?;
    let render_state = egui_kittest::wgpu::create_render_state(
        qjulia::explore::wgpu_setup(),
        egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let mut app = ExplorerApp::with_scene(scene);
    // A few samples, so that the view accumulates (and the comparisons check the running mean)
    // without the default 64 passes of every settle.
    app.preview_samples = samples;
    app.attach_gpu(&render_state);
    assert!(
        app.slice_texture().is_some(),
        "the explorer found no GPU tracer"
    );
    let harness = Harness::builder()
        .with_size(window)
        .with_pixels_per_point(1.0)
        .renderer(egui_kittest::wgpu::WgpuTestRenderer::from_render_state(
            render_state,
        ))
        .build_ui_state(|ui, app: &mut ExplorerApp| app.frame(ui), app);
    Some(harness)
}

/// Whether the f64 part of `test` runs: true where the adapter has f64. Where it has none (GL
/// llvmpipe) the deep view must stay in f32 with a note that says why (the refusal a user sees
/// on the status line), and the f64 part is said skipped.
fn runs_f64(test: &str, precision: qjulia::Precision, note: &str) -> bool {
    if common::gpu_has(common::Capability::F64, test, "the view in f64") {
        return true;
    }
    assert_eq!(
        precision,
        qjulia::Precision::F32,
        "{test}: without f64, f32"
    );
    assert!(note.contains("f64 unavailable"), "{test}: {note}");
    false
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
    let rect = harness.state().view_rect();
    let [w, h] = harness.state().view_pixels();
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

/// Steps frames until the explorer's status line says an export or render is done.
fn wait_for_message(harness: &mut Harness<'static, ExplorerApp>, done: &str) {
    let start = Instant::now();
    loop {
        harness.step();
        match harness.state().message() {
            Some((m, false)) if m.starts_with(done) => return,
            Some((m, true)) => panic!("the explorer failed: {m}"),
            _ => {}
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the explorer never said {done:?}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Exports the view to a PNG and renders `qjulia render ARGS -o cli.png`: the two must be the
/// same bytes. On a difference both PNGs are kept under target/ (NAME_actual.png, the export,
/// and NAME_expected.png) and the panic counts the pixels that differ. Returns render's stderr.
fn assert_export_is_render(
    harness: &mut Harness<'static, ExplorerApp>,
    name: &str,
    args: &[&str],
) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("export.png");
    harness.state_mut().start_export(path.clone());
    // This export's own message: an earlier export's "exported" may still be showing.
    wait_for_message(harness, &format!("exported {}", path.display()));
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", "cli.png"]);
    let out = common::qjulia(dir.path(), &all);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let (exported, cli) = (
        std::fs::read(&path).unwrap(),
        std::fs::read(dir.path().join("cli.png")).unwrap(),
    );
    if exported != cli {
        let decode = |p: &std::path::Path| qjulia::output::read_png_rgb(p).unwrap();
        let ([w, h], a) = decode(&path);
        let (_, b) = decode(&dir.path().join("cli.png"));
        let differ = a.chunks(3).zip(b.chunks(3)).filter(|(x, y)| x != y).count();
        let target = common::output_dir();
        std::fs::create_dir_all(&target).unwrap();
        std::fs::copy(&path, target.join(format!("{name}_actual.png"))).unwrap();
        std::fs::copy(
            dir.path().join("cli.png"),
            target.join(format!("{name}_expected.png")),
        )
        .unwrap();
        panic!(
            "{name}: Export PNG and `qjulia render` differ: {differ} of {} pixels (both PNGs \
             under {})",
            w * h,
            target.display()
        );
    }
    common::stderr(&out)
}

/// Every byte equal.
const EXACT: qjulia::compare::Tolerance = qjulia::compare::Tolerance {
    mask_agreement: 1.0,
    depth_abs: 0.0,
    depth_agreement: 1.0,
    colour_abs: 0,
    colour_agreement: 1.0,
};
