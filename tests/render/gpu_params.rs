//! `qjulia gpu-params --json`: its layout is naga's reflection of the WGSL structs, its bytes
//! decode (field by field, through its own layout) to what the scene says, computed here from
//! the scene's keys, its override constants are the tracer's, and bad input exits 2.

use crate::common;

use qjulia::gpu::shaders::{
    JULIA2D_MODULE, JULIA2D64_MODULE, ShaderModuleSource, TRACE_MODULE, TRACE64_MODULE,
    validate_wgsl,
};
use serde_json::Value;

/// `qjulia gpu-params --json ARGS`, parsed; panics unless it exits 0 with JSON on stdout.
fn gpu_params(args: &[&str]) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let mut all = vec!["gpu-params", "--json"];
    all.extend_from_slice(args);
    let out = common::qjulia(dir.path(), &all);
    assert!(out.status.success(), "{all:?}: {}", common::stderr(&out));
    serde_json::from_slice(&out.stdout).expect("gpu-params prints JSON")
}

/// The JSON layout against naga's struct `name` of `module`.
fn assert_layout_is_nagas(layout: &Value, module: &ShaderModuleSource, name: &str) {
    let ir = validate_wgsl(&module.source()).unwrap();
    let (members, size, align) = common::wgsl_struct(&ir, name);
    assert_eq!(layout["name"], name);
    let fields = layout["fields"].as_array().unwrap();
    let json: Vec<common::WgslMember> = fields
        .iter()
        .map(|f| common::WgslMember {
            name: f["name"].as_str().unwrap().to_string(),
            offset: f["offset"].as_u64().unwrap() as usize,
            size: f["size"].as_u64().unwrap() as usize,
            ty: f["type"].as_str().unwrap().to_string(),
        })
        .collect();
    let context = format!("{}: gpu-params' layout is not WGSL's", module.name);
    common::assert_members_eq(&context, &members, &json);
    assert_eq!(
        layout["size"].as_u64(),
        Some(size as u64),
        "{}",
        module.name
    );
    assert_eq!(
        layout["align"].as_u64(),
        Some(align as u64),
        "{}",
        module.name
    );
}

#[test]
fn the_layouts_are_nagas_reflection_of_the_shaders() {
    for (precision, trace, julia2d) in [
        ("f32", TRACE_MODULE, JULIA2D_MODULE),
        ("f64", TRACE64_MODULE, JULIA2D64_MODULE),
    ] {
        let json = gpu_params(&["--precision", precision]);
        assert_eq!(json["precision"], precision);
        assert_layout_is_nagas(&json["layout"], &trace, "Params");
        assert_layout_is_nagas(&json["julia2d"]["layout"], &julia2d, "Julia2dParams");
        for uniform in [&json, &json["julia2d"]] {
            let bytes = uniform["bytes"].as_str().unwrap();
            assert_eq!(
                bytes.len(),
                2 * uniform["layout"]["size"].as_u64().unwrap() as usize
            );
            assert!(
                bytes
                    .bytes()
                    .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
            );
        }
    }
    // Only the band, its placement and its samples are per dispatch.
    let json = gpu_params(&[]);
    let per_dispatch: Vec<&str> = json["layout"]["fields"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["per_dispatch"] == true)
        .map(|f| f["name"].as_str().unwrap())
        .collect();
    let band = ["row_offset", "row_count", "row_stride", "out_row"];
    assert_eq!(
        per_dispatch,
        [&band[..], &["sample_start", "sample_end"]].concat()
    );
}

/// A uniform's fields, decoded through its JSON layout.
struct Decoded {
    bytes: Vec<u8>,
    fields: Vec<(String, usize, usize, String)>,
}

