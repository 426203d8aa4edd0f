// The f64 prelude (shaders/real.wgsl imports it with the feature F64): the float type `Real` of
// shaders/algebra.wgsl, trace.wgsl and julia2d.wgsl is f64, with its limits, and the functions
// those files take through `real_*` are built from what f64 reliably has on the GPU. Twin of
// shaders/real32.wgsl, the same names in the same order.
//
// Vulkan's GLSL.std.450 defines log, exp, sin, cos and pow for 16- and 32-bit floats only, and
// lavapipe returns wrong f64 values for them without an error. So nothing here calls them on an
// f64: the logarithm is a polynomial in f64 after the exponent is split off, and the
// shading's pow and cos go through f32, on arguments that stay in f32's range. sqrt, division,
// the exponent's split and the conversions are checked on each device at start-up (src/gpu/f64check.rs, which
// runs shaders/f64check.wgsl after this file); where the adapter's sqrt fails that check,
// SQRT_NEWTON replaces it.

alias Real = f64;

// As in real32.wgsl, for f64 (twins: `<f64 as Real>::DERIVATIVE_LIMIT`, `RELATIVE_EPSILON`,
// `f64::MIN_POSITIVE`).
const DERIVATIVE_LIMIT: Real = 1e200;
const RELATIVE_EPSILON: Real = 1.7763568394002505e-15;
const MIN_NORMAL: Real = 2.2250738585072014e-308;

// Set by the start-up check where the adapter's f64 sqrt is wrong: real_sqrt is then an f32
// sqrt of the mantissa and two f64 Newton steps.
override SQRT_NEWTON: bool = false;

const LN2: Real = 0.6931471805599453;
const SQRT_HALF: Real = 0.7071067811865476;
const SQRT_TWO: Real = 1.4142135623730951;

// x = m 2^e with m in [sqrt(1/2), sqrt(2)) and e an integer, for a normal x > 0, as (m, e): by
// exact scalings with powers of two, a binary search of the exponent. (WGSL's frexp of an f64
// gives an i64 exponent, which needs 64-bit integers on the device.)
fn split_exponent(x: Real) -> vec2<Real> {
    var m = x;
    var e: Real = 0.0;
    if m < 0x1p-512 {
        m *= 0x1p512;
        e -= 512.0;
    }
    if m < 0x1p-256 {
        m *= 0x1p256;
        e -= 256.0;
    }
    if m < 0x1p-128 {
        m *= 0x1p128;
        e -= 128.0;
    }
    if m < 0x1p-64 {
        m *= 0x1p64;
        e -= 64.0;
    }
    if m < 0x1p-32 {
        m *= 0x1p32;
        e -= 32.0;
    }
    if m < 0x1p-16 {
        m *= 0x1p16;
        e -= 16.0;
    }
    if m < 0x1p-8 {
        m *= 0x1p8;
        e -= 8.0;
    }
    if m < 0x1p-4 {
        m *= 0x1p4;
        e -= 4.0;
    }
    if m < 0x1p-2 {
        m *= 0x1p2;
        e -= 2.0;
    }
    if m < 0x1p-1 {
        m *= 0x1p1;
        e -= 1.0;
    }
    if m >= 0x1p512 {
        m *= 0x1p-512;
        e += 512.0;
    }
    if m >= 0x1p256 {
        m *= 0x1p-256;
        e += 256.0;
    }
    if m >= 0x1p128 {
        m *= 0x1p-128;
        e += 128.0;
    }
    if m >= 0x1p64 {
        m *= 0x1p-64;
        e += 64.0;
    }
    if m >= 0x1p32 {
        m *= 0x1p-32;
        e += 32.0;
    }
    if m >= 0x1p16 {
        m *= 0x1p-16;
        e += 16.0;
    }
    if m >= 0x1p8 {
        m *= 0x1p-8;
        e += 8.0;
    }
    if m >= 0x1p4 {
        m *= 0x1p-4;
        e += 4.0;
    }
    if m >= 0x1p2 {
        m *= 0x1p-2;
        e += 2.0;
    }
    if m >= 0x1p1 {
        m *= 0x1p-1;
        e += 1.0;
    }
    if m >= SQRT_TWO {
        m *= 0.5;
        e += 1.0;
    } else if m < SQRT_HALF {
        m *= 2.0;
        e -= 1.0;
    }
    return vec2<Real>(m, e);
}

