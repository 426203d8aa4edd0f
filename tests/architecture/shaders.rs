//! Every WGSL file parses and validates with naga (wgpu's version), and the host's view of the
//! shader (the uniforms' layout tables, shared constants) matches the shader's own.

use std::mem::offset_of;

use qjulia::algebra::Real;
use qjulia::cpu::trace::{NORMAL_LIMIT, TINY};
use qjulia::gpu::shaders::{ALL_MODULES, ShaderModuleSource, TRACE_MODULE, validate_wgsl};
use qjulia::uniform::Layout;

use crate::common;
use crate::common::WgslMember;

#[test]
fn every_module_validates() {
    for module in ALL_MODULES {
        if let Err(e) = validate_wgsl(&module.source()) {
            panic!("shader module {} does not validate:\n{e}", module.name);
        }
    }
}

/// shaders/ holds exactly the files the binary composes from, and each is in some kernel, so that
/// naga validates it.
#[test]
fn every_wgsl_file_is_part_of_a_validated_module() {
    use qjulia::gpu::shaders::{FILES, declaration};
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    let mut on_disk: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let listed: Vec<&str> = FILES.iter().map(|f| f.0).collect();
    assert_eq!(
        on_disk, listed,
        "src/gpu/shaders.rs's FILES is shaders/, sorted"
    );
    let d = declaration();
    let composed: Vec<Vec<String>> = d
        .kernels
        .iter()
        .map(|k| d.compose(k).unwrap().files)
        .collect();
    for (name, text) in FILES {
        assert!(
            !text.contains('\r'),
            "shaders/{name}.wgsl has a carriage return"
        );
        assert!(
            composed.iter().any(|files| files.iter().any(|f| f == name)),
            "shaders/{name}.wgsl is in no kernel, so nothing validates it"
        );
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

/// A host layout table against naga's reflection of the WGSL struct: the same members in the
/// same order (names, offsets, sizes, types), the same size and alignment.
fn assert_layout_matches(module: &ShaderModuleSource, host: &Layout) {
    let ir = validate_wgsl(&module.source()).unwrap();
    let (shader, size, align) = common::wgsl_struct(&ir, host.name);
    let host_members: Vec<WgslMember> = host
        .fields
        .iter()
        .map(|f| WgslMember {
            name: f.name.to_string(),
            offset: f.offset,
            size: f.size,
            ty: f.ty.to_string(),
        })
        .collect();
    let context = format!(
        "{}: the host's table and WGSL {} disagree (keep them in sync)",
        module.name, host.name
    );
    common::assert_members_eq(&context, &shader, &host_members);
    assert_eq!((size, align), (host.size, host.align), "{}", module.name);
}

#[test]
fn uniform_layout_matches_the_shader() {
    use qjulia::gpu::shaders::TRACE64_MODULE;
    use qjulia::gpu::{GpuParams, GpuParams64};
    assert_layout_matches(&TRACE_MODULE, &GpuParams::LAYOUT);
    assert_layout_matches(&TRACE64_MODULE, &GpuParams64::LAYOUT);
    // The table is the bytemuck struct's: the struct is the table's size, and a field written
    // through the struct lands at the table's offset.
    for (layout, size) in [
        (GpuParams::LAYOUT, size_of::<GpuParams>()),
        (GpuParams64::LAYOUT, size_of::<GpuParams64>()),
    ] {
        assert_eq!(layout.size, size);
    }
    let gpu = GpuParams {
        cut: 7,
        sample_end: 9,
        ..Default::default()
    };
    for (name, value) in [("cut", 7u32), ("sample_end", 9)] {
        let at = GpuParams::LAYOUT.field(name).unwrap().offset;
        assert_eq!(gpu.bytes()[at..at + 4], value.to_le_bytes(), "{name}");
    }
}

/// The path tracer's own uniform: the host's table is naga's `PathParams`, in both precisions'
/// modules, and the bytemuck struct's offsets.
#[test]
fn path_uniform_layout_matches_the_shader() {
    use qjulia::gpu::path::GpuPathParams;
    use qjulia::gpu::shaders::{PATH_MODULE, PATH64_MODULE};
    assert_layout_matches(&PATH_MODULE, &GpuPathParams::LAYOUT);
    assert_layout_matches(&PATH64_MODULE, &GpuPathParams::LAYOUT);
    assert_eq!(GpuPathParams::LAYOUT.size, size_of::<GpuPathParams>());
    let offsets: Vec<(String, u32)> = GpuPathParams::LAYOUT
        .fields
        .iter()
        .map(|f| (f.name.to_string(), f.offset as u32))
        .collect();
    assert_eq!(
        offsets,
        host_offsets!(GpuPathParams: sky_zenith, sky_intensity, sky_horizon, bounces, sky_ground,
            roulette_start, sky_up, clamp_contribution, sun_direction, sun_one_minus_cos,
            sun_irradiance, sampler, light_intensity, strategy, roughness, metallic, specular,
            multiscatter, regularize, seed, step_scale, pad1, emission, pad2)
    );
}

/// The sampler's grid uniform (binding 7 of the sample module) is the host's GpuSampleGrid, and
/// the sampler's Params the tracer's.
#[test]
fn sample_grid_uniform_layout_matches_the_shader() {
    use qjulia::gpu::shaders::SAMPLE_MODULE;
    use qjulia::gpu::{GpuParams, GpuSampleGrid};
    let module = validate_wgsl(&SAMPLE_MODULE.source()).unwrap();
    let (shader, span) = shader_layout(&module, "SampleGrid");
    assert_eq!(
        shader,
        host_offsets!(GpuSampleGrid: origin, width, step, rows, row_offset, row_count)
    );
    assert_eq!(span, size_of::<GpuSampleGrid>());
    assert_layout_matches(&SAMPLE_MODULE, &GpuParams::LAYOUT);
    // Bound at 6, as SAMPLE_KERNEL says.
    let binding = module
        .global_variables
        .iter()
        .find(|(_, v)| v.name.as_deref() == Some("grid"))
        .and_then(|(_, v)| v.binding)
        .expect("the sampler's grid uniform");
    let second = qjulia::gpu::SAMPLE_KERNEL
        .second_uniform
        .expect("a second uniform");
    assert_eq!((binding.group, binding.binding), (0, second.binding));
    assert_eq!(second.bytes as usize, size_of::<GpuSampleGrid>());
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

/// `module` with its overrides set to `constants` for `entry` (naga's pipeline-constant pass,
/// which also drops what `entry` does not reach), validated; panics naming `what` otherwise.
fn specialise(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    constants: &naga::back::PipelineConstants,
    what: &str,
) -> naga::Module {
    let (specialised, _) = naga::back::pipeline_constants::process_overrides(
        module,
        info,
        Some((naga::ShaderStage::Compute, entry)),
        constants,
    )
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&specialised)
    .unwrap_or_else(|e| panic!("{what} does not validate: {e:?}"));
    specialised.into_owned()
}

/// `text` parsed and validated once, with the validation's info (what [`specialise`] takes);
/// panics naming `what` with naga's message otherwise.
fn parsed(text: &str, what: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(text)
        .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(text)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(text)));
    (module, info)
}

