// A path vertex's light and its fate: the rays that ran out of steps (exhausted), the shadow rays
// (unoccluded, visibility), the clamp, next-event estimation at a surface or in the fog
// (light_term, add_light, direct_light), the fog's vertex (path_fog), Russian roulette, and what a
// path gathers when it escapes or meets the sphere light (escaped, light_emission).
//
// Part of the path tracer that shaders/path.wgsl composes. Twin: src/cpu/path/vertex.rs, same
// names, same order (tests/architecture/twins.rs, which lists the functions only one side has); a
// change to one is a change to both.
#import real
#import params
#import environment
#import march
#import atmosphere
#import bsdf
#import light
#import medium
#import sobol
#import path_uniform

// Rays leave a hit from p + SURFACE_OFFSET epsilon n: the estimate is about half the true
// distance near the surface, so there it is at least 2 epsilon, clear of the hit threshold (a
// ray that starts within it would hit the surface it leaves).
const SURFACE_OFFSET: Real = 4.0;

// Rays of this invocation's pixel that ran out of max_steps (exhausted): camera, shadow and
// bounce rays, every sample (`--stats`' exhausted_rays).
var<private> exhausted_rays: u32;

// The light next-event estimation brings to a vertex (light_term, direct_light): all of it, and
// the part of it a surface's specular lobes reflect (bsdf_specular; 0 in the fog).
struct Light {
    total: vec3<f32>,
    specular: vec3<f32>,
}

// Whether a trace that ended at or before t_end without a hit ran out of max_steps there
// (sphere_trace's miss by leaving always ends past t_end): a ray that ran out is neither a hit
// nor an escape, and counts as dark (a crevice is where rays run out).
fn exhausted(trace: Trace, t_end: Real) -> bool {
    return !trace.hit && trace.t <= t_end;
}

// Whether nothing of the set lies between origin and origin + t_max dir: the shadow ray, the
// tracer's own sphere trace (no pixel epsilon, over-relaxed by path.step_scale) within the
// bounding ball. A shadow ray that runs out of steps (exhausted) is occluded.
fn unoccluded(origin: vec3<Real>, dir: vec3<Real>, t_max: Real) -> bool {
    let bounds = intersect_bounds(origin, dir);
    let t_end = min(bounds.t_exit, t_max);
    if !bounds.hit || bounds.t_enter >= t_end {
        return true;
    }
    let trace = sphere_trace_by(origin, dir, bounds.t_enter, t_end, 0.0, Real(path.step_scale));
    if exhausted(trace, t_end) {
        exhausted_rays += 1u;
        return false;
    }
    return !trace.hit;
}

// What of the light at origin + t_max dir reaches origin: 0 where the set occludes it
// (unoccluded), else the fog's transmittance over the stretch (1 without fog). The fog's
// shadow: light shafts where the set casts its shadow into the fog.
fn visibility(origin: vec3<Real>, dir: vec3<Real>, t_max: Real) -> f32 {
    if !unoccluded(origin, dir, t_max) {
        return 0.0;
    }
    return fog_transmittance(origin, dir, t_max);
}

// A path's contribution, clamped where its light reached the camera through more than one
// scattering event: `vertex` is the index of the last scattering event (0 the first hit) of the
// path the light took, the same for the light that next-event estimation finds at vertex v and
// for the light that the ray leaving vertex v meets, so both halves of MIS are clamped alike.
// From vertex 1 on the contribution is scaled so that its largest channel is at most
// path.clamp_contribution (0: off); direct light at the first hit, and what a camera ray sees,
// are never clamped.
fn clamp_indirect(c: vec3<f32>, vertex: u32) -> vec3<f32> {
    let m = max(c.x, max(c.y, c.z));
    if vertex == 0u || path.clamp_contribution <= 0.0 || m <= path.clamp_contribution {
        return c;
    }
    return c * (path.clamp_contribution / m);
}

