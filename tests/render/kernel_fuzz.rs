//! Numerical fuzz of the tracer kernel (issue 22): random scenes (c, the slice, the camera,
//! epsilon, iterations, radii, the algebra, every shading feature) traced on the GPU and by its
//! CPU twin in f32. The pipelines' variants are drawn from a small set (each new one costs about
//! half a second of compilation on lavapipe) and the uniforms randomised. For every case:
//! - no NaN or Inf anywhere but the depth's miss marker (NaN), on either backend;
//! - every primary ray within max_steps;
//! - where the scene is well-conditioned, the GPU's picture is the CPU twin's within
//!   CONTRACT_TOLERANCE. *Well-conditioned* here: f32 resolves it (no precision warning), and
//!   the CPU twin in f32 agrees with itself in f64 within CONTRACT_TOLERANCE, so that the
//!   picture does not turn on f32's rounding (where it does, no two f32 tracers need agree).
//!
//! 200 cases here; `QJULIA_FUZZ_CASES=10000` (and `QJULIA_FUZZ_SEED`) for the long run
//! (scripts/kernel-fuzz.sh).

use crate::common;

use qjulia::compare::{Agreement, CONTRACT_TOLERANCE};
use qjulia::scene::{Algebra, Scene};
use qjulia::{Frame, Precision, TraceParams, cpu};

/// A small deterministic generator (PCG-style LCG), so that a failing case can be replayed by
/// its seed and index.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[(self.unit() * items.len() as f64) as usize % items.len()]
    }
    fn unit_vector(&mut self, n: usize) -> Vec<f64> {
        loop {
            let v: Vec<f64> = (0..n).map(|_| self.range(-1.0, 1.0)).collect();
            let l = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if l > 0.1 {
                return v.iter().map(|x| x / l).collect();
            }
        }
    }
}

/// The variants the cases are drawn from: which shading features are on (the rest of the
/// scene is random uniforms).
#[derive(Clone, Copy, Debug)]
struct Features {
    shadows: bool,
    orbit_trap: bool,
    cut: bool,
    occlusion: bool,
    samples: u32,
    rotated_slice: bool,
}

const VARIANTS: [Features; 5] = [
    Features {
        shadows: true,
        orbit_trap: false,
        cut: false,
        occlusion: false,
        samples: 1,
        rotated_slice: false,
    },
    Features {
        shadows: false,
        orbit_trap: true,
        cut: false,
        occlusion: false,
        samples: 1,
        rotated_slice: true,
    },
    Features {
        shadows: true,
        orbit_trap: false,
        cut: true,
        occlusion: true,
        samples: 1,
        rotated_slice: false,
    },
    Features {
        shadows: true,
        orbit_trap: true,
        cut: false,
        occlusion: false,
        samples: 2,
        rotated_slice: true,
    },
    Features {
        shadows: false,
        orbit_trap: false,
        cut: true,
        occlusion: false,
        samples: 1,
        rotated_slice: true,
    },
];

/// A random scene of `size` pixels a side.
fn random_scene(rng: &mut Rng, size: u32) -> (Scene, Features) {
    let f = rng.pick(&VARIANTS);
    let mut s = Scene::default();
    s.image.width = size;
    s.image.height = size;
    s.image.samples = f.samples;
    let algebra = rng.pick(&[Algebra::Quaternion, Algebra::Quaternion, Algebra::Octonion]);
    s.set_algebra(algebra);
    let dim = algebra.dim();
    for (k, c) in s.fractal.c.iter_mut().enumerate() {
        *c = if k < 4 {
            rng.range(-1.0, 1.0)
        } else {
            rng.range(-0.2, 0.2)
        };
    }
    s.fractal.max_iterations = rng.range(4.0, 20.0) as u32;
    s.fractal.epsilon = 10f64.powf(rng.range(-3.5, -2.0));
    s.fractal.escape_radius_squared = rng.range(4.0, 16.0);
    s.fractal.bounding_radius_squared = rng.range(2.0, 4.0);
    if f.rotated_slice {
        let (a, b) = (rng.range(0.0, 6.3), rng.range(0.0, 6.3));
        let mut axes = s.slice.axes(dim);
        axes[0][0] = a.cos();
        axes[0][3] = a.sin();
        axes[1][1] = b.cos();
        axes[1][2] = b.sin();
        axes[2][1] = -b.sin();
        axes[2][2] = b.cos();
        [s.slice.x, s.slice.y, s.slice.z] = axes;
        s.slice.offset = (0..dim).map(|_| rng.range(-0.2, 0.2)).collect();
    }
    let dir = rng.unit_vector(3);
    let distance = rng.range(1.2, 4.0);
    s.camera.eye = [dir[0] * distance, dir[1] * distance, dir[2] * distance];
    s.camera.target = [
        rng.range(-0.2, 0.2),
        rng.range(-0.2, 0.2),
        rng.range(-0.2, 0.2),
    ];
    s.camera.up = [0.0, 1.0, 0.0];
    if dir[1].abs() > 0.95 {
        s.camera.up = [1.0, 0.0, 0.0];
    }
    s.camera.fov_y_degrees = rng.range(20.0, 70.0);
    s.light.position = [
        rng.range(-3.0, 3.0),
        rng.range(0.5, 3.0),
        rng.range(-3.0, 3.0),
    ];
    s.shading.shadows = f.shadows;
    s.shading.diffuse = [rng.unit(), rng.unit(), rng.unit()];
    s.shading.specular = rng.range(0.0, 0.8);
    s.shading.shininess = rng.range(2.0, 40.0);
    if f.orbit_trap {
        s.shading.colouring = qjulia::scene::Colouring::OrbitTrap;
        s.shading.trap_radius = rng.range(0.1, 1.0);
    }
    if f.occlusion {
        s.shading.occlusion = rng.range(0.2, 1.0);
        s.shading.ambient = rng.range(0.0, 0.3);
    }
    if f.cut {
        s.cut.enabled = true;
        let n = rng.unit_vector(3);
        s.cut.normal = [n[0], n[1], n[2]];
        s.cut.offset = rng.range(-0.3, 0.3);
    }
    (s, f)
}

