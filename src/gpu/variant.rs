//! Per-scene specialisation: the shader a scene runs holds only what it uses. A [`Variant`]
//! names the features a scene needs as constants ([`Variant::constants`]), which decide the
//! scene features of shaders/kernels.json the text is composed with
//! ([`super::shaders::split_constants`]), and the tracer builds and caches one pipeline per
//! variant.

use crate::algebra::Real;
use crate::params::TraceParams;
use crate::scene::{Algebra, NormalMethod};

/// Whether scenes get pipelines of their own variant: yes, unless `QJULIA_SPECIALISE=0`, which
/// runs every scene on the generic pipeline (to measure the gain).
pub fn specialise_from_env() -> bool {
    std::env::var_os("QJULIA_SPECIALISE").is_none_or(|v| v != "0")
}

/// Camera rays an invocation of the tracer (`main`) traces together (the kernels' `INTERLEAVE`
/// override) unless `QJULIA_INTERLEAVE` says otherwise: two, samples k and k + 1 of a pixel
/// fused step for step and orbit iteration for orbit iteration (on lavapipe the two chains of
/// dependent arithmetic overlap: docs/PERFORMANCE.md measures it). The pixels are the same bit
/// for bit with 1 or 2.
pub const DEFAULT_INTERLEAVE: u32 = 2;

/// As [`DEFAULT_INTERLEAVE`], for the path tracer (`path_main`): one, since on lavapipe pairing
/// a path's camera ray did not pay (docs/PERFORMANCE.md: the rest of the path dominates, and
/// with the lens the pair cost more than it saved).
pub const DEFAULT_PATH_INTERLEAVE: u32 = 1;

/// The `INTERLEAVE` of a pipeline: `QJULIA_INTERLEAVE=1` traces every camera ray alone, `2` in
/// pairs; unset (or anything else) the kernel's `default` ([`DEFAULT_INTERLEAVE`],
/// [`DEFAULT_PATH_INTERLEAVE`]). A device's choice, not a scene's: it is no part of a
/// [`Variant`], and the generic pipeline gets it too.
pub fn interleave_from_env(default: u32) -> u32 {
    match std::env::var("QJULIA_INTERLEAVE").as_deref() {
        Ok("1") => 1,
        Ok("2") => 2,
        _ => default,
    }
}

/// The override constant of an `interleave` of 1 or 2 (the kernels' `INTERLEAVE`).
pub fn interleave_constant(interleave: u32) -> (&'static str, f64) {
    assert!(
        interleave == 1 || interleave == 2,
        "interleave {interleave}: 1 or 2"
    );
    ("INTERLEAVE", interleave as f64)
}

/// Whether adaptive sampling's later dispatches pack each workgroup's live pixels into its
/// first invocations (the kernels' `COMPACT` override; shaders/trace.wgsl's `compacted_pixel`):
/// yes unless `QJULIA_COMPACT=0`, which leaves a done pixel's invocation to return at once
/// where it lies (the early-out alone). On lavapipe compaction paid (docs/PERFORMANCE.md). The
/// pixels are the same bit for bit either way; like the interleaving, a device's choice, in no
/// [`Variant`].
pub fn compact_from_env() -> bool {
    std::env::var_os("QJULIA_COMPACT").is_none_or(|v| v != "0")
}

/// The override constant of `compact` (the kernels' `COMPACT`).
pub fn compact_constant(compact: bool) -> (&'static str, f64) {
    ("COMPACT", if compact { 1.0 } else { 0.0 })
}

/// When a kernel's runs bake the scene's values into their pipeline
/// ([`super::kernel::BAKE_VALUES`]): a pipeline compiled for one scene's numbers, which the
/// driver folds (on lavapipe the seed's look at 512x512 in 0.076 s against 0.177 s with the
/// values read from storage; docs/PERFORMANCE.md), at the price of a pipeline built per set of
/// values. `QJULIA_BAKE=0` never, `1` always; unset, [`Bake::Auto`]. A device's choice, like
/// the interleaving: the explorer's live views never bake (their values change at each drag),
/// whatever this says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bake {
    Never,
    Always,
    /// A run bakes where it has at least [`BAKE_MIN_RAYS`] camera rays (pixels x samples; a
    /// mesh's grid points): there the time it saves pays for a pipeline of its own even in a
    /// process that renders many scenes (a report, an animation, the tests). A process that
    /// renders once builds one pipeline either way, baked or not, at the same cost.
    Auto,
}

