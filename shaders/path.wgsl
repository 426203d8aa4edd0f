// The path tracer (shading.model = "path"): one invocation per pixel, paths of up to `bounces`
// scattering events through the set and the fog, with next-event estimation toward the sun and
// the sphere light, combined with BSDF or phase sampling by the power heuristic, Russian
// roulette and a clamp. The book's chapters "Path tracing" and "Atmosphere" give the estimator
// exactly.
//
// Twin: src/cpu/path.rs, same names, same order (tests/architecture/twins.rs). Imports trace.wgsl (its Params,
// outputs, sphere tracing, normals, camera and orbit trap), bsdf.wgsl, light.wgsl, medium.wgsl
// and sobol.wgsl. Geometry is in
// `Real` (f32 or f64); the material, the light and the radiance are f32 (shaders/bsdf.wgsl says
// why).
//
// Why it passes 600 lines: it is one estimator, surface and fog vertices alike; the fog's vertex
// (direct_light with in_fog, path_fog) reads the sampler (path_random) and the path uniform, which
// live here, so it cannot join medium.wgsl, which comes before them; and its twin is split alike.
#import trace
#import bsdf
#import light
#import medium
#import sobol

// The path tracer's own parameters, a second uniform beside the tracer's Params (keep in sync
// with `GpuPathParams` in src/gpu/path.rs; its CPU twin is `PathParams` in src/cpu/path.rs).
struct PathParams {
    sky_zenith: vec3<f32>,
    sky_intensity: f32,
    sky_horizon: vec3<f32>,
    bounces: u32,
    sky_ground: vec3<f32>,
    roulette_start: u32,
    sky_up: vec3<f32>,
    clamp_contribution: f32,
    sun_direction: vec3<f32>,
    sun_one_minus_cos: f32,
    sun_irradiance: vec3<f32>,
    sampler: u32,
    light_intensity: vec3<f32>,
    strategy: u32,
    roughness: f32,
    metallic: f32,
    specular: f32,
    // material.multiscatter: 1 on, 0 off.
    multiscatter: u32,
    // path.regularize: the GGX roughness floor after a diffuse scattering (0: off).
    regularize: f32,
    // The sampler's seed (path.seed, plus the frame with path.animated_seed): 0 the default.
    seed: u32,
    // path.step_scale: the over-relaxation of shadow and bounce rays (sphere_trace_by's omega).
    step_scale: f32,
    pad1: u32,
    // material.emission: the radiance the surface emits, times its albedo (0: none).
    emission: vec3<f32>,
    pad2: u32,
}

@group(0) @binding(7) var<uniform> path: PathParams;

// path.strategy: which estimators light a hit (the MIS test's hook; scenes use both).
const STRATEGY_BOTH: u32 = 0u;
const STRATEGY_LIGHT: u32 = 1u;
const STRATEGY_BSDF: u32 = 2u;

// Rays leave a hit from p + SURFACE_OFFSET epsilon n: the estimate is about half the true
// distance near the surface, so there it is at least 2 epsilon, clear of the hit threshold (a
// ray that starts within it would hit the surface it leaves).
const SURFACE_OFFSET: Real = 4.0;

// Rays of this invocation's pixel that ran out of max_steps (exhausted): camera, shadow and
// bounce rays, every sample (`--stats`' exhausted_rays).
var<private> exhausted_rays: u32;

// Path mode's word of out_colour (the colour itself is the host's display transform of the
// radiance): the samples dropped as not finite in its low COUNTER_DROPPED_BITS bits (at most
// image.samples, 4,096), the rays that ran out of steps above them (at most 4,096 samples x 49
// rays, 200,704, under 2^19).
const COUNTER_DROPPED_BITS: u32 = 13u;
const COUNTER_DROPPED_MASK: u32 = 0x1fffu;

// One sample of a pixel: its linear radiance, its primary ray's depth and steps and whether it
// hit, and there the material's albedo and the shading normal (0 on a miss); the direct light
// its first hit reflected by the specular lobes (the denoiser's specular signal: trace_path),
// and there the cosine of the view direction to the shading normal (0 on a miss or a first
// vertex in the fog).
struct PathResult {
    radiance: vec3<f32>,
    depth: Real,
    steps: u32,
    hit: bool,
    albedo: vec3<f32>,
    normal: vec3<f32>,
    specular: vec3<f32>,
    cosine: f32,
}

