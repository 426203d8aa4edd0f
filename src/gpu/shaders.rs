//! The WGSL sources, compiled into the binary from shaders/ so that it stands alone.

/// Quaternion arithmetic (twin: src/algebra.rs).
pub const ALGEBRA_WGSL: &str = include_str!("../../shaders/algebra.wgsl");
/// The tracer kernel (twin: src/cpu/trace.rs); needs [`ALGEBRA_WGSL`] in front of it.
pub const TRACE_WGSL: &str = include_str!("../../shaders/trace.wgsl");
/// The voxel sampler of `qjulia mesh` (twin: src/cpu/sample.rs); needs [`ALGEBRA_WGSL`] and
/// [`TRACE_WGSL`] in front of it, whose estimate it runs.
pub const SAMPLE_WGSL: &str = include_str!("../../shaders/sample.wgsl");
/// The 2D Julia view's kernel (twin: src/cpu/julia2d.rs); stands alone.
pub const JULIA2D_WGSL: &str = include_str!("../../shaders/julia2d.wgsl");

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
}

/// The tracer: quaternion arithmetic, then the kernel.
pub const TRACE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "trace",
    parts: &[ALGEBRA_WGSL, TRACE_WGSL],
};

/// The voxel sampler: quaternion arithmetic, the tracer (its estimate), then the sampler.
pub const SAMPLE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "sample",
    parts: &[ALGEBRA_WGSL, TRACE_WGSL, SAMPLE_WGSL],
};

/// The 2D Julia view.
pub const JULIA2D_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "julia2d",
    parts: &[JULIA2D_WGSL],
};

/// Every module the GPU path builds; the tests validate each with naga.
pub const ALL_MODULES: &[ShaderModuleSource] = &[TRACE_MODULE, JULIA2D_MODULE, SAMPLE_MODULE];

/// Parses and validates WGSL with naga (the version wgpu uses), as the GPU path would.
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
