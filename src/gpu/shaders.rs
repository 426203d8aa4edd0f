//! The WGSL kernels, composed from the files of shaders/ (compiled into the binary, so that it
//! stands alone) as shaders/kernels.json declares them.
//!
//! # Files, imports and kernels
//!
//! Each file of shaders/ names the files it needs with `#import` lines and gates its text with
//! `#if FEATURE` ([`super::compose`] gives the rules). shaders/kernels.json declares the
//! features and the kernels: each kernel's root file, entry point and features. A kernel's WGSL
//! is its root composed with its features; no host keeps a join order, and the page composes
//! the same declaration the same way (web/src/compose.ts).
//!
//! # One source, two precisions
//!
//! shaders/algebra.wgsl, trace.wgsl and julia2d.wgsl are written against a float type `Real`
//! (`vec3<Real>`, `Real(i)`, ...) and call the few functions whose f64 form needs care through
//! `real_sqrt`, `real_log`, `real_pow`, `real_cos` and `real_normalize`. They import
//! shaders/real.wgsl, which imports real32.wgsl (`alias Real = f32;`, the builtins themselves)
//! or, with the feature F64, real64.wgsl (`alias Real = f64;`, those functions built from checked
//! f64 operations). That choice is the whole transform: no text of the kernels is rewritten, an
//! f32 kernel is exactly the kernel it was before f64 came, and the f64 one is a separate module
//! with its own pipelines, so f32 scenes pay nothing. What stays f32 in the f64 kernels is
//! written `f32` there: the packed colour, the samples' running mean, the 2D view's grey.

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use serde::Deserialize;

use super::compose::{Composed, Composer};

/// Every file of shaders/ by its stem (a test holds the list to the folder).
pub const FILES: &[(&str, &str)] = &[
    ("accumulate", include_str!("../../shaders/accumulate.wgsl")),
    ("algebra", include_str!("../../shaders/algebra.wgsl")),
    ("atmosphere", include_str!("../../shaders/atmosphere.wgsl")),
    ("bsdf", include_str!("../../shaders/bsdf.wgsl")),
    ("bsdf_probe", include_str!("../../shaders/bsdf_probe.wgsl")),
    ("camera", include_str!("../../shaders/camera.wgsl")),
    ("colour", include_str!("../../shaders/colour.wgsl")),
    ("cut", include_str!("../../shaders/cut.wgsl")),
    ("denoise", include_str!("../../shaders/denoise.wgsl")),
    (
        "environment",
        include_str!("../../shaders/environment.wgsl"),
    ),
    ("estimate", include_str!("../../shaders/estimate.wgsl")),
    ("f64check", include_str!("../../shaders/f64check.wgsl")),
    ("ggx_albedo", include_str!("../../shaders/ggx_albedo.wgsl")),
    ("julia2d", include_str!("../../shaders/julia2d.wgsl")),
    ("light", include_str!("../../shaders/light.wgsl")),
    ("march", include_str!("../../shaders/march.wgsl")),
    ("medium", include_str!("../../shaders/medium.wgsl")),
    ("normal", include_str!("../../shaders/normal.wgsl")),
    ("params", include_str!("../../shaders/params.wgsl")),
    ("path", include_str!("../../shaders/path.wgsl")),
    (
        "path_uniform",
        include_str!("../../shaders/path_uniform.wgsl"),
    ),
    (
        "path_vertex",
        include_str!("../../shaders/path_vertex.wgsl"),
    ),
    ("real", include_str!("../../shaders/real.wgsl")),
    ("real32", include_str!("../../shaders/real32.wgsl")),
    ("real64", include_str!("../../shaders/real64.wgsl")),
    ("sample", include_str!("../../shaders/sample.wgsl")),
    ("shading", include_str!("../../shaders/shading.wgsl")),
    ("sobol", include_str!("../../shaders/sobol.wgsl")),
    (
        "sobol_probe",
        include_str!("../../shaders/sobol_probe.wgsl"),
    ),
    ("trace", include_str!("../../shaders/trace.wgsl")),
];

/// shaders/kernels.json as written.
pub const DECLARATION_JSON: &str = include_str!("../../shaders/kernels.json");

/// The text of shaders/`name`.wgsl.
pub fn file(name: &str) -> Option<&'static str> {
    FILES.iter().find(|f| f.0 == name).map(|f| f.1)
}

/// shaders/kernels.json: the features a file may test and the kernels the hosts build.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Declaration {
    pub format: u32,
    /// What a feature marked `scene` means (the rule [`split_constants`] follows).
    pub scene_features: String,
    pub features: Vec<FeatureDecl>,
    pub kernels: Vec<KernelDecl>,
}

/// A feature: its name (what `#if` tests), whether the scene decides it, and what it turns on.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureDecl {
    pub name: String,
    /// Decided by the scene's variant ([`split_constants`]); else by the kernel (`F64`).
    #[serde(default)]
    pub scene: bool,
    /// A scene feature's constant: its own name unless given.
    #[serde(default)]
    pub constant: Option<String>,
    /// The values of [`Self::constant`] that turn a scene feature on: `[1]` unless given.
    #[serde(default)]
    pub on: Option<Vec<f64>>,
    pub doc: String,
}

