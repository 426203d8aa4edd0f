//! The stiff and extreme cases on every tracer: each finishes under a time limit (a hang fails
//! the test instead of stalling CI), no NaN or Inf anywhere, the same result twice, and f32 close
//! to the f64 reference wherever f32 can resolve the scene (where it cannot, a warning says so).

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::report::stability::{self, Runner};
use qjulia::report::stability_path;

#[test]
fn every_case_finishes_finite_and_repeatable_on_every_tracer() {
    let gpu = common::gpu("stability").map(|_| {
        Arc::new(
            qjulia::gpu::GpuContext::new()
                .map(qjulia::gpu::GpuKernels::new)
                .expect("a second GPU device"),
        )
    });
    let limit = Duration::from_secs(120);
    let outcomes = stability::run_all(40, gpu, limit, |o| {
        eprintln!(
            "{:<28} {:<8} {:?} passed={}",
            o.case,
            o.runner.name(),
            o.seconds,
            o.passed()
        );
    });
    eprintln!("{}", stability::markdown(&outcomes));
    let failed: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.passed())
        .map(|o| format!("{} on {}: {:?}", o.case, o.runner.name(), o.error))
        .collect();
    assert!(failed.is_empty(), "cases failed: {failed:#?}");
    for o in &outcomes {
        if let (Some(a), true) = (o.versus_f64, o.warnings.is_empty()) {
            assert!(
                a.within(&CONTRACT_TOLERANCE),
                "{} on {} strays from f64 without a warning: {a}",
                o.case,
                o.runner.name()
            );
        }
    }
    // The CPU's two, and the GPU's f32 and (where the device passes its check) f64.
    let runners = 2 + outcomes
        .iter()
        .filter(|o| o.case == stability::CASES[0].name)
        .filter(|o| matches!(o.runner, Runner::GpuF32 | Runner::GpuF64))
        .count();
    // Where the adapter has f64 the suite holds the GPU's f64 to the CPU's; where it has none
    // (GL llvmpipe) the suite runs without it, and says so.
    let test = "every_case_finishes_finite_and_repeatable_on_every_tracer";
    if common::gpu_has(common::Capability::F64, test, "the GPU's f64 runner") {
        assert!(
            outcomes.iter().any(|o| o.runner == Runner::GpuF64),
            "the adapter runs f64: the suite holds it to the CPU's"
        );
    } else {
        assert!(!outcomes.iter().any(|o| o.runner == Runner::GpuF64));
    }
    assert_eq!(outcomes.len(), stability::CASES.len() * runners);
    assert!(outcomes.iter().any(|o| o.runner == Runner::CpuF64));
}

/// Path mode's cases (issue 35: the sun from 0.001 to 90 degrees, sphere lights of radius 1e-4
/// and 1, intensities of 1e-6 and 1e6, the roughness and metallic extremes, 16 bounces, rays that
/// run out of steps, the eye inside the set, a deep zoom in f64, the clamp): on every tracer
/// finite, repeatable, and the image's mean luminance within 3 standard errors of the f64 CPU's
/// (the error from an independent render with the `random` sampler).
#[test]
fn every_path_case_is_finite_repeatable_and_agrees_with_f64() {
    let gpu = common::gpu("path stability").map(|_| {
        Arc::new(
            qjulia::gpu::GpuContext::new()
                .map(qjulia::gpu::GpuKernels::new)
                .expect("a second GPU device"),
        )
    });
    let on_gpu = gpu.is_some();
    let outcomes = stability_path::run_all_path(16, gpu, Duration::from_secs(120), |_| {});
    eprintln!("{}", stability_path::path_markdown(16, &outcomes));
    let failed: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.passed())
        .map(|o| {
            format!(
                "{} on {}: {:?} {:?}",
                o.case,
                o.runner.name(),
                o.error,
                o.versus_f64
            )
        })
        .collect();
    assert!(failed.is_empty(), "path cases failed: {failed:#?}");
    let gpu_runs = outcomes
        .iter()
        .filter(|o| o.runner == Runner::GpuF32)
        .count();
    assert_eq!(
        gpu_runs,
        if on_gpu {
            stability_path::PATH_CASES.len()
        } else {
            0
        }
    );
    // Every run but the reference's is compared with it, but f32 on the f64-only case.
    for o in &outcomes {
        let f32_on_f64_only =
            o.case.contains("f64 only") && matches!(o.runner, Runner::CpuF32 | Runner::GpuF32);
        let compared = o.runner != Runner::CpuF64 && !f32_on_f64_only;
        assert_eq!(
            o.versus_f64.is_some(),
            compared,
            "{} on {}",
            o.case,
            o.runner.name()
        );
    }
    let crevice = outcomes
        .iter()
        .find(|o| o.case.starts_with("crevice"))
        .unwrap();
    assert!(crevice.exhausted > 0, "the crevice's rays run out");
}

#[test]
fn a_hang_fails_instead_of_stalling() {
    let result = stability::with_time_limit(Duration::from_millis(50), || {
        std::thread::sleep(Duration::from_secs(5))
    });
    assert!(result.is_none());
    assert_eq!(
        stability::with_time_limit(Duration::from_secs(5), || 7),
        Some(7)
    );
}
