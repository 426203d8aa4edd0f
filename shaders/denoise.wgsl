// The denoiser (image.denoise = "atrous"): one pass of an edge-avoiding a-trous wavelet filter
// (Dammertz et al. 2010), with SVGF's edge-stopping functions and variance (Schied et al.
// 2017). The host demodulates the linear image by the albedo AOV before the first pass and
// multiplies it back after the last (src/denoise.rs); each pass here filters the illumination
// and its variance with a 5 x 5 B3-spline kernel whose taps lie `step` pixels apart, each tap
// weighted by how alike its normal, depth and luminance are to the centre's. The book's chapter
// "Denoising" (docs/book/denoise.md) gives the filter exactly.
//
// Twin: src/cpu/denoise.rs, same names, same order (tests/architecture/twins.rs). A module of its own: it
// needs no other file.

// The pass's parameters (keep in sync with `GpuDenoiseParams` in src/gpu/denoise.rs; the CPU
// twin's are `DenoiseParams` in src/cpu/denoise.rs).
struct DenoiseParams {
    width: u32,
    height: u32,
    // The taps' spacing in pixels, 2^pass.
    step: u32,
    // 0: read image_a, write image_b; 1: the other way.
    source: u32,
    sigma_luminance: f32,
    sigma_normal: f32,
    sigma_depth: f32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> params: DenoiseParams;
// Each pixel's illumination (the linear colour over the albedo) and the variance of its
// luminance: one is read, the other written (params.source).
@group(0) @binding(1) var<storage, read_write> image_a: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> image_b: array<vec4<f32>>;
// Each pixel's guide: the mean shading normal of its hits, and its depth (sample 0's t; -1 where
// its primary ray missed).
@group(0) @binding(3) var<storage, read_write> guide: array<vec4<f32>>;

// A relative floor on the depth test's scale (of the centre's depth): a surface seen face on has
// no depth slope, and its neighbours' depths differ by the rounding of t.
const DEPTH_EPSILON: f32 = 1e-3;
// A floor on the luminance test's scale, where the variance is 0.
const LUMINANCE_EPSILON: f32 = 1e-10;

// Rec. 709 luminance of a linear colour (as shaders/bsdf.wgsl's).
fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// The B3-spline's weight of tap k in -2..2: 1/16, 1/4, 3/8, 1/4, 1/16.
fn spline_tap(k: i32) -> f32 {
    let a = abs(k);
    if a == 0 {
        return 0.375;
    }
    if a == 1 {
        return 0.25;
    }
    return 0.0625;
}

fn load_image(index: u32) -> vec4<f32> {
    if params.source == 0u {
        return image_a[index];
    }
    return image_b[index];
}

fn store_image(index: u32, v: vec4<f32>) {
    if params.source == 0u {
        image_b[index] = v;
    } else {
        image_a[index] = v;
    }
}

// Whether a guide is a hit's (its depth is not the miss marker).
fn guide_hit(g: vec4<f32>) -> bool {
    return g.w >= 0.0;
}

// The depth of pixel (i, j), or -1 outside the image or where it missed.
fn depth_at(i: i32, j: i32) -> f32 {
    if i < 0 || j < 0 || i >= i32(params.width) || j >= i32(params.height) {
        return -1.0;
    }
    return guide[u32(j) * params.width + u32(i)].w;
}

// The change of depth per pixel at (i, j) along x and y: the central difference where both
// neighbours hit, one-sided where one does, 0 where none does (or the centre missed).
fn depth_slope(i: i32, j: i32) -> vec2<f32> {
    let z = depth_at(i, j);
    if z < 0.0 {
        return vec2<f32>(0.0);
    }
    return vec2<f32>(
        axis_slope(depth_at(i - 1, j), z, depth_at(i + 1, j)),
        axis_slope(depth_at(i, j - 1), z, depth_at(i, j + 1)),
    );
}

fn axis_slope(before: f32, z: f32, after: f32) -> f32 {
    if before >= 0.0 && after >= 0.0 {
        return 0.5 * (after - before);
    }
    if after >= 0.0 {
        return after - z;
    }
    if before >= 0.0 {
        return z - before;
    }
    return 0.0;
}

// The variance at (i, j) blurred by a 3 x 3 binomial kernel (1 2 1 / 4 each way) over the
// pixels inside the image, renormalised: SVGF's prefilter. The pass takes the smaller of it and
// the pixel's own: a firefly's variance, blurred, would open its neighbours to it and spread it.
fn blurred_variance(i: i32, j: i32) -> f32 {
    var sum = 0.0;
    var weights = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let x = i + dx;
            let y = j + dy;
            if x < 0 || y < 0 || x >= i32(params.width) || y >= i32(params.height) {
                continue;
            }
            let w = select(0.5, 1.0, dx == 0) * select(0.5, 1.0, dy == 0);
            sum += w * load_image(u32(y) * params.width + u32(x)).w;
            weights += w;
        }
    }
    return sum / weights;
}

