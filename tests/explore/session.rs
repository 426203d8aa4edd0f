//! The rest of a session: the timeline keyed and scrubbed, the switch to f64 (3D and 2D),
//! exports (a mesh, a deep PNG, a deep animation, one that goes on while another scene is chosen),
//! Ctrl+Q, and a scene file changed on disk.

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use qjulia::TraceParams;
use qjulia::explore::ExplorerApp;
use qjulia::explore::app::Mode;

use super::{
    assert_export_is_render, harness, headless, runs_f64, settle, shown_view, wait_for_message,
};
use crate::common;

/// Presses and releases the left button at `pos`, a frame between.
fn click_at(harness: &mut Harness<'static, ExplorerApp>, pos: egui::Pos2) {
    harness.hover_at(pos);
    harness.step();
    harness.drag_at(pos);
    harness.step();
    harness.drop_at(pos);
    harness.step();
}

#[test]
fn the_timeline_keys_the_view_scrubs_and_saves_what_animate_renders() {
    let Some(mut harness) = harness("explorer_timeline") else {
        return;
    };
    settle(&mut harness);
    // A key at frame 0 from the view, then one at frame 90 with the camera orbited.
    harness.get_by_label("Add key").click();
    harness.step();
    assert_eq!(harness.state().timeline.key_frames(), [0]);
    let (_, x0, x1) = harness.state().timeline_strip();
    let y = harness.state().timeline_strip().0.center().y;
    let x_of = |frame: f32| x0 + (x1 - x0) * frame / 119.0;
    click_at(&mut harness, egui::pos2(x_of(90.0), y));
    assert_eq!(harness.state().timeline.frame, 90);
    let centre = harness.state().view_rect().center();
    harness.hover_at(centre);
    harness.drag_at(centre);
    harness.step();
    for k in 1..=6 {
        harness.hover_at(centre + egui::vec2(15.0 * k as f32, 0.0));
        harness.step();
    }
    harness.drop_at(centre + egui::vec2(90.0, 0.0));
    harness.step();
    harness.get_by_label("Add key").click();
    harness.step();
    assert_eq!(harness.state().timeline.key_frames(), [0, 90]);

    // Drag the key at 90 to 100.
    harness.hover_at(egui::pos2(x_of(90.0), y));
    harness.step();
    harness.drag_at(egui::pos2(x_of(90.0), y));
    harness.step();
    for k in 1..=5 {
        harness.hover_at(egui::pos2(x_of(90.0 + 2.0 * k as f32), y));
        harness.step();
    }
    harness.drop_at(egui::pos2(x_of(100.0), y));
    harness.step();
    assert_eq!(harness.state().timeline.key_frames(), [0, 100]);

    // Scrub to frame 50: the view shows that frame of the animation, as the headless render.
    click_at(&mut harness, egui::pos2(x_of(50.0), y));
    let app = harness.state();
    assert_eq!(app.timeline.frame, 50);
    assert_eq!(app.scene, app.timeline.scene_at(50));
    assert_ne!(app.scene.camera.eye, app.timeline.scene_at(0).camera.eye);
    settle(&mut harness);
    let shown = shown_view(&mut harness);
    common::assert_agree(
        "explorer_timeline_frame",
        &headless(&harness),
        &shown,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );

    // Saved, the file reads back as this animation over this base.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("anim.toml");
    harness.state_mut().save(&path);
    let mut loader = qjulia::scene::SceneLoader::new();
    loader.file(&path).unwrap();
    let (base, animation) = loader.build_animated().unwrap();
    let app = harness.state();
    assert_eq!(animation, app.timeline.animation);
    assert_eq!(base, app.timeline.base);
    assert_eq!(animation.scene_at(&base, 50), app.scene);
}

