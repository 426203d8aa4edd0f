// Quaternion arithmetic for the tracer. A quaternion is a vec4<f32>: x is the real part,
// (y, z, w) the i, j, k parts, as in the scene file's [real, i, j, k].
// Twin: src/algebra.rs (`quat_mul`, `quat_sq`), same names, same order of terms.

// The quaternion product a b (not commutative: a b != b a in general).
fn quat_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        a.x * b.x - dot(a.yzw, b.yzw),
        a.x * b.yzw + b.x * a.yzw + cross(a.yzw, b.yzw),
    );
}

// The quaternion square q q: the cross product of the imaginary part with itself vanishes.
fn quat_sq(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(q.x * q.x - dot(q.yzw, q.yzw), 2.0 * q.x * q.yzw);
}
