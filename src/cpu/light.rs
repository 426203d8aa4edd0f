//! The path tracer's light (sky, sun, sphere light), its sampling for next-event estimation and
//! the power heuristic: the twin of shaders/light.wgsl (same names, same order;
//! tests/twins.rs), generic over f32 and f64 where the shader is f32. The book's chapter
//! "Light" gives every formula.
//!
//! Units: a light's `intensity` is the irradiance it gives a surface facing it (the sun), or at
//! distance 1 (the sphere light, whose radiance is then intensity / (pi r^2)): a point light and
//! a sphere of the same intensity light the far field alike, and the radius only softens.

use super::bsdf::{basis_from_normal, pi, to_world};
use crate::algebra::{Real, Vec2, Vec3};

/// WGSL's `mix(a, b, t)`.
fn mix3<F: Real>(a: Vec3<F>, b: Vec3<F>, t: F) -> Vec3<F> {
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

/// The sun (keep in sync with `Sun`): toward the sun, the cosine of its angular radius, its
/// colour times its intensity (0: no sun).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun<F> {
    pub direction: Vec3<F>,
    pub cos_radius: F,
    pub irradiance: Vec3<F>,
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

/// The solid angle of a cone of half-angle acos(cos_max): 2 pi (1 - cos_max).
pub fn cone_solid_angle<F: Real>(cos_max: F) -> F {
    F::lit(2.0) * pi::<F>() * (F::one() - cos_max)
}

/// A direction uniform over the cone about `axis` (unit) with cos(theta) >= cos_max, from `u`
/// in [0, 1)^2: cos(theta) = 1 - u.x (1 - cos_max), phi = 2 pi u.y. Its density is 1 / solid
/// angle.
pub fn sample_cone<F: Real>(axis: Vec3<F>, cos_max: F, u: Vec2<F>) -> Vec3<F> {
    let c = F::one() - u.x * (F::one() - cos_max);
    let s = (F::one() - c * c).max(F::zero()).sqrt();
    let phi = F::lit(2.0) * pi::<F>() * u.y;
    let f = basis_from_normal(axis);
    to_world(f, Vec3::new(s * phi.cos(), s * phi.sin(), c))
}

/// The sun's radiance along `d` (unit): irradiance / solid angle inside its disc, 0 outside.
pub fn sun_radiance<F: Real>(sun: Sun<F>, d: Vec3<F>) -> Vec3<F> {
    if d.dot(sun.direction) < sun.cos_radius {
        return Vec3::zero();
    }
    sun.irradiance / cone_solid_angle(sun.cos_radius)
}

/// A direction toward the sun's disc, uniform over it.
pub fn sample_sun<F: Real>(sun: Sun<F>, u: Vec2<F>) -> LightSample<F> {
    let wi = sample_cone(sun.direction, sun.cos_radius, u);
    let omega = cone_solid_angle(sun.cos_radius);
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
    if d.dot(sun.direction) < sun.cos_radius {
        return F::zero();
    }
    F::one() / cone_solid_angle(sun.cos_radius)
}

/// The nearest t > 0 where origin + t d (d unit) meets the sphere, or -1.
pub fn intersect_sphere<F: Real>(origin: Vec3<F>, d: Vec3<F>, center: Vec3<F>, radius: F) -> F {
    let oc = origin - center;
    let b = oc.dot(d);
    let c = oc.dot(oc) - radius * radius;
    let disc = b * b - c;
    if disc < F::zero() {
        return -F::one();
    }
    let root = disc.sqrt();
    let t0 = -b - root;
    if t0 > F::zero() {
        return t0;
    }
    let t1 = -b + root;
    if t1 > F::zero() {
        return t1;
    }
    -F::one()
}

/// The cosine of the half-angle the sphere light subtends from `p` (1 when p is inside it,
/// where it cannot be sampled).
pub fn sphere_light_cos_max<F: Real>(light: SphereLight<F>, p: Vec3<F>) -> F {
    let d2 = (light.center - p).dot(light.center - p);
    let r2 = light.radius * light.radius;
    if d2 <= r2 {
        return F::one();
    }
    (F::one() - r2 / d2).max(F::zero()).sqrt()
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
    let cos_max = sphere_light_cos_max(light, p);
    if cos_max >= F::one() {
        return LightSample {
            wi: axis,
            radiance: Vec3::zero(),
            pdf: F::zero(),
            distance: F::zero(),
            delta: false,
        };
    }
    let wi = sample_cone(axis, cos_max, u);
    let mut t = intersect_sphere(p, wi, light.center, light.radius);
    if t < F::zero() {
        // A direction at the cone's rim by rounding: the tangent point's distance.
        t = (d * d - light.radius * light.radius).max(F::zero()).sqrt();
    }
    LightSample {
        wi,
        radiance: sphere_light_radiance(light),
        pdf: F::one() / cone_solid_angle(cos_max),
        distance: t,
        delta: false,
    }
}

/// The density with which [`sample_sphere_light`] draws `wi` from `p` (0 if wi misses the
/// light, or for a point light, which no direction hits).
pub fn sphere_light_pdf<F: Real>(light: SphereLight<F>, p: Vec3<F>, wi: Vec3<F>) -> F {
    if light.radius <= F::zero() {
        return F::zero();
    }
    let cos_max = sphere_light_cos_max(light, p);
    if cos_max >= F::one() || intersect_sphere(p, wi, light.center, light.radius) < F::zero() {
        return F::zero();
    }
    F::one() / cone_solid_angle(cos_max)
}

/// The power heuristic (Veach 1997, beta = 2): the weight of a sample drawn with density `a`
/// against another strategy's density `b`.
pub fn power_heuristic<F: Real>(a: F, b: F) -> F {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 <= F::zero() {
        return F::zero();
    }
    a2 / (a2 + b2)
}
