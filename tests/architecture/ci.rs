//! CI's pass on GL llvmpipe covers every test with a part that depends on the adapter's
//! capabilities: each `#[test]` whose body names `Capability::` (or calls a helper of its file
//! or crate root that does) matches one of the filters of `gl_tests` in `.ci/run`, and each
//! filter matches such a test, so that neither a new capability test nor a stale filter goes
//! unseen.

use super::files_under;
use std::path::{Path, PathBuf};

/// The `gl_tests=(...)` filters of `.ci/run`.
fn gl_filters(ci: &str) -> Vec<String> {
    let line = ci
        .lines()
        .find(|l| l.starts_with("gl_tests=("))
        .expect(".ci/run names its GL tests in gl_tests=(...)");
    let inside = line.trim_start_matches("gl_tests=(").trim_end_matches(')');
    inside.split_whitespace().map(str::to_string).collect()
}

/// A function of a file: its name, whether it is a `#[test]`, and its body.
type Function = (String, bool, String);

/// The functions of `text`: name, whether it is a `#[test]`, and its body (to the next `fn`).
fn functions(text: &str) -> Vec<Function> {
    let lines: Vec<&str> = text.lines().collect();
    let starts: Vec<usize> = (0..lines.len())
        .filter(|&k| {
            let l = lines[k].trim_start();
            l.starts_with("fn ") || l.starts_with("pub fn ") || l.starts_with("pub(crate) fn ")
        })
        .collect();
    starts
        .iter()
        .enumerate()
        .map(|(n, &k)| {
            let head = lines[k].trim_start();
            let name = head[head.find("fn ").unwrap() + 3..]
                .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .next()
                .unwrap()
                .to_string();
            let is_test = k > 0 && lines[k - 1].trim() == "#[test]";
            let end = starts.get(n + 1).copied().unwrap_or(lines.len());
            (name, is_test, lines[k..end].join("\n"))
        })
        .collect()
}

/// The path of `name` in the test crate of `file` (its module path, then the name).
fn test_path(crate_dir: &Path, file: &Path, name: &str) -> String {
    let relative = file.strip_prefix(crate_dir).unwrap().with_extension("");
    let mut parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .filter(|p| p != "main" && p != "mod")
        .collect();
    parts.push(name.to_string());
    parts.join("::")
}

#[test]
fn the_gl_pass_runs_every_test_that_depends_on_a_capability() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let filters = gl_filters(&std::fs::read_to_string(root.join(".ci/run")).unwrap());
    let mut capability_tests = Vec::new();
    for krate in ["render", "cli", "explore"] {
        let crate_dir = root.join("tests").join(krate);
        let files: Vec<(PathBuf, Vec<Function>)> = files_under(&crate_dir, &["rs"])
            .into_iter()
            .map(|f| {
                let text = std::fs::read_to_string(&f).unwrap();
                (f, functions(&text))
            })
            .collect();
        // Helpers that name a capability, anywhere in the crate (a crate root's helpers are
        // called from its modules).
        let helpers: Vec<String> = files
            .iter()
            .flat_map(|(_, fns)| fns.iter())
            .filter(|(_, is_test, body)| !is_test && body.contains("Capability::"))
            .map(|(name, _, _)| format!("{name}("))
            .collect();
        for (file, fns) in &files {
            for (name, is_test, body) in fns {
                let depends = body.contains("Capability::")
                    || helpers.iter().any(|h| body.contains(h.as_str()));
                if *is_test && depends {
                    capability_tests.push(test_path(&crate_dir, file, name));
                }
            }
        }
    }
    assert!(
        capability_tests.len() >= 10,
        "the scan finds the capability tests: {capability_tests:?}"
    );
    let missed: Vec<&String> = capability_tests
        .iter()
        .filter(|t| !filters.iter().any(|f| t.contains(f.as_str())))
        .collect();
    assert!(
        missed.is_empty(),
        "tests that depend on a capability and that .ci/run's gl_tests does not run: {missed:?}"
    );
    let stale: Vec<&String> = filters
        .iter()
        .filter(|f| !capability_tests.iter().any(|t| t.contains(f.as_str())))
        .collect();
    assert!(
        stale.is_empty(),
        "gl_tests filters that match no capability test: {stale:?}"
    );
}

#[test]
fn the_scan_finds_tests_and_the_helpers_they_call() {
    let text = "fn helper() {\n    has(Capability::F64)\n}\n\n#[test]\nfn uses_it() {\n    \
                helper();\n}\n\n#[test]\nfn does_not() {\n    other();\n}\n";
    let fns = functions(text);
    let names: Vec<(&str, bool)> = fns.iter().map(|(n, t, _)| (n.as_str(), *t)).collect();
    assert_eq!(
        names,
        [("helper", false), ("uses_it", true), ("does_not", true)]
    );
    assert!(fns[1].2.contains("helper("));
    assert!(!fns[2].2.contains("helper("));
    assert_eq!(
        gl_filters("x\ngl_tests=(a:: b_c)\ny"),
        ["a::".to_string(), "b_c".to_string()]
    );
    let dir = Path::new("/t/render");
    assert_eq!(
        test_path(dir, Path::new("/t/render/gpu_f64.rs"), "x"),
        "gpu_f64::x"
    );
    assert_eq!(
        test_path(dir, Path::new("/t/render/mesh/mod.rs"), "y"),
        "mesh::y"
    );
}