// One light's sample ls seen from a vertex: nothing where it has no density or lies below the
// surface; else its shadow ray from origin over ls.distance (visibility: the set's occlusion and
// the fog's transmittance), and the light it brings, weighted against BSDF or phase sampling by
// the power heuristic (a point light, delta, is not). At a surface hit (in_fog false) the BSDF
// of m in the frame f, with wo, and the cosine; at a scattering event in the fog (in_fog true)
// the phase function (phase_hg of fog.anisotropy) of light that travelled along d, no cosine.
fn light_term(ls: LightSample, in_fog: bool, origin: vec3<Real>, f: Basis, wo: vec3<f32>, m: Material, d: vec3<f32>) -> Light {
    let none = Light(vec3<f32>(0.0), vec3<f32>(0.0));
    let wi = to_local(f, ls.wi);
    if ls.pdf <= 0.0 || !(in_fog || wi.z > 0.0) {
        return none;
    }
    let v = visibility(origin, vec3<Real>(ls.wi), Real(ls.distance));
    if v <= 0.0 {
        return none;
    }
    if in_fog {
        let phase = phase_hg(f32(params.fog_anisotropy), dot(d, ls.wi));
        if ls.delta {
            return Light(ls.radiance * (phase * v), vec3<f32>(0.0));
        }
        var w = 1.0;
        if path.strategy == STRATEGY_BOTH {
            w = power_heuristic(ls.pdf, phase);
        }
        return Light(ls.radiance * (phase * w / ls.pdf * v), vec3<f32>(0.0));
    }
    let f_wi = bsdf_eval(m, wo, wi) * ls.radiance;
    let s_wi = bsdf_specular(m, wo, wi) * ls.radiance;
    if ls.delta {
        return Light(f_wi * wi.z * v, s_wi * wi.z * v);
    }
    var w = 1.0;
    if path.strategy == STRATEGY_BOTH {
        w = power_heuristic(ls.pdf, bsdf_pdf(m, wo, wi));
    }
    return Light(f_wi * (wi.z * w / ls.pdf) * v, s_wi * (wi.z * w / ls.pdf) * v);
}

// The sum of two lights.
fn add_light(a: Light, b: Light) -> Light {
    return Light(a.total + b.total, a.specular + b.specular);
}

// Next-event estimation at a vertex: the sun, the environment map and the sphere light, each by
// one sample toward it (light_term: a shadow ray, weighted against BSDF or phase sampling). At a
// surface hit (in_fog false) shadow rays leave from p + SURFACE_OFFSET epsilon n; at a
// scattering event in the fog (in_fog true) from p itself. One function, so that the kernel
// holds one shadow trace per light.
fn direct_light(i: u32, j: u32, sample: u32, bounce: u32, in_fog: bool, p: vec3<Real>, f: Basis, wo: vec3<f32>, m: Material, d: vec3<f32>) -> Light {
    var sum = Light(vec3<f32>(0.0), vec3<f32>(0.0));
    let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE;
    var origin = p;
    if !in_fog {
        origin = p + SURFACE_OFFSET * params.epsilon * vec3<Real>(f.n);
    }
    // Each light its own point (DIM_SUN, DIM_ENVIRONMENT, DIM_SPHERE_LIGHT).
    if any(path.sun_irradiance > vec3<f32>(0.0)) {
        let u = vec2<f32>(path_random(i, j, sample, dim + DIM_SUN), path_random(i, j, sample, dim + DIM_SUN + 1u));
        sum = add_light(sum, light_term(sample_sun(path_sun(), u), in_fog, origin, f, wo, m, d));
    }
    if environment_on() {
        // The sun's group's other two dimensions.
        let u = vec2<f32>(path_random(i, j, sample, dim + DIM_ENVIRONMENT), path_random(i, j, sample, dim + DIM_ENVIRONMENT + 1u));
        let es = sample_environment(u);
        sum = add_light(sum, light_term(LightSample(es.wi, es.radiance, es.pdf, 3.4e38, false), in_fog, origin, f, wo, m, d));
    }
    if any(path.light_intensity > vec3<f32>(0.0)) {
        let u = vec2<f32>(path_random(i, j, sample, dim + DIM_SPHERE_LIGHT), path_random(i, j, sample, dim + DIM_SPHERE_LIGHT + 1u));
        sum = add_light(sum, light_term(sample_sphere_light(path_sphere_light(), vec3<f32>(p), u), in_fog, origin, f, wo, m, d));
    }
    return sum;
}