// 2^n for an integer n with |n| < 1024 (exact).
fn pow2(n: Real) -> Real {
    var r: Real = 1.0;
    var k = abs(n);
    if k >= 512.0 {
        r *= 0x1p512;
        k -= 512.0;
    }
    if k >= 256.0 {
        r *= 0x1p256;
        k -= 256.0;
    }
    if k >= 128.0 {
        r *= 0x1p128;
        k -= 128.0;
    }
    if k >= 64.0 {
        r *= 0x1p64;
        k -= 64.0;
    }
    if k >= 32.0 {
        r *= 0x1p32;
        k -= 32.0;
    }
    if k >= 16.0 {
        r *= 0x1p16;
        k -= 16.0;
    }
    if k >= 8.0 {
        r *= 0x1p8;
        k -= 8.0;
    }
    if k >= 4.0 {
        r *= 0x1p4;
        k -= 4.0;
    }
    if k >= 2.0 {
        r *= 0x1p2;
        k -= 2.0;
    }
    if k >= 1.0 {
        r *= 0x1p1;
        k -= 1.0;
    }
    if n < 0.0 {
        return 1.0 / r;
    }
    return r;
}

// sqrt(x) for x >= 0 without the adapter's f64 sqrt: x = m 2^e with e even and m in
// [sqrt(1/2), 2 sqrt(2)), an f32 sqrt of m (7 digits), two Newton steps y <- (y + m / y) / 2
// (each doubles the digits), then 2^(e/2).
fn sqrt_newton(x: Real) -> Real {
    if x < MIN_NORMAL {
        return 0.0;
    }
    let split = split_exponent(x);
    var m = split.x;
    var e = split.y;
    if e != 2.0 * floor(0.5 * e) {
        m *= 2.0;
        e -= 1.0;
    }
    var y = Real(sqrt(f32(m)));
    y = 0.5 * (y + m / y);
    y = 0.5 * (y + m / y);
    return y * pow2(0.5 * e);
}

fn real_sqrt(x: Real) -> Real {
    if SQRT_NEWTON {
        return sqrt_newton(x);
    }
    return sqrt(x);
}

// ln(x) for a normal x > 0 (estimate_julia takes no log below MIN_NORMAL): x = m 2^e with m in
// [sqrt(1/2), sqrt(2)) (split_exponent), ln x = e ln 2 + 2 atanh(s), s = (m - 1) / (m + 1),
// |s| <= 0.1716, and 2 atanh(s) = 2 (s + s^3 / 3 + ... + s^23 / 23): the first term left out is
// below 1e-18 of the sum. An f32 log of m would do for most x, but not near x = 1 (a |z|^2 near
// 1 at a deep zoom), where it would lose every digit of ln x: the series keeps them, relative to
// ln x itself.
fn real_log(x: Real) -> Real {
    let split = split_exponent(x);
    let m = split.x;
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    var sum: Real = 1.0 / 23.0;
    sum = sum * s2 + 1.0 / 21.0;
    sum = sum * s2 + 1.0 / 19.0;
    sum = sum * s2 + 1.0 / 17.0;
    sum = sum * s2 + 1.0 / 15.0;
    sum = sum * s2 + 1.0 / 13.0;
    sum = sum * s2 + 1.0 / 11.0;
    sum = sum * s2 + 1.0 / 9.0;
    sum = sum * s2 + 1.0 / 7.0;
    sum = sum * s2 + 1.0 / 5.0;
    sum = sum * s2 + 1.0 / 3.0;
    sum = sum * s2 + 1.0;
    return split.y * LN2 + 2.0 * s * sum;
}

// The shading's highlight max(E.R, 0)^shininess: x in (0, 1], in f32 (a colour needs no more).
fn real_pow(x: Real, y: Real) -> Real {
    return Real(pow(f32(x), f32(y)));
}

// The palette's cos, of 2 pi times a fraction: in f32.
fn real_cos(v: vec3<Real>) -> vec3<Real> {
    return vec3<Real>(cos(vec3<f32>(v)));
}

// v / |v| with real_sqrt (the adapter's normalize is not checked).
fn real_normalize(v: vec3<Real>) -> vec3<Real> {
    return v / real_sqrt(dot(v, v));
}
