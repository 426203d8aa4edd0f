//! `qjulia kernel`: the WGSL a render of a scene hands the GPU, composed for it. Each kernel the
//! scene runs, in order, with its header; the text validates with naga, its size and fingerprint
//! are its own; `--precision` and `--json` as the contract gives them; and a GPU render's
//! `--stats` names the same kernel, a CPU render's none.

use qjulia::gpu::compose::fingerprint;
use qjulia::gpu::shaders::validate_wgsl;
use serde_json::Value;

use crate::common::{assert_refused, qjulia, qjulia_env, stderr};

/// `qjulia kernel --json` with `args`, parsed.
fn kernels(args: &[&str]) -> Vec<Value> {
    kernels_env(args, &[])
}

/// `qjulia kernel --json` with `args` and the environment variables `env`, parsed.
fn kernels_env(args: &[&str], env: &[(&str, &str)]) -> Vec<Value> {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia_env(dir.path(), &[&["kernel", "--json"], args].concat(), env);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_slice::<Vec<Value>>(&out.stdout).unwrap()
}

/// As [`kernels`], with `QJULIA_SPECIALISE=0`: the generic kernels.
fn generic_kernels(args: &[&str]) -> Vec<Value> {
    kernels_env(args, &[("QJULIA_SPECIALISE", "0")])
}

fn names(kernels: &[Value]) -> Vec<&str> {
    kernels
        .iter()
        .map(|k| k["name"].as_str().unwrap())
        .collect()
}

fn files(kernel: &Value) -> Vec<&str> {
    let files = kernel["files"].as_array().unwrap();
    files.iter().map(|f| f.as_str().unwrap()).collect()
}

#[test]
fn each_scene_gets_its_kernels() {
    let seed = kernels(&[]);
    assert_eq!(names(&seed), ["trace"]);
    let trace = &seed[0];
    assert_eq!(trace["entry"], "main");
    let trace_files = files(trace);
    assert_eq!(
        trace_files.first(),
        Some(&"real32"),
        "the prelude comes first"
    );
    assert_eq!(trace_files.last(), Some(&"trace"), "the root comes last");
    for file in [
        "algebra",
        "params",
        "estimate",
        "march",
        "normal",
        "camera",
        "accumulate",
    ] {
        assert!(trace_files.contains(&file), "{file}");
    }
    for file in [
        "real64", "bsdf", "light", "medium", "sobol", "path", "denoise",
    ] {
        assert!(
            !trace_files.contains(&file),
            "{file} is no part of the tracer"
        );
    }
    let text = trace["text"].as_str().unwrap();
    assert_eq!(trace["bytes"].as_u64().unwrap() as usize, text.len());
    assert_eq!(trace["fingerprint"], fingerprint(text.as_bytes()));
    assert_eq!(
        trace["overrides"],
        serde_json::json!({}),
        "every constant of the variant is a feature"
    );
    assert_eq!(
        trace["features"],
        serde_json::json!(["SHADOWS", "SHADE", "QUATERNION", "CENTRAL_NORMAL"]),
        "the seed's look: quaternions, the central normal, shadows, one sample, plain steps, \
         no pixel epsilon"
    );
    validate_wgsl(text).unwrap();

    let path = kernels(&["--preset", "path-traced"]);
    assert_eq!(names(&path), ["path"]);
    assert_eq!(path[0]["entry"], "path_main");
    for file in ["bsdf", "ggx_albedo", "light", "medium", "sobol", "path"] {
        assert!(files(&path[0]).contains(&file), "{file}");
    }
    let denoised = kernels(&[
        "--preset",
        "path-traced",
        "--set",
        "image.denoise=\"atrous\"",
    ]);
    assert_eq!(names(&denoised), ["path", "denoise"]);
    assert_eq!(denoised[1]["entry"], "atrous_main");

    let f64 = kernels(&["--precision", "f64"]);
    assert_eq!(names(&f64), ["trace64"]);
    assert!(files(&f64[0]).contains(&"real64") && !files(&f64[0]).contains(&"real32"));
    assert!(f64[0]["after"].to_string().contains("f64 check"));
    let path64 = kernels(&["--preset", "path-traced", "--precision", "f64"]);
    assert_eq!(names(&path64), ["path64"]);
}

#[test]
fn without_specialisation_no_overrides_are_set() {
    let generic = generic_kernels(&["--preset", "path-traced"]);
    let specialised = kernels(&["--preset", "path-traced"]);
    assert_eq!(generic[0]["overrides"], serde_json::json!({}));
    assert!(!generic[0]["after"].to_string().contains("naga applies"));
    assert!(specialised[0]["after"].to_string().contains("naga applies"));
    let every = qjulia::gpu::shaders::declaration().scene_features();
    assert_eq!(
        generic[0]["features"],
        serde_json::json!(every),
        "every one on"
    );
    assert_eq!(
        specialised[0]["features"],
        serde_json::json!(["SAMPLES", "SHADE", "QUATERNION", "CENTRAL_NORMAL", "LENS"])
    );
    let bytes = |k: &Value| k["bytes"].as_u64().unwrap();
    assert!(bytes(&generic[0]) > bytes(&specialised[0]));
}

