//! The work-precision machinery on a tiny scene: the truth measured against itself is exact,
//! a coarser setting measures worse, and the report's files hold what they promise.

use qjulia::report::work_precision as wp;
use qjulia::scene::Scene;

fn tiny() -> Scene {
    let mut s = Scene::default();
    s.image.width = 40;
    s.image.height = 40;
    s
}

#[test]
fn the_truth_against_itself_has_no_error_and_coarse_settings_have_more() {
    let base = tiny();
    let truth = wp::Truth::new(&base).unwrap();
    let exact = wp::Setting {
        scene_name: "tiny",
        method: "self",
        label: "truth".into(),
        runner: qjulia::report::stability::Runner::CpuF64,
        scene: wp::truth_scene(&base),
    };
    let m = wp::measure(&exact, &truth.frame, &truth);
    assert_eq!(m.mask_disagreement, 0.0);
    assert_eq!(m.depth_error_max, 0.0);
    // Normals are recomputed at the hit from its f32-rounded depth: a hair off, no more.
    assert!(m.normal_error_deg_p95 < 1e-3, "{m:?}");
    assert_eq!(m.colour_rmse, 0.0);
    assert_eq!(m.psnr_db, 99.0);

    let mut coarse = exact.clone();
    coarse.scene.fractal.epsilon = 0.03;
    let (frame, _) = qjulia::cpu::render(&qjulia::TraceParams::<f64>::new(&coarse.scene));
    let worse = wp::measure(&coarse, &frame, &truth);
    assert!(
        worse.mask_disagreement > 0.0 && worse.colour_rmse > 1.0,
        "{worse:?}"
    );
}

#[test]
fn the_report_files_hold_every_setting() {
    let scenes = [("tiny", tiny())];
    let (rows, truth_seconds) = wp::run(&scenes, None, 1, |_, _, _| {}).unwrap();
    assert_eq!(rows.len(), wp::settings("tiny", &tiny(), false).len());
    assert!(rows.iter().all(|r| r.metrics.non_finite == 0));
    let csv = wp::csv(&rows);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for column in [
        "scene",
        "backend",
        "precision",
        "method",
        "epsilon",
        "max_iterations",
        "escape_radius_squared",
        "seconds",
        "mask_disagreement",
        "depth_error_p95",
        "normal_error_deg_p95",
        "psnr_db",
    ] {
        assert!(header.contains(&column), "no column {column}");
    }
    assert_eq!(csv.lines().count(), rows.len() + 1);
    let md = wp::markdown(&rows, &truth_seconds, "a test machine", "cargo test");
    assert!(
        md.contains("Pareto front") && md.contains("The seed's settings (cpu f32)"),
        "{md}"
    );
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("plot.png");
    wp::plot(&png, &rows).unwrap();
    let img = image::open(&png).unwrap();
    assert!(img.width() >= 800 && img.height() >= 400);
}

#[test]
fn the_zoom_sweep_shows_f32_leaving_f64_as_the_zoom_deepens() {
    use qjulia::report::stability::Runner;
    // The scene's pixel footprint at the target is the one asked for.
    for footprint in wp::ZOOM_FOOTPRINTS {
        let s = wp::zoom_scene(footprint, 32);
        let distance = 3.0; // the default eye to the default target
        let got = 2.0 * distance * (s.camera.fov_y_degrees.to_radians() / 2.0).tan() / 32.0;
        assert!((got / footprint - 1.0).abs() < 1e-9, "{footprint}: {got}");
    }
    let rows = wp::zoom_sweep(32, &[Runner::CpuF32], None, 1, |_, _, _| {}).unwrap();
    assert_eq!(rows.len(), wp::ZOOM_FOOTPRINTS.len() * 2);
    let f32_rows: Vec<&wp::ZoomRow> = rows.iter().filter(|r| r.runner == Runner::CpuF32).collect();
    let colour = |r: &wp::ZoomRow| r.versus_f64.as_ref().unwrap().colour;
    let (shallow, deep) = (f32_rows[0], f32_rows[f32_rows.len() - 1]);
    assert!(!shallow.f32_warned && deep.f32_warned);
    assert!(
        colour(shallow) > 0.9 && colour(deep) < 0.5,
        "f32's colour agreement with f64: {:.3} at {:e}, {:.3} at {:e}",
        colour(shallow),
        shallow.footprint,
        colour(deep),
        deep.footprint
    );
    let md = wp::zoom_markdown(&rows, 32);
    eprintln!("{md}");
    assert_eq!(md.matches("| cpu f64 |").count(), wp::ZOOM_FOOTPRINTS.len());
}

