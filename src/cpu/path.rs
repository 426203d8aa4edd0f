//! The path tracer (`shading.model = "path"`): the twin of shaders/path.wgsl, same names, same
//! order (tests/architecture/twins.rs), generic over f32 and f64 (the shader's material, light and radiance
//! are f32 in both of its precisions). The book's chapter "Path tracing" gives the estimator.
//!
//! Why it passes 600 lines: it mirrors shaders/path.wgsl function by function (Rust's
//! signatures and its generic float take more lines than WGSL's), and it ends with the row
//! driver the renderer calls (`render_path_rows`, 80 lines), which needs the module's private
//! helpers; a twin pair is split alike or not at all.

use super::bsdf::{
    Basis, Material, basis_from_normal, bsdf_eval, bsdf_pdf, bsdf_sample, bsdf_specular,
    specular_probability, to_local, to_world,
};
use super::environment::{environment_pdf, sample_environment};
use super::light::{
    LightSample, Sky, SphereLight, Sun, intersect_sphere, power_heuristic, sample_sphere_light,
    sample_sun, sky_radiance, sphere_light_pdf, sphere_light_radiance, sun_one_minus_cos, sun_pdf,
    sun_radiance,
};
use super::medium::{fog_event, phase_hg, sample_hg};
use super::sobol::{
    DIM_BOUNCE_BASE, DIM_BSDF, DIM_BSDF_CHOICE, DIM_ENVIRONMENT, DIM_FOG, DIM_LENS, DIM_PIXEL,
    DIM_ROULETTE, DIM_SPHERE_LIGHT, DIM_SUN, DIMS_PER_BOUNCE, sample_bits, to_unit,
};
use super::trace::{
    Aovs, Halves, Primary, Streams, Trace, add_aovs, add_to_halves, finish_aovs, halves_mean,
    streams_halves,
};
use crate::algebra::{Real, Vec3};
use crate::params::{TraceParams, unit};
use crate::scene::Scene;

thread_local! {
    /// Rays of the pixel this thread is sampling that ran out of `max_steps` (`exhausted`):
    /// camera, shadow and bounce rays, every sample (`--stats`' `exhausted_rays`); the shader's
    /// private `exhausted_rays`.
    static EXHAUSTED_RAYS: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
}

/// Path mode's counter word's layout, defined with the frame that reads it back.
pub use crate::frame::{COUNTER_DROPPED_BITS, COUNTER_DROPPED_MASK};

/// Which estimators light a hit (the MIS test's hook; scenes use both): the shader's
/// `path.strategy`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Strategy {
    #[default]
    Both = 0,
    Light = 1,
    Bsdf = 2,
}

/// Rays leave a hit from p + SURFACE_OFFSET epsilon n: the estimate is about half the true
/// distance near the surface, so there it is at least 2 epsilon, clear of the hit threshold.
pub const SURFACE_OFFSET: f64 = 4.0;

/// The least cosine between the shading normal and the direction back along the ray
/// ([`TraceParams::face_viewer`]).
pub const MIN_FACING: f64 = 1e-3;

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

/// Where a ray's stretch through the fog ends and with what weight (`path_fog`): the
/// scattering event's point where there is one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathFog<F> {
    pub point: Vec3<F>,
    pub scattered: bool,
    pub weight: Vec3<F>,
}

/// One sample of a pixel: its linear radiance, its primary ray's depth and steps and whether it
/// hit, and there the material's albedo and the shading normal (0 on a miss); the direct light
/// its first hit reflected by the specular lobes (the denoiser's specular signal:
/// [`TraceParams::trace_path_from`]), and there the cosine of the view direction to the
/// shading normal (0 on a miss or a first vertex in the fog).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathResult<F> {
    pub radiance: Vec3<F>,
    pub depth: F,
    pub steps: u32,
    pub hit: bool,
    pub albedo: Vec3<F>,
    pub normal: Vec3<F>,
    pub specular: Vec3<F>,
    pub cosine: F,
}