/// No NaN or Inf but the depth's miss marker; every primary ray within max_steps.
fn assert_sane(what: &str, scene: &Scene, frame: &Frame) {
    assert!(
        frame.depth.iter().all(|d| d.is_nan() || d.is_finite()),
        "{what}: an infinite depth"
    );
    assert!(
        frame.colour.iter().all(|c| c >> 24 == 0xff),
        "{what}: a colour without its alpha"
    );
    let max = scene.fractal.max_steps;
    let worst = frame.steps.iter().copied().max().unwrap_or(0);
    assert!(
        worst <= max,
        "{what}: {worst} steps, more than max_steps {max}"
    );
}

#[test]
fn random_scenes_are_sane_and_agree_where_well_conditioned() {
    let Some(gpu) = common::gpu("kernel fuzz") else {
        return;
    };
    let cases: usize = std::env::var("QJULIA_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let seed: u64 = std::env::var("QJULIA_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(22);
    let mut rng = Rng(seed);
    let (mut compared, mut ill, mut unresolved) = (0, 0, 0);
    for case in 0..cases {
        let (scene, features) = random_scene(&mut rng, 24);
        let what = format!("case {case} of seed {seed} ({features:?})");
        // Every case is a scene the loader takes (the generator draws only valid ones).
        let mut loader = qjulia::scene::SceneLoader::new();
        loader
            .toml_str(&scene.to_toml(), qjulia::scene::SceneSource::Default)
            .and_then(|()| loader.build())
            .unwrap_or_else(|e| panic!("{what}: an invalid scene: {e}"));
        let (cpu32, _) = cpu::render(&TraceParams::<f32>::new(&scene));
        let gpu32 = common::gpu_frame(gpu, &scene);
        assert_sane(&format!("{what}, CPU"), &scene, &cpu32);
        assert_sane(&format!("{what}, GPU"), &scene, &gpu32);
        if !qjulia::precision::slice_warnings(&scene, Precision::F32).is_empty() {
            unresolved += 1;
            continue;
        }
        let (cpu64, _) = cpu::render(&TraceParams::<f64>::new(&scene));
        if !Agreement::measure(&cpu64, &cpu32, &CONTRACT_TOLERANCE).within(&CONTRACT_TOLERANCE) {
            ill += 1;
            continue;
        }
        compared += 1;
        let agreement = Agreement::measure(&cpu32, &gpu32, &CONTRACT_TOLERANCE);
        if !agreement.within(&CONTRACT_TOLERANCE) {
            common::assert_agree(
                &format!("kernel-fuzz-{seed}-{case}"),
                &cpu32,
                &gpu32,
                &CONTRACT_TOLERANCE,
            );
        }
    }
    eprintln!(
        "kernel fuzz, seed {seed}: {cases} cases sane on both backends; {compared} well-conditioned, \
         each GPU = CPU within CONTRACT_TOLERANCE; {ill} turned on f32's rounding (CPU f32 vs f64), \
         {unresolved} beyond f32"
    );
    assert!(
        compared * 2 >= cases,
        "only {compared} of {cases} cases compared"
    );
}
