//! The persistent pipeline cache (src/gpu/pipeline_cache.rs), through the binary on the GPU: a
//! render leaves a cache file in `QJULIA_CACHE_DIR`; a corrupt one is ignored (the same picture)
//! and replaced; `QJULIA_NO_PIPELINE_CACHE=1` writes none. On an adapter without pipeline
//! caches (GL) a render writes no file, and the test says it skipped the rest, except under CI
//! on Vulkan (lavapipe has them: `common::Capability`), where it fails.

use crate::common;

use std::path::Path;
use std::process::Command;

/// Renders 16x16 on the GPU into `out` with `env`; the PNG's bytes.
fn render(dir: &Path, out: &str, env: &[(&str, &std::ffi::OsStr)]) -> Vec<u8> {
    let mut command = Command::new(env!("CARGO_BIN_EXE_qjulia"));
    command
        .args([
            "render",
            "--backend",
            "gpu",
            "--width",
            "16",
            "--height",
            "16",
            "-o",
            out,
        ])
        .current_dir(dir)
        .env_remove("QJULIA_NO_PIPELINE_CACHE");
    for (k, v) in env {
        command.env(k, v);
    }
    let result = command.output().unwrap();
    assert!(result.status.success(), "{}", common::stderr(&result));
    std::fs::read(dir.join(out)).unwrap()
}

/// The cache files in `dir`.
fn caches(dir: &Path) -> Vec<std::path::PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bin"))
        .collect()
}

#[test]
fn a_render_keeps_a_cache_and_a_corrupt_one_is_replaced() {
    let test = "a_render_keeps_a_cache_and_a_corrupt_one_is_replaced";
    if common::gpu(test).is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let env = [("QJULIA_CACHE_DIR", cache.as_os_str())];
    let first = render(dir.path(), "a.png", &env);
    let files = caches(&cache);
    if !common::gpu_has(common::Capability::PipelineCache, test, "the cache file") {
        assert!(
            files.is_empty(),
            "a cache without PIPELINE_CACHE: {files:?}"
        );
        return;
    }
    assert_eq!(files.len(), 1, "{files:?}");
    let name = files[0].file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with("wgpu_pipeline_cache_"), "{name}");
    assert_eq!(&std::fs::read(&files[0]).unwrap()[..8], b"QJPCACH1");
    // Read back: the same picture.
    assert!(render(dir.path(), "b.png", &env) == first);
    // Corrupt, then foreign: ignored, the same picture, and the file replaced by a good one.
    for bad in [b"QJPCACH1 but the rest is noise".to_vec(), vec![0u8; 4096]] {
        std::fs::write(&files[0], &bad).unwrap();
        assert!(render(dir.path(), "c.png", &env) == first);
        let now = std::fs::read(&files[0]).unwrap();
        assert_eq!(&now[..8], b"QJPCACH1", "the bad file is replaced");
        assert_ne!(now, bad);
    }
    // Turned off: nothing written.
    let off = dir.path().join("off");
    let mut env_off = env.to_vec();
    env_off[0].1 = off.as_os_str();
    env_off.push(("QJULIA_NO_PIPELINE_CACHE", "1".as_ref()));
    assert!(render(dir.path(), "d.png", &env_off) == first);
    assert!(caches(&off).is_empty());
}