#[test]
fn a_deep_view_switches_to_f64_by_itself_and_back() {
    let test = "a_deep_view_switches_to_f64_by_itself_and_back";
    let Some(mut harness) = harness(test) else {
        return;
    };
    let deep = qjulia::scene::presets::find("deep-zoom").unwrap().scene();
    harness.state_mut().set_scene(deep);
    settle(&mut harness);
    let precision =
        |h: &Harness<'static, ExplorerApp>| h.state().slice_texture().unwrap().precision();
    let view = harness.state().slice_texture().unwrap();
    if !runs_f64(test, view.precision(), view.precision_note()) {
        return;
    }
    assert_eq!(precision(&harness), qjulia::Precision::F64);
    // The view is the GPU's f64 render of the view's scene.
    let tracer = common::gpu("headless f64").expect("GPU");
    let tracer64 = qjulia::gpu::GpuTracer::<f64>::new_f64(tracer.context().clone())
        .expect("lavapipe runs f64");
    let mut expected = tracer64
        .render(&TraceParams::<f64>::new(&harness.state().view_scene()))
        .unwrap()
        .frame;
    expected.depth.iter_mut().for_each(|d| *d = 0.0);
    expected.depth_f64.clear();
    common::assert_agree(
        "explorer_deep_f64",
        &expected,
        &shown_view(&mut harness),
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
    // Zoomed back out, the preset's epsilon (1e-12) still asks for f64, as `render` would
    // decide; with an epsilon f32 resolves too, the view returns to f32.
    harness.state_mut().scene.camera.fov_y_degrees = 40.0;
    settle(&mut harness);
    assert_eq!(precision(&harness), qjulia::Precision::F64);
    harness.state_mut().scene.fractal.epsilon = 1e-4;
    settle(&mut harness);
    assert_eq!(precision(&harness), qjulia::Precision::F32);
}

#[test]
fn a_deep_2d_view_switches_to_f64_by_itself() {
    let test = "a_deep_2d_view_switches_to_f64_by_itself";
    let Some(mut harness) = harness(test) else {
        return;
    };
    let deep = qjulia::scene::presets::find("deep-zoom-2d")
        .unwrap()
        .scene();
    harness.state_mut().set_scene(deep);
    harness.state_mut().mode = Mode::Julia2d;
    settle(&mut harness);
    let precision =
        |h: &Harness<'static, ExplorerApp>| h.state().julia2d_texture().unwrap().precision();
    let view = harness.state().julia2d_texture().unwrap();
    if !runs_f64(test, view.precision(), view.precision_note()) {
        return;
    }
    assert_eq!(precision(&harness), qjulia::Precision::F64);
    let tracer = common::gpu("headless 2d f64").expect("GPU");
    let julia = qjulia::gpu::GpuJulia2d::<f64>::new_f64(tracer.context().clone()).unwrap();
    let (mut expected, _) = julia
        .render(&qjulia::Julia2dParams::<f64>::new(
            &harness.state().view_scene(),
        ))
        .unwrap();
    expected.depth.iter_mut().for_each(|d| *d = 0.0);
    expected.depth_f64.clear();
    let shown = shown_view(&mut harness);
    common::assert_agree(
        "explorer_deep_2d",
        &expected,
        &shown,
        &qjulia::compare::JULIA2D_TOLERANCE,
    );
    assert!(
        shown.colour.contains(&0xffff_ffff) && shown.colour.iter().any(|&c| c != 0xffff_ffff),
        "the lace of the rabbit's alpha point, not a blank"
    );
    harness.state_mut().scene.view2d.extent = 3.0;
    settle(&mut harness);
    assert_eq!(precision(&harness), qjulia::Precision::F32);
}

#[test]
fn export_mesh_writes_a_closed_mesh_of_the_view_with_progress() {
    let Some(mut harness) = harness("export_mesh_writes_a_closed_mesh_of_the_view_with_progress")
    else {
        return;
    };
    settle(&mut harness);
    // The File menu offers it, with its resolution beside it, and opens the save dialog.
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness.get_by_label("Export mesh…").click();
    harness.run_steps(2);
    harness.get_by_label("Export mesh");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("view.stl");
    harness.state_mut().mesh_resolution = 40;
    harness.state_mut().start_mesh_export(path.clone());
    let start = Instant::now();
    let mut saw_progress = false;
    while harness
        .state()
        .message()
        .is_none_or(|(m, _)| !m.starts_with("exported"))
    {
        harness.step();
        saw_progress |= harness.query_by_label_contains("grid layers").is_some();
        if let Some((m, true)) = harness.state().message() {
            panic!("the export failed: {m}");
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the export never finished"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let _ = saw_progress; // A fast device may finish between two frames.
    let mut f = std::fs::File::open(&path).unwrap();
    let triangles: Vec<_> = stl_io::create_stl_reader(&mut f)
        .unwrap()
        .map(|t| t.unwrap().vertices.map(|v| v.0.map(f32::to_bits)))
        .collect();
    assert!(triangles.len() > 1000, "{} triangles", triangles.len());
    // Closed: every edge (by its corners' positions) in exactly two triangles.
    let mut edges: std::collections::HashMap<_, u32> = Default::default();
    for t in &triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *edges
                .entry(if a < b { (a, b) } else { (b, a) })
                .or_default() += 1;
        }
    }
    assert!(
        edges.values().all(|&n| n == 2),
        "the exported mesh is not closed"
    );
    // The very bytes `qjulia mesh` writes of the same scene at the same resolution.
    std::fs::write(
        dir.path().join("view.toml"),
        harness.state().scene.to_toml(),
    )
    .unwrap();
    let out = common::qjulia(
        dir.path(),
        &[
            "mesh",
            "--scene",
            "view.toml",
            "--resolution",
            "40",
            "-o",
            "cli.stl",
        ],
    );
    assert!(out.status.success(), "{}", common::stderr(&out));
    assert!(
        std::fs::read(&path).unwrap() == std::fs::read(dir.path().join("cli.stl")).unwrap(),
        "Export mesh and `qjulia mesh` wrote different bytes"
    );
}

/// The deep-zoom preset (f64 where the view shows it) at a small image size.
fn deep_scene() -> qjulia::Scene {
    let mut deep = qjulia::scene::presets::find("deep-zoom").unwrap().scene();
    deep.image.width = 96;
    deep.image.height = 72;
    deep
}

#[test]
fn a_deep_export_writes_the_bytes_of_qjulia_render() {
    let test = "a_deep_export_writes_the_bytes_of_qjulia_render";
    let Some(mut harness) = harness(test) else {
        return;
    };
    harness.state_mut().set_scene(deep_scene());
    settle(&mut harness);
    // Showing the panel leaves the scene as loaded (a slider's range clamps no value).
    assert_eq!(harness.state().scene, deep_scene());
    // The view shows f64 where the adapter has it; the export is `render`'s (in f64, on the
    // CPU where the GPU has none) either way.
    let view = harness.state().slice_texture().unwrap();
    if runs_f64(test, view.precision(), view.precision_note()) {
        assert_eq!(
            view.precision(),
            qjulia::Precision::F64,
            "the view shows f64"
        );
    }
    let stderr = assert_export_is_render(
        &mut harness,
        "explorer_deep_export",
        &["--preset", "deep-zoom", "--width", "96", "--height", "72"],
    );
    assert!(stderr.contains("rendering in f64"), "{stderr}");
}

#[test]
fn a_deep_animation_renders_the_frames_of_qjulia_animate() {
    let Some(mut harness) = harness("explorer deep animation") else {
        return;
    };
    harness.state_mut().set_scene(deep_scene());
    settle(&mut harness);
    let dir = tempfile::tempdir().unwrap();
    let (gui, cli) = (dir.path().join("gui"), dir.path().join("cli"));
    harness.state_mut().start_render_into(&gui, 0, Some(1));
    let start = Instant::now();
    while harness.state().rendering() {
        harness.step();
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the render never ended"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    if let Some((m, true)) = harness.state().message() {
        panic!("the render failed: {m}");
    }
    // `animate` on the file the explorer saves, the same two frames.
    let scene_file = dir.path().join("anim.toml");
    harness.state_mut().save(&scene_file);
    let out = common::qjulia(
        dir.path(),
        &[
            "animate",
            "--scene",
            "anim.toml",
            "--frames",
            "0..1",
            "--out",
            "cli",
        ],
    );
    assert!(out.status.success(), "{}", common::stderr(&out));
    assert_eq!(
        common::files_in(&gui),
        ["frame-00000.png", "frame-00001.png"]
    );
    assert_eq!(common::files_in(&gui), common::files_in(&cli));
    for name in common::files_in(&cli) {
        assert!(
            std::fs::read(gui.join(&name)).unwrap() == std::fs::read(cli.join(&name)).unwrap(),
            "{name}: the explorer's frame and `qjulia animate`'s differ"
        );
    }
    // Both ran f64: the frame reads back as a deep scene.
    let stats = common::stderr(&out);
    assert!(stats.contains("(f64)"), "{stats}");
}

#[test]
fn an_export_goes_on_and_is_announced_when_another_scene_is_chosen() {
    let Some(mut harness) = harness("explorer export across scenes") else {
        return;
    };
    settle(&mut harness);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("before.stl");
    harness.state_mut().mesh_resolution = 16;
    harness.state_mut().start_mesh_export(path.clone());
    // A preset chosen while the export runs: the export stays the app's, and says it is done.
    let other = qjulia::scene::presets::find("gallery").unwrap().scene();
    harness.state_mut().set_scene(other);
    wait_for_message(&mut harness, "exported");
    assert!(path.is_file());
}

#[test]
fn ctrl_q_closes_the_window_as_the_help_says() {
    let Some(mut harness) = harness("explorer ctrl+q") else {
        return;
    };
    harness.step();
    let closes = |h: &Harness<'static, ExplorerApp>| {
        h.output()
            .viewport_output
            .values()
            .any(|v| v.commands.contains(&egui::ViewportCommand::Close))
    };
    assert!(!closes(&harness));
    // One key-down event, so that the step that handles it is the one whose output is read.
    harness.event(egui::Event::Key {
        key: egui::Key::Q,
        physical_key: None,
        pressed: true,
        repeat: false,
        modifiers: egui::Modifiers::COMMAND,
    });
    harness.step();
    assert!(closes(&harness), "Ctrl+Q asked nothing to close");
}

