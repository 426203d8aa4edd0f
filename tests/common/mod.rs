//! Helpers shared by the integration tests: the GPU (shared, loud when missing), what a test
//! needs of its adapter (`adapter`), scenes from `--set` strings, and frame comparison that
//! writes diff images on failure.
#![allow(dead_code)]

mod adapter;

#[allow(unused_imports)]
pub use adapter::{Capability, gpu_has, has, own_process, say_skipped, skip_outside_ci, under_ci};

use std::path::PathBuf;
use std::sync::OnceLock;

use qjulia::algebra::Vec3;
use qjulia::compare::{Agreement, Tolerance, write_diff_images};
use qjulia::gpu::{GpuContext, GpuTracer};
use qjulia::scene::SceneLoader;
use qjulia::{Frame, Scene};

/// Set to 1 to run the suite without GPU tests (they then say so, one line each).
pub const SKIP_GPU_ENV: &str = "QJULIA_SKIP_GPU_TESTS";

/// Whether the GPU tests are opted out of (`QJULIA_SKIP_GPU_TESTS=1`); if so, says that `test`
/// skipped its GPU part (a `skipped:` line). Under CI (`QJULIA_CI=1`) they never are.
pub fn gpu_skipped(test: &str) -> bool {
    let skip = std::env::var(SKIP_GPU_ENV).is_ok_and(|v| v == "1");
    if skip {
        skip_outside_ci(test, "its GPU part", &format!("{SKIP_GPU_ENV}=1"));
    }
    skip
}

/// The shared GPU tracer. Panics with how to get an adapter when wgpu finds none, unless
/// `QJULIA_SKIP_GPU_TESTS=1`, in which case it returns None and the test says it skipped. On
/// GL the calling test holds the GPU alone until it ends (`adapter::one_test_at_a_time_on_gl`).
pub fn gpu(test: &str) -> Option<&'static GpuTracer> {
    if gpu_skipped(test) {
        return None;
    }
    static TRACER: OnceLock<Result<GpuTracer, String>> = OnceLock::new();
    let tracer = TRACER.get_or_init(|| {
        let tracer = GpuContext::new()
            .and_then(GpuTracer::new)
            .map_err(|e| e.to_string())?;
        eprintln!("GPU tests run on {}", tracer.context().adapter_label());
        Ok(tracer)
    });
    match tracer {
        Ok(t) => {
            adapter::one_test_at_a_time_on_gl(t.context());
            Some(t)
        }
        Err(e) => panic!(
            "{test} needs a GPU adapter and found none ({e}).\n\
             Install Mesa's software Vulkan driver: `sudo apt-get install mesa-vulkan-drivers`,\n\
             or opt out of the GPU tests explicitly with {SKIP_GPU_ENV}=1."
        ),
    }
}

/// The tests' GPU kernels (every kernel on the shared tracer's device), or None where GPU
/// tests are skipped.
pub fn kernels(test: &str) -> Option<std::sync::Arc<qjulia::gpu::GpuKernels>> {
    let tracer = gpu(test)?;
    static KERNELS: OnceLock<std::sync::Arc<qjulia::gpu::GpuKernels>> = OnceLock::new();
    Some(
        KERNELS
            .get_or_init(|| {
                std::sync::Arc::new(qjulia::gpu::GpuKernels::new(tracer.context().clone()))
            })
            .clone(),
    )
}

/// The GPU renderer in f32 for `scene` on `kernels`, as `--backend gpu --precision f32` plans
/// it.
pub fn gpu_renderer(
    kernels: &std::sync::Arc<qjulia::gpu::GpuKernels>,
    scene: &Scene,
) -> qjulia::Renderer {
    qjulia::Planner::on_device(
        kernels.clone(),
        qjulia::Backend::Gpu,
        qjulia::PrecisionChoice::F32,
    )
    .plan(scene, qjulia::Picture::SHADED.into(), &mut |_| {})
    .expect("a GPU plan")
    .renderer
}

