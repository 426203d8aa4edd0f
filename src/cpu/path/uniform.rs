//! The CPU twin of shaders/path_uniform.wgsl (same names, same order, generic over f32 and f64;
//! tests/architecture/twins.rs). The path tracer's uniform and what is read from it: `PathParams`
//! (binding 7, beside the tracer's Params) and the strategies, a sample's stream and its random
//! numbers (path_stream, path_random, seed_mask), the sky, the sun and the sphere light, and the
//! material at a point (regularized, path_material).

use crate::algebra::{Real, Vec3};
use crate::cpu::bsdf::Material;
use crate::cpu::light::{Sky, SphereLight, Sun, sun_one_minus_cos};
use crate::cpu::sobol::{sample_bits, to_unit};
use crate::params::{TraceParams, unit};
use crate::scene::Scene;

/// Which estimators light a hit (the MIS test's hook; scenes use both): the shader's
/// `path.strategy`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Strategy {
    #[default]
    Both = 0,
    Light = 1,
    Bsdf = 2,
}

/// The path tracer's own parameters (the shader's `PathParams`, a second uniform; keep in
/// sync with `GpuPathParams`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathParams<F> {
    pub sky: Sky<F>,
    pub sun: Sun<F>,
    /// The sphere light's colour times its intensity; its centre and radius are the tracer's
    /// `light` and `light_radius`.
    pub light_intensity: Vec3<F>,
    pub bounces: u32,
    pub roulette_start: u32,
    /// 0: off.
    pub clamp_contribution: F,
    /// `SAMPLER_SOBOL` or `SAMPLER_RANDOM` (src/cpu/sobol.rs).
    pub sampler: u32,
    pub strategy: Strategy,
    pub roughness: F,
    pub metallic: F,
    pub specular: F,
    /// `material.multiscatter`: Kulla and Conty's multiple-scattering lobe.
    pub multiscatter: bool,
    /// `path.regularize`: the GGX roughness floor after a diffuse scattering (0: off).
    pub regularize: F,
    /// The sampler's seed: `path.seed` (animate adds the frame with `path.animated_seed`).
    pub seed: u32,
    /// `path.step_scale`: the over-relaxation of shadow and bounce rays.
    pub step_scale: F,
    /// `material.emission`: the radiance the surface emits, times its albedo (0: none).
    pub emission: Vec3<F>,
}

/// Russian roulette starts at this scattering event (1-based: the paths of up to two events
/// are never cut short).
pub const ROULETTE_START: u32 = 3;

impl<F: Real> PathParams<F> {
    /// A scene's path parameters (`[sky]`, `[sun]`, `light.intensity`, `[path]`, `[material]`),
    /// precomputed in f64 and rounded to `F`; both lighting estimators (`Strategy::Both`).
    pub fn new(scene: &Scene) -> Self {
        let v = |c: [f64; 3]| Vec3::from_f64(c);
        let (sky, sun) = (&scene.sky, &scene.sun);
        Self {
            sky: Sky {
                zenith: v(sky.zenith),
                horizon: v(sky.horizon),
                ground: v(sky.ground),
                up: v(unit(sky.up)),
                intensity: F::lit(sky.intensity),
            },
            sun: Sun {
                direction: v(unit(sun.direction)),
                one_minus_cos: F::lit(sun_one_minus_cos(sun.angular_radius_degrees)),
                irradiance: v(sun.colour.map(|c| c * sun.intensity)),
            },
            light_intensity: Vec3::splat(F::lit(scene.light.intensity)),
            bounces: scene.path.bounces,
            roulette_start: ROULETTE_START,
            clamp_contribution: F::lit(scene.path.clamp),
            sampler: scene.path.sampler.code(),
            strategy: Strategy::Both,
            roughness: F::lit(scene.material.roughness),
            metallic: F::lit(scene.material.metallic),
            specular: F::lit(scene.material.specular),
            multiscatter: scene.material.multiscatter,
            regularize: F::lit(scene.path.regularize),
            seed: scene.path.seed,
            step_scale: F::lit(scene.path.step_scale),
            emission: v(scene.material.emission),
        }
    }
}

impl<F: Real> TraceParams<F> {
    /// A path sample's stream and its index in it, as (stream, index): wherever a pixel takes
    /// two samples or more, adaptively or not, sample k is sample k / 2 of stream k % 2
    /// ([`TraceParams::sample_stream`] when adaptive), so that the pixel's two halves
    /// ([`super::trace::Halves`]) are drawn independently and their disagreement is its error
    /// estimate; a single sample is stream 0's.
    pub fn path_stream(&self, k: u32) -> (u32, u32) {
        if self.samples > 1 {
            return (k & 1, k >> 1);
        }
        (0, k)
    }

    /// The number in [0, 1) of dimension `dim` of sample `sample` of pixel (i, j), from the
    /// scene's sampler (src/cpu/sobol.rs: the dimensions' order is stated there): the point of
    /// the sample's index in its stream ([`Self::path_stream`]), stream 1 drawn as if its
    /// pixel's number had bit 31 set (no pixel's has), so that its points are scrambled
    /// independently of stream 0's.
    pub fn path_random(&self, path: &PathParams<F>, i: u32, j: u32, sample: u32, dim: u32) -> F {
        let (stream, index) = self.path_stream(sample);
        let pixel = j.wrapping_mul(self.width).wrapping_add(i) | (stream << 31);
        let pixel = pixel ^ self.seed_mask(path);
        F::lit(to_unit(sample_bits(path.sampler, pixel, index, dim)) as f64)
    }

    /// What the seed does to a pixel's number in `path_random`: XORs in seed * 0x9e3779b9 (the
    /// golden ratio's 32 bits), so that seed 0 leaves every number as it was and each other seed
    /// draws independently scrambled points.
    pub fn seed_mask(&self, path: &PathParams<F>) -> u32 {
        path.seed.wrapping_mul(0x9e37_79b9)
    }

    pub fn path_sky(&self, path: &PathParams<F>) -> Sky<F> {
        path.sky
    }

    pub fn path_sun(&self, path: &PathParams<F>) -> Sun<F> {
        path.sun
    }

    pub fn path_sphere_light(&self, path: &PathParams<F>) -> SphereLight<F> {
        SphereLight {
            center: self.light,
            radius: self.light_radius,
            intensity: path.light_intensity,
        }
    }

    /// Path regularisation (Kaplanyan and Dachsbacher 2013; Cycles' "filter glossy"): the
    /// material of a vertex after the path has scattered by the cosine lobe (diffuse or multiple
    /// scattering), its GGX roughness held at `path.regularize` at least, so that a caustic path
    /// (diffuse, then glossy, then the sun) is a soft highlight and not a rare glint. A bias; 0
    /// (the default) is off: the material unchanged.
    pub fn regularized(&self, path: &PathParams<F>, m: Material<F>) -> Material<F> {
        Material {
            roughness: m.roughness.max(path.regularize),
            ..m
        }
    }

    /// The hit's material: the albedo is the hit's base colour (hit_albedo: the diffuse colour,
    /// or the orbit trap's palette colour).
    pub fn path_material(&self, path: &PathParams<F>, p: Vec3<F>) -> Material<F> {
        Material {
            albedo: self.hit_albedo(p),
            roughness: path.roughness,
            metallic: path.metallic,
            specular: path.specular,
            multiscatter: path.multiscatter,
        }
    }
}
