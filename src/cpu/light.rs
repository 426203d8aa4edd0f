//! The path tracer's light (sky, sun, sphere light), its sampling for next-event estimation and
//! the power heuristic: the twin of shaders/light.wgsl (same names, same order;
//! tests/architecture/twins.rs), generic over f32 and f64 where the shader is f32. The book's chapter
//! "Light" gives every formula.
//!
//! Units: a light's `intensity` is the irradiance it gives a surface facing it (the sun), or at
//! distance 1 (the sphere light, whose radiance is then intensity / (pi r^2)): a point light and
//! a sphere of the same intensity light the far field alike, and the radius only softens.

use super::bsdf::{basis_from_normal, pi, to_world};
use crate::algebra::{Real, Vec2, Vec3};

/// WGSL's `mix(a, b, t)`.
pub(crate) fn mix3<F: Real>(a: Vec3<F>, b: Vec3<F>, t: F) -> Vec3<F> {
    a * (F::one() - t) + b * t
}

/// The sky (keep in sync with `Sky` in shaders/light.wgsl): a gradient about `up`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sky<F> {
    pub zenith: Vec3<F>,
    pub horizon: Vec3<F>,
    pub ground: Vec3<F>,
    pub up: Vec3<F>,
    pub intensity: F,
}

/// The sun (keep in sync with `Sun`): toward the sun, 1 - the cosine of its angular radius,
/// its colour times its intensity (0: no sun).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun<F> {
    pub direction: Vec3<F>,
    /// 1 - the cosine of the angular radius, made in f64 (where cos(0.01 degrees) does not
    /// round to 1) and at least [`SUN_MIN_ONE_MINUS_COS`].
    pub one_minus_cos: F,
    pub irradiance: Vec3<F>,
}

/// The least 1 - cos(angular radius) a sun is given: a sun of under 8e-14 degrees is drawn as
/// one of that size, so that its solid angle (and the radiance and density divided by it) stays
/// a normal f32.
pub const SUN_MIN_ONE_MINUS_COS: f64 = 1e-30;

/// A sun's 1 - cos(angular radius) from its radius in degrees, in f64 as 2 sin^2(theta / 2)
/// (no cancellation), at least [`SUN_MIN_ONE_MINUS_COS`]. The host's, not the kernels': the
/// browser's host computes it the same way (web/src/uniform.ts).
pub fn sun_one_minus_cos(angular_radius_degrees: f64) -> f64 {
    let half = 0.5 * angular_radius_degrees.to_radians();
    (2.0 * half.sin() * half.sin()).max(SUN_MIN_ONE_MINUS_COS)
}

/// The sphere light (keep in sync with `SphereLight`): centre, radius (0: a point light) and
/// its colour times its intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereLight<F> {
    pub center: Vec3<F>,
    pub radius: F,
    pub intensity: Vec3<F>,
}

/// A direction toward a light with the radiance arriving along it, the density (per solid
/// angle) it was drawn with and the distance to the light (for the shadow ray). pdf 0: no
/// sample. A point light has no density: `delta` is true and `radiance` is the irradiance it
/// gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample<F> {
    pub wi: Vec3<F>,
    pub radiance: Vec3<F>,
    pub pdf: F,
    pub distance: F,
    pub delta: bool,
}

/// The sky's radiance along `d` (unit): with s = dot(d, up), mix(horizon, zenith, sqrt(s))
/// above the horizon and mix(horizon, ground, sqrt(-s)) below it, times the intensity.
pub fn sky_radiance<F: Real>(sky: Sky<F>, d: Vec3<F>) -> Vec3<F> {
    let s = d.dot(sky.up).max(-F::one()).min(F::one());
    let c = if s >= F::zero() {
        mix3(sky.horizon, sky.zenith, s.sqrt())
    } else {
        mix3(sky.horizon, sky.ground, (-s).sqrt())
    };
    c * sky.intensity
}