/// The constants `split_constants` leaves for a pipeline, as naga takes them.
fn pipeline_constants(left: &[(&str, f64)]) -> naga::back::PipelineConstants {
    left.iter().map(|&(n, v)| (n.to_string(), v)).collect()
}

/// Specialises `source` for each variant and `entry` (the f64 modules with and without the
/// start-up check's sqrt repair, alternating) and validates it: the text composed for the scene
/// features the variant leaves on ([`qjulia::gpu::shaders::split_constants`]), parsed once for
/// each set, and the other constants applied. Hands each specialised module to `check` with its
/// index.
fn validate_variants(
    source: &ShaderModuleSource,
    entry: &str,
    variants: &[qjulia::gpu::Variant],
    check: &mut dyn FnMut(usize, &naga::Module),
) {
    let mut texts: Vec<(Vec<&str>, naga::Module, naga::valid::ModuleInfo)> = Vec::new();
    for (k, variant) in variants.iter().enumerate() {
        let (scene, left) = qjulia::gpu::shaders::split_constants(&variant.constants());
        if !texts.iter().any(|p| p.0 == scene) {
            let what = format!("{} with {scene:?}", source.name);
            let (module, info) = parsed(&source.composed_with(&scene).text, &what);
            texts.push((scene.clone(), module, info));
        }
        let (_, module, info) = texts.iter().find(|p| p.0 == scene).unwrap();
        let mut constants = pipeline_constants(&left);
        if source.is_f64() {
            constants.insert("SQRT_NEWTON".to_string(), (k % 2) as f64);
        }
        let what = format!("{} {variant:?}", source.name);
        check(k, &specialise(module, info, entry, &constants, &what));
    }
}

/// Whether a variant of [`qjulia::gpu::Variant::all`] is in the set the tests validate: every
/// base variant (each of the 64 sets of the six base switches, with each normal and algebra)
/// with none and with all ten of the picture's features, and each picture feature alone on the
/// bases whose six switches are all off or all on. Every variant is a text of its own (its
/// features composed), so validating all 6,912 would parse 6,912 texts in each precision; this
/// set holds every feature on and off beside every other's both ways.
fn covering(v: &qjulia::gpu::Variant) -> bool {
    let picture = [
        v.samples,
        v.soft_shadows,
        v.occlusion,
        v.orbit_trap,
        v.cut,
        v.lens,
        v.adaptive,
        v.fog,
        v.glow,
        v.environment,
    ];
    let base = [
        v.shadows,
        v.standard_slice,
        v.over_relaxed,
        v.pixel_epsilon,
        v.shade,
        v.cone,
    ];
    let on = picture.iter().filter(|b| **b).count();
    on == 0 || on == picture.len() || base.iter().all(|b| *b) || base.iter().all(|b| !*b)
}

