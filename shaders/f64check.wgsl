// The start-up check of the adapter's f64 (src/gpu/f64check.rs): every f64 operation the f64
// kernels rely on, on a few known values, for the host to compare with its own. It imports
// shaders/real64.wgsl (the kernels' own `real_*` functions, with the repairs the host chose as
// its override constants). One invocation per case.
#import real64

// Keep in sync with `CheckParams` in src/gpu/f64check.rs.
struct CheckParams {
    // Each case's operands (a, b) in x and y.
    cases: array<vec4<f64>, 8>,
    count: u32,
}

// The operations, in the order of their results (`OPS` in src/gpu/f64check.rs).
const OP_ADD: u32 = 0u;
const OP_SUB: u32 = 1u;
const OP_MUL: u32 = 2u;
const OP_DIV: u32 = 3u;
const OP_SQRT: u32 = 4u;
const OP_REAL_SQRT: u32 = 5u;
const OP_REAL_LOG: u32 = 6u;
const OP_SPLIT_MANTISSA: u32 = 7u;
const OP_SPLIT_EXPONENT: u32 = 8u;
const OP_POW2: u32 = 9u;
const OP_TO_F32: u32 = 10u;
const OP_FROM_U32: u32 = 11u;
const OP_FLOOR: u32 = 12u;
const OP_FRACT: u32 = 13u;
const OP_ABS: u32 = 14u;
const OP_MIN: u32 = 15u;
const OP_MAX: u32 = 16u;
const OP_LESS: u32 = 17u;
const OP_REAL_POW: u32 = 18u;
const OP_REAL_COS: u32 = 19u;
const OP_REAL_NORMALIZE: u32 = 20u;
const OPS: u32 = 21u;

// The test hook: 1 + the operation whose result is made wrong on purpose (0: none), so that a
// test can see the check fail loudly. The host sets it from QJULIA_F64_CHECK_INJECT only.
override INJECT: u32 = 0u;

@group(0) @binding(0) var<uniform> check: CheckParams;
// Case k's result of operation op at k * OPS + op.
@group(0) @binding(1) var<storage, read_write> results: array<f64>;

// The operation's result, made wrong (by a relative 1e-9 and 1) when it is the injected one.
fn injected(op: u32, r: f64) -> f64 {
    if INJECT == op + 1u {
        return r * (1.0 + 1e-9) + 1.0;
    }
    return r;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= check.count || id.y != 0u {
        return;
    }
    let a = check.cases[k].x;
    let b = check.cases[k].y;
    let base = k * OPS;
    let split = split_exponent(abs(a));
    results[base + OP_ADD] = injected(OP_ADD, a + b);
    results[base + OP_SUB] = injected(OP_SUB, a - b);
    results[base + OP_MUL] = injected(OP_MUL, a * b);
    results[base + OP_DIV] = injected(OP_DIV, a / b);
    results[base + OP_SQRT] = injected(OP_SQRT, sqrt(abs(a)));
    results[base + OP_REAL_SQRT] = injected(OP_REAL_SQRT, real_sqrt(abs(a)));
    results[base + OP_REAL_LOG] = injected(OP_REAL_LOG, real_log(abs(a)));
    results[base + OP_SPLIT_MANTISSA] = injected(OP_SPLIT_MANTISSA, split.x);
    results[base + OP_SPLIT_EXPONENT] = injected(OP_SPLIT_EXPONENT, split.y);
    results[base + OP_POW2] = injected(OP_POW2, a * pow2(f64(k) * 150.0 - 600.0));
    results[base + OP_TO_F32] = injected(OP_TO_F32, f64(f32(a)));
    results[base + OP_FROM_U32] = injected(OP_FROM_U32, f64(k * 1000003u + 7u));
    results[base + OP_FLOOR] = injected(OP_FLOOR, floor(a));
    results[base + OP_FRACT] = injected(OP_FRACT, fract(a));
    results[base + OP_ABS] = injected(OP_ABS, abs(a));
    results[base + OP_MIN] = injected(OP_MIN, min(a, b));
    results[base + OP_MAX] = injected(OP_MAX, max(a, b));
    results[base + OP_LESS] = injected(OP_LESS, select(f64(0.0), f64(1.0), a < b));
    results[base + OP_REAL_POW] = injected(OP_REAL_POW, real_pow(fract(abs(a)), 10.0));
    results[base + OP_REAL_COS] = injected(OP_REAL_COS, real_cos(vec3<f64>(fract(a))).x);
    let v = real_normalize(vec3<f64>(a, b, 1.0));
    results[base + OP_REAL_NORMALIZE] = injected(OP_REAL_NORMALIZE, v.x);
}