/// The light next-event estimation brings to a vertex ([`TraceParams::light_term`],
/// [`TraceParams::direct_light`]): all of it, and the part of it a surface's specular lobes
/// reflect ([`bsdf_specular`]; 0 in the fog).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light<F> {
    pub total: Vec3<F>,
    pub specular: Vec3<F>,
}

impl<F: Real> Light<F> {
    fn none() -> Self {
        Self {
            total: Vec3::zero(),
            specular: Vec3::zero(),
        }
    }
}

fn max3<F: Real>(c: Vec3<F>) -> F {
    c.x.max(c.y.max(c.z))
}

fn any_positive<F: Real>(c: Vec3<F>) -> bool {
    c.x > F::zero() || c.y > F::zero() || c.z > F::zero()
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

    /// Whether a trace that ended at or before `t_end` without a hit ran out of `max_steps`
    /// there (sphere_trace's miss by leaving always ends past `t_end`): a ray that ran out is
    /// neither a hit nor an escape, and counts as dark (a crevice is where rays run out).
    pub fn exhausted(&self, trace: Trace<F>, t_end: F) -> bool {
        !trace.hit && trace.t <= t_end
    }

    /// Whether nothing of the set lies between origin and origin + t_max dir: the shadow ray,
    /// the tracer's own sphere trace (no pixel epsilon) within the bounding ball. A shadow ray
    /// that runs out of steps ([`Self::exhausted`]) is occluded.
    pub fn unoccluded(
        &self,
        path: &PathParams<F>,
        origin: Vec3<F>,
        dir: Vec3<F>,
        t_max: F,
    ) -> bool {
        let bounds = self.intersect_bounds(origin, dir);
        let t_end = bounds.t_exit.min(t_max);
        if !bounds.hit || bounds.t_enter >= t_end {
            return true;
        }
        let trace = self.sphere_trace_by(
            origin,
            dir,
            bounds.t_enter,
            t_end,
            F::zero(),
            path.step_scale,
        );
        if self.exhausted(trace, t_end) {
            EXHAUSTED_RAYS.set(EXHAUSTED_RAYS.get() + 1);
            return false;
        }
        !trace.hit
    }

    /// What of the light at origin + t_max dir reaches origin: 0 where the set occludes it
    /// ([`Self::unoccluded`]), else the fog's transmittance over the stretch (1 without fog).
    /// The fog's shadow: light shafts where the set casts its shadow into the fog.
    pub fn visibility(&self, path: &PathParams<F>, origin: Vec3<F>, dir: Vec3<F>, t_max: F) -> F {
        if !self.unoccluded(path, origin, dir, t_max) {
            return F::zero();
        }
        F::lit(self.fog_transmittance(origin, dir, t_max) as f64)
    }

    /// A path's contribution, clamped where its light reached the camera through more than
    /// one scattering event: `vertex` is the index of the last scattering event (0 the first
    /// hit) of the path the light took, the same for the light that next-event estimation
    /// finds at vertex v and for the light that the ray leaving vertex v meets, so both halves
    /// of MIS are clamped alike. From vertex 1 on the contribution is scaled so that its
    /// largest channel is at most `clamp_contribution` (0: off); direct light at the first hit,
    /// and what a camera ray sees, are never clamped.
    pub fn clamp_indirect(&self, path: &PathParams<F>, c: Vec3<F>, vertex: u32) -> Vec3<F> {
        let m = max3(c);
        if vertex == 0 || path.clamp_contribution <= F::zero() || m <= path.clamp_contribution {
            return c;
        }
        c * (path.clamp_contribution / m)
    }

    /// One light's sample `ls` seen from a vertex: nothing where it has no density or lies below
    /// the surface; else its shadow ray from `origin` over `ls.distance` ([`Self::visibility`]:
    /// the set's occlusion and the fog's transmittance), and the light it brings, weighted
    /// against BSDF or phase sampling by the power heuristic (a point light, delta, is not). At a
    /// surface hit (`in_fog` false) the BSDF of m in the frame f, with wo, and the cosine; at a
    /// scattering event in the fog (`in_fog` true) the phase function ([`phase_hg`] of
    /// `fog.anisotropy`) of light that travelled along d, no cosine.
    pub fn light_term(
        &self,
        path: &PathParams<F>,
        ls: LightSample<F>,
        (in_fog, origin): (bool, Vec3<F>),
        (f, wo, m): (Basis<F>, Vec3<F>, Material<F>),
        d: Vec3<F>,
    ) -> Light<F> {
        let wi = to_local(f, ls.wi);
        if ls.pdf <= F::zero() || !(in_fog || wi.z > F::zero()) {
            return Light::none();
        }
        let v = self.visibility(path, origin, ls.wi, ls.distance);
        if v <= F::zero() {
            return Light::none();
        }
        let fog_light = |total| Light {
            total,
            specular: Vec3::zero(),
        };
        let weight = |other_pdf: F| match path.strategy {
            Strategy::Both => power_heuristic(ls.pdf, other_pdf),
            _ => F::one(),
        };
        if in_fog {
            let phase = phase_hg(self.fog_anisotropy, d.dot(ls.wi));
            if ls.delta {
                return fog_light(ls.radiance * (phase * v));
            }
            return fog_light(ls.radiance * (phase * weight(phase) / ls.pdf * v));
        }
        let f_wi = bsdf_eval(m, wo, wi).mul_elem(ls.radiance);
        let s_wi = bsdf_specular(m, wo, wi).mul_elem(ls.radiance);
        if ls.delta {
            return Light {
                total: f_wi * wi.z * v,
                specular: s_wi * wi.z * v,
            };
        }
        let scale = wi.z * weight(bsdf_pdf(m, wo, wi)) / ls.pdf;
        Light {
            total: f_wi * scale * v,
            specular: s_wi * scale * v,
        }
    }

    /// The sum of two lights.
    pub fn add_light(&self, a: Light<F>, b: Light<F>) -> Light<F> {
        Light {
            total: a.total + b.total,
            specular: a.specular + b.specular,
        }
    }

    /// Next-event estimation at a vertex: the sun, the environment map and the sphere light,
    /// each by one sample toward it ([`Self::light_term`]: a shadow ray, weighted against BSDF
    /// or phase sampling). At a surface hit (`in_fog` false) shadow rays leave from p +
    /// SURFACE_OFFSET epsilon n; at a scattering event in the fog (`in_fog` true) from p itself.
    /// One function, as in the kernel, which then holds one shadow trace per light.
    #[allow(clippy::too_many_arguments)]
    pub fn direct_light(
        &self,
        path: &PathParams<F>,
        (i, j, sample): (u32, u32, u32),
        bounce: u32,
        in_fog: bool,
        p: Vec3<F>,
        surface: (Basis<F>, Vec3<F>, Material<F>),
        d: Vec3<F>,
    ) -> Light<F> {
        let mut sum = Light::none();
        let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE;
        // Each light its own point (DIM_SUN, DIM_ENVIRONMENT, DIM_SPHERE_LIGHT).
        let point = |first: u32| {
            crate::algebra::Vec2::new(
                self.path_random(path, i, j, sample, dim + first),
                self.path_random(path, i, j, sample, dim + first + 1),
            )
        };
        let mut origin = p;
        if !in_fog {
            origin = p + surface.0.n * (F::lit(SURFACE_OFFSET) * self.epsilon);
        }
        let vertex = (in_fog, origin);
        if any_positive(path.sun.irradiance) {
            let ls = sample_sun(self.path_sun(path), point(DIM_SUN));
            sum = self.add_light(sum, self.light_term(path, ls, vertex, surface, d));
        }
        if self.environment_on() {
            // The sun's group's other two dimensions.
            let es = sample_environment(self, point(DIM_ENVIRONMENT));
            let ls = LightSample {
                wi: es.wi,
                radiance: es.radiance,
                pdf: es.pdf,
                distance: F::lit(3.4e38),
                delta: false,
            };
            sum = self.add_light(sum, self.light_term(path, ls, vertex, surface, d));
        }
        if any_positive(path.light_intensity) {
            let light = self.path_sphere_light(path);
            let ls = sample_sphere_light(light, p, point(DIM_SPHERE_LIGHT));
            sum = self.add_light(sum, self.light_term(path, ls, vertex, surface, d));
        }
        sum
    }

    /// Where a ray's stretch through the fog ends and with what weight: free flight
    /// ([`fog_event`]) over the part of origin + t dir, t up to `t_stop`, within the bounding
    /// ball, from the sampler's `DIM_FOG` of the bounce. `point` is the scattering event's,
    /// where there is one.
    pub fn path_fog(
        &self,
        path: &PathParams<F>,
        (i, j, sample): (u32, u32, u32),
        bounce: u32,
        (origin, dir): (Vec3<F>, Vec3<F>),
        t_stop: F,
    ) -> PathFog<F> {
        let bounds = self.intersect_bounds(origin, dir);
        let t_end = bounds.t_exit.min(t_stop);
        if !bounds.hit || t_end <= bounds.t_enter {
            return PathFog {
                point: origin,
                scattered: false,
                weight: Vec3::splat(F::one()),
            };
        }
        let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE + DIM_FOG;
        let u = self.path_random(path, i, j, sample, dim);
        let e = fog_event(self.fog_density, self.fog_colour, t_end - bounds.t_enter, u);
        PathFog {
            point: origin + dir * (bounds.t_enter + e.distance),
            scattered: e.scattered,
            weight: e.weight,
        }
    }

    /// Russian roulette after the scattering event `bounce`, from bounce `roulette_start` on:
    /// the path goes on with probability q, the throughput's largest channel (at most 0.95),
    /// and is then divided by it, so the mean is kept. Returns the divisor: q, 1 before
    /// `roulette_start`, 0 where the path ends.
    pub fn roulette(
        &self,
        path: &PathParams<F>,
        (i, j, sample): (u32, u32, u32),
        bounce: u32,
        throughput: Vec3<F>,
    ) -> F {
        if bounce + 1 < path.roulette_start {
            return F::one();
        }
        let q = max3(throughput).min(F::lit(0.95));
        let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE + DIM_ROULETTE;
        if self.path_random(path, i, j, sample, dim) >= q {
            return F::zero();
        }
        q
    }

    /// The radiance reaching a ray that leaves the bounding region: the sky (the environment
    /// map where the scene has one), and the sun's disc, the map and the sun weighted against
    /// their next-event estimation (`bsdf_pdf_prev` the density the ray was drawn with; a
    /// camera ray, drawn with no density, sees them whole).
    pub fn escaped(
        &self,
        path: &PathParams<F>,
        dir: Vec3<F>,
        bounce: u32,
        bsdf_pdf_prev: F,
    ) -> Vec3<F> {
        let mut c;
        if self.environment_on() {
            // The map, weighted against its own next-event estimation as the sun is.
            let mut w = F::one();
            if bounce > 0 {
                if path.strategy == Strategy::Light {
                    w = F::zero();
                } else if path.strategy == Strategy::Both {
                    w = power_heuristic(bsdf_pdf_prev, environment_pdf(self, dir));
                }
            }
            c = Vec3::from_f32(self.env_radiance(dir.to_f32())) * w;
        } else {
            c = sky_radiance(self.path_sky(path), dir);
        }
        if any_positive(path.sun.irradiance) {
            let mut w = F::one();
            if bounce > 0 {
                if path.strategy == Strategy::Light {
                    w = F::zero();
                } else if path.strategy == Strategy::Both {
                    w = power_heuristic(bsdf_pdf_prev, sun_pdf(self.path_sun(path), dir));
                }
            }
            c += sun_radiance(self.path_sun(path), dir) * w;
        }
        c
    }

    /// The emission of the sphere light seen along a ray from `origin`, weighted as
    /// [`Self::escaped`] weights the sun.
    pub fn light_emission(
        &self,
        path: &PathParams<F>,
        origin: Vec3<F>,
        dir: Vec3<F>,
        bounce: u32,
        bsdf_pdf_prev: F,
    ) -> Vec3<F> {
        let light = self.path_sphere_light(path);
        let mut w = F::one();
        if bounce > 0 {
            if path.strategy == Strategy::Light {
                w = F::zero();
            } else if path.strategy == Strategy::Both {
                w = power_heuristic(bsdf_pdf_prev, sphere_light_pdf(light, origin, dir));
            }
        }
        sphere_light_radiance(light) * w
    }

    /// The shading normal turned toward `v` (the direction back along the ray) where it faces
    /// away: at a sharp crease the estimated normal can, and the path would end black there.
    /// Bent within the plane of n and v until cos(n, v) >= [`MIN_FACING`] (unchanged
    /// everywhere else).
    pub fn face_viewer(&self, n: Vec3<F>, v: Vec3<F>) -> Vec3<F> {
        let c = n.dot(v);
        let min = F::lit(MIN_FACING);
        if c >= min {
            return n;
        }
        (n + v * (min - c)).normalize()
    }

    /// The camera ray of sample `sample` of pixel (i, j): sample 0 through the pixel's centre,
    /// the others at the sampler's image-plane dimensions, and where the aperture is open every
    /// sample (sample 0 too) through the lens at its lens dimensions; against the bounds (the
    /// whole stretch within the ball).
    pub fn path_camera_ray(&self, path: &PathParams<F>, i: u32, j: u32, sample: u32) -> Primary<F> {
        let half = F::lit(0.5);
        let mut s = (half, half);
        if sample > 0 {
            s = (
                self.path_random(path, i, j, sample, DIM_PIXEL),
                self.path_random(path, i, j, sample, DIM_PIXEL + 1),
            );
        }
        let x = F::lit(i as f64) + s.0;
        let y = F::lit(j as f64) + s.1;
        let mut dir = self.camera_ray_at(x, y);
        let mut origin = self.eye;
        // Through the thin lens (every sample where the aperture is open): the lens point from
        // the sampler's lens dimensions.
        if self.lens_open() {
            let uv = (
                self.path_random(path, i, j, sample, DIM_LENS).to_f64() as f32,
                self.path_random(path, i, j, sample, DIM_LENS + 1).to_f64() as f32,
            );
            let ray = self.thin_lens_ray(x, y, self.aperture_point(uv));
            origin = ray.origin;
            dir = ray.dir;
        }
        let bounds = self.intersect_bounds(origin, dir);
        Primary {
            origin,
            dir,
            t_start: bounds.t_enter,
            t_end: bounds.t_exit,
            hit: bounds.hit,
        }
    }

    /// One path through sample `sample` of pixel (i, j) from its camera ray `camera`
    /// (`path_camera_ray`) and that ray's trace `first` (`trace_primary`, or a pair's): WGSL's
    /// `trace_path`, which takes the camera ray and its trace (this file's `trace_path` takes
    /// the sample alone, as its callers want). At each of up to `bounces` hits add the direct light and scatter by the BSDF; a ray that leaves
    /// the region takes the sky and the sun, one that meets the sphere light first its
    /// emission. The last scattered ray is traced for that alone.
    pub fn trace_path_from(
        &self,
        path: &PathParams<F>,
        (i, j, sample): (u32, u32, u32),
        camera: &Primary<F>,
        first: Trace<F>,
    ) -> PathResult<F> {
        let mut dir = camera.dir;
        let mut origin = camera.origin;
        let mut throughput = Vec3::splat(F::one());
        let mut radiance = Vec3::zero();
        let mut result = PathResult {
            radiance: Vec3::zero(),
            depth: -F::one(),
            steps: 0,
            hit: false,
            albedo: Vec3::zero(),
            normal: Vec3::zero(),
            specular: Vec3::zero(),
            cosine: F::zero(),
        };
        let mut pdf_prev = F::zero();
        // The first hit's specular light (the denoiser's specular signal): the part of the
        // direct light there that its specular lobes reflect (`Light::specular`). The light
        // gathered after the first bounce stays with the diffuse signal (the kernel's comment
        // says why). A first vertex in the fog has none: its light is diffuse.
        let mut specular = Vec3::zero();
        // Whether the path has scattered by the cosine lobe (`regularized`), with
        // path.regularize on.
        let mut diffuse_before = false;
        let light_on = self.light_radius > F::zero() && any_positive(path.light_intensity);
        for bounce in 0..=path.bounces {
            // The camera ray's trace is given; a scattered ray's is made here (no pixel
            // epsilon).
            let mut trace = first;
            // A scattered ray that ran out of steps: it sees the sphere light only short of
            // where it stopped, and ends its path there, dark.
            let mut ran_out = false;
            if bounce > 0 {
                trace = Trace::untraced();
                let bounds = self.intersect_bounds(origin, dir);
                if bounds.hit {
                    let (t_enter, t_exit) = (bounds.t_enter, bounds.t_exit);
                    trace = self.sphere_trace_by(
                        origin,
                        dir,
                        t_enter,
                        t_exit,
                        F::zero(),
                        path.step_scale,
                    );
                    // Only scattered rays end so: a camera ray that runs out stays a miss, as
                    // in phong mode.
                    if self.exhausted(trace, t_exit) {
                        EXHAUSTED_RAYS.set(EXHAUSTED_RAYS.get() + 1);
                        ran_out = true;
                    }
                }
            } else if camera.hit && self.exhausted(trace, camera.t_end) {
                EXHAUSTED_RAYS.set(EXHAUSTED_RAYS.get() + 1);
            }
            // The light this ray meets left the path's last scattering event, bounce - 1
            // (none for the camera ray): clamp_indirect's vertex.
            let vertex = bounce.max(1) - 1;
            if bounce == 0 {
                result.depth = trace.t;
                result.steps = trace.steps;
                result.hit = trace.hit;
            }
            // Whether the ray meets the sphere light before the set (or before leaving), at
            // t_light.
            let mut t_light = -F::one();
            if light_on {
                let light = self.path_sphere_light(path);
                t_light = intersect_sphere(origin, dir, light.center, light.radius);
            }
            let left = !trace.hit && !ran_out;
            let meets_light = t_light > F::zero() && (left || t_light < trace.t);
            // In fog, the ray may scatter before its stretch ends (at the light, the set, where
            // it ran out, or where it leaves): a scattering event is the path's next vertex, lit
            // by next-event estimation and left by phase sampling, and counts as a bounce.
            let mut in_fog = false;
            let mut p = origin;
            if self.fog_on() {
                let mut t_stop = trace.t;
                if meets_light {
                    t_stop = t_light;
                } else if left {
                    t_stop = F::lit(3.0e38);
                }
                let fog = self.path_fog(path, (i, j, sample), bounce, (origin, dir), t_stop);
                throughput = throughput.mul_elem(fog.weight);
                if fog.scattered {
                    if bounce == path.bounces {
                        break;
                    }
                    in_fog = true;
                    p = fog.point;
                }
            }
            // A surface vertex's normal, frame, wo and material (unused in the fog).
            let mut n = Vec3::new(F::zero(), F::zero(), F::one());
            let mut f = Basis {
                t: Vec3::new(F::one(), F::zero(), F::zero()),
                b: Vec3::new(F::zero(), F::one(), F::zero()),
                n,
            };
            let mut wo = n;
            let mut m = Material {
                albedo: Vec3::zero(),
                roughness: F::one(),
                metallic: F::zero(),
                specular: F::zero(),
                multiscatter: false,
            };
            if !in_fog {
                if meets_light {
                    let e = self.light_emission(path, origin, dir, bounce, pdf_prev);
                    radiance += self.clamp_indirect(path, throughput.mul_elem(e), vertex);
                    break;
                }
                if ran_out {
                    break;
                }
                if !trace.hit {
                    let e = self.escaped(path, dir, bounce, pdf_prev);
                    radiance += self.clamp_indirect(path, throughput.mul_elem(e), vertex);
                    break;
                }
                p = origin + dir * trace.t;
                // material.emission: the set's own light, the hit's albedo times the emission
                // (found by the rays alone: no light sampling aims at it).
                if any_positive(path.emission) {
                    let e = path.emission.mul_elem(self.hit_albedo(p));
                    radiance += self.clamp_indirect(path, throughput.mul_elem(e), vertex);
                }
                if bounce == path.bounces {
                    break;
                }
                n = self.face_viewer(self.estimate_normal(p, dir), -dir);
                f = basis_from_normal(n);
                wo = to_local(f, -dir);
                m = self.path_material(path, p);
                if diffuse_before {
                    m = self.regularized(path, m);
                }
                if bounce == 0 {
                    result.albedo = m.albedo;
                    result.normal = n;
                    result.cosine = wo.z.max(F::zero());
                }
                if wo.z <= F::zero() {
                    break;
                }
            }
            if path.strategy != Strategy::Bsdf {
                let at = (i, j, sample);
                let light = self.direct_light(path, at, bounce, in_fog, p, (f, wo, m), dir);
                radiance += self.clamp_indirect(path, throughput.mul_elem(light.total), bounce);
                if bounce == 0 {
                    specular = throughput.mul_elem(light.specular);
                }
            }
            let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE;
            let u = crate::algebra::Vec2::new(
                self.path_random(path, i, j, sample, dim + DIM_BSDF),
                self.path_random(path, i, j, sample, dim + DIM_BSDF + 1),
            );
            if in_fog {
                let ps = sample_hg(self.fog_anisotropy, dir, u);
                // The phase sample's weight, phase / pdf, is 1.
                pdf_prev = ps.pdf;
                origin = p;
                dir = ps.wi.normalize();
            } else {
                let lobe = self.path_random(path, i, j, sample, dim + DIM_BSDF_CHOICE);
                let bs = bsdf_sample(m, wo, lobe, u);
                if bs.pdf <= F::zero() {
                    break;
                }
                if path.regularize > F::zero() && lobe >= specular_probability(m, wo) {
                    diffuse_before = true;
                }
                throughput = throughput.mul_elem(bs.f) * (bs.wi.z / bs.pdf);
                pdf_prev = bs.pdf;
                origin = p + n * (F::lit(SURFACE_OFFSET) * self.epsilon);
                dir = to_world(f, bs.wi).normalize();
            }
            let q = self.roulette(path, (i, j, sample), bounce, throughput);
            if q <= F::zero() {
                break;
            }
            throughput = throughput / q;
        }
        result.radiance = radiance;
        result.specular = specular;
        result
    }

    /// One path through sample `sample` of pixel (i, j), its camera ray traced alone
    /// (`trace_path_from` of `path_camera_ray` and `trace_primary`): WGSL's `trace_path` with
    /// its camera ray traced here.
    pub fn trace_path(&self, path: &PathParams<F>, i: u32, j: u32, sample: u32) -> PathResult<F> {
        let camera = self.path_camera_ray(path, i, j, sample);
        let first = self.trace_primary(&camera);
        self.trace_path_from(path, (i, j, sample), &camera, first)
    }
}

