// The path tracer's uniform and what is read from it: `PathParams` (binding 7, beside the tracer's
// Params) and the strategies, a sample's stream and its random numbers (path_stream, path_random,
// seed_mask), the sky, the sun and the sphere light, and the material at a point (regularized,
// path_material).
//
// Part of the path tracer that shaders/path.wgsl composes. Twin: src/cpu/path/uniform.rs, same
// names, same order (tests/architecture/twins.rs, which lists the functions only one side has); a
// change to one is a change to both.
#import real
#import params
#import colour
#import bsdf
#import light
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