/// Every specialised variant of the tracer of the covering set ([`covering`]) validates in both
/// precisions; the f64 ones with and without the start-up check's sqrt repair (alternating).
#[test]
fn every_specialised_variant_validates() {
    use qjulia::gpu::Variant;
    use qjulia::gpu::shaders::TRACE64_MODULE;
    let all = Variant::all();
    // 576 base variants, each with none, each one and all ten of the picture's features.
    assert_eq!(all.len(), 576 * 12);
    let variants: Vec<Variant> = all.into_iter().filter(covering).collect();
    // 576 twice, and ten features alone on 18 bases.
    assert_eq!(variants.len(), 576 * 2 + 18 * 10);
    for source in [TRACE_MODULE, TRACE64_MODULE] {
        validate_variants(&source, "main", &variants, &mut |_, _| {});
    }
}

/// The AOV pipelines (the AOVS override on) validate: the tracer's and the path tracer's, in
/// both precisions, generic and specialised with none and all of the picture's features.
#[test]
fn the_aov_pipelines_validate() {
    use qjulia::gpu::Variant;
    use qjulia::gpu::shaders::{PATH_MODULE, PATH64_MODULE, TRACE64_MODULE};
    let base = Variant::all_base()[0];
    let all = *Variant::all()
        .iter()
        .find(|v| v.samples && v.lens && v.cut && v.adaptive)
        .unwrap();
    for (source, entry) in [
        (TRACE_MODULE, "main"),
        (TRACE64_MODULE, "main"),
        (PATH_MODULE, "path_main"),
        (PATH64_MODULE, "path_main"),
    ] {
        for variant in [None, Some(base), Some(all)] {
            let constants = variant.map(|v| v.constants()).unwrap_or_default();
            let (scene, left) = qjulia::gpu::shaders::split_constants(&constants);
            let what = format!("{} {variant:?} with AOVS", source.name);
            let (module, info) = parsed(&source.composed_with(&scene).text, &what);
            let mut constants = pipeline_constants(&left);
            constants.insert("AOVS".to_string(), 1.0);
            specialise(&module, &info, entry, &constants, &what);
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
    for (module, host, host_size) in [
        (
            JULIA2D_MODULE,
            GpuJulia2dParams::LAYOUT,
            size_of::<GpuJulia2dParams>(),
        ),
        (
            JULIA2D64_MODULE,
            GpuJulia2dParams64::LAYOUT,
            size_of::<GpuJulia2dParams64>(),
        ),
    ] {
        assert_layout_matches(&module, &host);
        assert_eq!(host.size, host_size, "{}", module.name);
        let module_ir = validate_wgsl(&module.source()).unwrap();
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

/// Every path variant (the tracer's variants as path mode has them) validates in both
/// precisions, and the path pipeline holds none of phong's shading: after specialisation and
/// compaction for `path_main`, the functions `phong`, `in_shadow`, `soft_shadow`, `occlusion`,
/// `trace_pixel` and `cone_start` are gone, as the path tracer's `trace_path` is from the
/// tracer's module, which never contains it.
#[test]
fn path_variants_validate_and_hold_no_phong_shading() {
    use qjulia::gpu::Variant;
    use qjulia::gpu::shaders::{PATH_MODULE, PATH64_MODULE};
    let mut variants: Vec<Variant> = Vec::new();
    for v in Variant::all().into_iter().filter(covering) {
        let path = Variant {
            shadows: false,
            cone: false,
            soft_shadows: false,
            occlusion: false,
            shade: true,
            ..v
        };
        if !variants.contains(&path) {
            variants.push(path);
        }
    }
    assert!(variants.len() >= 100, "{} path variants", variants.len());
    let phong_only = [
        "phong",
        "in_shadow",
        "soft_shadow",
        "occlusion",
        "trace_pixel",
        "cone_start",
    ];
    for source in [PATH_MODULE, PATH64_MODULE] {
        let module = validate_wgsl(&source.source()).unwrap();
        assert!(
            module
                .functions
                .iter()
                .any(|(_, f)| f.name.as_deref() == Some("phong")),
            "the module holds the tracer's shading before specialisation"
        );
        validate_variants(&source, "path_main", &variants, &mut |k, specialised| {
            if k == 0 {
                let names: Vec<&str> = specialised
                    .functions
                    .iter()
                    .filter_map(|(_, f)| f.name.as_deref())
                    .collect();
                assert!(names.contains(&"trace_path"), "{names:?}");
                for name in phong_only {
                    assert!(!names.contains(&name), "{}: {name} is left in", source.name);
                }
            }
        });
    }
}
