//! Every WGSL file parses and validates with naga (wgpu's version), and the host's view of the
//! shader (uniform layout, shared constants) matches the shader's own.

use std::mem::offset_of;

use qjulia::algebra::Real;
use qjulia::cpu::trace::{NORMAL_LIMIT, TINY};
use qjulia::gpu::GpuParams;
use qjulia::gpu::shaders::{ALGEBRA_WGSL, ALL_MODULES, TRACE_MODULE, validate_wgsl};

#[test]
fn every_module_validates() {
    for module in ALL_MODULES {
        if let Err(e) = validate_wgsl(&module.source()) {
            panic!("shader module {} does not validate:\n{e}", module.name);
        }
    }
    // The library file stands alone too, after either prelude.
    use qjulia::gpu::shaders::{REAL32_WGSL, REAL64_WGSL};
    for prelude in [REAL32_WGSL, REAL64_WGSL] {
        validate_wgsl(&format!("{prelude}\n{ALGEBRA_WGSL}"))
            .expect("algebra.wgsl validates after a prelude");
    }
}

#[test]
fn every_wgsl_file_is_part_of_a_validated_module() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let text = std::fs::read_to_string(&path).unwrap();
            let used = ALL_MODULES.iter().any(|m| m.parts.contains(&text.as_str()));
            assert!(
                used,
                "{} is in no shader module, so nothing validates it",
                path.display()
            );
        }
    }
}

/// The members (name, offset) and size of a struct of a module, as naga lays it out.
fn shader_layout(module: &naga::Module, name: &str) -> (Vec<(String, u32)>, usize) {
    module
        .types
        .iter()
        .find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
                let members = members
                    .iter()
                    .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                    .collect();
                Some((members, *span as usize))
            }
            _ => None,
        })
        .unwrap_or_else(|| panic!("struct {name} in the module"))
}

/// The offsets of a host struct's fields, by name.
macro_rules! host_offsets {
    ($ty:ty: $($field:ident),* $(,)?) => {
        vec![$((stringify!($field).to_string(), offset_of!($ty, $field) as u32)),*]
    };
}

/// GpuParams's fields in WGSL's order (the padding at the end is the host's alone).
macro_rules! trace_fields {
    ($ty:ty) => {
        host_offsets!($ty: c, slice_x, slice_y, slice_z, slice_offset, eye, epsilon, cam_forward,
            tan_half_fov_y, cam_right, aspect, cam_up, escape_radius_squared, light,
            bounds_radius_squared, bounds_center, normal_tint, diffuse, specular, background,
            shininess, palette_phase, trap_scale, cut_normal, cut_offset, shadow_factor,
            normal_delta, step_scale, pixel_epsilon, pixel_angle, light_radius, ambient,
            occlusion, trap_radius, max_iterations, max_steps, width, height, shadows,
            row_offset, row_count, row_stride, out_row, normal_method, tracing, algebra_parts,
            samples, sample_start, sample_end, colouring, cut)
    };
}

#[test]
fn uniform_layout_matches_the_shader() {
    use qjulia::gpu::GpuParams64;
    use qjulia::gpu::shaders::TRACE64_MODULE;
    for (module, host, host_size) in [
        (
            TRACE_MODULE,
            trace_fields!(GpuParams),
            size_of::<GpuParams>(),
        ),
        (
            TRACE64_MODULE,
            trace_fields!(GpuParams64),
            size_of::<GpuParams64>(),
        ),
    ] {
        let (shader, span) = shader_layout(&validate_wgsl(&module.source()).unwrap(), "Params");
        assert_eq!(
            shader, host,
            "{}: the host's params and WGSL Params disagree: keep them in sync",
            module.name
        );
        assert_eq!(span, host_size, "{}", module.name);
    }
}

/// The f64 check's uniform too.
#[test]
fn f64_check_uniform_layout_matches_the_shader() {
    use qjulia::gpu::f64check::CheckParams;
    use qjulia::gpu::shaders::F64CHECK_MODULE;
    let module = validate_wgsl(&F64CHECK_MODULE.source()).unwrap();
    let (shader, span) = shader_layout(&module, "CheckParams");
    assert_eq!(shader, host_offsets!(CheckParams: cases, count));
    assert_eq!(span, size_of::<CheckParams>());
    // The kernel's operations are the host's, in order.
    let ops = qjulia::gpu::f64check::OPS;
    for (k, op) in ops.iter().enumerate() {
        let name = format!("OP_{}", op.to_uppercase());
        let (_, constant) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name.as_str()))
            .unwrap_or_else(|| panic!("const {name} in f64check.wgsl"));
        match module.global_expressions[constant.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => assert_eq!(v as usize, k, "{name}"),
            ref other => panic!("{name}: {other:?}"),
        }
    }
}

