//! A scene's uniforms as data, for a host that packs them itself (the browser's):
//! `qjulia gpu-params --json` prints [`GpuParamsJson`]. The layout is the host's table
//! ([`crate::uniform::Layout`]), which the tests hold against naga's reflection of the WGSL.

use serde::{Serialize, Serializer};

use super::kernel::Band;
use super::path::GpuPathParams;
use super::{
    GpuJulia2dParams, GpuJulia2dParams64, GpuParams, GpuParams64, GpuReal, GpuTracer, Variant,
};
use crate::cpu::path::PathParams;
use crate::params::{Julia2dParams, TraceParams};
use crate::precision::Precision;
use crate::scene::Scene;
use crate::uniform::Layout;

/// What `qjulia gpu-params --json` prints for a scene: the tracer's uniform `Params` (its
/// layout and the bytes of the scene's first dispatch over the whole image as one band), its
/// pipeline's override constants, and the 2D view's uniform.
#[derive(Clone, Debug, Serialize)]
pub struct GpuParamsJson {
    /// The scene, resolved (defaults, preset, file and flags), as TOML with every key: what a
    /// host that loads the same scene itself must arrive at.
    pub scene: String,
    /// "f32" or "f64": the module (shaders/real32.wgsl or real64.wgsl in front) and the layout.
    pub precision: &'static str,
    /// WGSL `struct Params` of shaders/params.wgsl in this precision.
    pub layout: Layout,
    /// The uniform of the first dispatch, lowercase hex, two digits a byte in memory order
    /// (little-endian): row_offset 0, row_count = height, row_stride = width, out_row 0, the
    /// samples [0, samples_per_dispatch).
    pub bytes: String,
    /// Samples each dispatch adds; a render makes `dispatches` of them, the k-th with
    /// sample_start = k * samples_per_dispatch and sample_end = min(that + samples_per_dispatch,
    /// samples), the running mean kept in the `accumulated` output between them.
    pub samples_per_dispatch: u32,
    pub dispatches: u32,
    /// The pipeline's override constants for the shaded picture (path mode's: the path
    /// kernel's variant), in the numbers wgpu's
    /// `constants` map takes (f64; a bool is 1 or 0). An f64 pipeline also gets the repairs the
    /// device's f64 check asks for (`SQRT_NEWTON` and the like), which only the device knows.
    #[serde(serialize_with = "in_order")]
    pub overrides: Vec<(&'static str, f64)>,
    /// The 2D view's uniform (`struct Julia2dParams` of shaders/julia2d.wgsl, no override
    /// constants): its layout and bytes for the whole image as one band.
    pub julia2d: UniformJson,
    /// What this precision cannot resolve in the 3D slice (`precision::slice_warnings`): each
    /// warning's line, in order (the browser stops zooming where f32 stops resolving the view).
    pub warnings: Vec<String>,
    /// What this precision cannot resolve in the 2D view (`precision::julia2d_warnings`), each
    /// warning's line (the browser's 2D zoom stops there).
    pub julia2d_warnings: Vec<String>,
    /// The path tracer's own uniform (`struct PathParams` of shaders/path_uniform.wgsl, binding 7, f32
    /// in either precision): its layout and bytes, whatever the model (path mode reads it).
    pub path: UniformJson,
}

/// A uniform's layout and bytes.
#[derive(Clone, Debug, Serialize)]
pub struct UniformJson {
    pub layout: Layout,
    /// Lowercase hex, two digits a byte.
    pub bytes: String,
}

impl GpuParamsJson {
    /// The uniforms of `scene` in `precision`.
    pub fn new(scene: &Scene, precision: Precision) -> Self {
        match precision {
            Precision::F32 => Self::of::<f32>(scene, GpuParams::LAYOUT, GpuJulia2dParams::LAYOUT),
            Precision::F64 => {
                Self::of::<f64>(scene, GpuParams64::LAYOUT, GpuJulia2dParams64::LAYOUT)
            }
        }
    }

    fn of<F: GpuReal>(scene: &Scene, layout: Layout, julia2d: Layout) -> Self {
        let p = TraceParams::<F>::new(scene);
        let per_dispatch = GpuTracer::<F>::samples_per_dispatch_in(p.height, p.width, p.samples);
        let band = Band {
            row: 0,
            rows: p.height,
            dispatch: 0,
        };
        let j = Julia2dParams::<F>::new(scene);
        Self {
            scene: scene.to_toml(),
            precision: F::NAME,
            layout,
            bytes: hex(&F::trace_uniform(&p, band, (0, per_dispatch))),
            samples_per_dispatch: per_dispatch,
            dispatches: p.samples.max(1).div_ceil(per_dispatch),
            overrides: match crate::Picture::SHADED.path_traced(scene) {
                true => Variant::of_path(&p).constants(),
                false => Variant::of(&p, true).constants(),
            },
            julia2d: UniformJson {
                layout: julia2d,
                bytes: hex(&F::julia2d_uniform(&j, band)),
            },
            warnings: crate::precision::slice_warnings(scene, precision_of::<F>())
                .into_iter()
                .map(|w| w.text)
                .collect(),
            julia2d_warnings: crate::precision::julia2d_warnings(scene, precision_of::<F>())
                .into_iter()
                .map(|w| w.text)
                .collect(),
            path: UniformJson {
                layout: GpuPathParams::LAYOUT,
                bytes: hex(bytemuck::bytes_of(&GpuPathParams::new(
                    &PathParams::<F>::new(scene),
                ))),
            },
        }
    }

    /// Pretty-printed.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serialises")
    }
}

/// The precision of `F`.
fn precision_of<F: GpuReal>() -> Precision {
    Precision::of_name(F::NAME)
}

/// Bytes as lowercase hex.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Pairs as a JSON object, in their order.
pub(super) fn in_order<S: Serializer>(
    pairs: &[(&'static str, f64)],
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_map(pairs.iter().map(|(k, v)| (k, v)))
}
