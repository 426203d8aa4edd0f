//! The CPU twin of shaders/path_vertex.wgsl (same names, same order, generic over f32 and f64;
//! tests/architecture/twins.rs). A path vertex's light and its fate: the rays that ran out of steps
//! (exhausted), the shadow rays (unoccluded, visibility), the clamp, next-event estimation at a
//! surface or in the fog (light_term, add_light, direct_light), the fog's vertex (path_fog),
//! Russian roulette, and what a path gathers when it escapes or meets the sphere light (escaped,
//! light_emission).

use super::uniform::{PathParams, Strategy};
use crate::algebra::{Real, Vec3};
use crate::cpu::bsdf::{Basis, Material, bsdf_eval, bsdf_pdf, bsdf_specular, to_local};
use crate::cpu::environment::{environment_pdf, sample_environment};
use crate::cpu::light::{
    LightSample, power_heuristic, sample_sphere_light, sample_sun, sky_radiance, sphere_light_pdf,
    sphere_light_radiance, sun_pdf, sun_radiance,
};
use crate::cpu::medium::{fog_event, phase_hg};
use crate::cpu::sobol::{
    DIM_BOUNCE_BASE, DIM_ENVIRONMENT, DIM_FOG, DIM_ROULETTE, DIM_SPHERE_LIGHT, DIM_SUN,
    DIMS_PER_BOUNCE,
};
use crate::cpu::trace::Trace;
use crate::params::TraceParams;

thread_local! {
    /// Rays of the pixel this thread is sampling that ran out of `max_steps` (`exhausted`):
    /// camera, shadow and bounce rays, every sample (`--stats`' `exhausted_rays`); the shader's
    /// private `exhausted_rays`.
    pub(super) static EXHAUSTED_RAYS: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
}

/// Rays leave a hit from p + SURFACE_OFFSET epsilon n: the estimate is about half the true
/// distance near the surface, so there it is at least 2 epsilon, clear of the hit threshold.
pub const SURFACE_OFFSET: f64 = 4.0;

/// Where a ray's stretch through the fog ends and with what weight (`path_fog`): the
/// scattering event's point where there is one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathFog<F> {
    pub point: Vec3<F>,
    pub scattered: bool,
    pub weight: Vec3<F>,
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
    pub(super) fn none() -> Self {
        Self {
            total: Vec3::zero(),
            specular: Vec3::zero(),
        }
    }
}

pub(super) fn max3<F: Real>(c: Vec3<F>) -> F {
    c.x.max(c.y.max(c.z))
}

pub(super) fn any_positive<F: Real>(c: Vec3<F>) -> bool {
    c.x > F::zero() || c.y > F::zero() || c.z > F::zero()
}

impl<F: Real> TraceParams<F> {
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
}