// The light next-event estimation brings to a vertex (light_term, direct_light): all of it, and
// the part of it a surface's specular lobes reflect (bsdf_specular; 0 in the fog).
struct Light {
    total: vec3<f32>,
    specular: vec3<f32>,
}

// A path sample's stream and its index in it, as (stream, index): wherever a pixel takes two
// samples or more, adaptively or not, sample k is sample k / 2 of stream k % 2 (accumulate.wgsl's
// sample_stream when adaptive), so that the pixel's two halves (Halves) are drawn independently
// and their disagreement is its error estimate; a single sample is stream 0's.
fn path_stream(k: u32) -> vec2<u32> {
    if params.samples > 1u {
        return vec2<u32>(k & 1u, k >> 1u);
    }
    return vec2<u32>(0u, k);
}

// The number in [0, 1) of dimension `dim` of sample `sample` of pixel (i, j), from the scene's
// sampler (shaders/sobol.wgsl: the dimensions' order is stated there): the point of the
// sample's index in its stream (path_stream), stream 1 drawn as if its pixel's number had bit 31
// set (no pixel's has), so that its points are scrambled independently of stream 0's.
fn path_random(i: u32, j: u32, sample: u32, dim: u32) -> f32 {
    let s = path_stream(sample);
    let pixel = ((j * params.width + i) | (s.x << 31u)) ^ seed_mask();
    return to_unit(sample_bits(path.sampler, pixel, s.y, dim));
}

// What the seed does to a pixel's number in path_random: XORs in seed * 0x9e3779b9 (the golden
// ratio's 32 bits), so that seed 0 leaves every number as it was and each other seed draws
// independently scrambled points.
fn seed_mask() -> u32 {
    return path.seed * 0x9e3779b9u;
}

fn path_sky() -> Sky {
    return Sky(path.sky_zenith, path.sky_horizon, path.sky_ground, path.sky_up, path.sky_intensity);
}

fn path_sun() -> Sun {
    return Sun(path.sun_direction, path.sun_one_minus_cos, path.sun_irradiance);
}

fn path_sphere_light() -> SphereLight {
    return SphereLight(vec3<f32>(params.light), f32(params.light_radius), path.light_intensity);
}

// Path regularisation (Kaplanyan and Dachsbacher 2013; Cycles' "filter glossy"): the material
// of a vertex after the path has scattered by the cosine lobe (diffuse or multiple scattering),
// its GGX roughness held at path.regularize at least, so that a caustic path (diffuse, then
// glossy, then the sun) is a soft highlight and not a rare glint. A bias; 0 (the default) is
// off: the material unchanged.
fn regularized(m: Material) -> Material {
    var out = m;
    out.roughness = max(m.roughness, path.regularize);
    return out;
}

