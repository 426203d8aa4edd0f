//! The twin check: each WGSL file and its Rust twin define their shared functions with the same
//! names in the same order, so that the two can be read side by side.
//!
//! The names are read from the source text (WGSL `fn name(`, Rust `fn name` including methods
//! and generics; comments, strings and Rust's `#[cfg(test)]` module left out). A WGSL file is
//! read with every feature on (`#if F` kept, `#if !F` and `#else` dropped): a feature's stubs for
//! when it is off have no twin, as the CPU reads every feature from its parameters. A function that
//! exists on one side only must be listed below with the reason; everything else must match
//! one to one. The arithmetic inside the functions is held together by the GPU-vs-CPU tests.
//!
//! Why it passes 600 lines: most of it is the table of twin pairs, each exception with its
//! reason, which is data; the reader and the checks are a third of it.

use std::fmt::Write as _;

/// Which file of a twin pair a function exists in alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Wgsl,
    Rust,
}

/// A function that one side has and the other has not, and why.
struct OnlyIn {
    side: Side,
    name: &'static str,
    reason: &'static str,
}

/// A WGSL file and its Rust twin.
struct Twin {
    wgsl: &'static str,
    rust: &'static str,
    /// Where the twin starts in the Rust file (a line holding this text), when the file holds
    /// more than the twin; the reason is in `rust_from_reason`.
    rust_from: Option<&'static str>,
    rust_from_reason: &'static str,
    only_in: &'static [OnlyIn],
}

const TRACE: Twin = Twin {
    wgsl: "shaders/trace.wgsl",
    rust: "src/cpu/trace/mod.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Wgsl,
            name: "shade_on",
            reason: "the feature SHADE's switch (true, or false composed without it); the CPU \
                     twin's `shade_pixel` takes `shade` as an argument",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "add_work",
            reason: "adds a dispatch's counts to the pixel's 64-bit counts held as two u32 \
                     words each; the CPU counts into u64s (cpu::counters)",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "compacted_pixel",
            reason: "packs a workgroup's live pixels into its first invocations (adaptive \
                     sampling's compaction); the CPU has no lanes to pack: `cpu::render_rows` \
                     skips a done pixel's samples by breaking out of its loop",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "pixel_samples",
            reason: "image.samples, or 1 composed without the feature SAMPLES; on the CPU \
                     `cpu::render_rows` reads `samples`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "cone_tracing",
            reason: "the feature CONE_TRACING's switch (false composed without it); on the \
                     CPU `cpu::cone_starts` (src/cpu/mod.rs) matches on `tracing`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "main",
            reason: "the entry point: a workgroup's cone start, then one pixel traced and \
                     written; on the CPU `cpu::render_rows` in src/cpu/mod.rs (rows in \
                     parallel, `cone_starts` per row, `trace_pixel`, `pack_colour`, the writes)",
        },
    ],
};

const CUT: Twin = Twin {
    wgsl: "shaders/cut.wgsl",
    rust: "src/cpu/trace/cut.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

const ESTIMATE: Twin = Twin {
    wgsl: "shaders/estimate.wgsl",
    rust: "src/cpu/trace/estimate.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Wgsl,
            name: "algebra_parts",
            reason: "the one algebra's constant where the kernel is composed for one \
                     (QUATERNION, OCTONION); the CPU reads `algebra_parts` from its parameters",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "slice_axis_x",
            reason: "the constant standard axis where the kernel is composed without SLICE; \
                     the CPU reads `slice_x` from its parameters",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "slice_axis_y",
            reason: "as slice_axis_x, for `slice_y`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "slice_axis_z",
            reason: "as slice_axis_x, for `slice_z`",
        },
        OnlyIn {
            side: Side::Rust,
            name: "iterate_orbit_parts",
            reason: "iterate_orbit's loop compiled once per algebra (a const generic), which a \
                     kernel gets from algebra_parts() composed for one algebra",
        },
        OnlyIn {
            side: Side::Rust,
            name: "iterate_orbit_pair_parts",
            reason: "iterate_orbit_pair's loop compiled once per algebra, as \
                     iterate_orbit_parts is iterate_orbit's",
        },
        OnlyIn {
            side: Side::Rust,
            name: "count",
            reason: "the CPU's work counters (`cpu::count_work`); the GPU counts nothing",
        },
    ],
};

