// The path tracer's light: the sky (rays that leave the bounding region), the sun (a disc of a
// given angular radius) and the sphere light, their sampling for next-event estimation, and
// the power heuristic that weighs light samples against BSDF samples.
// Twin: src/cpu/light.rs, same names, same order (tests/architecture/twins.rs). The book's chapter "Light"
// (docs/book/light.md) gives every formula. f32 throughout, as shaders/bsdf.wgsl, which it
// imports (its PI and its shading frame).
//
// Units: a light's `intensity` is the irradiance it gives a surface facing it (the sun), or at
// distance 1 (the sphere light, whose radiance is then intensity / (pi r^2)): a point light and a
// sphere of the same intensity light the far field alike, and the radius only softens.
#import bsdf

// The sky (keep in sync with `Sky` in src/cpu/light.rs): a gradient about `up`.
struct Sky {
    zenith: vec3<f32>,
    horizon: vec3<f32>,
    ground: vec3<f32>,
    up: vec3<f32>,
    intensity: f32,
}

// The sun (keep in sync with `Sun`): toward the sun, 1 - the cosine of its angular radius (made
// on the host in f64, where cos(0.01 degrees) does not round to 1), its colour times its
// intensity (0: no sun).
struct Sun {
    direction: vec3<f32>,
    one_minus_cos: f32,
    irradiance: vec3<f32>,
}

// The sphere light (keep in sync with `SphereLight`): centre, radius (0: a point light) and its
// colour times its intensity.
struct SphereLight {
    center: vec3<f32>,
    radius: f32,
    intensity: vec3<f32>,
}

// A direction toward a light with the radiance arriving along it, the density (per solid angle)
// it was drawn with and the distance to the light (for the shadow ray). pdf 0: no sample.
// A point light has no density: `delta` is true and `radiance` is the irradiance it gives.
struct LightSample {
    wi: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
    distance: f32,
    delta: bool,
}

// The sky's radiance along d (unit): with s = dot(d, up), mix(horizon, zenith, sqrt(s)) above the
// horizon and mix(horizon, ground, sqrt(-s)) below it, times the intensity.
fn sky_radiance(sky: Sky, d: vec3<f32>) -> vec3<f32> {
    let s = clamp(dot(d, sky.up), -1.0, 1.0);
    var c: vec3<f32>;
    if s >= 0.0 {
        c = mix(sky.horizon, sky.zenith, sqrt(s));
    } else {
        c = mix(sky.horizon, sky.ground, sqrt(-s));
    }
    return c * sky.intensity;
}

// The solid angle of a cone of half-angle theta, from 1 - cos(theta): 2 pi (1 - cos(theta)).
fn cone_solid_angle(one_minus_cos: f32) -> f32 {
    return 2.0 * PI * one_minus_cos;
}

// Whether the unit direction d lies in the cone about `axis` (unit) of half-angle theta, given
// 1 - cos(theta): 1 - cos(d, axis) = |d - axis|^2 / 2 for unit vectors, a difference that keeps
// its precision where the cosine itself rounds to 1.
fn in_cone(axis: vec3<f32>, one_minus_cos: f32, d: vec3<f32>) -> bool {
    let e = d - axis;
    return 0.5 * dot(e, e) <= one_minus_cos;
}

// A direction uniform over the cone about `axis` (unit) of half-angle theta, given 1 - cos(theta),
// from u in [0, 1)^2: 1 - cos = u.x (1 - cos(theta)), sin = sqrt((1 - cos) (1 + cos)), phi = 2 pi
// u.y, each formed without cancellation (pbrt-v4's small-angle care). Its density is 1 / solid
// angle.
fn sample_cone(axis: vec3<f32>, one_minus_cos: f32, u: vec2<f32>) -> vec3<f32> {
    let h = u.x * one_minus_cos;
    let c = 1.0 - h;
    let s = sqrt(max(h * (2.0 - h), 0.0));
    let phi = 2.0 * PI * u.y;
    let f = basis_from_normal(axis);
    return to_world(f, vec3<f32>(s * cos(phi), s * sin(phi), c));
}

// The sun's radiance along d (unit): irradiance / solid angle inside its disc, 0 outside.
fn sun_radiance(sun: Sun, d: vec3<f32>) -> vec3<f32> {
    if !in_cone(sun.direction, sun.one_minus_cos, d) {
        return vec3<f32>(0.0);
    }
    return sun.irradiance / cone_solid_angle(sun.one_minus_cos);
}

// A direction toward the sun's disc, uniform over it.
fn sample_sun(sun: Sun, u: vec2<f32>) -> LightSample {
    let wi = sample_cone(sun.direction, sun.one_minus_cos, u);
    let omega = cone_solid_angle(sun.one_minus_cos);
    return LightSample(wi, sun.irradiance / omega, 1.0 / omega, 3.4e38, false);
}