/// What marks each feature's code in a kernel (its comments left out): reads of the uniform's
/// members that only the feature's own functions make, its constants, bindings and functions.
const MARKS: &[(&str, &[&str])] = &[
    (
        "path",
        &["fn path_main(", "fn trace_path(", "var<uniform> path"],
    ),
    (
        "fog",
        &["params.fog_density", "params.fog_density * length"],
    ),
    ("glow", &["params.glow_strength", "params.glow_radius"]),
    (
        "environment",
        &[
            "var<storage, read> environment",
            "fn env_frame(",
            "ENV_TEXELS",
        ],
    ),
    ("cut", &["params.cut_offset", "params.cut != 0u"]),
    ("occlusion", &["params.occlusion", "OCCLUSION_STEP"]),
    ("traps", &["params.trap_radius", "params.palette_phase"]),
    ("lens", &["params.aperture", "params.blades"]),
];

/// The kernel's text without its `//` comments.
fn code(kernel: &Value) -> String {
    let text = kernel["text"].as_str().unwrap();
    let lines = text.lines().map(|l| l.split("//").next().unwrap_or(""));
    lines.collect::<Vec<_>>().join("\n")
}

/// The features of `code` whose marks it holds: all of a feature's or none, else a panic.
fn features_in(code: &str, what: &str) -> Vec<&'static str> {
    let mut found = Vec::new();
    for (feature, marks) in MARKS {
        let held: Vec<bool> = marks.iter().map(|m| code.contains(m)).collect();
        assert!(
            held.iter().all(|h| *h) || held.iter().all(|h| !*h),
            "{what}: some of {feature}'s marks but not all: {marks:?} {held:?}"
        );
        if held[0] {
            found.push(*feature);
        }
    }
    found
}

/// The seed's look holds no code of path mode, fog, glow, the environment map, the cut,
/// occlusion, orbit traps or the lens; turning each on brings its code in, and only its; the
/// generic kernel (`QJULIA_SPECIALISE=0`) holds every one's.
#[test]
fn the_seeds_kernel_holds_only_what_it_uses() {
    let seed = kernels(&[]);
    assert_eq!(features_in(&code(&seed[0]), "the seed's look"), [""; 0]);
    let seed_features = ["SHADOWS", "SHADE", "QUATERNION", "CENTRAL_NORMAL"];
    assert_eq!(seed[0]["features"], serde_json::json!(seed_features));
    let turned_on: [(&str, &[&str], &[&str]); 8] = [
        ("path", &["shading.model=\"path\""], &["path"]),
        ("fog", &["fog.density=0.5"], &["fog"]),
        ("glow", &["glow.strength=0.5"], &["glow"]),
        (
            "environment",
            &["environment.file=\"qjulia:dusk.hdr\""],
            &["environment"],
        ),
        ("cut", &["cut.enabled=true"], &["cut"]),
        ("occlusion", &["shading.occlusion=0.5"], &["occlusion"]),
        ("traps", &["shading.colouring=\"orbit_trap\""], &["traps"]),
        ("lens", &["camera.aperture=0.05"], &["lens"]),
    ];
    for (feature, sets, expected) in turned_on {
        let mut args = Vec::new();
        for set in sets {
            args.extend(["--set", set]);
        }
        let kernel = &kernels(&args)[0];
        assert_eq!(features_in(&code(kernel), feature), expected, "{args:?}");
        validate_wgsl(kernel["text"].as_str().unwrap()).unwrap();
    }
    let generic = generic_kernels(&[]);
    let all: Vec<&str> = MARKS.iter().map(|m| m.0).filter(|f| *f != "path").collect();
    assert_eq!(features_in(&code(&generic[0]), "generic"), all);
}

#[test]
fn the_text_is_valid_wgsl_with_its_header() {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(dir.path(), &["kernel", "--preset", "path-traced"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let json = kernels(&["--preset", "path-traced"]);
    let first = text.lines().next().unwrap();
    assert_eq!(
        first,
        format!(
            "// qjulia kernel path (entry point path_main): {} bytes, fingerprint {}",
            json[0]["bytes"],
            json[0]["fingerprint"].as_str().unwrap()
        )
    );
    assert!(
        text.lines()
            .any(|l| l == "// features: SAMPLES SHADE QUATERNION CENTRAL_NORMAL LENS")
    );
    assert!(text.ends_with(json[0]["text"].as_str().unwrap()));
    validate_wgsl(&text).unwrap();
}

#[test]
fn bad_scenes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    assert_refused(
        dir.path(),
        &["kernel", "--set", "image.width=0"],
        "error: ",
        "image.width",
    );
    assert_refused(
        dir.path(),
        &["kernel", "--preset", "nope"],
        "error: ",
        "nope",
    );
}

#[test]
fn stats_name_the_kernel_on_the_gpu_only() {
    let dir = tempfile::tempdir().unwrap();
    let stats = |backend: &str| -> Value {
        let args = [
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--stats",
            "s.json",
            "--backend",
        ];
        let out = qjulia(dir.path(), &[&args[..], &[backend]].concat());
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap()
    };
    let cpu = stats("cpu");
    assert!(cpu.get("kernel").is_none() && cpu.get("kernel_fingerprint").is_none());
    if crate::common::gpu("stats_name_the_kernel_on_the_gpu_only").is_none() {
        return;
    }
    let gpu = stats("gpu");
    let trace = &kernels(&[])[0];
    assert_eq!(gpu["kernel"], "trace");
    assert_eq!(gpu["kernel_bytes"], trace["bytes"]);
    assert_eq!(gpu["kernel_fingerprint"], trace["fingerprint"]);
}