/// Camera rays (pixels x samples) from which a run bakes by default: the break-even of a
/// baked pipeline's build (about 0.1 s for phong, 0.3 s for path mode on lavapipe) against what
/// it saves (0.37 us a phong ray, 0.85 us a path sample at the seed's scene): about 512x512
/// either way (docs/PERFORMANCE.md).
pub const BAKE_MIN_RAYS: u64 = 512 * 512;

/// [`Bake`] from `QJULIA_BAKE`.
pub fn bake_from_env() -> Bake {
    match std::env::var("QJULIA_BAKE").as_deref() {
        Ok("0") => Bake::Never,
        Ok("1") => Bake::Always,
        _ => Bake::Auto,
    }
}

impl Bake {
    /// Whether a run of `rays` camera rays (pixels x samples; a mesh's grid points) bakes.
    pub fn bakes(self, rays: u64) -> bool {
        match self {
            Bake::Never => false,
            Bake::Always => true,
            Bake::Auto => rays >= BAKE_MIN_RAYS,
        }
    }

    /// [`super::kernel::BAKE_VALUES`] where a run of `rays` camera rays bakes ([`Self::bakes`]),
    /// for its pipeline's constants.
    pub fn constant(self, rays: u64) -> Option<(&'static str, f64)> {
        self.bakes(rays).then_some(super::kernel::BAKE_VALUES)
    }
}

/// The camera rays of a render of `params`: pixels x samples, the whole image's (a tile of
/// it decides as the whole image does, so that the tiles merge into the same bytes).
pub fn camera_rays<F: Real>(params: &TraceParams<F>) -> u64 {
    params.width as u64 * params.height as u64 * params.samples.max(1) as u64
}

/// What one pipeline is built for. Keep in sync with the `override` constants of
/// shaders/trace.wgsl.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    pub shadows: bool,
    pub normal: NormalMethod,
    /// The slice is x, y, z = 1, i, j: no slice transform.
    pub standard_slice: bool,
    /// step_scale > 1.
    pub over_relaxed: bool,
    /// pixel_epsilon > 0.
    pub pixel_epsilon: bool,
    /// Colour is wanted (false: only depth and steps, no normal, light or shadow).
    pub shade: bool,
    /// fractal.tracing = "cone".
    pub cone: bool,
    /// fractal.algebra.
    pub algebra: Algebra,
    /// image.samples > 1.
    pub samples: bool,
    /// light.radius > 0 with shadows on.
    pub soft_shadows: bool,
    /// shading.occlusion > 0.
    pub occlusion: bool,
    /// shading.colouring = "orbit_trap".
    pub orbit_trap: bool,
    /// cut.enabled.
    pub cut: bool,
    /// The thin lens: camera.aperture > 0 (every sample through it, sample 0 too).
    pub lens: bool,
    /// Adaptive sampling: path.noise_target > 0 with image.samples > 1.
    pub adaptive: bool,
    /// fog.density > 0 (with colour wanted).
    pub fog: bool,
    /// Phong mode's halo: glow.strength > 0 (with colour wanted).
    pub glow: bool,
    /// An environment map (environment.file, loaded; with colour wanted).
    pub environment: bool,
}

impl Variant {
    /// The variant a scene needs; `shade` is false when only depth and steps are wanted.
    pub fn of<F: Real>(p: &TraceParams<F>, shade: bool) -> Self {
        let unit = |v: crate::algebra::Hyper<F>, k: usize| {
            let a: Vec<F> = v.iter().flat_map(|q| [q.x, q.y, q.z, q.w]).collect();
            (0..16).all(|i| a[i] == if i == k { F::one() } else { F::zero() })
        };
        Self {
            shadows: p.shadows,
            normal: p.normal_method,
            standard_slice: unit(p.slice_x, 0) && unit(p.slice_y, 1) && unit(p.slice_z, 2),
            over_relaxed: p.step_scale > F::one(),
            pixel_epsilon: p.pixel_epsilon > F::zero(),
            shade,
            cone: p.tracing == crate::scene::Tracing::Cone,
            algebra: match p.algebra_parts {
                1 => Algebra::Quaternion,
                2 => Algebra::Octonion,
                _ => Algebra::Sedenion,
            },
            samples: p.samples > 1,
            soft_shadows: p.shadows && p.light_radius > F::zero(),
            occlusion: shade && p.occlusion > F::zero(),
            orbit_trap: shade && p.colouring == crate::scene::Colouring::OrbitTrap,
            cut: p.cut,
            lens: p.aperture > F::zero(),
            adaptive: p.samples > 1 && p.noise_target > F::zero(),
            fog: shade && p.fog_density > F::zero(),
            glow: shade && p.glow_strength > F::zero(),
            environment: shade && p.env_map,
        }
    }

