//! Path mode in the view (issues 19 and 20): the render and its display transform, the lighting
//! switch, path exports, the f64 path tracer, adaptive sampling, the samples view and the denoiser.

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use qjulia::Frame;
use qjulia::explore::ExplorerApp;
use qjulia::scene::View;

use super::{
    EXACT, assert_export_is_render, changed_fraction, harness_of, harness_sampling, headless,
    runs_f64, settle, shown_view,
};
use crate::common;

/// A small window for the path-traced views (the path tracer is slow on lavapipe).
const PATH_WINDOW: [f32; 2] = [560.0, 330.0];

/// The path-traced preset, a little cheaper (the view's samples are the harness's 3).
fn path_scene() -> qjulia::Scene {
    let mut scene = qjulia::scene::presets::find("path-traced").unwrap().scene();
    scene.fractal.max_iterations = 8;
    scene.camera.aperture = 0.0;
    scene
}

/// What `qjulia render` makes of the view's scene (its size, the view's samples), decided as
/// the explorer's exports decide it, on the view's device: the frame and its radiance, depth
/// zeroed (the screen has none).
fn rendered(harness: &Harness<'static, ExplorerApp>) -> Frame {
    let scene = harness.state().view_scene();
    let picture = qjulia::Picture::SHADED;
    let plan = harness
        .state()
        .planner()
        .plan(&scene, picture.into(), &mut |_| {})
        .unwrap();
    assert_eq!(plan.renderer.backend_name(), "gpu");
    let (mut frame, _) = plan.renderer.render_frame(&scene, picture).unwrap();
    assert!(!frame.radiance.is_empty(), "not path traced");
    frame.depth.iter_mut().for_each(|d| *d = 0.0);
    frame.depth_f64.clear();
    frame
}

/// `frame` with its colour made again from its radiance by `display`.
fn displayed(frame: &Frame, display: qjulia::display::Display) -> Frame {
    Frame {
        colour: display.pack_all(&frame.radiance),
        ..frame.clone()
    }
}

/// Issue 19: in path mode the view shows what `qjulia render` writes of the same scene and
/// samples, byte for byte; exposure and tone map from the panel change it at once, without a
/// trace, to the display transform of the radiance kept.
#[test]
fn path_mode_shows_the_render_and_exposure_and_tone_map_need_no_new_trace() {
    let Some(mut harness) = harness_of("explorer path", path_scene(), PATH_WINDOW) else {
        return;
    };
    settle(&mut harness);
    let view = harness.state().slice_texture().unwrap();
    assert!(view.path_traced(), "the view is not the path tracer's");
    let kept = view.kept_radiance().expect("radiance kept");
    assert_eq!(kept.samples, 3, "the view's samples");
    let [w, h] = harness.state().view_pixels();
    assert_eq!(kept.size, [w, h]);
    eprintln!("path view {w}x{h}");
    let expected = rendered(&harness);
    assert!(
        kept.radiance == expected.radiance,
        "the view's radiance is not the render's"
    );
    let shown = shown_view(&mut harness);
    common::assert_agree("explorer_path", &expected, &shown, &EXACT);

    // Exposure, from the panel's slider.
    let view = harness.state().slice_texture().unwrap();
    let (dispatches, encodes) = (view.dispatches(), view.encodes());
    assert!(dispatches > 0);
    harness
        .get_by_role_and_label(egui::Role::Slider, "exposure (stops)")
        .set_value_accesskit(1.25);
    // The view thread encodes the mean again while the UI draws on: wait for it.
    settle(&mut harness);
    assert_eq!(harness.state().scene.image.exposure, 1.25);
    let view = harness.state().slice_texture().unwrap();
    assert_eq!(
        view.dispatches(),
        dispatches,
        "an exposure change traced again"
    );
    assert!(
        view.encodes() > encodes,
        "the radiance was not encoded again"
    );
    assert!(harness.state().view_refined());
    let display = qjulia::display::Display::of(&harness.state().view_scene());
    let brighter = shown_view(&mut harness);
    assert!(
        changed_fraction(&shown, &brighter) > 0.3,
        "the exposure left the view unchanged"
    );
    common::assert_agree(
        "explorer_path_exposure",
        &displayed(&expected, display),
        &brighter,
        &EXACT,
    );

    // The tone map, from the panel's menu.
    harness
        .get_by_role_and_label(egui::Role::ComboBox, "tone map")
        .click_accesskit();
    harness.run_steps(2);
    harness.get_by_label("reinhard").click_accesskit();
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(
        harness.state().scene.image.tone_map,
        qjulia::display::ToneMap::Reinhard
    );
    let view = harness.state().slice_texture().unwrap();
    assert_eq!(
        view.dispatches(),
        dispatches,
        "a tone-map change traced again"
    );
    let display = qjulia::display::Display::of(&harness.state().view_scene());
    let reinhard = shown_view(&mut harness);
    assert!(changed_fraction(&brighter, &reinhard) > 0.3);
    common::assert_agree(
        "explorer_path_reinhard",
        &displayed(&expected, display),
        &reinhard,
        &EXACT,
    );
    // A key the tracer reads does trace again, and the view shows its render.
    harness.state_mut().scene.material.roughness = 0.8;
    settle(&mut harness);
    let view = harness.state().slice_texture().unwrap();
    assert!(view.dispatches() > dispatches);
    common::assert_agree(
        "explorer_path_rough",
        &rendered(&harness),
        &shown_view(&mut harness),
        &EXACT,
    );
}