impl Decoded {
    fn new(uniform: &Value) -> Self {
        let hex = uniform["bytes"].as_str().unwrap();
        let bytes = (0..hex.len() / 2)
            .map(|k| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).unwrap())
            .collect();
        let fields = uniform["layout"]["fields"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| {
                (
                    f["name"].as_str().unwrap().to_string(),
                    f["offset"].as_u64().unwrap() as usize,
                    f["size"].as_u64().unwrap() as usize,
                    f["type"].as_str().unwrap().to_string(),
                )
            })
            .collect();
        Self { bytes, fields }
    }

    /// Field `name`'s scalars, widened to f64, by its WGSL type.
    fn get(&self, name: &str) -> Vec<f64> {
        let (_, offset, size, ty) = self
            .fields
            .iter()
            .find(|f| f.0 == name)
            .unwrap_or_else(|| panic!("field {name} in the layout"));
        let raw = &self.bytes[*offset..offset + size];
        let word = |k: usize| <[u8; 4]>::try_from(&raw[4 * k..4 * k + 4]).unwrap();
        let double = |k: usize| <[u8; 8]>::try_from(&raw[8 * k..8 * k + 8]).unwrap();
        if ty.contains("f64") {
            (0..size / 8)
                .map(|k| f64::from_le_bytes(double(k)))
                .collect()
        } else if ty.contains("f32") {
            (0..size / 4)
                .map(|k| f32::from_le_bytes(word(k)) as f64)
                .collect()
        } else {
            assert_eq!(ty, "u32");
            vec![u32::from_le_bytes(word(0)) as f64]
        }
    }

    fn one(&self, name: &str) -> f64 {
        let v = self.get(name);
        assert_eq!(v.len(), 1, "{name}");
        v[0]
    }

    /// The bytes after the last field (the padding to the struct's size) are zero.
    fn assert_padding_is_zero(&self) {
        let end = self.fields.iter().map(|f| f.1 + f.2).max().unwrap();
        assert!(self.bytes[end..].iter().all(|&b| b == 0), "padding");
    }
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.map(|x| x / n)
}

/// `a` and `b` agree to the precision's rounding.
fn assert_close(name: &str, a: &[f64], b: &[f64], precision: &str) {
    let tol = if precision == "f32" { 1e-6 } else { 1e-14 };
    assert_eq!(a.len(), b.len(), "{name}");
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= tol * y.abs().max(1.0),
            "{name}: {a:?} vs {b:?}"
        );
    }
}

/// The values a scene's keys give, read back from the bytes; each computed here from the
/// keys themselves (CONTRACT: forward = normalize(target - eye)).
#[test]
fn the_bytes_decode_to_the_scene() {
    let eye = [0.3, 2.5, -1.75];
    let target = [0.1, -0.2, 0.05];
    let c = [-0.2, 0.6, 0.2, 0.2];
    for precision in ["f32", "f64"] {
        let json = gpu_params(&[
            "--precision",
            precision,
            "--width",
            "96",
            "--height",
            "40",
            "--set",
            "camera.eye=[0.3, 2.5, -1.75]",
            "--set",
            "camera.target=[0.1, -0.2, 0.05]",
            "--set",
            "fractal.epsilon=0.002",
            "--set",
            "fractal.max_iterations=11",
            "--set",
            "fractal.c=[-0.2, 0.6, 0.2, 0.2]",
            "--set",
            "shading.shadows=false",
            "--set",
            "view2d.center=[0.25, -0.5]",
        ]);
        let d = Decoded::new(&json);
        let round = |v: f64| {
            if precision == "f32" {
                v as f32 as f64
            } else {
                v
            }
        };
        assert_eq!(d.get("eye"), eye.map(round));
        assert_eq!(d.one("epsilon"), round(0.002));
        assert_eq!(d.one("width"), 96.0);
        assert_eq!(d.one("height"), 40.0);
        assert_eq!(d.one("max_iterations"), 11.0);
        assert_eq!(d.one("shadows"), 0.0);
        assert_eq!(d.one("cut"), 0.0);
        assert_eq!(d.one("samples"), 1.0);
        assert_eq!(d.one("aspect"), round(96.0 / 40.0));
        // c's first quaternion, the other three zero (a quaternion scene).
        let mut hyper = c.to_vec();
        hyper.resize(16, 0.0);
        assert_eq!(
            d.get("c"),
            hyper.iter().map(|&x| round(x)).collect::<Vec<_>>()
        );
        let forward = normalize([0, 1, 2].map(|k| target[k] - eye[k]));
        assert_close("cam_forward", &d.get("cam_forward"), &forward, precision);
        // The whole image as one band, written at the start of a band-sized output, all its
        // samples in one dispatch.
        for (name, value) in [
            ("row_offset", 0.0),
            ("row_count", 40.0),
            ("row_stride", 96.0),
            ("out_row", 0.0),
            ("sample_start", 0.0),
            ("sample_end", 1.0),
        ] {
            assert_eq!(d.one(name), value, "{name}");
        }
        assert_eq!(json["samples_per_dispatch"], 1);
        assert_eq!(json["dispatches"], 1);
        d.assert_padding_is_zero();

        let j = Decoded::new(&json["julia2d"]);
        assert_eq!(j.get("c"), [c[0], c[1]].map(round));
        assert_eq!(j.get("center"), [0.25, -0.5].map(round));
        assert_eq!(j.one("width"), 96.0);
        assert_eq!(j.one("row_count"), 40.0);
        assert_eq!(j.one("row_stride"), 96.0);
        j.assert_padding_is_zero();
    }

    // The gallery (its keys in src/scene/presets.rs): 16 samples, 8 a dispatch; cut open.
    let json = gpu_params(&["--preset", "gallery", "--width", "64", "--height", "64"]);
    let d = Decoded::new(&json);
    assert_eq!(d.one("samples"), 16.0);
    assert_eq!((d.one("sample_start"), d.one("sample_end")), (0.0, 8.0));
    assert_eq!(
        (
            json["samples_per_dispatch"].as_u64(),
            json["dispatches"].as_u64()
        ),
        (Some(8), Some(2))
    );
    assert_eq!(d.one("cut"), 1.0);
    assert_close(
        "cut_normal",
        &d.get("cut_normal"),
        &normalize([0.2, 1.0, 0.5]),
        "f32",
    );
    assert_eq!(d.one("cut_offset"), 0.2f32 as f64);
    assert_eq!(d.one("light_radius"), 0.2f32 as f64);
    assert_eq!(d.one("colouring"), 1.0, "orbit trap");
    let forward = normalize([-2.0, -2.2, -1.8]);
    assert_close("cam_forward", &d.get("cam_forward"), &forward, "f32");
}

