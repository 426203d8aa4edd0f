//! The kernels a scene runs on the GPU, as `qjulia kernel` shows them and `--stats` names them:
//! each one's composed WGSL (what the host parses), its size and fingerprint, the override
//! constants the scene's variant sets, and what the host does to the module after the text.

use serde::Serialize;

use super::params_json::in_order;

use super::shaders::{
    DENOISE_MODULE, JULIA2D_MODULE, JULIA2D64_MODULE, PATH_MODULE, PATH64_MODULE,
    ShaderModuleSource, TRACE_MODULE, TRACE64_MODULE, declaration,
};
use super::variant::{self, Variant};
use crate::params::TraceParams;
use crate::picture::Picture;
use crate::precision::Precision;
use crate::scene::{Denoiser, Scene};

/// One kernel of a scene: what `qjulia kernel --json` prints for it.
#[derive(Clone, Debug, Serialize)]
pub struct SceneKernel {
    /// The kernel's name in shaders/kernels.json.
    pub name: &'static str,
    /// The entry point the host runs.
    pub entry: String,
    /// The features it is composed with: the kernel's own (`F64`), then the scene features the
    /// variant leaves on (every one without a variant) that its files test, in
    /// shaders/kernels.json's order.
    pub features: Vec<String>,
    /// The files composed into it, in the order they were appended.
    pub files: Vec<String>,
    /// The composed text's size in bytes and its 64-bit FNV-1a fingerprint (16 hex digits).
    pub bytes: usize,
    pub fingerprint: String,
    /// The override constants the scene's variant sets (none where `QJULIA_SPECIALISE=0`), in
    /// the numbers wgpu's `constants` map takes: those that are no scene feature.
    #[serde(serialize_with = "in_order")]
    pub overrides: Vec<(&'static str, f64)>,
    /// What the host does after the text, in order, one line each.
    pub after: Vec<String>,
    /// The composed WGSL.
    pub text: String,
}

/// The kernel that draws `picture` of `scene` in `precision`: the 2D view's, the path tracer's
/// or the tracer's.
pub fn picture_module(scene: &Scene, picture: Picture, precision: Precision) -> ShaderModuleSource {
    let f64 = precision == Precision::F64;
    match picture {
        Picture::Julia2d if f64 => JULIA2D64_MODULE,
        Picture::Julia2d => JULIA2D_MODULE,
        _ if picture.path_traced(scene) && f64 => PATH64_MODULE,
        _ if picture.path_traced(scene) => PATH_MODULE,
        _ if f64 => TRACE64_MODULE,
        _ => TRACE_MODULE,
    }
}

/// The kernels a render of `picture` of `scene` in `precision` runs: the picture's, then the
/// denoiser's where `image.denoise` asks for it.
pub fn scene_kernels(scene: &Scene, picture: Picture, precision: Precision) -> Vec<SceneKernel> {
    let mut kernels = vec![picture_kernel(scene, picture, precision)];
    if picture != Picture::Julia2d && scene.image.denoise == Denoiser::Atrous {
        kernels.push(describe(DENOISE_MODULE, Vec::new(), Vec::new()));
    }
    kernels
}

/// The kernel that draws `picture` of `scene` in `precision`, composed for the scene's variant.
fn picture_kernel(scene: &Scene, picture: Picture, precision: Precision) -> SceneKernel {
    let module = picture_module(scene, picture, precision);
    let specialised = variant::specialise_from_env();
    let tracer = picture != Picture::Julia2d;
    let overrides = match specialised && tracer {
        false => Vec::new(),
        true => {
            let p = TraceParams::<f64>::new(scene);
            match picture.path_traced(scene) {
                true => Variant::of_path(&p).constants(),
                false => Variant::of(&p, picture == Picture::SHADED).constants(),
            }
        }
    };
    let mut after = Vec::new();
    if tracer {
        after.push(
            "the host adds INTERLEAVE and COMPACT (the device's choices), AOVS = 1 where the \
             render reads the AOVs back, and BAKE_VALUES where it bakes the scene's numbers \
             (QJULIA_BAKE)"
                .to_string(),
        );
    }
    if precision == Precision::F64 {
        after.push("the f64 check's repairs, which the device chooses at start-up".into());
    }
    if specialised {
        after.push(
            "naga applies the constants and removes the branches they decide (and those that \
             a switch the text folds decides, such as fog_on() composed without FOG), and what \
             no entry point reaches (src/gpu/kernel/specialise.rs)"
                .into(),
        );
    }
    after.push(
        "where the driver mistreats uniforms, they become read-only storage \
         (QJULIA_UNIFORMS_AS_STORAGE)"
            .into(),
    );
    describe(module, overrides, after)
}

/// What `--stats` records of the kernel that draws `picture` of `scene` in `precision`: the
/// first of [`scene_kernels`].
pub fn kernel_stats(
    scene: &Scene,
    picture: Picture,
    precision: Precision,
) -> crate::stats::KernelStats {
    let kernel = picture_kernel(scene, picture, precision);
    crate::stats::KernelStats {
        name: kernel.name.to_string(),
        bytes: kernel.bytes,
        fingerprint: kernel.fingerprint,
    }
}

fn describe(
    module: ShaderModuleSource,
    overrides: Vec<(&'static str, f64)>,
    after: Vec<String>,
) -> SceneKernel {
    let declared = declaration()
        .kernel(module.name)
        .expect("every module is declared");
    let (scene, overrides) = super::shaders::split_constants(&overrides);
    let composed = module.composed_with(&scene);
    // The scene features its files test (none of the denoiser's, say).
    let texts = composed
        .files
        .iter()
        .filter_map(|f| super::shaders::file(f));
    let tested = super::compose::features_tested(texts);
    let scene: Vec<&str> = scene.into_iter().filter(|f| tested.contains(*f)).collect();
    let own = declared.features.iter().cloned();
    SceneKernel {
        name: module.name,
        entry: declared.entry.clone(),
        features: own.chain(scene.iter().map(|f| f.to_string())).collect(),
        files: composed.files,
        bytes: composed.text.len(),
        fingerprint: super::compose::fingerprint(composed.text.as_bytes()),
        overrides,
        after,
        text: composed.text,
    }
}

impl SceneKernel {
    /// The kernel as `qjulia kernel` prints it: a header of `//` lines (name, entry point, size,
    /// fingerprint, files, overrides, what follows), then the text.
    pub fn to_text(&self) -> String {
        let mut out = format!(
            "// qjulia kernel {} (entry point {}): {} bytes, fingerprint {}\n// features: {}\n\
             // files: {}\n",
            self.name,
            self.entry,
            self.bytes,
            self.fingerprint,
            match self.features.is_empty() {
                true => "none".to_string(),
                false => self.features.join(" "),
            },
            self.files.join(" ")
        );
        if !self.overrides.is_empty() {
            let pairs: Vec<String> = self
                .overrides
                .iter()
                .map(|(k, v)| format!("{k} = {v}"))
                .collect();
            out.push_str(&format!("// overrides: {}\n", pairs.join(", ")));
        }
        for line in &self.after {
            out.push_str(&format!("// then: {line}\n"));
        }
        out.push_str(&self.text);
        if !self.text.ends_with('\n') {
            out.push('\n');
        }
        out
    }
}