/// Whether a sample's radiance may enter the pixel's mean: every channel finite (neither NaN
/// nor infinite) and not negative.
pub fn sample_valid<F: Real>(c: Vec3<F>) -> bool {
    [c.x, c.y, c.z]
        .iter()
        .all(|v| v.is_finite() && *v >= F::zero())
}

/// Renders the rows `rows` (0 at the top) of the path-traced image, in parallel over rows, as
/// `path_main` does: each pixel's mean linear radiance over its `samples` paths (the running
/// mean the kernel keeps), sample 0's depth and steps, and with `aovs` the AOVs (`add_aovs`,
/// as the kernel's AOVS override adds them). A sample whose radiance is not valid
/// ([`sample_valid`]) is dropped, as `path_main` drops it. The colour holds the kernel's counter
/// word ([`COUNTER_DROPPED_BITS`]): the renderer takes it out and makes the colour from the
/// radiance by the display transform.
pub fn render_path_rows<F: Real>(
    params: &TraceParams<F>,
    path: &PathParams<F>,
    aovs: bool,
    rows: std::ops::Range<u32>,
) -> crate::frame::Frame {
    let keep = super::Keep {
        f64: super::is_f64::<F>(),
        radiance: true,
        aovs,
        samples: params.adaptive(),
    };
    super::fill_rows(params.width, rows, keep, |j| {
        move |i| {
            let before = (super::ESTIMATES.get(), super::ITERATIONS.get());
            EXHAUSTED_RAYS.set(0);
            // Where the lens is open, the depth and the steps are the pinhole ray's, traced for
            // them alone.
            let pinhole = params
                .lens_open()
                .then(|| params.trace_primary(&params.pinhole_ray(i, j, 0, F::zero())));
            let mut dropped = 0u32;
            // Without adaptive sampling, the pixel's halves (`add_to_halves`), in f32 as the
            // kernel keeps them.
            let mut halves = Halves::default();
            let mut first = None;
            let mut made = Aovs::default();
            // As `path_main` with INTERLEAVE 2: the camera rays of samples k and k + 1 traced as
            // a pair at k (`trace_primary_pair`), k + 1's trace kept for it; an odd one left
            // traced alone.
            let samples = params.samples.max(1);
            // Adaptive sampling's state, as `path_main` keeps it: the pixel's streams
            // (`add_to_streams`), and the samples taken.
            let (mut streams, mut taken) = (Streams::default(), samples);
            let mut second = None;
            for k in 0..samples {
                let camera = params.path_camera_ray(path, i, j, k);
                let traced = match second.take() {
                    Some(trace) => trace,
                    None if k + 1 < samples => {
                        let next = params.path_camera_ray(path, i, j, k + 1);
                        let [a, b] = params.trace_primary_pair(&camera, &next);
                        second = Some(b);
                        a
                    }
                    None => params.trace_primary(&camera),
                };
                let r = params.trace_path_from(path, (i, j, k), &camera, traced);
                first.get_or_insert(r);
                let valid = sample_valid(r.radiance);
                if !valid {
                    dropped += 1;
                }
                let add = |made: Aovs, n: u32| {
                    let (radiance, albedo) = (r.radiance.to_f32(), r.albedo.to_f32());
                    let (normal, depth) = (r.normal.to_f32(), r.depth.to_f64() as f32);
                    let first = (r.specular.to_f32(), r.cosine.to_f64() as f32);
                    add_aovs(made, n - 1, radiance, r.hit, albedo, normal, depth, first)
                };
                if params.adaptive() {
                    // The samples the pixel's colours hold, and whether this one joined them.
                    let before = streams.rule_a[3] + streams.b[3];
                    streams = params.add_to_streams(streams, k, valid, r.radiance.to_f32());
                    let n = streams.rule_a[3] + streams.b[3];
                    if aovs && n > before {
                        made = add(made, n as u32);
                    }
                    if params.sampling_done(&streams, k + 1) {
                        taken = k + 1;
                        break;
                    }
                } else if valid {
                    // The samples the halves hold, this one with them: the samples kept.
                    let n = k + 1 - dropped;
                    halves = add_to_halves(halves, k, r.radiance.to_f32());
                    if aovs {
                        made = add(made, n);
                    }
                }
            }
            if params.adaptive() {
                // Every pixel is done by its last sample (`sampling_done`).
                if aovs {
                    made = finish_aovs(made, &streams, taken);
                }
                halves = streams_halves(&streams);
            }
            let first = first.expect("at least one sample");
            let mean = halves_mean(&halves);
            let radiance = [mean.x, mean.y, mean.z];
            let (hit, depth, steps) = match pinhole {
                Some(t) => (t.hit, t.t, t.steps),
                None => (first.hit, first.depth, first.steps),
            };
            super::PixelOut {
                colour: dropped | (EXHAUSTED_RAYS.get() << COUNTER_DROPPED_BITS),
                depth: if hit { depth.to_f64() } else { f64::NAN },
                steps,
                non_finite: radiance.iter().filter(|c| !c.is_finite()).count() as u64,
                estimates: super::ESTIMATES.get() - before.0,
                iterations: super::ITERATIONS.get() - before.1,
                radiance,
                halves: [halves.a, halves.b].map(|m| crate::estimate::half_colour(&m)),
                aovs: made,
                samples: taken,
            }
        }
    })
}
