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
    // The library file stands alone too.
    validate_wgsl(ALGEBRA_WGSL).expect("algebra.wgsl validates on its own");
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

#[test]
fn uniform_layout_matches_the_shader() {
    let module = validate_wgsl(&TRACE_MODULE.source()).unwrap();
    let (members, span) = module
        .types
        .iter()
        .find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some("Params") => {
                Some((members.clone(), *span))
            }
            _ => None,
        })
        .expect("struct Params in trace.wgsl");
    macro_rules! host_offsets {
        ($($field:ident),* $(,)?) => { vec![$((stringify!($field).to_string(), offset_of!(GpuParams, $field) as u32)),*] };
    }
    let host = host_offsets!(
        c,
        slice_x,
        slice_y,
        slice_z,
        slice_offset,
        eye,
        epsilon,
        cam_forward,
        tan_half_fov_y,
        cam_right,
        aspect,
        cam_up,
        escape_radius_squared,
        light,
        bounds_radius_squared,
        bounds_center,
        normal_tint,
        diffuse,
        specular,
        background,
        shininess,
        max_iterations,
        max_steps,
        width,
        height,
        shadows,
        shadow_factor,
        row_offset,
        row_count,
        row_stride,
        out_row,
        normal_method,
        normal_delta,
        step_scale,
        pixel_epsilon,
        pixel_angle,
        tracing,
        algebra_parts,
        samples,
        sample_start,
        sample_end,
        light_radius,
        ambient,
        occlusion,
        trap_radius,
        palette_phase,
        trap_scale,
        cut_normal,
        cut_offset,
        colouring,
        cut,
    );
    let shader: Vec<(String, u32)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
        .collect();
    assert_eq!(
        shader, host,
        "GpuParams and WGSL Params disagree: keep them in sync"
    );
    assert_eq!(span as usize, size_of::<GpuParams>());
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

#[test]
fn every_specialised_variant_validates() {
    use qjulia::gpu::Variant;
    let module = validate_wgsl(&TRACE_MODULE.source()).unwrap();
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap();
    let variants = Variant::all();
    // 576 base variants, each with none, each one and all five of the picture's features.
    assert_eq!(variants.len(), 576 * 7);
    for variant in variants {
        let mut constants = naga::back::PipelineConstants::default();
        for (name, value) in variant.constants() {
            constants.insert(name.to_string(), value);
        }
        let (specialised, _) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            Some((naga::ShaderStage::Compute, "main")),
            &constants,
        )
        .unwrap_or_else(|e| panic!("{variant:?}: {e}"));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&specialised)
        .unwrap_or_else(|e| panic!("{variant:?} does not validate: {e:?}"));
    }
}

#[test]
fn julia2d_uniform_layout_and_constants_match_the_host() {
    use qjulia::gpu::GpuJulia2dParams;
    use qjulia::gpu::shaders::JULIA2D_MODULE;
    let module = validate_wgsl(&JULIA2D_MODULE.source()).unwrap();
    let (members, span) = module
        .types
        .iter()
        .find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span }
                if ty.name.as_deref() == Some("Julia2dParams") =>
            {
                Some((members.clone(), *span))
            }
            _ => None,
        })
        .expect("struct Julia2dParams in julia2d.wgsl");
    macro_rules! host_offsets {
        ($($field:ident),* $(,)?) => { vec![$((stringify!($field).to_string(), offset_of!(GpuJulia2dParams, $field) as u32)),*] };
    }
    let host = host_offsets!(
        c,
        center,
        half_extent,
        max_iterations,
        width,
        height,
        row_offset,
        row_count,
        row_stride,
        out_row,
        pad,
    );
    let shader: Vec<(String, u32)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
        .collect();
    assert_eq!(
        shader, host,
        "GpuJulia2dParams and WGSL Julia2dParams disagree: keep them in sync"
    );
    assert_eq!(span as usize, size_of::<GpuJulia2dParams>());
    let (_, bailout) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some("BAILOUT_SQUARED"))
        .expect("const BAILOUT_SQUARED in julia2d.wgsl");
    match module.global_expressions[bailout.init] {
        naga::Expression::Literal(naga::Literal::F32(v)) => {
            assert_eq!(v as f64, qjulia::cpu::julia2d::BAILOUT_SQUARED)
        }
        ref other => panic!("BAILOUT_SQUARED is not an f32 literal: {other:?}"),
    }
}