/// The overrides are the constants of the variant the tracer builds for the scene, and say what
/// the scene's keys say.
#[test]
fn the_overrides_are_the_tracers() {
    use qjulia::TraceParams;
    use qjulia::scene::SceneLoader;
    let overrides = |json: &Value| -> Vec<(String, f64)> {
        json["overrides"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, v)| (k.clone(), v.as_f64().unwrap()))
            .collect()
    };
    let gallery = overrides(&gpu_params(&["--preset", "gallery"]));
    let seed = overrides(&gpu_params(&["--preset", "seed"]));
    let value = |all: &[(String, f64)], name: &str| all.iter().find(|(k, _)| k == name).unwrap().1;
    assert!(
        gallery.iter().all(|(k, _)| k != "SPECIALISED"),
        "no longer one"
    );
    for name in [
        "SHADE",
        "SAMPLES",
        "CUT",
        "ORBIT_TRAP",
        "SOFT_SHADOWS",
        "OCCLUSION",
    ] {
        assert_eq!(value(&gallery, name), 1.0, "gallery {name}");
    }
    for name in [
        "SAMPLES",
        "CUT",
        "ORBIT_TRAP",
        "SOFT_SHADOWS",
        "OCCLUSION",
        "CONE_TRACING",
    ] {
        assert_eq!(value(&seed, name), 0.0, "seed {name}");
    }
    assert_eq!(value(&seed, "SHADOWS"), 1.0);
    assert_eq!(value(&seed, "ALGEBRA_PARTS"), 1.0);

    let Some(gpu) = common::gpu("the_overrides_are_the_tracers") else {
        return;
    };
    for (preset, json) in [("gallery", &gallery), ("seed", &seed)] {
        let mut loader = SceneLoader::new();
        loader.preset(preset).unwrap();
        let p = TraceParams::<f32>::new(&loader.build().unwrap());
        let Some(variant) = gpu.variant_for(&p, true) else {
            eprintln!("specialisation is off (QJULIA_SPECIALISE=0): the generic pipeline runs");
            return;
        };
        let built: Vec<(String, f64)> = variant
            .constants()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect();
        let mut sorted = json.clone();
        let mut built_sorted = built.clone();
        sorted.sort_by(|a, b| a.0.cmp(&b.0));
        built_sorted.sort_by(|a, b| a.0.cmp(&b.0));
        assert_eq!(sorted, built_sorted, "{preset}");
    }
    // The JSON's samples per dispatch are this device's for a one-band image.
    let p = TraceParams::<f32>::new(&common::scene(&["image.samples=16"]));
    let json = gpu_params(&["--set", "image.samples=16"]);
    assert_eq!(
        json["samples_per_dispatch"].as_u64(),
        Some(gpu.samples_per_dispatch(&p) as u64)
    );
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    common::assert_refused(d, &["gpu-params"], "error:", "--json");
    common::assert_refused(
        d,
        &["gpu-params", "--json", "--preset", "nope"],
        "error:",
        "nope",
    );
    common::assert_refused(
        d,
        &["gpu-params", "--json", "--set", "fractal.nope=1"],
        "error:",
        "fractal.nope",
    );
    common::assert_refused(
        d,
        &["gpu-params", "--json", "--scene", "missing.toml"],
        "error:",
        "missing.toml",
    );
    common::assert_refused(
        d,
        &["gpu-params", "--json", "--width", "0"],
        "error:",
        "width",
    );
    common::assert_refused(
        d,
        &["gpu-params", "--json", "--precision", "f16"],
        "error:",
        "f16",
    );
}