/// The whole shaded picture of `scene` by `renderer`, with its AOVs (`Readback::Hdr`).
pub fn render_hdr(renderer: &qjulia::Renderer, scene: &Scene) -> Frame {
    let mut frame = Frame::empty(scene.image.width);
    renderer
        .render_with(
            scene,
            qjulia::Picture::SHADED,
            qjulia::Readback::Hdr,
            &mut |band| {
                frame.append(band);
                Ok(())
            },
        )
        .expect("a render");
    frame
}

/// The path-traced preset at `size` x `size` and `samples`, changed by `change`.
pub fn path_traced(size: u32, samples: u32, change: impl Fn(&mut Scene)) -> Scene {
    let mut scene = qjulia::scene::presets::find("path-traced")
        .expect("the path-traced preset")
        .scene();
    scene.image.width = size;
    scene.image.height = size;
    scene.image.samples = samples;
    change(&mut scene);
    scene
}

/// A validated scene: the defaults with these `--set KEY=VALUE` overrides.
pub fn scene(sets: &[&str]) -> Scene {
    let mut loader = SceneLoader::new();
    for s in sets {
        loader
            .set(s)
            .unwrap_or_else(|e| panic!("bad test scene: {e}"));
    }
    loader
        .build()
        .unwrap_or_else(|e| panic!("bad test scene: {e}"))
}

/// Where failed comparisons leave their pictures.
pub fn output_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("image-diffs")
}

/// Compares frames; on failure writes expected, actual and diff PNGs under target/ and panics
/// with the figures and the paths.
pub fn assert_agree(name: &str, expected: &Frame, actual: &Frame, tol: &Tolerance) -> Agreement {
    let agreement = Agreement::measure(expected, actual, tol);
    eprintln!("{name}: {agreement}");
    if !agreement.within(tol) {
        let paths = write_diff_images(&output_dir(), name, expected, actual)
            .map(|p| {
                p.iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            })
            .unwrap_or_else(|e| format!("(could not write diff images: {e})"));
        panic!("{name}: frames disagree beyond {tol:?}: {agreement}\nimages: {paths}");
    }
    agreement
}

/// Steps are integers computed by the same loop on both tracers: they agree on at least 98% of
/// pixels where the frames are within tolerance.
pub fn assert_steps_mostly_agree(name: &str, expected: &Frame, actual: &Frame) {
    let same_steps = expected
        .steps
        .iter()
        .zip(&actual.steps)
        .filter(|(a, b)| a == b)
        .count();
    let frac = same_steps as f64 / expected.pixel_count() as f64;
    assert!(
        frac >= 0.98,
        "{name}: steps agree on only {:.2}% of pixels",
        frac * 100.0
    );
}

/// The GPU tracer's frame of a scene (f32).
pub fn gpu_frame(gpu: &GpuTracer, scene: &Scene) -> Frame {
    gpu.render(&qjulia::TraceParams::<f32>::new(scene))
        .expect("GPU render")
        .frame
}

/// The shaded frame of `scene` as `render` makes it on the tests' GPU in f32 (through the
/// renderer: phong or path mode, the display transform), or None where GPU tests are skipped.
pub fn gpu_render_frame(test: &str, scene: &Scene) -> Option<Frame> {
    use qjulia::gpu::GpuKernels;
    use qjulia::{Backend, Picture, Planner, PrecisionChoice};
    use std::sync::Arc;
    let tracer = gpu(test)?;
    static KERNELS: OnceLock<Arc<GpuKernels>> = OnceLock::new();
    let kernels = KERNELS.get_or_init(|| Arc::new(GpuKernels::new(tracer.context().clone())));
    let plan = Planner::on_device(kernels.clone(), Backend::Gpu, PrecisionChoice::F32)
        .plan(scene, Picture::SHADED.into(), &mut |_| {})
        .expect("a GPU plan");
    Some(
        plan.renderer
            .render_frame(scene, Picture::SHADED)
            .expect("GPU render")
            .0,
    )
}

/// Runs the qjulia binary in `dir` with `args`.
pub fn qjulia(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    qjulia_env(dir, args, &[])
}

/// Runs the qjulia binary in `dir` with `args` and the environment variables `env` set.
pub fn qjulia_env(
    dir: &std::path::Path,
    args: &[&str],
    env: &[(&str, &str)],
) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(dir)
        .output()
        .expect("run qjulia")
}