// The density with which sample_sun draws d: 1 / solid angle inside the disc, 0 outside.
fn sun_pdf(sun: Sun, d: vec3<f32>) -> f32 {
    if !in_cone(sun.direction, sun.one_minus_cos, d) {
        return 0.0;
    }
    return 1.0 / cone_solid_angle(sun.one_minus_cos);
}

// The nearest t > 0 where origin + t d (d unit) meets the sphere, or -1. The discriminant is
// r^2 - |oc - b d|^2 (the squared distance from the centre to the line, not b^2 - c, which
// cancels for a small or far sphere), and the nearer root comes from the farther one by
// t0 t1 = c (Ray Tracing Gems, chapter 7).
fn intersect_sphere(origin: vec3<f32>, d: vec3<f32>, center: vec3<f32>, radius: f32) -> f32 {
    let oc = origin - center;
    let b = dot(oc, d);
    let c = dot(oc, oc) - radius * radius;
    let foot = oc - b * d;
    let disc = radius * radius - dot(foot, foot);
    if disc < 0.0 {
        return -1.0;
    }
    let root = sqrt(disc);
    // q = -(b + sign(b) root): its two terms never cancel.
    var q = -b + root;
    if b > 0.0 {
        q = -b - root;
    }
    if q == 0.0 {
        return -1.0;
    }
    let t0 = min(q, c / q);
    let t1 = max(q, c / q);
    if t0 > 0.0 {
        return t0;
    }
    if t1 > 0.0 {
        return t1;
    }
    return -1.0;
}

// 1 - the cosine of the half-angle the sphere light subtends from p, in the stable form
// (r^2 / d^2) / (1 + cos): sin^2 = r^2 / d^2 and 1 - cos = sin^2 / (1 + cos), which keeps its
// precision where the cosine rounds to 1 (a small or far light). 0 when p is inside the light,
// where it cannot be sampled.
fn sphere_light_one_minus_cos(light: SphereLight, p: vec3<f32>) -> f32 {
    let d2 = dot(light.center - p, light.center - p);
    let r2 = light.radius * light.radius;
    if d2 <= r2 {
        return 0.0;
    }
    let sin2 = r2 / d2;
    return sin2 / (1.0 + sqrt(max(1.0 - sin2, 0.0)));
}

// The sphere light's radiance: intensity / (pi r^2), so that it gives `intensity` at distance 1.
fn sphere_light_radiance(light: SphereLight) -> vec3<f32> {
    return light.intensity / (PI * light.radius * light.radius);
}

// A direction from p toward the sphere light: uniform over the cone it subtends (its density
// 1 / solid angle), or for a point light (radius 0) the one direction, with the irradiance
// intensity / d^2 and `delta`.
fn sample_sphere_light(light: SphereLight, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let to_center = light.center - p;
    let d = length(to_center);
    let axis = to_center / d;
    if light.radius <= 0.0 {
        return LightSample(axis, light.intensity / (d * d), 1.0, d, true);
    }
    let one_minus_cos = sphere_light_one_minus_cos(light, p);
    if one_minus_cos <= 0.0 {
        return LightSample(axis, vec3<f32>(0.0), 0.0, 0.0, false);
    }
    let wi = sample_cone(axis, one_minus_cos, u);
    var t = intersect_sphere(p, wi, light.center, light.radius);
    if t < 0.0 {
        // A direction at the cone's rim by rounding: the tangent point's distance.
        t = sqrt(max(d * d - light.radius * light.radius, 0.0));
    }
    return LightSample(wi, sphere_light_radiance(light), 1.0 / cone_solid_angle(one_minus_cos), t, false);
}

// The density with which sample_sphere_light draws wi from p: 1 / solid angle inside the cone
// the light subtends (in_cone, the region sample_cone draws from), 0 outside it, and 0 for a
// point light, which no direction hits.
fn sphere_light_pdf(light: SphereLight, p: vec3<f32>, wi: vec3<f32>) -> f32 {
    if light.radius <= 0.0 {
        return 0.0;
    }
    let one_minus_cos = sphere_light_one_minus_cos(light, p);
    if one_minus_cos <= 0.0 || !in_cone(normalize(light.center - p), one_minus_cos, wi) {
        return 0.0;
    }
    return 1.0 / cone_solid_angle(one_minus_cos);
}

// The power heuristic (Veach 1997, beta = 2): the weight of a sample drawn with density a
// against another strategy's density b, a^2 / (a^2 + b^2), formed as 1 / (1 + (b / a)^2) so that
// the density of a tiny light (1e9 and more) cannot overflow its square.
fn power_heuristic(a: f32, b: f32) -> f32 {
    if a <= 0.0 {
        return 0.0;
    }
    let r = b / a;
    return 1.0 / (1.0 + r * r);
}