/// The solid angle of a cone of half-angle theta, from 1 - cos(theta): 2 pi (1 - cos(theta)).
pub fn cone_solid_angle<F: Real>(one_minus_cos: F) -> F {
    F::lit(2.0) * pi::<F>() * one_minus_cos
}

/// Whether the unit direction `d` lies in the cone about `axis` (unit) of half-angle theta,
/// given 1 - cos(theta): 1 - cos(d, axis) = |d - axis|^2 / 2 for unit vectors, a difference
/// that keeps its precision where the cosine itself rounds to 1.
pub fn in_cone<F: Real>(axis: Vec3<F>, one_minus_cos: F, d: Vec3<F>) -> bool {
    let e = d - axis;
    F::lit(0.5) * e.dot(e) <= one_minus_cos
}

/// A direction uniform over the cone about `axis` (unit) of half-angle theta, given
/// 1 - cos(theta), from `u` in [0, 1)^2: 1 - cos = u.x (1 - cos(theta)), sin = sqrt((1 - cos)
/// (1 + cos)), phi = 2 pi u.y, each formed without cancellation (pbrt-v4's small-angle care).
/// Its density is 1 / solid angle.
pub fn sample_cone<F: Real>(axis: Vec3<F>, one_minus_cos: F, u: Vec2<F>) -> Vec3<F> {
    let h = u.x * one_minus_cos;
    let c = F::one() - h;
    let s = (h * (F::lit(2.0) - h)).max(F::zero()).sqrt();
    let phi = F::lit(2.0) * pi::<F>() * u.y;
    let f = basis_from_normal(axis);
    to_world(f, Vec3::new(s * phi.cos(), s * phi.sin(), c))
}

/// The sun's radiance along `d` (unit): irradiance / solid angle inside its disc, 0 outside.
pub fn sun_radiance<F: Real>(sun: Sun<F>, d: Vec3<F>) -> Vec3<F> {
    if !in_cone(sun.direction, sun.one_minus_cos, d) {
        return Vec3::zero();
    }
    sun.irradiance / cone_solid_angle(sun.one_minus_cos)
}

/// A direction toward the sun's disc, uniform over it.
pub fn sample_sun<F: Real>(sun: Sun<F>, u: Vec2<F>) -> LightSample<F> {
    let wi = sample_cone(sun.direction, sun.one_minus_cos, u);
    let omega = cone_solid_angle(sun.one_minus_cos);
    LightSample {
        wi,
        radiance: sun.irradiance / omega,
        pdf: F::one() / omega,
        distance: F::lit(3.4e38),
        delta: false,
    }
}

/// The density with which [`sample_sun`] draws `d`: 1 / solid angle inside the disc, 0
/// outside.
pub fn sun_pdf<F: Real>(sun: Sun<F>, d: Vec3<F>) -> F {
    if !in_cone(sun.direction, sun.one_minus_cos, d) {
        return F::zero();
    }
    F::one() / cone_solid_angle(sun.one_minus_cos)
}

/// The nearest t > 0 where origin + t d (d unit) meets the sphere, or -1. The discriminant is
/// r^2 - |oc - b d|^2 (the squared distance from the centre to the line, not b^2 - c, which
/// cancels for a small or far sphere), and the nearer root comes from the farther one by
/// t0 t1 = c (Ray Tracing Gems, chapter 7).
pub fn intersect_sphere<F: Real>(origin: Vec3<F>, d: Vec3<F>, center: Vec3<F>, radius: F) -> F {
    let oc = origin - center;
    let b = oc.dot(d);
    let c = oc.dot(oc) - radius * radius;
    let foot = oc - d * b;
    let disc = radius * radius - foot.dot(foot);
    if disc < F::zero() {
        return -F::one();
    }
    let root = disc.sqrt();
    // q = -(b + sign(b) root): its two terms never cancel.
    let mut q = -b + root;
    if b > F::zero() {
        q = -b - root;
    }
    if q == F::zero() {
        return -F::one();
    }
    let t0 = q.min(c / q);
    let t1 = q.max(c / q);
    if t0 > F::zero() {
        return t0;
    }
    if t1 > F::zero() {
        return t1;
    }
    -F::one()
}