const MARCH: Twin = Twin {
    wgsl: "shaders/march.wgsl",
    rust: "src/cpu/trace/march.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "untraced",
            reason: "a Trace of a ray not traced; WGSL writes the literal \
                     `Trace(0.0, 0u, false, NO_APPROACH)`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "over_relaxation",
            reason: "step_scale, or 1 composed without the feature OVER_RELAXED; the CPU \
                     reads `step_scale`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "pixel_epsilon_on",
            reason: "true, or false composed without the feature PIXEL_EPSILON; on the CPU \
                     the footprint's term is eps_slope t, 0 where pixel_epsilon is",
        },
    ],
};

const NORMAL: Twin = Twin {
    wgsl: "shaders/normal.wgsl",
    rust: "src/cpu/trace/normal.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[OnlyIn {
        side: Side::Wgsl,
        name: "normal_method",
        reason: "the normal's method, a constant where the scene's kernel has one method \
                 (shaders/kernels.json's CENTRAL_NORMAL, TETRAHEDRAL_NORMAL, ANALYTIC_NORMAL); \
                 the CPU twin's `estimate_normal` matches on `normal_method`",
    }],
};

const SHADING: Twin = Twin {
    wgsl: "shaders/shading.wgsl",
    rust: "src/cpu/trace/shading.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

const COLOUR: Twin = Twin {
    wgsl: "shaders/colour.wgsl",
    rust: "src/cpu/trace/colour.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

const CAMERA: Twin = Twin {
    wgsl: "shaders/camera.wgsl",
    rust: "src/cpu/trace/camera.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

const ATMOSPHERE: Twin = Twin {
    wgsl: "shaders/atmosphere.wgsl",
    rust: "src/cpu/trace/atmosphere.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

const ACCUMULATE: Twin = Twin {
    wgsl: "shaders/accumulate.wgsl",
    rust: "src/cpu/trace/accumulate.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Wgsl,
            name: "load_streams",
            reason: "reads a pixel's streams from the accumulator's four planes in the storage \
                     array (arrayLength); the CPU keeps a pixel's streams in a local",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "store_streams",
            reason: "as load_streams, writing them back (a done pixel's first plane and its \
                     halves)",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "load_halves",
            reason: "reads a pixel's halves from the accumulator's second and third planes; the \
                     CPU keeps them in a local",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "store_halves",
            reason: "as load_halves, writing them back",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "load_aovs",
            reason: "reads a pixel's AOVs back from the out_aovs buffer between dispatches; the \
                     CPU keeps them in a local `Aovs` across all samples (`cpu::render_rows`)",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "store_aovs",
            reason: "writes a pixel's AOVs to the out_aovs buffer; on the CPU `cpu::fill_rows` \
                     puts them in the frame",
        },
    ],
};

const ALGEBRA: Twin = Twin {
    wgsl: "shaders/algebra.wgsl",
    rust: "src/algebra.rs",
    rust_from: Some("// ----- twins of shaders/algebra.wgsl -----"),
    rust_from_reason: "above the line are `Real` and `Vec2`/`Vec3`/`Vec4` with their \
                       operators, the CPU's stand-ins for WGSL's f32 and built-in vector types",
    only_in: &[OnlyIn {
        side: Side::Rust,
        name: "hyper_from_f64",
        reason: "host-side f64 numbers to the working precision; the GPU gets its numbers \
                 from the uniform buffer",
    }],
};

const JULIA2D: Twin = Twin {
    wgsl: "shaders/julia2d.wgsl",
    rust: "src/cpu/julia2d.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "julia_pixel",
            reason: "the entry point's work for one pixel (escape, grey, packing), which WGSL \
                     does inline in `main`",
        },
        OnlyIn {
            side: Side::Rust,
            name: "render_rows",
            reason: "the dispatch: rows in parallel and the writes, which the GPU does by \
                     workgroups in `main`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "main",
            reason: "the entry point; on the CPU `julia_pixel` and `render_rows`",
        },
    ],
};

const SAMPLE: Twin = Twin {
    wgsl: "shaders/sample.wgsl",
    rust: "src/cpu/sample.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "sample_rows",
            reason: "the dispatch: rows in parallel and the writes, which the GPU does by \
                     workgroups in `sample`",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "sample",
            reason: "the entry point; on the CPU `sample_rows`",
        },
    ],
};

