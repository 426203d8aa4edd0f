// The fog's medium (fog.density > 0): a homogeneous medium of grey extinction and coloured
// albedo filling the bounding ball. The Henyey-Greenstein phase function and its sampling, and
// free-flight distance sampling along a ray's stretch within the ball. The book's chapter
// "Atmosphere" (docs/book/atmosphere.md) gives every formula.
// Twin: src/cpu/medium.rs, same names, same order (tests/architecture/twins.rs). f32 throughout, as
// shaders/bsdf.wgsl, which it imports (its PI and its shading frame).
#import bsdf

// A direction drawn by sample_hg, with the density (per solid angle) it was drawn with.
struct PhaseSample {
    wi: vec3<f32>,
    pdf: f32,
}

// Below this |g| the phase function is sampled as isotropic (the inverse below divides by g).
const HG_ISOTROPIC: f32 = 1e-3;

// The Henyey-Greenstein phase function of asymmetry g in (-1, 1) at c, the cosine between the
// direction the light travelled and the direction it scatters into:
// (1 - g^2) / (4 pi (1 + g^2 - 2 g c)^(3/2)); it integrates to 1 over the sphere, and g > 0
// scatters forward. Below HG_ISOTROPIC it is the isotropic 1 / (4 pi) that sample_hg draws.
fn phase_hg(g: f32, c: f32) -> f32 {
    if abs(g) < HG_ISOTROPIC {
        return 1.0 / (4.0 * PI);
    }
    let denom = max(1.0 + g * g - 2.0 * g * c, 1e-12);
    return (1.0 - g * g) / (4.0 * PI * denom * sqrt(denom));
}

// A direction about d (unit, the way the light travelled) drawn with density phase_hg from u in
// [0, 1)^2: the cosine by inverting the phase function's distribution,
// c = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u.x))^2) / (2 g) (isotropic, 1 - 2 u.x, below
// HG_ISOTROPIC), the azimuth 2 pi u.y. The pdf is phase_hg's at that cosine, so a phase sample's
// weight, phase / pdf, is 1.
fn sample_hg(g: f32, d: vec3<f32>, u: vec2<f32>) -> PhaseSample {
    var c = 1.0 - 2.0 * u.x;
    if abs(g) >= HG_ISOTROPIC {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
        c = (1.0 + g * g - s * s) / (2.0 * g);
    }
    c = clamp(c, -1.0, 1.0);
    let sin_theta = sqrt(max(1.0 - c * c, 0.0));
    let phi = 2.0 * PI * u.y;
    let wi = to_world(basis_from_normal(d), vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), c));
    return PhaseSample(wi, phase_hg(g, c));
}

#if FOG
// What free-flight sampling found along a stretch of fog: the distance into the stretch of a
// scattering event (scattered) or the stretch's length (none), and the weight the path's
// throughput takes.
struct FogEvent {
    distance: f32,
    scattered: bool,
    weight: vec3<f32>,
}

// Free-flight sampling over a stretch of `length` of the medium of extinction `density` (grey)
// and single-scattering albedo `albedo`, from u in [0, 1): a tentative event at
// s = -ln(1 - u) / (density a), a = the albedo's largest channel (a is in (0, 1]). Where s falls
// within the stretch the light scatters there, weighted (albedo / a) exp(-density (1 - a) s);
// else it passes, weighted exp(-density (1 - a) length). Each weight is the transmittance, times
// the scattering coefficient at an event, over the density it was drawn with, so that the
// estimate is unbiased, and no channel's weight exceeds 1. An albedo of 0 never scatters: the
// weight is then the transmittance exp(-density length) exactly.
fn fog_event(density: f32, albedo: vec3<f32>, length: f32, u: f32) -> FogEvent {
    let a = max(albedo.x, max(albedo.y, albedo.z));
    let absorbed = density * (1.0 - a);
    if a > 0.0 {
        let s = -log(1.0 - u) / (density * a);
        if s < length {
            return FogEvent(s, true, albedo / a * exp(-absorbed * s));
        }
    }
    return FogEvent(length, false, vec3<f32>(exp(-absorbed * length)));
}
#endif
