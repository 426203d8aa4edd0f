// The 2D Julia view (`qjulia render2d`, the explorer's 2D mode): the filled Julia set of the
// complex c, grey by smooth iteration count as in Crane's Figure 3. One invocation per pixel.
//
// Twin: src/cpu/julia2d.rs, function by function, with the same names in the same order (checked
// by tests/architecture/twins.rs, which lists the functions only one side has); a change to one is a change to
// both. Written against the float type `Real` of shaders/real.wgsl: z and the pixel's
// point in `Real`, the grey in f32 (src/gpu/shaders.rs).
//
// WGSL may assume NaN and Inf never occur, so every guard comes before the operation it guards.
#import real

// Keep in sync with the table of `Julia2dParams` in src/params.rs, which makes the host's f32 and
// f64 images of it, `GpuJulia2dParams` and `GpuJulia2dParams64` (tests/architecture/shaders.rs compares their
// layouts with this struct's). The last four are each dispatch's: its band and where it lands.
struct Julia2dParams {
    c: vec2<Real>,
    center: vec2<Real>,
    // Half the width and half the height of the image in the complex plane.
    half_extent: vec2<Real>,
    max_iterations: u32,
    width: u32,
    height: u32,
    row_offset: u32,
    row_count: u32,
    row_stride: u32,
    out_row: u32,
}

// |z|^2 above this counts as escaped: |z| > 16, far enough out that the smooth count is smooth
// (above 2, the escape radius of every c with |c| <= 2, the orbit only grows).
const BAILOUT_SQUARED: Real = 256.0;
// The same in f32, for the grey.
const BAILOUT_SQUARED_F32: f32 = 256.0;

@group(0) @binding(0) var<uniform> params: Julia2dParams;
// RGBA8 packed 0xFFBBGGRR, grey.
@group(0) @binding(1) var<storage, read_write> out_colour: array<u32>;
// 0 for a point in the set, -1 for one that escapes (as the tracer's depth marks a miss).
@group(0) @binding(2) var<storage, read_write> out_depth: array<Real>;
// Iterations of z <- z^2 + c made.
@group(0) @binding(3) var<storage, read_write> out_steps: array<u32>;

// z^2 for z = x + y i.
fn complex_sq(z: vec2<Real>) -> vec2<Real> {
    return vec2<Real>(z.x * z.x - z.y * z.y, 2.0 * z.x * z.y);
}

// The complex number at the centre of pixel (i, j), row 0 at the top: the imaginary axis points up.
fn pixel_point(i: u32, j: u32) -> vec2<Real> {
    let x = (2.0 * (Real(i) + 0.5) / Real(params.width) - 1.0) * params.half_extent.x;
    let y = (1.0 - 2.0 * (Real(j) + 0.5) / Real(params.height)) * params.half_extent.y;
    return params.center + vec2<Real>(x, y);
}

struct Escape {
    // The last z reached: the first with |z|^2 > BAILOUT_SQUARED when escaped.
    z: vec2<Real>,
    // Iterations made.
    n: u32,
    escaped: bool,
}

// Iterates z <- z^2 + c from z0, testing |z|^2 > BAILOUT_SQUARED before each iteration:
// z_0, ..., z_max_iterations are tested, and a point none of them escapes is in the set.
fn escape(z0: vec2<Real>) -> Escape {
    var z = z0;
    var n = 0u;
    var escaped = false;
    loop {
        if dot(z, z) > BAILOUT_SQUARED {
            escaped = true;
            break;
        }
        if n >= params.max_iterations {
            break;
        }
        z = complex_sq(z) + params.c;
        n = n + 1u;
    }
    return Escape(z, n, escaped);
}

// The smooth iteration count of an escaped point, n - log2(ln|z_n| / ln 16), clamped at 0:
// n where |z_n| is just above 16, continuous across n (z_n squares from one n to the next).
fn smooth_count(e: Escape) -> f32 {
    // In f32 whatever the precision: |z|^2 is just past the bailout, and a grey needs no more.
    let ratio = log(f32(dot(e.z, e.z))) / log(BAILOUT_SQUARED_F32);
    return max(f32(e.n) - log2(ratio), 0.0);
}

// Grey of a point: ln(1 + smooth count) / ln(1 + max_iterations), 0 (black) for a point that
// escapes at once, 1 (white) for one in the set.
fn grey(e: Escape) -> f32 {
    if !e.escaped {
        return 1.0;
    }
    return min(log(1.0 + smooth_count(e)) / log(1.0 + f32(params.max_iterations)), 1.0);
}

// Grey clamped to [0, 1], times 255, rounded half up, packed as RGBA8 0xFFBBGGRR (opaque).
fn pack_grey(g: f32) -> u32 {
    let v = u32(floor(clamp(g, 0.0, 1.0) * 255.0 + 0.5));
    return v | (v << 8u) | (v << 16u) | 0xff000000u;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let r = id.y;
    if i >= params.width || r >= params.row_count {
        return;
    }
    let e = escape(pixel_point(i, params.row_offset + r));
    let k = (params.out_row + r) * params.row_stride + i;
    out_colour[k] = pack_grey(grey(e));
    out_depth[k] = select(Real(-1.0), Real(0.0), !e.escaped);
    out_steps[k] = e.n;
}