const BSDF: Twin = Twin {
    wgsl: "shaders/bsdf.wgsl",
    rust: "src/cpu/bsdf.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[OnlyIn {
        side: Side::Rust,
        name: "pi",
        reason: "the shader's `PI` constant, in the precision of the generic float",
    }],
};

const GGX_ALBEDO: Twin = Twin {
    wgsl: "shaders/ggx_albedo.wgsl",
    rust: "src/cpu/ggx_albedo.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "unorm16",
            reason: "decodes a half of a table word as WGSL's `unpack2x16unorm` does, for \
                     `parse_tables`",
        },
        OnlyIn {
            side: Side::Rust,
            name: "parse_tables",
            reason: "reads the shader's tables, so that the twin uses its very numbers",
        },
    ],
};

const PATH: Twin = Twin {
    wgsl: "shaders/path.wgsl",
    rust: "src/cpu/path/mod.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "trace_path_from",
            reason: "WGSL's `trace_path`, which takes the camera ray and its trace (path_main \
                     traces camera rays in pairs); the CPU's `trace_path` keeps the one-sample \
                     signature its callers use, traces the camera ray and calls this",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "path_main",
            reason: "the entry point: the samples' running mean and the writes; on the CPU \
                     `render_path_rows` loops over `path_camera_ray`, `trace_primary_pair` and \
                     `trace_path_from` as it does",
        },
        OnlyIn {
            side: Side::Rust,
            name: "render_path_rows",
            reason: "the CPU's `path_main`: rows in parallel, each pixel's running mean of \
                     `trace_path`, as the entry point keeps it",
        },
    ],
};

const PATH_UNIFORM: Twin = Twin {
    wgsl: "shaders/path_uniform.wgsl",
    rust: "src/cpu/path/uniform.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[OnlyIn {
        side: Side::Rust,
        name: "new",
        reason: "the host makes `PathParams` of a scene; the shader reads it as a uniform",
    }],
};

const PATH_VERTEX: Twin = Twin {
    wgsl: "shaders/path_vertex.wgsl",
    rust: "src/cpu/path/vertex.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "max3",
            reason: "WGSL's `max(c.x, max(c.y, c.z))`, written out there",
        },
        OnlyIn {
            side: Side::Rust,
            name: "any_positive",
            reason: "WGSL's `any(c > vec3(0.0))`",
        },
        OnlyIn {
            side: Side::Rust,
            name: "none",
            reason: "a `Light` of no light; WGSL writes the literal \
                     `Light(vec3<f32>(0.0), vec3<f32>(0.0))`",
        },
    ],
};

const DENOISE: Twin = Twin {
    wgsl: "shaders/denoise.wgsl",
    rust: "src/cpu/denoise.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "xyz",
            reason: "WGSL's `.xyz` swizzle of a vec4, written out there",
        },
        OnlyIn {
            side: Side::Wgsl,
            name: "store_image",
            reason: "writes the pass's output buffer (image_a or image_b, by params.source); on                      the CPU `atrous_pass` collects `atrous_main`'s pixels into a new image",
        },
        OnlyIn {
            side: Side::Rust,
            name: "atrous_pass",
            reason: "the CPU's dispatch: rows in parallel, `atrous_main` per pixel",
        },
    ],
};

const MEDIUM: Twin = Twin {
    wgsl: "shaders/medium.wgsl",
    rust: "src/cpu/medium.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

const ENVIRONMENT: Twin = Twin {
    wgsl: "shaders/environment.wgsl",
    rust: "src/cpu/environment.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[OnlyIn {
        side: Side::Rust,
        name: "env_word",
        reason: "reads a float of the packed map, which WGSL indexes as the `environment` \
                     binding directly",
    }],
};

const LIGHT: Twin = Twin {
    wgsl: "shaders/light.wgsl",
    rust: "src/cpu/light.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[
        OnlyIn {
            side: Side::Rust,
            name: "mix3",
            reason: "WGSL's builtin `mix` for vectors",
        },
        OnlyIn {
            side: Side::Rust,
            name: "sun_one_minus_cos",
            reason: "the host's, in f64: the kernels get the sun's 1 - cos in the path uniform",
        },
    ],
};

