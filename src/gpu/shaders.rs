//! The WGSL sources, compiled into the binary from shaders/ so that it stands alone.
//!
//! # One source, two precisions
//!
//! shaders/algebra.wgsl, trace.wgsl and julia2d.wgsl are written against a float type `Real`
//! (`vec3<Real>`, `Real(i)`, ...) and call the few functions whose f64 form needs care through
//! `real_sqrt`, `real_log`, `real_pow`, `real_cos` and `real_normalize`. They do not define
//! `Real`: a prelude in front of them does. The f32 modules put shaders/real32.wgsl first
//! (`alias Real = f32;`, the builtins themselves), the f64 modules shaders/real64.wgsl
//! (`alias Real = f64;`, those functions built from checked f64 operations). That choice of
//! prelude is the whole transform: no text of the kernels is rewritten, an f32 module is
//! exactly the kernel it was before f64 came, and the f64 one is a separate module with its own
//! pipelines, so f32 scenes pay nothing. What stays f32 in the f64 kernels is written `f32`
//! there: the packed colour, the samples' running mean, the 2D view's grey.

/// The f32 prelude: `Real` is f32.
pub const REAL32_WGSL: &str = include_str!("../../shaders/real32.wgsl");
/// The f64 prelude: `Real` is f64, with the functions f64 lacks on Vulkan.
pub const REAL64_WGSL: &str = include_str!("../../shaders/real64.wgsl");
/// Quaternion arithmetic (twin: src/algebra.rs); needs a prelude.
pub const ALGEBRA_WGSL: &str = include_str!("../../shaders/algebra.wgsl");
/// The tracer kernel (twin: src/cpu/trace.rs); needs a prelude and [`ALGEBRA_WGSL`] in front.
pub const TRACE_WGSL: &str = include_str!("../../shaders/trace.wgsl");
/// The environment map (twin: src/cpu/environment.rs): its lookup, irradiance and sampling;
/// f32, reads [`TRACE_WGSL`]'s `params` and overrides, which every module with it holds.
pub const ENVIRONMENT_WGSL: &str = include_str!("../../shaders/environment.wgsl");
/// The voxel sampler of `qjulia mesh` (twin: src/cpu/sample.rs); needs a prelude,
/// [`ALGEBRA_WGSL`] and [`TRACE_WGSL`] in front of it, whose estimate it runs.
pub const SAMPLE_WGSL: &str = include_str!("../../shaders/sample.wgsl");
/// The path tracer's BSDF (twin: src/cpu/bsdf.rs); f32 throughout, needs no prelude.
pub const BSDF_WGSL: &str = include_str!("../../shaders/bsdf.wgsl");
/// GGX's albedo tables for the material's multiple scattering (twin: src/cpu/ggx_albedo.rs);
/// f32, needs nothing in front of it; [`BSDF_WGSL`] reads it.
pub const GGX_ALBEDO_WGSL: &str = include_str!("../../shaders/ggx_albedo.wgsl");
/// The path tracer's light (twin: src/cpu/light.rs); f32, needs [`BSDF_WGSL`] in front (its
/// shading frame).
pub const LIGHT_WGSL: &str = include_str!("../../shaders/light.wgsl");
/// The fog's medium (twin: src/cpu/medium.rs): the phase function and free flight; f32, needs
/// [`BSDF_WGSL`] in front (its PI and shading frame).
pub const MEDIUM_WGSL: &str = include_str!("../../shaders/medium.wgsl");
/// The path tracer (twin: src/cpu/path.rs); needs a prelude, [`ALGEBRA_WGSL`], [`TRACE_WGSL`],
/// [`BSDF_WGSL`], [`LIGHT_WGSL`], [`MEDIUM_WGSL`] and [`SOBOL_WGSL`] in front.
pub const PATH_WGSL: &str = include_str!("../../shaders/path.wgsl");
/// A test kernel over [`BSDF_WGSL`] (src/gpu/bsdf_probe.rs).
pub const BSDF_PROBE_WGSL: &str = include_str!("../../shaders/bsdf_probe.wgsl");
/// The 2D Julia view's kernel (twin: src/cpu/julia2d.rs); needs a prelude.
pub const JULIA2D_WGSL: &str = include_str!("../../shaders/julia2d.wgsl");
/// The path tracer's sampler (twin: src/cpu/sobol.rs); integer only, needs nothing in front of
/// it, so that a kernel can put it before its own code.
pub const SOBOL_WGSL: &str = include_str!("../../shaders/sobol.wgsl");
/// The sampler's test-support kernel (src/gpu/sobol_probe.rs); needs [`SOBOL_WGSL`].
pub const SOBOL_PROBE_WGSL: &str = include_str!("../../shaders/sobol_probe.wgsl");
/// The denoiser's a-trous pass (twin: src/cpu/denoise.rs); needs nothing in front of it.
pub const DENOISE_WGSL: &str = include_str!("../../shaders/denoise.wgsl");
/// The start-up check of the adapter's f64 (src/gpu/f64check.rs); needs [`REAL64_WGSL`].
pub const F64CHECK_WGSL: &str = include_str!("../../shaders/f64check.wgsl");

