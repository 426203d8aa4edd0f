// The path tracer (shading.model = "path"): one invocation per pixel, paths of up to `bounces`
// scattering events through the set and the fog, with next-event estimation toward the sun and
// the sphere light, combined with BSDF or phase sampling by the power heuristic, Russian
// roulette and a clamp. The book's chapters "Path tracing" and "Atmosphere" give the estimator
// exactly. This file is the root: a path's camera ray, the path loop (trace_path) and the entry
// point (path_main); its parts are shaders/path_uniform.wgsl (the path uniform, the sampler, the
// lights and the material) and shaders/path_vertex.wgsl (direct light, the fog vertex, roulette,
// escape and emission).
//
// Twin: src/cpu/path/mod.rs, same names, same order (tests/architecture/twins.rs). Imports trace.wgsl (its Params,
// outputs, sphere tracing, normals, camera and orbit trap), bsdf.wgsl, light.wgsl, medium.wgsl
// and sobol.wgsl. Geometry is in
// `Real` (f32 or f64); the material, the light and the radiance are f32 (shaders/bsdf.wgsl says
// why).
#import real
#import params
#import estimate
#import march
#import normal
#import colour
#import accumulate
#import camera
#import atmosphere
#import trace
#import bsdf
#import light
#import medium
#import sobol
#import path_uniform
#import path_vertex

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
        if fog_on() {
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
