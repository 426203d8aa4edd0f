// A test kernel for shaders/bsdf.wgsl and shaders/light.wgsl: one BSDF sample and one sample of
// each light per item, from inputs every side derives
// the same way from the item's index, written out whole, so that tests/render/bsdf.rs can hold the GPU's
// BSDF to its CPU twin (src/cpu/bsdf.rs). Host side and the inputs' definition:
// src/gpu/bsdf_probe.rs.
#import bsdf
#import light
#import sobol

// The probe's uniform (keep in sync with `GpuBsdfProbe` in src/gpu/bsdf_probe.rs).
struct Probe {
    albedo: vec3<f32>,
    roughness: f32,
    metallic: f32,
    specular: f32,
    width: u32,
    row_offset: u32,
    row_count: u32,
    // The material's multiscatter: 1 on, 0 off.
    multiscatter: u32,
}

@group(0) @binding(0) var<uniform> probe: Probe;
// Per item: (wi, pdf) and (f, the specular probability).
@group(0) @binding(1) var<storage, read_write> out_sample: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> out_value: array<vec4<f32>>;
// Per item: the sun's sample (wi, pdf), the sphere light's (wi, pdf), and (the sphere light's
// radiance.x and distance, the sky's radiance.x along the sun's wi, the sphere light's pdf of it).
@group(0) @binding(3) var<storage, read_write> out_sun: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> out_light: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> out_light_value: array<vec4<f32>>;

// The probe's lights (keep in sync with `probe_lights` in src/gpu/bsdf_probe.rs).
fn probe_sky() -> Sky {
    return Sky(vec3<f32>(0.2, 0.4, 0.9), vec3<f32>(0.8, 0.85, 0.9), vec3<f32>(0.3, 0.25, 0.2), vec3<f32>(0.0, 1.0, 0.0), 1.5);
}

fn probe_sun() -> Sun {
    return Sun(normalize(vec3<f32>(0.3, 0.8, 0.52)), 0.01, vec3<f32>(3.0, 2.0, 1.0));
}

fn probe_sphere_light() -> SphereLight {
    return SphereLight(vec3<f32>(1.0, 2.0, 3.0), 0.5, vec3<f32>(2.0, 2.0, 2.0));
}

// Input k (0..4) of item n, in [0, 1): the random sampler's number for (n, 0, k)
// (shaders/sobol.wgsl).
fn probe_input(n: u32, k: u32) -> f32 {
    return to_unit(random_sample(n, 0u, k));
}

@compute @workgroup_size(8, 8, 1)
fn bsdf_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= probe.width || gid.y >= probe.row_count {
        return;
    }
    let n = (probe.row_offset + gid.y) * probe.width + gid.x;
    let m = Material(probe.albedo, probe.roughness, probe.metallic, probe.specular, probe.multiscatter != 0u);
    // wo on a cosine hemisphere from inputs 0 and 1, then the sample from 2 (lobe) and 3, 0.
    let wo = sample_cosine_hemisphere(vec2<f32>(probe_input(n, 0u), probe_input(n, 1u)));
    let u = vec2<f32>(probe_input(n, 3u), probe_input(n, 0u));
    let s = bsdf_sample(m, wo, probe_input(n, 2u), u);
    let row = gid.y * probe.width + gid.x;
    out_sample[row] = vec4<f32>(s.wi, s.pdf);
    out_value[row] = vec4<f32>(s.f, specular_probability(m, wo));
    // The lights, seen from a point in the cube [-1, 1]^3.
    let p = vec3<f32>(probe_input(n, 0u), probe_input(n, 1u), probe_input(n, 2u)) * 2.0 - 1.0;
    let sun = sample_sun(probe_sun(), u);
    out_sun[row] = vec4<f32>(sun.wi, sun.pdf);
    let light = sample_sphere_light(probe_sphere_light(), p, u);
    out_light[row] = vec4<f32>(light.wi, light.pdf);
    out_light_value[row] = vec4<f32>(
        light.radiance.x,
        light.distance,
        sky_radiance(probe_sky(), sun.wi).x,
        sphere_light_pdf(probe_sphere_light(), p, sun.wi),
    );
}