/// 1 - the cosine of the half-angle the sphere light subtends from `p`, in the stable form
/// (r^2 / d^2) / (1 + cos): sin^2 = r^2 / d^2 and 1 - cos = sin^2 / (1 + cos), which keeps its
/// precision where the cosine rounds to 1 (a small or far light). 0 when p is inside the
/// light, where it cannot be sampled.
pub fn sphere_light_one_minus_cos<F: Real>(light: SphereLight<F>, p: Vec3<F>) -> F {
    let d2 = (light.center - p).dot(light.center - p);
    let r2 = light.radius * light.radius;
    if d2 <= r2 {
        return F::zero();
    }
    let sin2 = r2 / d2;
    sin2 / (F::one() + (F::one() - sin2).max(F::zero()).sqrt())
}

/// The sphere light's radiance: intensity / (pi r^2), so that it gives `intensity` at
/// distance 1.
pub fn sphere_light_radiance<F: Real>(light: SphereLight<F>) -> Vec3<F> {
    light.intensity / (pi::<F>() * light.radius * light.radius)
}

/// A direction from `p` toward the sphere light: uniform over the cone it subtends (its
/// density 1 / solid angle), or for a point light (radius 0) the one direction, with the
/// irradiance intensity / d^2 and `delta`.
pub fn sample_sphere_light<F: Real>(
    light: SphereLight<F>,
    p: Vec3<F>,
    u: Vec2<F>,
) -> LightSample<F> {
    let to_center = light.center - p;
    let d = to_center.length();
    let axis = to_center / d;
    if light.radius <= F::zero() {
        return LightSample {
            wi: axis,
            radiance: light.intensity / (d * d),
            pdf: F::one(),
            distance: d,
            delta: true,
        };
    }
    let one_minus_cos = sphere_light_one_minus_cos(light, p);
    if one_minus_cos <= F::zero() {
        return LightSample {
            wi: axis,
            radiance: Vec3::zero(),
            pdf: F::zero(),
            distance: F::zero(),
            delta: false,
        };
    }
    let wi = sample_cone(axis, one_minus_cos, u);
    let mut t = intersect_sphere(p, wi, light.center, light.radius);
    if t < F::zero() {
        // A direction at the cone's rim by rounding: the tangent point's distance.
        t = (d * d - light.radius * light.radius).max(F::zero()).sqrt();
    }
    LightSample {
        wi,
        radiance: sphere_light_radiance(light),
        pdf: F::one() / cone_solid_angle(one_minus_cos),
        distance: t,
        delta: false,
    }
}

/// The density with which [`sample_sphere_light`] draws `wi` from `p`: 1 / solid angle inside
/// the cone the light subtends ([`in_cone`], the region [`sample_cone`] draws from), 0 outside
/// it, and 0 for a point light, which no direction hits.
pub fn sphere_light_pdf<F: Real>(light: SphereLight<F>, p: Vec3<F>, wi: Vec3<F>) -> F {
    if light.radius <= F::zero() {
        return F::zero();
    }
    let one_minus_cos = sphere_light_one_minus_cos(light, p);
    if one_minus_cos <= F::zero() || !in_cone((light.center - p).normalize(), one_minus_cos, wi) {
        return F::zero();
    }
    F::one() / cone_solid_angle(one_minus_cos)
}

/// The power heuristic (Veach 1997, beta = 2): the weight of a sample drawn with density `a`
/// against another strategy's density `b`, a^2 / (a^2 + b^2), formed as 1 / (1 + (b / a)^2) so
/// that the density of a tiny light (1e9 and more) cannot overflow its square.
pub fn power_heuristic<F: Real>(a: F, b: F) -> F {
    if a <= F::zero() {
        return F::zero();
    }
    let r = b / a;
    F::one() / (F::one() + r * r)
}