/// A run's standard error as text.
pub fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The names of the files in `dir`, sorted.
pub fn files_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read the test folder")
        .map(|e| {
            let name = e.expect("a folder entry").file_name();
            name.to_string_lossy().into_owned()
        })
        .collect();
    names.sort();
    names
}

/// Runs qjulia in `dir` on bad input: it must exit 2 with one line on stderr that starts with
/// `prefix` and names `key`, and leave `dir` as it was (nothing written).
pub fn assert_refused(dir: &std::path::Path, args: &[&str], prefix: &str, key: &str) {
    let before = files_in(dir);
    let out = qjulia(dir, args);
    let stderr = stderr(&out);
    let context = args.join(" ");
    assert_eq!(out.status.code(), Some(2), "{context}: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{context}: {stderr}");
    assert!(
        lines[0].starts_with(prefix) && lines[0].contains(key),
        "{context}: {stderr}"
    );
    assert_eq!(files_in(dir), before, "{context} wrote a file");
}

/// The CPU renderer in `precision` for `scene`, as `--backend cpu --precision P` plans it.
pub fn cpu_renderer(scene: &Scene, precision: qjulia::Precision) -> qjulia::Renderer {
    let choice = match precision {
        qjulia::Precision::F32 => qjulia::PrecisionChoice::F32,
        qjulia::Precision::F64 => qjulia::PrecisionChoice::F64,
    };
    qjulia::Planner::new(qjulia::Backend::Cpu, choice)
        .plan(scene, qjulia::Picture::SHADED.into(), &mut |_| {})
        .expect("a CPU plan")
        .renderer
}

/// A member of a WGSL struct as naga lays it out: name, offset, size and type (written as
/// `f32`, `vec3<f64>`, `array<vec4<f32>, 4>`).
#[derive(Clone, Debug, PartialEq)]
pub struct WgslMember {
    pub name: String,
    pub offset: usize,
    pub size: usize,
    pub ty: String,
}

/// The members, size and alignment of struct `name` of `module`, by naga's reflection.
pub fn wgsl_struct(module: &naga::Module, name: &str) -> (Vec<WgslMember>, usize, usize) {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .expect("naga lays out the module");
    let (handle, members, span) = module
        .types
        .iter()
        .find_map(|(handle, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
                Some((handle, members, *span))
            }
            _ => None,
        })
        .unwrap_or_else(|| panic!("struct {name} in the module"));
    let members = members
        .iter()
        .map(|m| WgslMember {
            name: m.name.clone().unwrap_or_default(),
            offset: m.offset as usize,
            size: layouter[m.ty].size as usize,
            ty: wgsl_type(module, &module.types[m.ty].inner),
        })
        .collect();
    let align = layouter[handle].alignment.round_up(1) as usize;
    (members, span as usize, align)
}

/// A type as WGSL writes it (the scalars, vectors and fixed-size arrays of uniforms).
fn wgsl_type(module: &naga::Module, inner: &naga::TypeInner) -> String {
    let scalar = |s: &naga::Scalar| match (s.kind, s.width) {
        (naga::ScalarKind::Float, w) => format!("f{}", 8 * w),
        (naga::ScalarKind::Uint, w) => format!("u{}", 8 * w),
        (naga::ScalarKind::Sint, w) => format!("i{}", 8 * w),
        (naga::ScalarKind::Bool, _) => "bool".to_string(),
        (kind, w) => format!("{kind:?}{w}"),
    };
    match inner {
        naga::TypeInner::Scalar(s) => scalar(s),
        naga::TypeInner::Vector { size, scalar: s } => format!("vec{}<{}>", *size as u8, scalar(s)),
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            ..
        } => format!(
            "array<{}, {n}>",
            wgsl_type(module, &module.types[*base].inner)
        ),
        other => format!("{other:?}"),
    }
}