#[test]
fn a_scene_file_changed_on_disk_is_not_overwritten_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, "[fractal]\nmax_iterations = 9\n").unwrap();
    let mut app = ExplorerApp::with_scene(qjulia::Scene::default());
    app.open(&path);
    assert_eq!(app.scene.fractal.max_iterations, 9);
    // Unchanged on disk: Save writes at once.
    app.state.scene.fractal.max_iterations = 11;
    app.save(&path);
    assert!(
        std::fs::read_to_string(&path)
            .unwrap()
            .contains("max_iterations = 11")
    );
    // Another program writes the file (later, and longer).
    let newer = "# edited elsewhere\n[fractal]\nmax_iterations = 12\n";
    std::fs::write(&path, newer).unwrap();
    let later = std::time::SystemTime::now() + std::time::Duration::from_secs(5);
    std::fs::File::options()
        .write(true)
        .open(&path)
        .unwrap()
        .set_modified(later)
        .unwrap();
    // The view keeps its scene; the first Save says so and writes nothing.
    app.state.scene.fractal.max_iterations = 13;
    app.save(&path);
    let (message, error) = app.message().unwrap();
    assert!(
        error && message.contains("changed on disk since it was opened"),
        "{message}"
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), newer);
    assert_eq!(app.scene.fractal.max_iterations, 13);
    // The second overwrites it.
    app.save(&path);
    assert!(
        std::fs::read_to_string(&path)
            .unwrap()
            .contains("max_iterations = 13")
    );
}