const SOBOL: Twin = Twin {
    wgsl: "shaders/sobol.wgsl",
    rust: "src/cpu/sobol.rs",
    rust_from: None,
    rust_from_reason: "",
    only_in: &[],
};

/// The source text with comments and string literals blanked out (replaced by spaces, so that
/// nothing inside them reads as code).
fn code_only(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len());
    let mut i = 0;
    while i < chars.len() {
        let next = chars.get(i + 1).copied();
        match (chars[i], next) {
            ('/', Some('/')) => {
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
            }
            ('/', Some('*')) => {
                i += 2;
                while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                    i += 1;
                }
                i += 2;
                out.push(' ');
            }
            ('"', _) => {
                i += 1;
                while i < chars.len() && chars[i] != '"' {
                    i += if chars[i] == '\\' { 2 } else { 1 };
                }
                i += 1;
                out.push(' ');
            }
            (c, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    out
}

/// The names of the functions defined in `source` (WGSL or Rust), in order: every identifier
/// that follows the keyword `fn`.
fn function_names(source: &str) -> Vec<String> {
    let code = code_only(source);
    let words: Vec<&str> = code
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .collect();
    words
        .windows(2)
        .filter(|pair| pair[0] == "fn")
        .map(|pair| pair[1].to_string())
        .collect()
}

/// A WGSL file's lines as composed with every feature on: what `#if F` gates kept, what `#if !F`
/// and `#else` gate dropped, and the directives' own lines dropped.
fn every_feature_on(source: &str) -> String {
    let mut kept: Vec<bool> = Vec::new();
    let mut out = String::new();
    for line in source.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["#if", f] => kept.push(!f.starts_with('!')),
            ["#else"] => {
                let last = kept.last_mut().expect("#else after #if");
                *last = !*last;
            }
            ["#endif"] => {
                kept.pop();
            }
            _ if line.starts_with('#') => {}
            _ if kept.iter().all(|k| *k) => {
                out.push_str(line);
                out.push('\n');
            }
            _ => {}
        }
    }
    out
}

