// Hypercomplex arithmetic for the tracer. A quaternion is a vec4<Real>: x is the real part,
// (y, z, w) the i, j, k parts, as in the scene file's [real, i, j, k]. Octonions and sedenions
// come from quaternions by the Cayley-Dickson construction: an octonion is a pair (a, b) of
// quaternions, a sedenion a pair of octonions, with the product
// (a, b)(c, d) = (a c - conj(d) b, d a + b conj(c)) and conj((a, b)) = (conj(a), -b).
// Twin: src/algebra.rs, same names, same order of terms, same order of functions (checked by
// tests/architecture/twins.rs).
#import real

// The quaternion product a b (not commutative: a b != b a in general). (The seed's quatMult.)
fn quat_mul(a: vec4<Real>, b: vec4<Real>) -> vec4<Real> {
    return vec4<Real>(
        a.x * b.x - dot(a.yzw, b.yzw),
        a.x * b.yzw + b.x * a.yzw + cross(a.yzw, b.yzw),
    );
}

// The quaternion square q q: the cross product of the imaginary part with itself vanishes.
// (The seed's quatSq.) The real part's products are fused multiply-adds (fma): the iteration is
// a chain of dependent arithmetic, and each fusion takes a step off it (6% of a render on
// lavapipe, docs/PERFORMANCE.md). The CPU twin rounds each product: the two agree to rounding.
fn quat_sq(q: vec4<Real>) -> vec4<Real> {
    let v2 = fma(q.y, q.y, fma(q.z, q.z, q.w * q.w));
    return vec4<Real>(fma(q.x, q.x, -v2), 2.0 * q.x * q.yzw);
}

fn quat_conj(q: vec4<Real>) -> vec4<Real> {
    return vec4<Real>(q.x, -q.yzw);
}

// A number of the scene's algebra as quaternion parts: part 0 alone for a quaternion, parts 0-1
// for an octonion (a, b), all four for a sedenion ((p0, p1), (p2, p3)); unused parts are 0.
alias Hyper = array<vec4<Real>, 4>;

// An octonion as its two quaternion halves.
struct Octonion {
    a: vec4<Real>,
    b: vec4<Real>,
}

fn oct_mul(x: Octonion, y: Octonion) -> Octonion {
    return Octonion(
        quat_mul(x.a, y.a) - quat_mul(quat_conj(y.b), x.b),
        quat_mul(y.b, x.a) + quat_mul(x.b, quat_conj(y.a)),
    );
}

fn oct_conj(x: Octonion) -> Octonion {
    return Octonion(quat_conj(x.a), -x.b);
}

// The octonion square (a, b)^2 = (a^2 - |b|^2, 2 Re(a) b): conj(b) b = |b|^2 and
// b a + b conj(a) = 2 Re(a) b, so no product is needed.
fn oct_sq(x: Octonion) -> Octonion {
    return Octonion(quat_sq(x.a) - vec4<Real>(dot(x.b, x.b), 0.0, 0.0, 0.0), 2.0 * x.a.x * x.b);
}

// The product x y of two numbers with `parts` quaternion parts (1, 2 or 4).
fn hyper_mul(x: Hyper, y: Hyper, parts: u32) -> Hyper {
    if parts == 1u {
        return Hyper(quat_mul(x[0], y[0]), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    }
    let xa = Octonion(x[0], x[1]);
    let ya = Octonion(y[0], y[1]);
    if parts == 2u {
        let p = oct_mul(xa, ya);
        return Hyper(p.a, p.b, vec4<Real>(0.0), vec4<Real>(0.0));
    }
    // Sedenions: (A, B)(C, D) = (A C - conj(D) B, D A + B conj(C)) over octonions.
    let xb = Octonion(x[2], x[3]);
    let yb = Octonion(y[2], y[3]);
    let ac = oct_mul(xa, ya);
    let db = oct_mul(oct_conj(yb), xb);
    let da = oct_mul(yb, xa);
    let bc = oct_mul(xb, oct_conj(ya));
    return Hyper(ac.a - db.a, ac.b - db.b, da.a + bc.a, da.b + bc.b);
}

// The square x x, by (A, B)^2 = (A^2 - |B|^2, 2 Re(A) B) at each level of the construction.
fn hyper_sq(x: Hyper, parts: u32) -> Hyper {
    if parts == 1u {
        return Hyper(quat_sq(x[0]), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    }
    let a = oct_sq(Octonion(x[0], x[1]));
    if parts == 2u {
        return Hyper(a.a, a.b, vec4<Real>(0.0), vec4<Real>(0.0));
    }
    let b_squared = dot(x[2], x[2]) + dot(x[3], x[3]);
    let re = 2.0 * x[0].x;
    return Hyper(a.a - vec4<Real>(b_squared, 0.0, 0.0, 0.0), a.b, re * x[2], re * x[3]);
}

// The Euclidean inner product of the first `parts` parts, part 0's by fused multiply-adds (as
// quat_sq). (No loops and only constant indices in this file: a specialised pipeline then keeps
// a quaternion in registers, with the unused parts folded away.)
fn hyper_dot(x: Hyper, y: Hyper, parts: u32) -> Real {
    var sum = fma(x[0].x, y[0].x, fma(x[0].y, y[0].y, fma(x[0].z, y[0].z, x[0].w * y[0].w)));
    if parts >= 2u {
        sum += dot(x[1], y[1]);
    }
    if parts >= 4u {
        sum += dot(x[2], y[2]);
        sum += dot(x[3], y[3]);
    }
    return sum;
}

fn hyper_add(x: Hyper, y: Hyper) -> Hyper {
    return Hyper(x[0] + y[0], x[1] + y[1], x[2] + y[2], x[3] + y[3]);
}

fn hyper_scale(s: Real, x: Hyper) -> Hyper {
    return Hyper(s * x[0], s * x[1], s * x[2], s * x[3]);
}

fn hyper_sub(x: Hyper, y: Hyper) -> Hyper {
    return Hyper(x[0] - y[0], x[1] - y[1], x[2] - y[2], x[3] - y[3]);
}

// The derivative of the square at z along j: z j + j z = 2 (Re(z) j + Re(j) z - <z, j>), the
// same in every Cayley-Dickson algebra (the linear part of (z + j)^2 = 2 Re(z + j)(z + j) -
// |z + j|^2), written so that for quaternions it is 2 (z.x j.x - z.yzw . j.yzw,
// z.x j.yzw + j.x z.yzw).
fn square_derivative(z: Hyper, j: Hyper, parts: u32) -> Hyper {
    var inner = dot(z[0].yzw, j[0].yzw);
    if parts >= 2u {
        inner += dot(z[1], j[1]);
    }
    if parts >= 4u {
        inner += dot(z[2], j[2]);
        inner += dot(z[3], j[3]);
    }
    var out = Hyper(
        vec4<Real>(z[0].x * j[0].x - inner, z[0].x * j[0].yzw + j[0].x * z[0].yzw),
        vec4<Real>(0.0),
        vec4<Real>(0.0),
        vec4<Real>(0.0),
    );
    if parts >= 2u {
        out[1] = z[0].x * j[1] + j[0].x * z[1];
    }
    if parts >= 4u {
        out[2] = z[0].x * j[2] + j[0].x * z[2];
        out[3] = z[0].x * j[3] + j[0].x * z[3];
    }
    return hyper_scale(2.0, out);
}