    /// The variant of the path kernel a scene needs: the geometry's features as
    /// [`Self::of`] has them, the albedo's colouring and the lens; the Phong shading's (the
    /// shadow rays, soft shadows, occlusion) and the cone's are off, as path mode has none of
    /// them, so scenes that differ only there share one pipeline.
    pub fn of_path<F: Real>(p: &TraceParams<F>) -> Self {
        let v = Self::of(p, true);
        Self {
            shadows: false,
            cone: false,
            soft_shadows: false,
            occlusion: false,
            orbit_trap: p.colouring == crate::scene::Colouring::OrbitTrap,
            glow: false,
            ..v
        }
    }

    /// The pipeline override constants for this variant.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        let b = |v: bool| if v { 1.0 } else { 0.0 };
        vec![
            ("SHADOWS", b(self.shadows)),
            ("NORMAL_METHOD", self.normal.code() as f64),
            ("STANDARD_SLICE", b(self.standard_slice)),
            ("OVER_RELAXED", b(self.over_relaxed)),
            ("PIXEL_EPSILON", b(self.pixel_epsilon)),
            ("SHADE", b(self.shade)),
            ("CONE_TRACING", b(self.cone)),
            ("ALGEBRA_PARTS", self.algebra.parts() as f64),
            ("SAMPLES", b(self.samples)),
            ("SOFT_SHADOWS", b(self.soft_shadows)),
            ("OCCLUSION", b(self.occlusion)),
            ("ORBIT_TRAP", b(self.orbit_trap)),
            ("CUT", b(self.cut)),
            ("LENS", b(self.lens)),
            ("ADAPTIVE", b(self.adaptive)),
            ("FOG", b(self.fog)),
            ("GLOW", b(self.glow)),
            ("ENVIRONMENT", b(self.environment)),
        ]
    }

    /// Every variant before the picture's features (all of those off).
    pub fn all_base() -> Vec<Variant> {
        let mut out = Vec::new();
        for (normal, algebra) in NormalMethod::ALL
            .into_iter()
            .flat_map(|n| Algebra::ALL.map(|a| (n, a)))
        {
            for bits in 0..64u32 {
                let bit = |k: u32| bits & (1 << k) != 0;
                out.push(Variant {
                    shadows: bit(0),
                    normal,
                    standard_slice: bit(1),
                    over_relaxed: bit(2),
                    pixel_epsilon: bit(3),
                    shade: bit(4),
                    cone: bit(5),
                    algebra,
                    samples: false,
                    soft_shadows: false,
                    occlusion: false,
                    orbit_trap: false,
                    cut: false,
                    lens: false,
                    adaptive: false,
                    fog: false,
                    glow: false,
                    environment: false,
                });
            }
        }
        out
    }

    /// The variants the tests validate: every base variant with none of the picture's
    /// features, with each one alone, and with all of them.
    pub fn all() -> Vec<Variant> {
        let features: [fn(&mut Variant); 10] = [
            |v| v.samples = true,
            |v| v.soft_shadows = true,
            |v| v.occlusion = true,
            |v| v.orbit_trap = true,
            |v| v.cut = true,
            |v| v.lens = true,
            |v| v.adaptive = true,
            |v| v.fog = true,
            |v| v.glow = true,
            |v| v.environment = true,
        ];
        let mut out = Vec::new();
        for base in Variant::all_base() {
            out.push(base);
            for f in features {
                let mut v = base;
                f(&mut v);
                out.push(v);
            }
            let mut all = base;
            features.iter().for_each(|f| f(&mut all));
            out.push(all);
        }
        out
    }
}
