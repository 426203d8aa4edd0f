//! The parsers' fuzz targets (fuzz/, cargo-fuzz) replayed without libFuzzer: every input of the
//! checked-in corpora and every finding (fuzz/regressions/TARGET/, each named for what it
//! found) must pass its target's checks, so that a fixed finding stays fixed. The targets'
//! bodies are fuzz/src/lib.rs, included here as they are.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

#[path = "../../fuzz/src/lib.rs"]
mod targets;

/// Every file under fuzz/DIR/TARGET, for each target.
fn replay(dir: &str) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz").join(dir);
    let (mut count, mut failed) = (0, Vec::new());
    for (name, target) in targets::TARGETS {
        let Ok(entries) = std::fs::read_dir(root.join(name)) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            let bytes = std::fs::read(&path).unwrap();
            count += 1;
            if catch_unwind(AssertUnwindSafe(|| target(&bytes))).is_err() {
                failed.push(path.display().to_string());
            }
        }
    }
    assert!(
        failed.is_empty(),
        "inputs that fail their target: {failed:?}"
    );
    count
}

#[test]
fn every_finding_of_the_fuzzers_stays_fixed() {
    let count = replay("regressions");
    assert!(
        count >= 4,
        "only {count} findings found under fuzz/regressions"
    );
}

#[test]
fn every_corpus_input_passes_its_target() {
    let count = replay("corpus");
    assert!(
        count >= 50,
        "only {count} corpus inputs found under fuzz/corpus"
    );
}

#[test]
fn every_target_has_a_corpus_and_a_fuzz_target_file() {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    for (name, _) in targets::TARGETS {
        assert!(
            fuzz.join("fuzz_targets")
                .join(format!("{name}.rs"))
                .is_file(),
            "{name}"
        );
        let corpus = std::fs::read_dir(fuzz.join("corpus").join(name))
            .unwrap_or_else(|e| panic!("fuzz/corpus/{name}: {e}"));
        assert!(corpus.count() > 0, "fuzz/corpus/{name} is empty");
    }
}