/// Issue 19: the panel's lighting switch turns the Phong view into the path tracer's, and
/// back; the Phong-only keys are greyed out in path mode.
#[test]
fn the_lighting_switch_turns_the_phong_view_into_a_path_traced_one() {
    let mut scene = path_scene();
    scene.shading.model = qjulia::scene::ShadingModel::Phong;
    let Some(mut harness) = harness_of("explorer lighting switch", scene, PATH_WINDOW) else {
        return;
    };
    settle(&mut harness);
    assert!(!harness.state().slice_texture().unwrap().path_traced());
    let phong = shown_view(&mut harness);
    common::assert_agree(
        "explorer_switch_phong",
        &headless(&harness),
        &phong,
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
    // Phong: no "Path tracing" group, the Phong keys enabled.
    assert!(harness.query_by_label("Path tracing").is_none());
    harness.get_by_label("Light and shading").click_accesskit();
    harness.run_steps(2);
    let disabled = |h: &Harness<'static, ExplorerApp>, role, label| {
        h.get_by_role_and_label(role, label)
            .accesskit_node()
            .is_disabled()
    };
    assert!(!disabled(&harness, egui::Role::CheckBox, "shadows"));

    harness.get_by_label("Path traced").click();
    settle(&mut harness);
    assert_eq!(
        harness.state().scene.shading.model,
        qjulia::scene::ShadingModel::Path
    );
    assert!(harness.state().slice_texture().unwrap().path_traced());
    let path = shown_view(&mut harness);
    assert!(
        changed_fraction(&phong, &path) > 0.3,
        "the path-traced view looks like the Phong one"
    );
    common::assert_agree("explorer_switch_path", &rendered(&harness), &path, &EXACT);
    harness.get_by_label("Path tracing");
    assert!(disabled(&harness, egui::Role::CheckBox, "shadows"));
    assert!(disabled(&harness, egui::Role::Slider, "ambient"));
    assert!(!disabled(&harness, egui::Role::Slider, "light radius"));

    harness.get_by_label("Phong").click();
    settle(&mut harness);
    assert!(!harness.state().slice_texture().unwrap().path_traced());
    common::assert_agree(
        "explorer_switch_back",
        &headless(&harness),
        &shown_view(&mut harness),
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
}

/// Issue 19: a path-mode export writes the bytes of `qjulia render`.
#[test]
fn a_path_export_writes_the_bytes_of_qjulia_render() {
    let mut scene = qjulia::scene::presets::find("path-traced").unwrap().scene();
    scene.image.width = 64;
    scene.image.height = 48;
    scene.image.samples = 2;
    let Some(mut harness) = harness_of("explorer path export", scene, PATH_WINDOW) else {
        return;
    };
    harness.step();
    assert_export_is_render(
        &mut harness,
        "explorer_path_export",
        &[
            "--preset",
            "path-traced",
            "--width",
            "64",
            "--height",
            "48",
            "--set",
            "image.samples=2",
        ],
    );
}

/// Issue 19: a deep path-traced view runs the f64 path tracer by itself, and shows what
/// `qjulia render` (deciding f64 too) writes of it.
#[test]
fn a_deep_path_view_runs_the_f64_path_tracer() {
    let mut deep = qjulia::scene::presets::find("deep-zoom").unwrap().scene();
    deep.shading.model = qjulia::scene::ShadingModel::Path;
    let test = "a_deep_path_view_runs_the_f64_path_tracer";
    let Some(mut harness) = harness_of(test, deep, PATH_WINDOW) else {
        return;
    };
    settle(&mut harness);
    let view = harness.state().slice_texture().unwrap();
    assert!(view.path_traced());
    if !runs_f64(test, view.precision(), view.precision_note()) {
        return;
    }
    assert_eq!(view.precision(), qjulia::Precision::F64);
    let expected = rendered(&harness);
    // Not byte for byte: `render` traces the 3 samples in one dispatch, the view one per pass,
    // and on lavapipe in f64 the two differ on about 9 of 34,368 pixels, where the view's equals
    // the CPU twin's and the render's does not (measured; see the branch's report). In f32
    // they agree exactly (the test above).
    common::assert_agree(
        "explorer_deep_path",
        &expected,
        &shown_view(&mut harness),
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
}

/// What `qjulia render` makes of the view's scene in either model, decided as the explorer's
/// exports decide it, on the view's device (depth zeroed: the screen has none).
fn rendered_any(harness: &Harness<'static, ExplorerApp>) -> Frame {
    let scene = harness.state().view_scene();
    let picture = qjulia::Picture::SHADED;
    let plan = harness
        .state()
        .planner()
        .plan(&scene, picture.into(), &mut |_| {})
        .unwrap();
    assert_eq!(plan.renderer.backend_name(), "gpu");
    let (mut frame, _) = plan.renderer.render_frame(&scene, picture).unwrap();
    frame.depth.iter_mut().for_each(|d| *d = 0.0);
    frame.depth_f64.clear();
    frame
}

/// Issue 20: with adaptive sampling (and the denoiser, whose variance takes each pixel's own
/// count) the view's passes stop the pixels `qjulia render` stops: the counts it reads back are
/// the render's, the status line's mean is theirs, and the view is the render byte for byte.
#[test]
fn an_adaptive_denoised_path_view_stops_the_pixels_the_render_stops() {
    let mut scene = path_scene();
    scene.image.denoise = qjulia::denoise::Denoiser::Atrous;
    scene.path.noise_target = 0.3;
    scene.path.min_samples = 2;
    let Some(mut harness) = harness_sampling("explorer adaptive path", scene, PATH_WINDOW, 6)
    else {
        return;
    };
    settle(&mut harness);
    let view = harness.state().slice_texture().unwrap();
    let kept = view.kept_radiance().expect("the mean kept");
    assert_eq!(kept.samples, 6);
    let frame = kept.frame.as_ref().expect("the mean's AOVs kept");
    let expected = rendered_any(&harness);
    assert!(
        frame.samples == expected.samples,
        "the view's counts are not the render's"
    );
    let mean =
        expected.samples.iter().map(|&n| n as f64).sum::<f64>() / expected.pixel_count() as f64;
    assert!(
        (4.0..6.0).contains(&mean),
        "no pixel stopped early, or all did: {mean}"
    );
    assert_eq!(view.stats().samples_taken, Some(mean));
    assert_eq!(
        view.stats().denoised_samples,
        Some(6),
        "the view is not denoised"
    );
    common::assert_agree(
        "explorer_adaptive_path",
        &expected,
        &shown_view(&mut harness),
        &EXACT,
    );
}

/// Issue 20: the samples view shows the heat map of the samples each pixel took, the render's
/// counts (`qjulia render --view samples`), in path mode with adaptive sampling.
#[test]
fn the_samples_view_shows_the_heat_map_of_the_counts() {
    let mut scene = path_scene();
    scene.path.noise_target = 0.3;
    scene.path.min_samples = 2;
    scene.image.view = View::Samples;
    let Some(mut harness) = harness_sampling("explorer samples view", scene, PATH_WINDOW, 6) else {
        return;
    };
    settle(&mut harness);
    let expected = rendered_any(&harness);
    let map = qjulia::heatmap::samples_view(&expected.samples, expected.width, expected.height);
    assert!(
        map.legend.min < map.legend.max,
        "no pixel stopped early: {:?}",
        map.legend
    );
    assert_eq!(harness.state().heat_legend(), Some(&map.legend));
    let shown = shown_view(&mut harness);
    // Above the legend strip at the bottom, the screen holds the heat map.
    let rows = (expected.height - qjulia::heatmap::LEGEND_HEIGHT - 4) as usize;
    let w = expected.width as usize;
    let screen = shown.rgb8();
    assert!(
        screen[..rows * w * 3] == map.rgb[..rows * w * 3],
        "the samples view is not the heat map of the render's counts"
    );
}

/// Issue 20: with the denoiser on, the idle view shows the denoised running mean, which once it
/// has the view's samples is what `qjulia render` writes of the same scene and samples, byte
/// for byte; the status line has its error figures; a `[denoise]` key from the panel denoises
/// the kept mean again, with no new trace, and the view is then the render with that key.
#[test]
fn a_denoised_path_view_shows_the_render_and_its_keys_need_no_new_trace() {
    let mut scene = path_scene();
    scene.image.denoise = qjulia::denoise::Denoiser::Atrous;
    let Some(mut harness) = harness_of("explorer denoised path", scene, PATH_WINDOW) else {
        return;
    };
    settle(&mut harness);
    let view = harness.state().slice_texture().unwrap();
    assert!(view.path_traced());
    let kept = view.kept_radiance().expect("the mean kept");
    assert_eq!(kept.samples, 3);
    let frame = kept.frame.as_ref().expect("the mean's AOVs kept");
    assert_eq!(frame.luminance_m2.len(), frame.pixel_count());
    let stats = view.stats();
    assert_eq!(stats.denoised_samples, Some(3), "the view is not denoised");
    assert_eq!(stats.denoise_error, None);
    // The error figures: the mean's, from its halves (the render's estimate of its raw image),
    // and the denoised image's, from the halves denoised alone (the render's --stats).
    let noise = stats.noise.expect("an error figure");
    assert!(noise > 0.0 && noise.is_finite(), "error {noise}");
    assert_eq!(frame.halves.len(), frame.pixel_count());
    assert_eq!(
        Some(noise),
        qjulia::estimate::raw(frame).map(|e| e.relative)
    );
    let denoised = stats
        .denoised_noise
        .expect("the denoised image's error figure");
    assert!(denoised > 0.0 && denoised.is_finite(), "error {denoised}");
    let expected = rendered_any(&harness);
    assert_eq!(expected.noisy.len(), expected.pixel_count(), "not denoised");
    assert!(
        kept.radiance == expected.noisy,
        "the view's mean is not the render's"
    );
    let shown = shown_view(&mut harness);
    common::assert_agree("explorer_denoised_path", &expected, &shown, &EXACT);
    // The denoiser did something: the mean's own display differs.
    let display = qjulia::display::Display::of(&harness.state().view_scene());
    let noisy = Frame {
        colour: display.pack_all(&expected.noisy),
        ..expected.clone()
    };
    assert!(
        changed_fraction(&noisy, &shown) > 0.2,
        "the denoised view looks like the mean"
    );

    // A [denoise] key from the panel: denoised again, no trace.
    let view = harness.state().slice_texture().unwrap();
    let (dispatches, encodes) = (view.dispatches(), view.encodes());
    harness
        .get_by_role_and_label(egui::Role::Slider, "sigma luminance")
        .set_value_accesskit(0.25);
    harness.step();
    settle(&mut harness);
    assert_eq!(harness.state().scene.denoise.sigma_luminance, 0.25);
    let view = harness.state().slice_texture().unwrap();
    assert_eq!(
        view.dispatches(),
        dispatches,
        "a [denoise] key traced again"
    );
    assert!(view.encodes() > encodes, "the mean was not denoised again");
    let sharper = shown_view(&mut harness);
    assert!(
        changed_fraction(&shown, &sharper) > 0.05,
        "sigma luminance left the view unchanged"
    );
    common::assert_agree(
        "explorer_denoised_path_sigma",
        &rendered_any(&harness),
        &sharper,
        &EXACT,
    );

    // Exposure on a denoised view: encoded again, neither traced nor denoised again.
    let encodes = harness.state().slice_texture().unwrap().encodes();
    harness.state_mut().scene.image.exposure = 1.0;
    settle(&mut harness);
    assert!(harness.state().view_refined());
    let view = harness.state().slice_texture().unwrap();
    assert_eq!(view.dispatches(), dispatches);
    assert_eq!(view.encodes(), encodes + 1);
    common::assert_agree(
        "explorer_denoised_path_exposure",
        &rendered_any(&harness),
        &shown_view(&mut harness),
        &EXACT,
    );
}

/// Issue 20: the panel's denoiser switch works in phong mode too: the view then shows the
/// denoised mean, `qjulia render`'s bytes of the same scene and samples; switched off, the
/// tracer's own mean again.
#[test]
fn the_denoiser_switch_denoises_the_phong_view_as_render_does() {
    let Some(mut harness) = harness_of(
        "explorer denoised phong",
        common::scene(&["fractal.max_iterations=8"]),
        PATH_WINDOW,
    ) else {
        return;
    };
    settle(&mut harness);
    let plain = shown_view(&mut harness);
    assert!(harness.query_by_label("Denoising").is_none());
    harness.get_by_label("atrous").click();
    settle(&mut harness);
    assert_eq!(
        harness.state().scene.image.denoise,
        qjulia::denoise::Denoiser::Atrous
    );
    harness.get_by_label("Denoising");
    let view = harness.state().slice_texture().unwrap();
    assert!(!view.path_traced());
    assert_eq!(view.stats().denoised_samples, Some(3));
    // Phong mode's samples are one stream: no halves, no error figure (as --stats' null).
    assert_eq!(view.stats().noise, None);
    assert_eq!(view.stats().denoised_noise, None);
    let expected = rendered_any(&harness);
    assert_eq!(expected.noisy.len(), expected.pixel_count(), "not denoised");
    let denoised = shown_view(&mut harness);
    common::assert_agree("explorer_denoised_phong", &expected, &denoised, &EXACT);
    assert!(
        changed_fraction(&plain, &denoised) > 0.05,
        "the denoised phong view looks like the plain one"
    );

    harness.get_by_label("none").click();
    settle(&mut harness);
    let view = harness.state().slice_texture().unwrap();
    assert_eq!(view.stats().denoised_samples, None);
    common::assert_agree(
        "explorer_denoiser_off",
        &headless(&harness),
        &shown_view(&mut harness),
        &qjulia::compare::CONTRACT_TOLERANCE,
    );
}

/// Issue 20: the export of a denoised view, phong and path traced, writes the bytes of
/// `qjulia render` with the denoiser.
#[test]
fn a_denoised_export_writes_the_bytes_of_qjulia_render() {
    let mut scene = qjulia::scene::presets::find("path-traced").unwrap().scene();
    scene.image.width = 64;
    scene.image.height = 48;
    scene.image.samples = 4;
    scene.image.denoise = qjulia::denoise::Denoiser::Atrous;
    scene.denoise.iterations = 3;
    let Some(mut harness) = harness_of("explorer denoised export", scene.clone(), PATH_WINDOW)
    else {
        return;
    };
    harness.step();
    let args = [
        "--width",
        "64",
        "--height",
        "48",
        "--set",
        "image.samples=4",
        "--set",
        "image.denoise=atrous",
        "--set",
        "denoise.iterations=3",
    ];
    let mut path = vec!["--preset", "path-traced"];
    path.extend_from_slice(&args);
    assert_export_is_render(&mut harness, "explorer_denoised_path_export", &path);

    let mut phong = vec!["--preset", "path-traced", "--set", "shading.model=phong"];
    phong.extend_from_slice(&args);
    harness.state_mut().scene.shading.model = qjulia::scene::ShadingModel::Phong;
    harness.step();
    assert_export_is_render(&mut harness, "explorer_denoised_phong_export", &phong);
}
