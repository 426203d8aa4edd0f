// The quaternion Julia set ray tracer of Crane (2005), fixed as docs/CONTRACT.md defines it:
// one invocation per pixel, through the distance estimate, sphere tracing, the normal, Phong
// shading and the shadow ray. This file is the kernel's root: a pixel's sample shaded and traced
// (shade_pixel, trace_pixel), the work counts, adaptive sampling's compaction and the entry point
// `main`; the parts are the files it imports, one concern each (estimate, cut, march, normal,
// shading, colour, camera, atmosphere, accumulate).
//
// Twin: src/cpu/trace/mod.rs, and each imported part's twin in src/cpu/trace/, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both. Written against the
// float type `Real` of shaders/real.wgsl: one source, an f32 and an f64 kernel (the feature F64,
// shaders/kernels.json). Its uniform and switches are shaders/params.wgsl.
//
// WGSL may assume NaN and Inf never occur, so every guard comes before the operation it guards.
#import real
#import params
#import estimate
#import march
#import normal
#import shading
#import colour
#import accumulate
#import camera
#import atmosphere

// params.tracing: the seed's sphere tracing of every ray, or a cone per 8x8 block first.
const TRACING_SEED: u32 = 0u;
const TRACING_CONE: u32 = 1u;

// The cone's start, shared by the workgroup's invocations.
var<workgroup> cone_t: Real;

// The band of rows [row_offset, row_offset + row_count) lands in the output arrays from row
// out_row on, row_stride pixels a row: pixel (i, row_offset + r) at (out_row + r) * row_stride + i.
// Colour as 0xFFBBGGRR (RGBA8, opaque).
@group(0) @binding(1) var<storage, read_write> out_colour: array<u32>;
// The hit's ray parameter t; -1 for a miss (the host turns it into NaN).
@group(0) @binding(2) var<storage, read_write> out_depth: array<Real>;
// Distance estimates along the primary ray.
@group(0) @binding(3) var<storage, read_write> out_steps: array<u32>;
// The work made for the pixel, every sample and every ray, summed across dispatches (add_work):
// its distance estimates and its quaternion iterations, each a 64-bit count as its low and
// high words (x and y the estimates, z and w the iterations).
@group(0) @binding(4) var<storage, read_write> out_work: array<vec4<u32>>;

#if SHADE
// Whether colour is wanted. Without SHADE (shaders/kernels.json: only the depth and the steps are
// read back) false, and a hit's shading is not in the kernel.
fn shade_on() -> bool {
    return true;
}
#else
fn shade_on() -> bool {
    return false;
}
#endif

// A sample's outcome from its camera ray and the ray's trace: normal, Phong, shadow, and the
// atmosphere over them.
fn shade_pixel(ray: Primary, trace: Trace) -> Pixel {
    let none = vec3<Real>(0.0);
    if !trace.hit {
        return Pixel(atmosphere(background(ray.dir), ray, trace), -1.0, trace.steps, false, none, none);
    }
    if !shade_on() {
        return Pixel(params.background, trace.t, trace.steps, true, none, none);
    }
    let origin = ray.origin;
    let dir = ray.dir;
    let p = origin + trace.t * dir;
    let n = estimate_normal(p, dir);
    if shading_features() {
        return Pixel(atmosphere(shade_features(p, n, origin), ray, trace), trace.t, trace.steps, true, p, n);
    }
    var colour = phong(params.light, origin, p, n);
    // An unlit point (black: the light is behind its surface) stays black in shadow: no ray.
    let lit = any(colour > vec3<Real>(0.0));
    if shadows_on() && lit && in_shadow(p, n) {
        colour *= params.shadow_factor;
    }
    return Pixel(atmosphere(colour, ray, trace), trace.t, trace.steps, true, p, n);
}

// Everything for one sample of pixel (i, j): its camera ray (primary_ray), sphere tracing,
// and shading (shade_pixel).
fn trace_pixel(i: u32, j: u32, sample: u32, t_min: Real) -> Pixel {
    let ray = primary_ray(i, j, sample, t_min);
    return shade_pixel(ray, trace_primary(ray));
}

// A pixel's work counts `held` (out_work) with this dispatch's estimates and iterations added,
// each carried into its high word where its low word wraps.
fn add_work(held: vec4<u32>) -> vec4<u32> {
    let e = held.x + estimates;
    let n = held.z + iterations;
    return vec4<u32>(e, held.y + select(0u, 1u, e < estimates), n, held.w + select(0u, 1u, n < iterations));
}

// The workgroup's live pixels (compacted_pixel): how many, and each one's local index.
var<workgroup> live_count: atomic<u32>;
var<workgroup> live_lanes: array<u32, 64>;

// The pixel, as (column, row of the band), that invocation `lid` of workgroup `wid` samples:
// its own (gid.xy), or with COMPACT in a later dispatch of adaptive sampling the lid-th live
// pixel of its 8 x 8 block (in no fixed order: a pixel's samples do not depend on the lane that
// takes them); (width, 0), none, where the block has fewer live pixels. Every invocation of the
// workgroup calls it, before any returns (it holds a barrier).
fn compacted_pixel(gid: vec3<u32>, wid: vec3<u32>, lid: u32) -> vec2<u32> {
    if !(COMPACT && adaptive() && params.sample_start > 0u) {
        return gid.xy;
    }
    if gid.x < params.width && gid.y < params.row_count {
        let index = (params.out_row + gid.y) * params.row_stride + gid.x;
        if accumulated[index].w >= 0.0 {
            live_lanes[atomicAdd(&live_count, 1u)] = lid;
        }
    }
    workgroupBarrier();
    if lid >= atomicLoad(&live_count) {
        return vec2<u32>(params.width, 0u);
    }
    let own = live_lanes[lid];
    return vec2<u32>(wid.x * 8u + own % 8u, wid.y * 8u + own / 8u);
}