/// A kernel: its name, its root file, the entry point the host runs, its features, and whether
/// the page builds it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KernelDecl {
    pub name: String,
    pub root: String,
    pub entry: String,
    pub features: Vec<String>,
    pub web: bool,
}

/// The declaration, parsed once (a test holds it well-formed).
pub fn declaration() -> &'static Declaration {
    static PARSED: OnceLock<Declaration> = OnceLock::new();
    PARSED.get_or_init(|| {
        serde_json::from_str(DECLARATION_JSON).expect("shaders/kernels.json is well-formed")
    })
}

impl Declaration {
    /// The kernel declared as `name`.
    pub fn kernel(&self, name: &str) -> Option<&KernelDecl> {
        self.kernels.iter().find(|k| k.name == name)
    }

    /// The declared features' names.
    pub fn feature_names(&self) -> Vec<&str> {
        self.features.iter().map(|f| f.name.as_str()).collect()
    }

    /// The features the scene decides ([`FeatureDecl::scene`]), in the declaration's order.
    pub fn scene_features(&self) -> Vec<&str> {
        let scene = self.features.iter().filter(|f| f.scene);
        scene.map(|f| f.name.as_str()).collect()
    }

    /// `kernel` composed from [`FILES`] with every scene feature on: the generic kernel, which
    /// reads each of them from the uniform at run time.
    pub fn compose(&self, kernel: &KernelDecl) -> Result<Composed, super::compose::ComposeError> {
        self.compose_with(kernel, &self.scene_features())
    }

    /// `kernel` composed from [`FILES`] with its own features and the scene features `scene`.
    pub fn compose_with(
        &self,
        kernel: &KernelDecl,
        scene: &[&str],
    ) -> Result<Composed, super::compose::ComposeError> {
        let lookup = |n: &str| file(n);
        let features = self.feature_names();
        let mut on: Vec<&str> = kernel.features.iter().map(String::as_str).collect();
        on.extend_from_slice(scene);
        Composer::new(&lookup, &features).compose(&kernel.root, &on)
    }
}

