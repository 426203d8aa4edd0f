// The path tracer's light: the sky (rays that leave the bounding region), the sun (a disc of a
// given angular radius) and the sphere light, their sampling for next-event estimation, and
// the power heuristic that weighs light samples against BSDF samples.
// Twin: src/cpu/light.rs, same names, same order (tests/twins.rs). The book's chapter "Light"
// (docs/book/light.md) gives every formula. f32 throughout, as shaders/bsdf.wgsl, which must come
// in front of it (its PI and its shading frame).
//
// Units: a light's `intensity` is the irradiance it gives a surface facing it (the sun), or at
// distance 1 (the sphere light, whose radiance is then intensity / (pi r^2)): a point light and a
// sphere of the same intensity light the far field alike, and the radius only softens.

// The sky (keep in sync with `Sky` in src/cpu/light.rs): a gradient about `up`.
struct Sky {
    zenith: vec3<f32>,
    horizon: vec3<f32>,
    ground: vec3<f32>,
    up: vec3<f32>,
    intensity: f32,
}

// The sun (keep in sync with `Sun`): toward the sun, the cosine of its angular radius, its
// colour times its intensity (0: no sun).
struct Sun {
    direction: vec3<f32>,
    cos_radius: f32,
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

// The solid angle of a cone of half-angle acos(cos_max): 2 pi (1 - cos_max).
fn cone_solid_angle(cos_max: f32) -> f32 {
    return 2.0 * PI * (1.0 - cos_max);
}

// A direction uniform over the cone about `axis` (unit) with cos(theta) >= cos_max, from u in
// [0, 1)^2: cos(theta) = 1 - u.x (1 - cos_max), phi = 2 pi u.y. Its density is 1 / solid angle.
fn sample_cone(axis: vec3<f32>, cos_max: f32, u: vec2<f32>) -> vec3<f32> {
    let c = 1.0 - u.x * (1.0 - cos_max);
    let s = sqrt(max(1.0 - c * c, 0.0));
    let phi = 2.0 * PI * u.y;
    let f = basis_from_normal(axis);
    return to_world(f, vec3<f32>(s * cos(phi), s * sin(phi), c));
}

// The sun's radiance along d (unit): irradiance / solid angle inside its disc, 0 outside.
fn sun_radiance(sun: Sun, d: vec3<f32>) -> vec3<f32> {
    if dot(d, sun.direction) < sun.cos_radius {
        return vec3<f32>(0.0);
    }
    return sun.irradiance / cone_solid_angle(sun.cos_radius);
}

// A direction toward the sun's disc, uniform over it.
fn sample_sun(sun: Sun, u: vec2<f32>) -> LightSample {
    let wi = sample_cone(sun.direction, sun.cos_radius, u);
    let omega = cone_solid_angle(sun.cos_radius);
    return LightSample(wi, sun.irradiance / omega, 1.0 / omega, 3.4e38, false);
}

// The density with which sample_sun draws d: 1 / solid angle inside the disc, 0 outside.
fn sun_pdf(sun: Sun, d: vec3<f32>) -> f32 {
    if dot(d, sun.direction) < sun.cos_radius {
        return 0.0;
    }
    return 1.0 / cone_solid_angle(sun.cos_radius);
}

// The nearest t > 0 where origin + t d (d unit) meets the sphere, or -1.
fn intersect_sphere(origin: vec3<f32>, d: vec3<f32>, center: vec3<f32>, radius: f32) -> f32 {
    let oc = origin - center;
    let b = dot(oc, d);
    let c = dot(oc, oc) - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return -1.0;
    }
    let root = sqrt(disc);
    let t0 = -b - root;
    if t0 > 0.0 {
        return t0;
    }
    let t1 = -b + root;
    if t1 > 0.0 {
        return t1;
    }
    return -1.0;
}

// The cosine of the half-angle the sphere light subtends from p (1 when p is inside it, where
// it cannot be sampled).
fn sphere_light_cos_max(light: SphereLight, p: vec3<f32>) -> f32 {
    let d2 = dot(light.center - p, light.center - p);
    let r2 = light.radius * light.radius;
    if d2 <= r2 {
        return 1.0;
    }
    return sqrt(max(1.0 - r2 / d2, 0.0));
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
    let cos_max = sphere_light_cos_max(light, p);
    if cos_max >= 1.0 {
        return LightSample(axis, vec3<f32>(0.0), 0.0, 0.0, false);
    }
    let wi = sample_cone(axis, cos_max, u);
    var t = intersect_sphere(p, wi, light.center, light.radius);
    if t < 0.0 {
        // A direction at the cone's rim by rounding: the tangent point's distance.
        t = sqrt(max(d * d - light.radius * light.radius, 0.0));
    }
    return LightSample(wi, sphere_light_radiance(light), 1.0 / cone_solid_angle(cos_max), t, false);
}

// The density with which sample_sphere_light draws wi from p (0 if wi misses the light, or for a
// point light, which no direction hits).
fn sphere_light_pdf(light: SphereLight, p: vec3<f32>, wi: vec3<f32>) -> f32 {
    if light.radius <= 0.0 {
        return 0.0;
    }
    let cos_max = sphere_light_cos_max(light, p);
    if cos_max >= 1.0 || intersect_sphere(p, wi, light.center, light.radius) < 0.0 {
        return 0.0;
    }
    return 1.0 / cone_solid_angle(cos_max);
}

// The power heuristic (Veach 1997, beta = 2): the weight of a sample drawn with density a
// against another strategy's density b.
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 <= 0.0 {
        return 0.0;
    }
    return a2 / (a2 + b2);
}