/// Two struct layouts agree member by member; a failure names the first member that differs.
pub fn assert_members_eq(context: &str, shader: &[WgslMember], host: &[WgslMember]) {
    if let Some(k) = (0..shader.len().max(host.len())).find(|&k| shader.get(k) != host.get(k)) {
        panic!(
            "{context}: member {k} differs: WGSL {:?}, host {:?}",
            shader.get(k),
            host.get(k)
        );
    }
}

/// A small deterministic generator for the tests' own random numbers (SplitMix64), independent
/// of the renderer's samplers.
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    pub fn vec2(&mut self) -> qjulia::algebra::Vec2<f64> {
        qjulia::algebra::Vec2::new(self.next(), self.next())
    }
}

/// Asserts that two files hold the same bytes. Where two PNGs differ, writes
/// `NAME-expected.png`, `NAME-actual.png` and `NAME-diff.png` (the largest channel difference
/// per pixel, times 16, in grey) under [`output_dir`] and names them in the panic.
pub fn assert_same_file(name: &str, expected: &std::path::Path, actual: &std::path::Path) {
    let (a, b) = (
        std::fs::read(expected).unwrap(),
        std::fs::read(actual).unwrap(),
    );
    if a == b {
        return;
    }
    let is_png = |p: &std::path::Path| p.extension().is_some_and(|e| e == "png");
    if !(is_png(expected) && is_png(actual)) {
        panic!(
            "{name}: {} and {} differ",
            expected.display(),
            actual.display()
        );
    }
    let ([w, h], e) = qjulia::output::read_png_rgb(expected).unwrap();
    let (size, x) = qjulia::output::read_png_rgb(actual).unwrap();
    let dir = output_dir();
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(expected, dir.join(format!("{name}-expected.png"))).unwrap();
    std::fs::copy(actual, dir.join(format!("{name}-actual.png"))).unwrap();
    let mut differ = 0;
    if size == [w, h] {
        let diff: Vec<u8> = e
            .chunks(3)
            .zip(x.chunks(3))
            .flat_map(|(p, q)| {
                let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
                differ += (d > 0) as usize;
                [d.saturating_mul(16); 3]
            })
            .collect();
        image::save_buffer(
            dir.join(format!("{name}-diff.png")),
            &diff,
            w,
            h,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
    }
    panic!(
        "{name}: the PNGs differ ({} and {}; {differ} pixels differ, sizes {:?} and {size:?}); \
         expected, actual and diff under {}",
        expected.display(),
        actual.display(),
        [w, h],
        dir.display()
    );
}

/// A direction from polar angles about +z.
pub fn dir(cos_theta: f64, phi: f64) -> Vec3<f64> {
    let s = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), cos_theta)
}

/// The integral of `f` over the sphere (or the upper hemisphere), midpoint rule in (cos theta,
/// phi), `n` x `2n` cells: exact for the measure, since d omega = d(cos theta) d phi.
pub fn integrate(n: usize, upper_only: bool, f: impl Fn(Vec3<f64>) -> f64) -> f64 {
    let (lo, hi) = if upper_only { (0.0, 1.0) } else { (-1.0, 1.0) };
    let dc = (hi - lo) / n as f64;
    let dphi = 2.0 * std::f64::consts::PI / (2 * n) as f64;
    let mut sum = 0.0;
    for a in 0..n {
        let c = lo + (a as f64 + 0.5) * dc;
        for b in 0..2 * n {
            sum += f(dir(c, (b as f64 + 0.5) * dphi));
        }
    }
    sum * dc * dphi
}

/// The directional albedo (red) of `m` from `wo` by importance sampling: the mean over `n`
/// samples of `bsdf_sample` of f cos / pdf (0 where a sample has no direction), and its
/// standard error.
pub fn sampled_albedo(
    m: qjulia::cpu::bsdf::Material<f64>,
    wo: Vec3<f64>,
    n: usize,
    rng: &mut SplitMix,
) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let s = qjulia::cpu::bsdf::bsdf_sample(m, wo, rng.next(), rng.vec2());
        let w = if s.pdf > 0.0 {
            (s.f.x * s.wi.z) / s.pdf
        } else {
            0.0
        };
        sum += w;
        sum2 += w * w;
    }
    let mean = sum / n as f64;
    (
        mean,
        ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}