// The hit's material: the albedo is the hit's base colour (hit_albedo: the diffuse colour, or
// the orbit trap's palette colour).
fn path_material(p: vec3<Real>) -> Material {
    return Material(vec3<f32>(hit_albedo(p)), path.roughness, path.metallic, path.specular, path.multiscatter != 0u);
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
    if (!SPECIALISED || ENVIRONMENT) && environment_on() {
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
    if (!SPECIALISED || ENVIRONMENT) && environment_on() {
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

// The shading normal turned toward v (the direction back along the ray) where it faces away: at
// a sharp crease the estimated normal can, and the path would end black there. Bent within the
// plane of n and v until cos(n, v) >= MIN_FACING (the normal is unchanged everywhere else).
const MIN_FACING: f32 = 1e-3;

fn face_viewer(n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let c = dot(n, v);
    if c >= MIN_FACING {
        return n;
    }
    return normalize(n + (MIN_FACING - c) * v);
}

// The camera ray of sample `sample` of pixel (i, j): sample 0 through the pixel's centre, the
// others at the sampler's image-plane dimensions, and where the aperture is open every sample
// (sample 0 too) through the lens at its lens dimensions; against the bounds (the whole stretch
// within the ball).
fn path_camera_ray(i: u32, j: u32, sample: u32) -> Primary {
    var s = vec2<f32>(0.5, 0.5);
    if sample > 0u {
        s = vec2<f32>(path_random(i, j, sample, DIM_PIXEL), path_random(i, j, sample, DIM_PIXEL + 1u));
    }
    let x = Real(i) + Real(s.x);
    let y = Real(j) + Real(s.y);
    var dir = camera_ray_at(x, y);
    var origin = params.eye;
    // Through the thin lens (every sample where the aperture is open): the lens point from the
    // sampler's lens dimensions.
    if lens_open() {
        let uv = vec2<f32>(path_random(i, j, sample, DIM_LENS), path_random(i, j, sample, DIM_LENS + 1u));
        let ray = thin_lens_ray(x, y, aperture_point(uv));
        origin = ray.origin;
        dir = ray.dir;
    }
    let bounds = intersect_bounds(origin, dir);
    return Primary(origin, dir, bounds.t_enter, bounds.t_exit, bounds.hit);
}

// One path through sample `sample` of pixel (i, j) from its camera ray `camera` (path_camera_ray)
// and that ray's trace `first` (trace_primary, or a pair's: path_main): at each of up to
// `bounces` hits add the direct light and scatter by the BSDF; a ray that leaves the region takes
// the sky and the sun, one that meets the sphere light first its emission. The last scattered ray
// is traced for that alone. (The CPU twin's trace_path takes the sample alone and traces its
// camera ray; its trace_path_from is this.)
fn trace_path(i: u32, j: u32, sample: u32, camera: Primary, first: Trace) -> PathResult {
    var dir = camera.dir;
    var origin = camera.origin;
    var throughput = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var result = PathResult(vec3<f32>(0.0), -1.0, 0u, false, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    var pdf_prev: f32 = 0.0;
    // The first hit's specular light (the denoiser's specular signal): the part of the direct
    // light there that its specular lobes reflect (Light.specular). The light gathered after
    // the first bounce stays with the diffuse signal whichever lobe drew the bounce: split by
    // the lobes' shares it made both signals noisier than their sum, and the denoised image
    // worse (docs/book/denoise.md). A first vertex in the fog has none: its light is diffuse.
    var specular = vec3<f32>(0.0);
    // Whether the path has scattered by the cosine lobe (regularized), with path.regularize on.
    var diffuse_before = false;
    let light_on = params.light_radius > 0.0 && any(path.light_intensity > vec3<f32>(0.0));
    for (var bounce = 0u; bounce <= path.bounces; bounce++) {
        // The camera ray's trace is given; a scattered ray's is made here (no pixel epsilon,
        // over-relaxed by path.step_scale).
        var trace = first;
        // A scattered ray that ran out of steps: it sees the sphere light only short of where
        // it stopped, and ends its path there, dark.
        var ran_out = false;
        if bounce > 0u {
            trace = Trace(0.0, 0u, false, NO_APPROACH);
            let bounds = intersect_bounds(origin, dir);
            if bounds.hit {
                trace = sphere_trace_by(origin, dir, bounds.t_enter, bounds.t_exit, 0.0, Real(path.step_scale));
                // Only scattered rays end so: a camera ray that runs out stays a miss, as
                // in phong mode.
                if exhausted(trace, bounds.t_exit) {
                    exhausted_rays += 1u;
                    ran_out = true;
                }
            }
        } else if camera.hit && exhausted(trace, camera.t_end) {
            exhausted_rays += 1u;
        }
        // The light this ray meets left the path's last scattering event, bounce - 1 (none
        // for the camera ray): clamp_indirect's vertex.
        let vertex = max(bounce, 1u) - 1u;
        if bounce == 0u {
            result.depth = trace.t;
            result.steps = trace.steps;
            result.hit = trace.hit;
        }
        let dir32 = vec3<f32>(dir);
        // Whether the ray meets the sphere light before the set (or before leaving), at t_light.
        var t_light: f32 = -1.0;
        if light_on {
            let light = path_sphere_light();
            t_light = intersect_sphere(vec3<f32>(origin), dir32, light.center, light.radius);
        }
        let left = !trace.hit && !ran_out;
        let meets_light = t_light > 0.0 && (left || Real(t_light) < trace.t);
        // In fog, the ray may scatter before its stretch ends (at the light, the set, where it
        // ran out, or where it leaves): a scattering event is the path's next vertex, lit by
        // next-event estimation and left by phase sampling, and counts as a bounce.
        var in_fog = false;
        var p = origin;
        if (!SPECIALISED || FOG) && fog_on() {
            var t_stop = trace.t;
            if meets_light {
                t_stop = Real(t_light);
            } else if left {
                t_stop = 3.0e38;
            }
            let fog = path_fog(i, j, sample, bounce, origin, dir, t_stop);
            throughput *= fog.weight;
            if fog.scattered {
                if bounce == path.bounces {
                    break;
                }
                in_fog = true;
                p = fog.point;
            }
        }
        // A surface vertex's normal, frame, wo and material (unused in the fog).
        var n = vec3<f32>(0.0, 0.0, 1.0);
        var f = Basis(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), n);
        var wo = n;
        var m = Material(vec3<f32>(0.0), 1.0, 0.0, 0.0, false);
        if !in_fog {
            if meets_light {
                let e = light_emission(vec3<f32>(origin), dir32, bounce, pdf_prev);
                radiance += clamp_indirect(throughput * e, vertex);
                break;
            }
            if ran_out {
                break;
            }
            if !trace.hit {
                radiance += clamp_indirect(throughput * escaped(dir32, bounce, pdf_prev), vertex);
                break;
            }
            p = origin + trace.t * dir;
            // material.emission: the set's own light, the hit's albedo times the emission
            // (found by the rays alone: no light sampling aims at it).
            if any(path.emission > vec3<f32>(0.0)) {
                radiance += clamp_indirect(throughput * path.emission * vec3<f32>(hit_albedo(p)), vertex);
            }
            if bounce == path.bounces {
                break;
            }
            n = face_viewer(vec3<f32>(estimate_normal(p, dir)), -dir32);
            f = basis_from_normal(n);
            wo = to_local(f, -dir32);
            m = path_material(p);
            if diffuse_before {
                m = regularized(m);
            }
            if bounce == 0u {
                result.albedo = m.albedo;
                result.normal = n;
                result.cosine = max(wo.z, 0.0);
            }
            if wo.z <= 0.0 {
                break;
            }
        }
        if path.strategy != STRATEGY_BSDF {
            let light = direct_light(i, j, sample, bounce, in_fog, p, f, wo, m, dir32);
            radiance += clamp_indirect(throughput * light.total, bounce);
            if bounce == 0u {
                specular = throughput * light.specular;
            }
        }
        let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE;
        let u = vec2<f32>(path_random(i, j, sample, dim + DIM_BSDF), path_random(i, j, sample, dim + DIM_BSDF + 1u));
        if in_fog {
            let ps = sample_hg(f32(params.fog_anisotropy), dir32, u);
            // The phase sample's weight, phase / pdf, is 1.
            pdf_prev = ps.pdf;
            origin = p;
            dir = real_normalize(vec3<Real>(ps.wi));
        } else {
            let lobe = path_random(i, j, sample, dim + DIM_BSDF_CHOICE);
            let bs = bsdf_sample(m, wo, lobe, u);
            if bs.pdf <= 0.0 {
                break;
            }
            if path.regularize > 0.0 && lobe >= specular_probability(m, wo) {
                diffuse_before = true;
            }
            throughput *= bs.f * (bs.wi.z / bs.pdf);
            pdf_prev = bs.pdf;
            origin = p + SURFACE_OFFSET * params.epsilon * vec3<Real>(n);
            dir = real_normalize(vec3<Real>(to_world(f, bs.wi)));
        }
        let q = roulette(i, j, sample, bounce, throughput);
        if q <= 0.0 {
            break;
        }
        throughput /= q;
    }
    result.radiance = radiance;
    result.specular = specular;
    return result;
}

// Whether a sample's radiance may enter the pixel's mean: every channel finite (neither NaN
// nor infinite, by its exponent bits, which no fast-math can fold away) and not negative.
fn sample_valid(c: vec3<f32>) -> bool {
    let exponent = vec3<u32>(0x7f800000u);
    let finite = (bitcast<vec3<u32>>(c) & exponent) != exponent;
    return all(finite) && all(c >= vec3<f32>(0.0));
}

// One workgroup is 8 x 8 pixels. This dispatch adds the samples [sample_start, sample_end) to
// the pixel's halves (add_to_halves: sample k to the running mean of its stream, path_stream)
// in the accumulator's second and third planes, and what the pixel shows (halves_mean) to its
// first; with AOVS it adds them to the AOVs (add_aovs: the first hits' albedo, normal and depth);
// sample 0 gives the depth and the steps (where the lens is open, the pinhole ray's through the
// pixel's centre, traced for them alone). A sample whose radiance is not valid (sample_valid) is
// dropped: counted in out_colour's word, and left out of the pixel's halves, its M2, its AOVs and
// its adaptive state. Adaptively (accumulate.wgsl's `adaptive`) the samples go to the pixel's two
// streams instead (add_to_streams), the AOVs take the samples that join the streams' colours,
// and the pixel stops after the sample that leaves it done (sampling_done), showing
// streams_mean; a later dispatch leaves it at once, or with COMPACT gives its invocation to a
// live pixel of its block (compacted_pixel).
@compute @workgroup_size(8, 8, 1)
fn path_main(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    // With compaction (params.wgsl's COMPACT) the block's live pixels, packed.
    let pixel = compacted_pixel(gid, wid, lid);
    let i = pixel.x;
    let row = pixel.y;
    if i >= params.width || row >= params.row_count {
        return;
    }
    let j = params.row_offset + row;
    let index = (params.out_row + row) * params.row_stride + i;
    estimates = 0u;
    iterations = 0u;
    // Without adaptive sampling, the pixel's halves (add_to_halves).
    var halves = Halves(vec4<f32>(0.0), vec4<f32>(0.0));
    var made = vec4<u32>(0u);
    var aovs = Aovs(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, vec3<f32>(0.0), 0.0);
    // Adaptively (accumulate.wgsl's `adaptive`), the pixel's streams (add_to_streams).
    var streams = Streams(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    // The samples dropped so far, and the counter word's exhausted rays of earlier dispatches.
    var dropped = 0u;
    var exhausted_before = 0u;
    exhausted_rays = 0u;
    if params.sample_start == 0u && lens_open() {
        let pinhole = trace_primary(pinhole_ray(i, j, 0u, 0.0));
        out_depth[index] = select(-1.0, pinhole.t, pinhole.hit);
        out_steps[index] = pinhole.steps;
    }
    if params.sample_start > 0u {
        let held = accumulated[index];
        if adaptive() && held.w < 0.0 {
            return;
        }
        made = out_work[index];
        let counters = out_colour[index];
        dropped = counters & COUNTER_DROPPED_MASK;
        exhausted_before = counters >> COUNTER_DROPPED_BITS;
        if adaptive() {
            streams = load_streams(index);
        } else {
            halves = load_halves(index);
        }
        if AOVS {
            aovs = load_aovs(index);
        }
    }
    // With INTERLEAVE 2 the camera rays of samples k and k + 1 are traced as a pair at k
    // (trace_primary_pair), and k + 1's trace kept for it; an odd sample left over is traced
    // alone. One call of trace_path for all three (two calls, each inlined, made the path
    // kernel 17% slower on lavapipe).
    var second = Trace(0.0, 0u, false, NO_APPROACH);
    var paired = false;
    var taken = 0u;
    for (var k = params.sample_start; k < params.sample_end; k++) {
        let camera = path_camera_ray(i, j, k);
        var first = second;
        if paired {
            paired = false;
        } else if INTERLEAVE >= 2u && k + 1u < params.sample_end {
            let pair = trace_primary_pair(camera, path_camera_ray(i, j, k + 1u));
            first = pair.first;
            second = pair.second;
            paired = true;
        } else {
            first = trace_primary(camera);
        }
        let r = trace_path(i, j, k, camera, first);
        if k == 0u && !lens_open() {
            out_depth[index] = select(-1.0, r.depth, r.hit);
            out_steps[index] = r.steps;
        }
        let valid = sample_valid(r.radiance);
        if !valid {
            dropped += 1u;
        }
        if adaptive() {
            // The samples the pixel's colours hold, and whether this one joined them.
            let before = streams.rule_a.w + streams.b.w;
            streams = add_to_streams(streams, k, valid, r.radiance);
            let n = streams.rule_a.w + streams.b.w;
            if AOVS && n > before {
                aovs = add_aovs(aovs, u32(n) - 1u, r.radiance, r.hit, r.albedo, r.normal, f32(r.depth), r.specular, r.cosine);
            }
            if sampling_done(streams, k + 1u) {
                taken = k + 1u;
                break;
            }
        } else if valid {
            // The samples the halves hold, this one with them: the samples kept.
            let n = k + 1u - dropped;
            halves = add_to_halves(halves, k, r.radiance);
            if AOVS {
                aovs = add_aovs(aovs, n - 1u, r.radiance, r.hit, r.albedo, r.normal, f32(r.depth), r.specular, r.cosine);
            }
        }
    }
    if adaptive() {
        if AOVS && taken > 0u {
            aovs = finish_aovs(aovs, streams, taken);
        }
        store_streams(index, streams, taken);
    } else {
        accumulated[index] = vec4<f32>(halves_mean(halves), 0.0);
        store_halves(index, halves);
    }
    if AOVS {
        store_aovs(index, aovs);
    }
    out_work[index] = add_work(made);
    out_colour[index] = dropped | ((exhausted_before + exhausted_rays) << COUNTER_DROPPED_BITS);
}
