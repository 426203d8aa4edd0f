// The f32 prelude (shaders/real.wgsl imports it without the feature F64): the float type `Real` of shaders/algebra.wgsl, trace.wgsl and julia2d.wgsl is
// f32, with its limits, and the functions those files take through `real_*` are WGSL's own
// builtins, so that an f32 scene runs exactly what it ran before f64 came (src/gpu/shaders.rs).
// Its twin for f64 is shaders/real64.wgsl: the same names in the same order.

alias Real = f32;

// |z'|^2 above this: iterating stops before z' can overflow, and the estimate is taken as 0.
// With |z|^2 <= escape_radius_squared <= 1e8 (the host clamps it for f32) the true estimate
// there is below 0.25 sqrt(1e8 / 1e28) ln(1e8) = 5e-10, and one more step gives
// |z'|^2 <= 4e36, still finite. (Twin: `Real::DERIVATIVE_LIMIT`.)
const DERIVATIVE_LIMIT: Real = 1e28;
// A hit needs d below epsilon, or below this fraction of t: the spacing of floats at t (8 ulps),
// under which a step no longer moves the ray.
const RELATIVE_EPSILON: Real = 9.5367431640625e-7;
// The smallest normal f32: a |z|^2 below it is 0 for the estimate (no log of it is taken).
const MIN_NORMAL: Real = 1.17549435e-38;

fn real_sqrt(x: Real) -> Real {
    return sqrt(x);
}

fn real_log(x: Real) -> Real {
    return log(x);
}

fn real_pow(x: Real, y: Real) -> Real {
    return pow(x, y);
}

fn real_cos(v: vec3<Real>) -> vec3<Real> {
    return cos(v);
}

fn real_normalize(v: vec3<Real>) -> vec3<Real> {
    return normalize(v);
}