#[test]
fn shared_constants_match_the_cpu_twin() {
    let module = validate_wgsl(&TRACE_MODULE.source()).unwrap();
    let value = |name: &str| -> f64 {
        let (_, constant) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("const {name} in trace.wgsl"));
        match module.global_expressions[constant.init] {
            naga::Expression::Literal(naga::Literal::F32(v)) => v as f64,
            ref other => panic!("{name} is not an f32 literal: {other:?}"),
        }
    };
    let code = |name: &str| -> u32 {
        let (_, constant) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap();
        match module.global_expressions[constant.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref other => panic!("{name} is not a u32 literal: {other:?}"),
        }
    };
    use qjulia::scene::NormalMethod;
    assert_eq!(code("NORMAL_CENTRAL"), NormalMethod::Central.code());
    assert_eq!(code("NORMAL_TETRAHEDRAL"), NormalMethod::Tetrahedral.code());
    assert_eq!(code("NORMAL_ANALYTIC"), NormalMethod::Analytic.code());
    use qjulia::scene::Tracing;
    assert_eq!(code("TRACING_SEED"), Tracing::Seed.code());
    assert_eq!(code("TRACING_CONE"), Tracing::Cone.code());
    assert_eq!(code("CONE_BLOCK"), qjulia::cpu::trace::CONE_BLOCK);
    assert_eq!(
        code("OCCLUSION_SAMPLES"),
        qjulia::cpu::trace::OCCLUSION_SAMPLES
    );
    for (name, cpu) in [
        ("DERIVATIVE_LIMIT", <f32 as Real>::DERIVATIVE_LIMIT),
        ("TINY", TINY),
        ("NORMAL_LIMIT", NORMAL_LIMIT),
        ("MIN_NORMAL", f32::MIN_POSITIVE as f64),
        ("RELATIVE_EPSILON", <f32 as Real>::RELATIVE_EPSILON),
        ("OCCLUSION_STEP", qjulia::cpu::trace::OCCLUSION_STEP),
    ] {
        assert_eq!(
            value(name),
            cpu as f32 as f64,
            "{name} differs between WGSL and Rust"
        );
    }
}

/// Every specialised variant of the tracer validates in both precisions; the f64 ones with
/// and without the start-up check's sqrt repair (alternating).
#[test]
fn every_specialised_variant_validates() {
    use qjulia::gpu::Variant;
    use qjulia::gpu::shaders::TRACE64_MODULE;
    let variants = Variant::all();
    // 576 base variants, each with none, each one and all five of the picture's features.
    assert_eq!(variants.len(), 576 * 7);
    for source in [TRACE_MODULE, TRACE64_MODULE] {
        let module = validate_wgsl(&source.source()).unwrap();
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap();
        for (k, variant) in variants.iter().enumerate() {
            let mut constants = naga::back::PipelineConstants::default();
            for (name, value) in variant.constants() {
                constants.insert(name.to_string(), value);
            }
            if source.is_f64() {
                constants.insert("SQRT_NEWTON".to_string(), (k % 2) as f64);
            }
            let (specialised, _) = naga::back::pipeline_constants::process_overrides(
                &module,
                &info,
                Some((naga::ShaderStage::Compute, "main")),
                &constants,
            )
            .unwrap_or_else(|e| panic!("{} {variant:?}: {e}", source.name));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&specialised)
            .unwrap_or_else(|e| panic!("{} {variant:?} does not validate: {e:?}", source.name));
        }
    }
}

/// The f64 prelude's limits are the CPU twin's in f64.
#[test]
fn f64_constants_match_the_cpu_twin() {
    use qjulia::gpu::shaders::TRACE64_MODULE;
    let module = validate_wgsl(&TRACE64_MODULE.source()).unwrap();
    for (name, cpu) in [
        ("DERIVATIVE_LIMIT", <f64 as Real>::DERIVATIVE_LIMIT),
        ("TINY", TINY),
        ("NORMAL_LIMIT", NORMAL_LIMIT),
        ("MIN_NORMAL", f64::MIN_POSITIVE),
        ("RELATIVE_EPSILON", <f64 as Real>::RELATIVE_EPSILON),
        ("OCCLUSION_STEP", qjulia::cpu::trace::OCCLUSION_STEP),
    ] {
        let (_, constant) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("const {name} in the f64 module"));
        match module.global_expressions[constant.init] {
            naga::Expression::Literal(naga::Literal::F64(v)) => {
                assert_eq!(v, cpu, "{name} differs between WGSL and Rust")
            }
            ref other => panic!("{name} is not an f64 literal: {other:?}"),
        }
    }
}

#[test]
fn julia2d_uniform_layout_and_constants_match_the_host() {
    use qjulia::gpu::shaders::{JULIA2D_MODULE, JULIA2D64_MODULE};
    use qjulia::gpu::{GpuJulia2dParams, GpuJulia2dParams64};
    macro_rules! julia2d_fields {
        ($ty:ty) => {
            host_offsets!($ty: c, center, half_extent, max_iterations, width, height, row_offset,
                row_count, row_stride, out_row, pad)
        };
    }
    for (module, host, host_size) in [
        (
            JULIA2D_MODULE,
            julia2d_fields!(GpuJulia2dParams),
            size_of::<GpuJulia2dParams>(),
        ),
        (
            JULIA2D64_MODULE,
            julia2d_fields!(GpuJulia2dParams64),
            size_of::<GpuJulia2dParams64>(),
        ),
    ] {
        let module_ir = validate_wgsl(&module.source()).unwrap();
        let (shader, span) = shader_layout(&module_ir, "Julia2dParams");
        assert_eq!(
            shader, host,
            "{}: the host's params and WGSL Julia2dParams disagree: keep them in sync",
            module.name
        );
        assert_eq!(span, host_size, "{}", module.name);
        let (_, bailout) = module_ir
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some("BAILOUT_SQUARED"))
            .expect("const BAILOUT_SQUARED in julia2d.wgsl");
        let value = match module_ir.global_expressions[bailout.init] {
            naga::Expression::Literal(naga::Literal::F32(v)) => v as f64,
            naga::Expression::Literal(naga::Literal::F64(v)) => v,
            ref other => panic!("BAILOUT_SQUARED is not a float literal: {other:?}"),
        };
        assert_eq!(value, qjulia::cpu::julia2d::BAILOUT_SQUARED);
    }
}