// Where a ray's stretch through the fog ends and with what weight: free flight (fog_event) over
// the part of origin + t dir, t up to t_stop, within the bounding ball, from the sampler's
// DIM_FOG of the bounce. `point` is the scattering event's, where there is one.
struct PathFog {
    point: vec3<Real>,
    scattered: bool,
    weight: vec3<f32>,
}

#if FOG
fn path_fog(i: u32, j: u32, sample: u32, bounce: u32, origin: vec3<Real>, dir: vec3<Real>, t_stop: Real) -> PathFog {
    let bounds = intersect_bounds(origin, dir);
    let t_end = min(bounds.t_exit, t_stop);
    if !bounds.hit || t_end <= bounds.t_enter {
        return PathFog(origin, false, vec3<f32>(1.0));
    }
    let u = path_random(i, j, sample, DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE + DIM_FOG);
    let e = fog_event(f32(params.fog_density), vec3<f32>(params.fog_colour), f32(t_end - bounds.t_enter), u);
    return PathFog(origin + (bounds.t_enter + Real(e.distance)) * dir, e.scattered, e.weight);
}
#else
// Never called: fog_on() is false.
fn path_fog(i: u32, j: u32, sample: u32, bounce: u32, origin: vec3<Real>, dir: vec3<Real>, t_stop: Real) -> PathFog {
    return PathFog(origin, false, vec3<f32>(1.0));
}
#endif

// Russian roulette after the scattering event `bounce`, from bounce roulette_start on: the path
// goes on with probability q, the throughput's largest channel (at most 0.95), and is then
// divided by it, so the mean is kept. Returns the divisor: q, 1 before roulette_start, 0 where
// the path ends.
fn roulette(i: u32, j: u32, sample: u32, bounce: u32, throughput: vec3<f32>) -> f32 {
    if bounce + 1u < path.roulette_start {
        return 1.0;
    }
    let q = min(max(throughput.x, max(throughput.y, throughput.z)), 0.95);
    if path_random(i, j, sample, DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE + DIM_ROULETTE) >= q {
        return 0.0;
    }
    return q;
}

// The radiance reaching a ray that leaves the bounding region: the sky (the environment map
// where the scene has one), and the sun's disc, the map and the sun weighted against their
// next-event estimation (bsdf_pdf the density the ray was drawn with; a camera ray, drawn with
// no density, sees them whole).
fn escaped(dir: vec3<f32>, bounce: u32, bsdf_pdf_prev: f32) -> vec3<f32> {
    var c = vec3<f32>(0.0);
    if environment_on() {
        // The map, weighted against its own next-event estimation as the sun is.
        var w = 1.0;
        if bounce > 0u {
            if path.strategy == STRATEGY_LIGHT {
                w = 0.0;
            } else if path.strategy == STRATEGY_BOTH {
                w = power_heuristic(bsdf_pdf_prev, environment_pdf(dir));
            }
        }
        c = w * env_radiance(dir);
    } else {
        c = sky_radiance(path_sky(), dir);
    }
    if any(path.sun_irradiance > vec3<f32>(0.0)) {
        var w = 1.0;
        if bounce > 0u {
            if path.strategy == STRATEGY_LIGHT {
                w = 0.0;
            } else if path.strategy == STRATEGY_BOTH {
                w = power_heuristic(bsdf_pdf_prev, sun_pdf(path_sun(), dir));
            }
        }
        c += w * sun_radiance(path_sun(), dir);
    }
    return c;
}

// The emission of the sphere light seen along a ray from origin, weighted as escaped weights the
// sun.
fn light_emission(origin: vec3<f32>, dir: vec3<f32>, bounce: u32, bsdf_pdf_prev: f32) -> vec3<f32> {
    var w = 1.0;
    if bounce > 0u {
        if path.strategy == STRATEGY_LIGHT {
            w = 0.0;
        } else if path.strategy == STRATEGY_BOTH {
            w = power_heuristic(bsdf_pdf_prev, sphere_light_pdf(path_sphere_light(), origin, dir));
        }
    }
    return w * sphere_light_radiance(path_sphere_light());
}