// A vector of length 1 along v, or 0 where v is 0.
fn unit_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if l > 0.0 {
        return v / l;
    }
    return vec3<f32>(0.0);
}

// How alike a tap's geometry is to the centre's: 0 between a hit and a miss, 1 between two
// misses; between two hits the normals' cosine to the power sigma_normal, times
// exp(-|z_p - z_q| / (sigma_depth |slope . offset| + DEPTH_EPSILON z_p)).
fn geometry_weight(p: vec4<f32>, q: vec4<f32>, slope: vec2<f32>, offset: vec2<f32>) -> f32 {
    let hit = guide_hit(p);
    if hit != guide_hit(q) {
        return 0.0;
    }
    if !hit {
        return 1.0;
    }
    var w = 1.0;
    if params.sigma_normal > 0.0 {
        let c = dot(unit_or_zero(p.xyz), unit_or_zero(q.xyz));
        if c <= 0.0 {
            return 0.0;
        }
        w = pow(c, params.sigma_normal);
    }
    if params.sigma_depth > 0.0 {
        let scale = params.sigma_depth * abs(dot(slope, offset)) + DEPTH_EPSILON * p.w;
        w *= exp(-abs(p.w - q.w) / max(scale, 1e-30));
    }
    return w;
}

// How alike a tap's luminance is to the centre's, in standard deviations of the centre's noise:
// exp(-|l_p - l_q| / (sigma_luminance sd + LUMINANCE_EPSILON)).
fn luminance_weight(lp: f32, lq: f32, sd: f32) -> f32 {
    if params.sigma_luminance <= 0.0 {
        return 1.0;
    }
    return exp(-abs(lp - lq) / (params.sigma_luminance * sd + LUMINANCE_EPSILON));
}

// One workgroup is 8 x 8 pixels. Pixel (i, j)'s illumination becomes the weighted mean of its 5 x
// 5 taps (the centre's weight is its spline weight alone), and its variance the taps' variances
// weighted by the squared weights over the squared sum.
@compute @workgroup_size(8, 8, 1)
fn atrous_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.height {
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let index = gid.y * params.width + gid.x;
    let centre = load_image(index);
    let g = guide[index];
    let slope = depth_slope(i, j);
    let sd = sqrt(min(blurred_variance(i, j), centre.w));
    let lp = luminance(centre.xyz);
    let step = i32(params.step);
    var sum = vec3<f32>(0.0);
    var weights = 0.0;
    var variance = 0.0;
    for (var dy = -2; dy <= 2; dy++) {
        for (var dx = -2; dx <= 2; dx++) {
            let x = i + dx * step;
            let y = j + dy * step;
            if x < 0 || y < 0 || x >= i32(params.width) || y >= i32(params.height) {
                continue;
            }
            let q_index = u32(y) * params.width + u32(x);
            let q = load_image(q_index);
            var w = spline_tap(dx) * spline_tap(dy);
            if dx != 0 || dy != 0 {
                let offset = vec2<f32>(f32(dx * step), f32(dy * step));
                w *= geometry_weight(g, guide[q_index], slope, offset);
                w *= luminance_weight(lp, luminance(q.xyz), sd);
            }
            sum += w * q.xyz;
            weights += w;
            variance += w * w * q.w;
        }
    }
    store_image(index, vec4<f32>(sum / weights, variance / (weights * weights)));
}