#if SAMPLES
// The samples a pixel takes (image.samples). Without SAMPLES (shaders/kernels.json: one sample)
// 1, and the loop over samples is not in the kernel.
fn pixel_samples() -> u32 {
    return params.samples;
}
#else
fn pixel_samples() -> u32 {
    return 1u;
}
#endif

#if CONE_TRACING
// Whether this pipeline traces a cone per block first. Without CONE_TRACING (shaders/kernels.json)
// false, and the cone is not in the kernel.
fn cone_tracing() -> bool {
    return params.tracing == TRACING_CONE;
}
#else
fn cone_tracing() -> bool {
    return false;
}
#endif

// One workgroup is one CONE_BLOCK x CONE_BLOCK block (bands start on block rows).
@compute @workgroup_size(8, 8, 1)
fn main(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let cone = cone_tracing();
    if cone {
        if lid == 0u {
            cone_t = cone_start(wid.x, params.row_offset / CONE_BLOCK + wid.y);
        }
        workgroupBarrier();
    }
    let t_min = select(0.0, cone_t, cone);
    // With compaction the block's live pixels, packed (the cone is the block's either way).
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
    let samples = pixel_samples();
    let no_aovs = Aovs(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, vec3<f32>(0.0), 0.0);
    // Where the lens is open, the depth and the steps are the pinhole ray's, traced for them.
    if params.sample_start == 0u && lens_open() {
        let pinhole = trace_primary(pinhole_ray(i, j, 0u, t_min));
        out_depth[index] = select(-1.0, pinhole.t, pinhole.hit);
        out_steps[index] = pinhole.steps;
    }
    if samples <= 1u {
        let pixel = trace_pixel(i, j, 0u, t_min);
        out_colour[index] = pack_colour(pixel.colour);
        if !lens_open() {
            out_depth[index] = select(-1.0, pixel.depth, pixel.hit);
            out_steps[index] = pixel.steps;
        }
        out_work[index] = add_work(vec4<u32>(0u));
        if AOVS {
            store_aovs(index, add_pixel_aovs(no_aovs, 0u, pixel));
        }
        return;
    }
    // This dispatch adds the samples [sample_start, sample_end) to the running mean of their
    // clamped colours, m_k = m_(k-1) + (c_k - m_(k-1)) / (k + 1), exact where every sample
    // has the same colour (adaptively, to the pixel's streams instead: add_to_streams); sample 0
    // gives the depth and the steps (where the lens is open, the pinhole ray's, traced above).
    var mean = vec3<Real>(0.0);
    var made = vec4<u32>(0u);
    var aovs = no_aovs;
    var streams = Streams(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    if params.sample_start > 0u {
        let held = accumulated[index];
        if adaptive() && held.w < 0.0 {
            return;
        }
        mean = vec3<Real>(held.xyz);
        made = out_work[index];
        if adaptive() {
            streams = load_streams(index);
        }
        if AOVS {
            aovs = load_aovs(index);
        }
    }
    // With INTERLEAVE 2 samples k and k + 1 are traced as a pair at k (trace_primary_pair), and
    // k + 1's trace kept for it; an odd sample left over is traced alone.
    var second = Trace(0.0, 0u, false, NO_APPROACH);
    var paired = false;
    var taken = 0u;
    for (var k = params.sample_start; k < params.sample_end; k++) {
        let ray = primary_ray(i, j, k, t_min);
        var trace: Trace;
        if paired {
            trace = second;
            paired = false;
        } else if INTERLEAVE >= 2u && k + 1u < params.sample_end {
            let pair = trace_primary_pair(ray, primary_ray(i, j, k + 1u, t_min));
            trace = pair.first;
            second = pair.second;
            paired = true;
        } else {
            trace = trace_primary(ray);
        }
        let pixel = shade_pixel(ray, trace);
        let c = clamp(pixel.colour, vec3<Real>(0.0), vec3<Real>(1.0));
        if k == 0u && !lens_open() {
            out_depth[index] = select(-1.0, pixel.depth, pixel.hit);
            out_steps[index] = pixel.steps;
        }
        if adaptive() {
            // The samples the pixel's colours hold, and whether this one joined them.
            let before = streams.rule_a.w + streams.b.w;
            streams = add_to_streams(streams, k, true, vec3<f32>(c));
            let n = streams.rule_a.w + streams.b.w;
            if AOVS && n > before {
                aovs = add_pixel_aovs(aovs, u32(n) - 1u, pixel);
            }
            if sampling_done(streams, k + 1u) {
                taken = k + 1u;
                break;
            }
        } else {
            mean += (c - mean) / Real(k + 1u);
            if AOVS {
                aovs = add_pixel_aovs(aovs, k, pixel);
            }
        }
    }
    if adaptive() {
        if AOVS && taken > 0u {
            aovs = finish_aovs(aovs, streams, taken);
        }
        store_streams(index, streams, taken);
        mean = vec3<Real>(streams_mean(streams));
    } else {
        accumulated[index] = vec4<f32>(vec3<f32>(mean), 0.0);
    }
    if AOVS {
        store_aovs(index, aovs);
    }
    out_work[index] = add_work(made);
    out_colour[index] = pack_colour(mean);
}
