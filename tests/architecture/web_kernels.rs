//! The browser's composer (web/src/compose.ts) is held to the library's
//! ([`qjulia::gpu::compose`]): the fixture web/test/fixtures/kernels.json holds every kernel of
//! shaders/kernels.json as the binary composes it (its size, fingerprint and files; the page
//! composes the same files and must arrive at the same bytes), and a set of small cases (files,
//! root, features) with the library's text or one-line error for each, so that every rule and
//! every message is held, not only those the real files use. `QJULIA_BLESS=1 cargo test
//! --release --test architecture web` writes it again.

use crate::web::{check_file, web};
use qjulia::gpu::compose::{Composer, fingerprint};
use qjulia::gpu::shaders::declaration;
use serde_json::{Value, json};

/// A small case: its files (name, text), the root and the features on.
type Case = (
    Vec<(&'static str, &'static str)>,
    &'static str,
    Vec<&'static str>,
);

/// Small cases, each a set of files, a root and the features on (A and B are declared).
fn cases() -> Vec<Case> {
    let main_ab = "#if A\n#import a\none\n#else\ntwo\n#endif\n#if !B\nthree\n#endif\n";
    vec![
        (
            vec![
                ("main", "#import b\n#import a\nmain\n"),
                ("a", "#import b\na\n"),
                ("b", "b"),
            ],
            "main",
            vec![],
        ),
        (vec![("main", main_ab), ("a", "a\n")], "main", vec![]),
        (vec![("main", main_ab), ("a", "a\n")], "main", vec!["A"]),
        (
            vec![("main", main_ab), ("a", "a\n")],
            "main",
            vec!["A", "B"],
        ),
        (
            vec![("main", "#if A\n  #if B\nab\n#else\na\n#endif\n#endif\nend")],
            "main",
            vec!["A"],
        ),
        (
            vec![("main", "#if A\n#if B\nab\n#else\na\n#endif\n#endif\nend")],
            "main",
            vec!["A", "B"],
        ),
        (
            vec![("main", "x\r\n#import  a \n"), ("a", "")],
            "main",
            vec![],
        ),
        (vec![("main", "#import gone")], "main", vec![]),
        (vec![("main", "x\n#if C\n#endif")], "main", vec![]),
        (vec![("main", "#if A\nx")], "main", vec![]),
        (vec![("main", "#endif")], "main", vec![]),
        (
            vec![("main", "#if A\n#else\n#else\n#endif")],
            "main",
            vec![],
        ),
        (vec![("main", "#include x")], "main", vec![]),
        (vec![("main", "#if")], "main", vec![]),
        (
            vec![
                ("main", "#import a"),
                ("a", "#import b"),
                ("b", "#import a"),
            ],
            "main",
            vec![],
        ),
        (vec![("main", "")], "main", vec!["Z"]),
        (vec![("main", "#import")], "main", vec![]),
    ]
}

/// A variant's name, its kernel and its constants.
type VariantSet = (String, &'static str, Vec<(&'static str, f64)>);

/// What turns a feature of a variant on.
type TurnOn = fn(&mut qjulia::gpu::Variant);

/// The kernels composed per variant: for every 3D preset its picture's kernel and variant (as
/// `qjulia kernel` has them), and the tracer's and the path tracer's base variant with each scene
/// feature alone and with all of them. Each with the variant's constants (what the page's
/// `overrides` gives, held to `gpu-params` by test/uniform.test.ts), the scene features they
/// leave on, the constants left, and the composed text's size and fingerprint.
fn variants() -> Vec<Value> {
    use qjulia::gpu::Variant;
    use qjulia::gpu::scene_kernel::scene_kernels;
    use qjulia::gpu::shaders::split_constants;
    use qjulia::picture::Picture;
    use qjulia::precision::Precision;
    let mut sets: Vec<VariantSet> = Vec::new();
    for p in qjulia::scene::presets::PRESETS.iter().filter(|p| !p.two_d) {
        let scene = p.scene();
        let path = Picture::SHADED.path_traced(&scene);
        let params = qjulia::params::TraceParams::<f64>::new(&scene);
        let variant = match path {
            true => Variant::of_path(&params),
            false => Variant::of(&params, true),
        };
        let kernel = scene_kernels(&scene, Picture::SHADED, Precision::F32).swap_remove(0);
        sets.push((p.slug.to_string(), kernel.name, variant.constants()));
    }
    let base = Variant::all_base()[0];
    let features: [(&str, TurnOn); 8] = [
        ("CUT", |v| v.cut = true),
        ("ORBIT_TRAP", |v| v.orbit_trap = true),
        ("OCCLUSION", |v| v.occlusion = true),
        ("SOFT_SHADOWS", |v| v.soft_shadows = true),
        ("LENS", |v| v.lens = true),
        ("FOG", |v| v.fog = true),
        ("GLOW", |v| v.glow = true),
        ("ENVIRONMENT", |v| v.environment = true),
    ];
    for kernel in ["trace", "path"] {
        let mut all = base;
        for (name, on) in features {
            let mut v = base;
            on(&mut v);
            on(&mut all);
            sets.push((format!("{kernel} with {name}"), kernel, v.constants()));
        }
        sets.push((format!("{kernel} base"), kernel, base.constants()));
        sets.push((format!("{kernel} with all"), kernel, all.constants()));
    }
    let module = |name: &str| {
        let all = qjulia::gpu::shaders::ALL_MODULES.iter();
        *all.clone().find(|m| m.name == name).unwrap()
    };
    sets.into_iter()
        .map(|(what, kernel, constants)| {
            let (on, left) = split_constants(&constants);
            let c = module(kernel).composed_with(&on);
            json!({
                "what": what,
                "kernel": kernel,
                "constants": constants,
                "on": on,
                "left": left,
                "bytes": c.text.len(),
                "fingerprint": fingerprint(c.text.as_bytes()),
            })
        })
        .collect()
}

#[test]
fn the_kernel_fixture_is_the_librarys() {
    let d = declaration();
    let kernels: Vec<Value> = d
        .kernels
        .iter()
        .map(|k| {
            let c = d.compose(k).unwrap();
            json!({
                "name": k.name,
                "bytes": c.text.len(),
                "fingerprint": fingerprint(c.text.as_bytes()),
                "files": c.files,
            })
        })
        .collect();
    let features = ["A", "B"];
    let cases: Vec<Value> = cases()
        .into_iter()
        .map(|(files, root, on)| {
            let lookup = |n: &str| files.iter().find(|f| f.0 == n).map(|f| f.1);
            let composed = Composer::new(&lookup, &features).compose(root, &on);
            let files: serde_json::Map<String, Value> = files
                .iter()
                .map(|(n, t)| (n.to_string(), json!(t)))
                .collect();
            json!({
                "files": files,
                "root": root,
                "on": on,
                "text": composed.as_ref().ok().map(|c| c.text.clone()),
                "error": composed.as_ref().err().map(|e| e.to_string()),
            })
        })
        .collect();
    let errors = cases.iter().filter(|c| !c["error"].is_null()).count();
    assert!(
        errors >= 8 && cases.len() - errors >= 6,
        "both kinds of case"
    );
    let made = json!({
        "features": features,
        "kernels": kernels,
        "variants": variants(),
        "cases": cases,
    });
    let mut text = serde_json::to_string_pretty(&made).unwrap();
    text.push('\n');
    check_file(&web().join("test/fixtures/kernels.json"), &text);
}