/// The Monte Carlo page on a tiny image on the CPU: every case has its points and a slope, and
/// the writers give the CSV's rows, the page's verdicts and a plot.
#[test]
fn the_monte_carlo_page_measures_every_case() {
    use qjulia::report::monte_carlo as mc;
    use qjulia::report::monte_carlo_page as page;
    let mut planner = qjulia::Planner::new(qjulia::Backend::Cpu, qjulia::PrecisionChoice::F32);
    let curves = mc::run(&mut planner, 8, 1024, &mut |_, _, _| {}).unwrap();
    assert_eq!(curves.len(), mc::cases().len());
    for c in &curves {
        assert_eq!(c.points.len(), mc::SAMPLES.len());
        assert!(
            c.slope.is_finite() && c.slope < 0.0,
            "{:?}: {}",
            c.case,
            c.slope
        );
        assert!(c.points.iter().all(|p| p.rmse > 0.0 && p.rmse.is_finite()));
        assert!(c.reference_mean > 0.0);
    }
    let csv = page::csv(&curves);
    assert_eq!(csv.lines().count(), 1 + curves.len() * mc::SAMPLES.len());
    // Each scene: denoised, adaptive, both, regularised, and regularised and denoised.
    assert_eq!(curves.iter().filter(|c| c.case.denoise).count(), 9);
    assert_eq!(curves.iter().filter(|c| c.case.adaptive).count(), 6);
    assert_eq!(curves.iter().filter(|c| c.case.regularize).count(), 6);
    for c in &curves {
        assert!(c.last_mean > 0.0 && c.last_mean.is_finite(), "{:?}", c.case);
    }
    for c in &curves {
        for p in &c.points {
            // Adaptive sampling takes at most the samples, and at most min_samples (16) always.
            let floor = p.samples.min(16) as f64;
            assert!(
                p.taken <= p.samples as f64 && p.taken >= floor,
                "{:?}: {p:?}",
                c.case
            );
            if !c.case.adaptive {
                assert_eq!(p.taken, p.samples as f64);
            }
            // Every render of two samples or more estimates its own error (its halves), and
            // one of one sample cannot.
            match p.estimated {
                Some(e) => assert!(
                    p.samples >= 2 && e > 0.0 && e.is_finite(),
                    "{:?}: {p:?}",
                    c.case
                ),
                None => assert_eq!(p.samples, 1, "{:?}: {p:?}", c.case),
            }
        }
    }
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .ends_with(",seconds,estimated_rmse")
    );
    for c in &curves {
        let s = c.split;
        assert!(s.edge.is_finite() && s.flat.is_finite() && (0.0..=1.0).contains(&s.edge_share));
    }
    let md = page::markdown(&curves, 8, 1024, "a test machine");
    for verdict in [
        "Sobol' against random",
        "**Bounces**",
        "rough metal",
        "the denoiser**",
        "adaptive sampling**",
        "Sobol' adaptive denoised",
        "on edge pixels",
        "regularisation**",
        "Sobol' regularized denoised",
        "off the reference's",
        "estimate / measured at 64",
    ] {
        assert!(md.contains(verdict), "{md}");
    }
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("mc.png");
    page::plot(&png, &curves).unwrap();
    assert!(image::open(&png).unwrap().width() >= 800);
}