/// One WGSL module the GPU runs: a name and its source files in order.
#[derive(Clone, Copy, Debug)]
pub struct ShaderModuleSource {
    pub name: &'static str,
    pub parts: &'static [&'static str],
}

impl ShaderModuleSource {
    /// The module's full source: its parts joined.
    pub fn source(&self) -> String {
        self.parts.join("\n")
    }

    /// Whether it computes in f64 (needs the adapter's SHADER_F64).
    pub fn is_f64(&self) -> bool {
        self.parts.first() == Some(&REAL64_WGSL)
    }
}

/// The tracer in f32: quaternion arithmetic, then the kernel.
pub const TRACE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "trace",
    parts: &[REAL32_WGSL, ALGEBRA_WGSL, TRACE_WGSL, ENVIRONMENT_WGSL],
};

/// The tracer in f64: the same files after the f64 prelude.
pub const TRACE64_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "trace64",
    parts: &[REAL64_WGSL, ALGEBRA_WGSL, TRACE_WGSL, ENVIRONMENT_WGSL],
};

/// The voxel sampler (f32): quaternion arithmetic, the tracer (its estimate), then the sampler.
pub const SAMPLE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "sample",
    parts: &[
        REAL32_WGSL,
        ALGEBRA_WGSL,
        TRACE_WGSL,
        ENVIRONMENT_WGSL,
        SAMPLE_WGSL,
    ],
};

/// The 2D Julia view in f32.
pub const JULIA2D_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "julia2d",
    parts: &[REAL32_WGSL, JULIA2D_WGSL],
};

/// The 2D Julia view in f64.
pub const JULIA2D64_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "julia2d64",
    parts: &[REAL64_WGSL, JULIA2D_WGSL],
};

/// The start-up check of f64.
pub const F64CHECK_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "f64check",
    parts: &[REAL64_WGSL, F64CHECK_WGSL],
};

/// The path tracer in f32: the tracer's module, the material, the light, the sampler, then the
/// path kernel.
pub const PATH_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "path",
    parts: &[
        REAL32_WGSL,
        ALGEBRA_WGSL,
        TRACE_WGSL,
        ENVIRONMENT_WGSL,
        BSDF_WGSL,
        GGX_ALBEDO_WGSL,
        LIGHT_WGSL,
        MEDIUM_WGSL,
        SOBOL_WGSL,
        PATH_WGSL,
    ],
};

/// The path tracer in f64 (geometry in f64; material, light and radiance in f32).
pub const PATH64_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "path64",
    parts: &[
        REAL64_WGSL,
        ALGEBRA_WGSL,
        TRACE_WGSL,
        ENVIRONMENT_WGSL,
        BSDF_WGSL,
        GGX_ALBEDO_WGSL,
        LIGHT_WGSL,
        MEDIUM_WGSL,
        SOBOL_WGSL,
        PATH_WGSL,
    ],
};

/// The BSDF's and the light's test kernel: the BSDF, the light, the sampler (its inputs), then
/// the probe.
pub const BSDF_PROBE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "bsdf_probe",
    parts: &[
        BSDF_WGSL,
        GGX_ALBEDO_WGSL,
        LIGHT_WGSL,
        SOBOL_WGSL,
        BSDF_PROBE_WGSL,
    ],
};

/// The sampler's probe (test support): the sampler alone, then the probe kernel.
pub const SOBOL_PROBE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "sobol_probe",
    parts: &[SOBOL_WGSL, SOBOL_PROBE_WGSL],
};

/// The denoiser: its pass alone (it works on f32 images in either precision).
pub const DENOISE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "denoise",
    parts: &[DENOISE_WGSL],
};

/// Every module the GPU path builds; the tests validate each with naga.
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