/// A pipeline's override constants split into the scene features the text is composed with and
/// the constants left for naga. A scene feature is on where the constants hold its constant
/// ([`FeatureDecl::constant`]) with one of its values ([`FeatureDecl::on`]), off where they hold
/// it with another, and on where they do not hold it: constants without a variant (none, or
/// only the device's choices) compose every scene feature on, the generic kernel. The scene
/// features' constants (a variant's, [`super::Variant::constants`]) are not passed on: the text
/// has no such override.
pub fn split_constants(
    constants: &[(&'static str, f64)],
) -> (Vec<&'static str>, Vec<(&'static str, f64)>) {
    let scene: Vec<&FeatureDecl> = declaration().features.iter().filter(|f| f.scene).collect();
    let on = scene.iter().filter(|f| {
        let held = constants.iter().find(|c| c.0 == f.constant());
        held.is_none_or(|c| f.on_values().contains(&c.1))
    });
    let on = on.map(|f| f.name.as_str()).collect();
    let consumed = |name: &str| scene.iter().any(|f| f.constant() == name);
    let left = constants.iter().copied().filter(|c| !consumed(c.0));
    (on, left.collect())
}

impl FeatureDecl {
    /// A scene feature's constant: [`Self::constant`] where given, else its name.
    pub fn constant(&self) -> &str {
        self.constant.as_deref().unwrap_or(&self.name)
    }

    /// The values of its constant that turn a scene feature on: [`Self::on`] where given, else
    /// 1.
    pub fn on_values(&self) -> &[f64] {
        self.on.as_deref().unwrap_or(&[1.0])
    }
}

/// One WGSL module the GPU runs: a kernel of shaders/kernels.json by name, or (for tests) a
/// text of its own.
#[derive(Clone, Copy, Debug)]
pub struct ShaderModuleSource {
    pub name: &'static str,
    text: Option<&'static str>,
}

impl ShaderModuleSource {
    /// The kernel shaders/kernels.json declares as `name`.
    pub const fn kernel(name: &'static str) -> Self {
        Self { name, text: None }
    }

    /// A module of one text (a test's or an experiment's kernel), composed as a root file: it
    /// may `#import` the files of shaders/.
    pub const fn text(name: &'static str, text: &'static str) -> Self {
        Self {
            name,
            text: Some(text),
        }
    }

    /// The module's full source: the generic kernel composed (every scene feature on).
    pub fn source(&self) -> String {
        self.composed().text
    }

    /// The generic module composed: its text and files.
    pub fn composed(&self) -> Composed {
        self.composed_with(&declaration().scene_features())
    }

    /// The module composed with the scene features `scene` on (the others off): its text and
    /// files, a declared kernel's composed once a process for each set of features.
    pub fn composed_with(&self, scene: &[&str]) -> Composed {
        let d = declaration();
        if let Some(text) = self.text {
            let lookup = |n: &str| if n == self.name { Some(text) } else { file(n) };
            let features = d.feature_names();
            let composer = Composer::new(&lookup, &features);
            let composed = composer.compose(self.name, scene);
            return composed.unwrap_or_else(|e| panic!("module {}: {e}", self.name));
        }
        type Cache = Mutex<HashMap<(&'static str, Vec<String>), Composed>>;
        static COMPOSED: OnceLock<Cache> = OnceLock::new();
        let key = (self.name, scene.iter().map(|f| f.to_string()).collect());
        let cache = COMPOSED.get_or_init(Default::default);
        if let Some(c) = cache.lock().expect("composed kernels").get(&key) {
            return c.clone();
        }
        let kernel = d
            .kernel(self.name)
            .unwrap_or_else(|| panic!("no kernel {} in shaders/kernels.json", self.name));
        let composed = d
            .compose_with(kernel, scene)
            .unwrap_or_else(|e| panic!("kernel {}: {e}", self.name));
        let mut cache = cache.lock().expect("composed kernels");
        cache.insert(key, composed.clone());
        composed
    }

    /// Whether it computes in f64 (needs the adapter's SHADER_F64).
    pub fn is_f64(&self) -> bool {
        let declared = declaration().kernel(self.name);
        declared.is_some_and(|k| k.features.iter().any(|f| f == "F64"))
    }
}

/// The tracer in f32.
pub const TRACE_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("trace");
/// The tracer in f64: the same files, with F64.
pub const TRACE64_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("trace64");
/// The voxel sampler of `qjulia mesh` (f32).
pub const SAMPLE_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("sample");
/// The 2D Julia view in f32.
pub const JULIA2D_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("julia2d");
/// The 2D Julia view in f64.
pub const JULIA2D64_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("julia2d64");
/// The start-up check of f64.
pub const F64CHECK_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("f64check");
/// The path tracer in f32.
pub const PATH_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("path");
/// The path tracer in f64 (geometry in f64; material, light and radiance in f32).
pub const PATH64_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("path64");
/// The BSDF's and the light's test kernel.
pub const BSDF_PROBE_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("bsdf_probe");
/// The sampler's probe (test support).
pub const SOBOL_PROBE_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("sobol_probe");
/// The denoiser's pass (it works on f32 images in either precision).
pub const DENOISE_MODULE: ShaderModuleSource = ShaderModuleSource::kernel("denoise");

/// Every module the GPU path builds, in shaders/kernels.json's order (a test holds the two
/// alike); the tests validate each with naga.
pub const ALL_MODULES: &[ShaderModuleSource] = &[
    TRACE_MODULE,
    TRACE64_MODULE,
    JULIA2D_MODULE,
    JULIA2D64_MODULE,
    F64CHECK_MODULE,
    SAMPLE_MODULE,
    BSDF_PROBE_MODULE,
    PATH_MODULE,
    PATH64_MODULE,
    SOBOL_PROBE_MODULE,
    DENOISE_MODULE,
];

/// Parses and validates WGSL with naga (the version wgpu uses), as the GPU path would, with
/// every capability (f64 included).
pub fn validate_wgsl(source: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    Ok(module)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The declaration lists every kernel of [`ALL_MODULES`] in its order, every kernel
    /// composes, and every feature a file tests is declared.
    #[test]
    fn the_declaration_is_the_hosts() {
        let d = declaration();
        assert_eq!(d.format, 1);
        let names: Vec<&str> = d.kernels.iter().map(|k| k.name.as_str()).collect();
        let modules: Vec<&str> = ALL_MODULES.iter().map(|m| m.name).collect();
        assert_eq!(names, modules);
        for k in &d.kernels {
            d.compose(k).unwrap_or_else(|e| panic!("{}: {e}", k.name));
        }
        let tested = super::super::compose::features_tested(FILES.iter().map(|f| f.1));
        for f in tested {
            assert!(
                d.feature_names().contains(&f.as_str()),
                "{f} is not declared"
            );
        }
    }

    /// The f32 and f64 kernels differ exactly in their prelude.
    #[test]
    fn f64_takes_the_other_prelude() {
        let d = declaration();
        let trace = d.compose(d.kernel("trace").unwrap()).unwrap();
        let trace64 = d.compose(d.kernel("trace64").unwrap()).unwrap();
        let without = |files: &[String], prelude: &str| -> Vec<String> {
            files.iter().filter(|f| *f != prelude).cloned().collect()
        };
        assert_eq!(
            without(&trace.files, "real32"),
            without(&trace64.files, "real64")
        );
        assert!(trace.files.contains(&"real32".into()) && !trace.files.contains(&"real64".into()));
        assert!(TRACE64_MODULE.is_f64() && !TRACE_MODULE.is_f64());
    }
}