fn read(path: &str) -> String {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

/// The part of a Rust file that is the twin: from `rust_from` on, up to the test module.
fn rust_twin_part(twin: &Twin) -> String {
    let source = read(twin.rust);
    let start = match twin.rust_from {
        Some(marker) => source
            .find(marker)
            .unwrap_or_else(|| panic!("{}: the line {marker:?} is gone", twin.rust)),
        None => 0,
    };
    let part = &source[start..];
    let end = part.find("#[cfg(test)]").unwrap_or(part.len());
    part[..end].to_string()
}

fn listing(names: &[String]) -> String {
    names
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{k:>3} {n}"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The failures of one twin pair, empty when it holds.
fn twin_failures(twin: &Twin) -> String {
    let wgsl = function_names(&every_feature_on(&read(twin.wgsl)));
    let rust = function_names(&rust_twin_part(twin));
    let mut failures = String::new();
    for only in twin.only_in {
        let (own, other) = match only.side {
            Side::Wgsl => (&wgsl, &rust),
            Side::Rust => (&rust, &wgsl),
        };
        if !own.iter().any(|n| n == only.name) {
            writeln!(
                failures,
                "`{}` is listed as {:?}-only but that side has no such function: remove it \
                 from the list",
                only.name, only.side
            )
            .unwrap();
        }
        if other.iter().any(|n| n == only.name) {
            writeln!(
                failures,
                "`{}` is listed as {:?}-only but both sides have it: remove it from the list",
                only.name, only.side
            )
            .unwrap();
        }
    }
    let shared = |names: &[String], side: Side| -> Vec<String> {
        names
            .iter()
            .filter(|n| {
                !twin
                    .only_in
                    .iter()
                    .any(|o| o.side == side && o.name == n.as_str())
            })
            .cloned()
            .collect()
    };
    let (wgsl_shared, rust_shared) = (shared(&wgsl, Side::Wgsl), shared(&rust, Side::Rust));
    if wgsl_shared != rust_shared {
        let first = wgsl_shared
            .iter()
            .zip(&rust_shared)
            .position(|(a, b)| a != b)
            .unwrap_or(wgsl_shared.len().min(rust_shared.len()));
        writeln!(
            failures,
            "the shared functions differ in name or order, first at position {first}\n\
             {} ({} shared):\n{}\n{} ({} shared):\n{}",
            twin.wgsl,
            wgsl_shared.len(),
            listing(&wgsl_shared),
            twin.rust,
            rust_shared.len(),
            listing(&rust_shared),
        )
        .unwrap();
    }
    if failures.is_empty() {
        return failures;
    }
    let mut report = format!(
        "{} and {} are not twins:\n{failures}\nAll functions, exceptions included:\n{}:\n{}\n{}:\n{}\n\
         Functions one side has for a reason are listed in tests/architecture/twins.rs.",
        twin.wgsl,
        twin.rust,
        twin.wgsl,
        listing(&wgsl),
        twin.rust,
        listing(&rust),
    );
    if let Some(marker) = twin.rust_from {
        write!(
            report,
            "\n(The Rust twin starts at {marker:?}: {}.)",
            twin.rust_from_reason
        )
        .unwrap();
    }
    report
}

fn check(twin: &Twin) {
    let failures = twin_failures(twin);
    assert!(failures.is_empty(), "{failures}");
}

#[test]
fn trace_twins_match() {
    check(&TRACE);
}

#[test]
fn cut_twins_match() {
    check(&CUT);
}

#[test]
fn estimate_twins_match() {
    check(&ESTIMATE);
}

#[test]
fn march_twins_match() {
    check(&MARCH);
}

#[test]
fn normal_twins_match() {
    check(&NORMAL);
}

#[test]
fn shading_twins_match() {
    check(&SHADING);
}

#[test]
fn colour_twins_match() {
    check(&COLOUR);
}

#[test]
fn camera_twins_match() {
    check(&CAMERA);
}

#[test]
fn atmosphere_twins_match() {
    check(&ATMOSPHERE);
}

#[test]
fn accumulate_twins_match() {
    check(&ACCUMULATE);
}

#[test]
fn algebra_twins_match() {
    check(&ALGEBRA);
}

#[test]
fn julia2d_twins_match() {
    check(&JULIA2D);
}

#[test]
fn sample_twins_match() {
    check(&SAMPLE);
}

#[test]
fn sobol_twins_match() {
    check(&SOBOL);
}

#[test]
fn bsdf_twins_match() {
    check(&BSDF);
}

#[test]
fn ggx_albedo_twins_match() {
    check(&GGX_ALBEDO);
}

#[test]
fn light_twins_match() {
    check(&LIGHT);
}

#[test]
fn environment_twins_match() {
    check(&ENVIRONMENT);
}

#[test]
fn medium_twins_match() {
    check(&MEDIUM);
}

#[test]
fn path_twins_match() {
    check(&PATH);
}

#[test]
fn path_uniform_twins_match() {
    check(&PATH_UNIFORM);
}

#[test]
fn path_vertex_twins_match() {
    check(&PATH_VERTEX);
}

#[test]
fn denoise_twins_match() {
    check(&DENOISE);
}

#[test]
fn every_exception_has_a_reason() {
    for twin in [
        &TRACE,
        &CUT,
        &ESTIMATE,
        &MARCH,
        &NORMAL,
        &SHADING,
        &COLOUR,
        &CAMERA,
        &ATMOSPHERE,
        &ACCUMULATE,
        &ALGEBRA,
        &JULIA2D,
        &SAMPLE,
        &SOBOL,
        &BSDF,
        &LIGHT,
        &ENVIRONMENT,
        &MEDIUM,
        &PATH,
        &PATH_UNIFORM,
        &PATH_VERTEX,
        &DENOISE,
    ] {
        for only in twin.only_in {
            assert!(!only.reason.trim().is_empty(), "{}: no reason", only.name);
        }
        assert_eq!(twin.rust_from.is_some(), !twin.rust_from_reason.is_empty());
    }
}

#[test]
fn names_are_read_from_code_only() {
    let source = r#"
        // fn in_a_comment() {}
        /* fn in_a_block() */
        fn plain(x: f32) -> f32 { return x; }
        pub fn generic<F: Real>(x: F) {}
        pub(crate) fn iterate<const N: u32>(&self) { let s = "fn in_a_string(\"x\")"; }
        @compute @workgroup_size(8, 8, 1)
        fn main(@builtin(global_invocation_id) id: vec3<u32>) {}
    "#;
    assert_eq!(
        function_names(source),
        ["plain", "generic", "iterate", "main"]
    );
}
