//! The stiff and extreme cases on every tracer: each finishes under a time limit (a hang fails
//! the test instead of stalling CI), no NaN or Inf anywhere, the same result twice, and f32 close
//! to the f64 reference wherever f32 can resolve the scene (where it cannot, a warning says so).

mod common;

use std::sync::Arc;
use std::time::Duration;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::report::stability::{self, Runner};

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
    if common::gpu("stability").is_some() {
        assert!(
            outcomes.iter().any(|o| o.runner == Runner::GpuF64),
            "lavapipe runs f64: the suite holds it to the CPU's"
        );
    }
    assert_eq!(outcomes.len(), stability::CASES.len() * runners);
    assert!(outcomes.iter().any(|o| o.runner == Runner::CpuF64));
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
