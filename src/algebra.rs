//! Small vector and hypercomplex arithmetic, generic over the float type (f32 or f64).
//!
//! The CPU tracer is written against these types so that it reads like the WGSL shader:
//! `Vec3` and `Vec4` play the parts of `vec3<f32>` and `vec4<f32>`, and a quaternion is a
//! `Vec4` with `x` the real part and `(y, z, w)` the i, j, k parts, exactly as in
//! `shaders/algebra.wgsl`. The functions from the line "twins of shaders/algebra.wgsl" on (the
//! quaternion, octonion and [`Hyper`] arithmetic) are that file's twins, with the same names in
//! the same order: tests/architecture/twins.rs checks it, and lists the ones only this side has.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use num_traits::Float;

/// The float types the reference tracer runs in: f32 (the GPU's precision) and f64.
pub trait Real: Float + Debug + Default + Send + Sync + 'static {
    /// Short name used in outputs ("f32" or "f64").
    const NAME: &'static str;
    /// The largest escape radius squared this precision iterates without overflow (with
    /// `DERIVATIVE_LIMIT`); larger settings are clamped to it.
    const ESCAPE_LIMIT: f64;
    /// |z'|^2 above this: iterating stops before z' overflows, and the estimate is taken as 0.
    /// Sound because it is far above ESCAPE_LIMIT: the true estimate there is below
    /// 0.25 sqrt(ESCAPE_LIMIT / DERIVATIVE_LIMIT) ln(ESCAPE_LIMIT) (5e-10 in f32, 6e-49 in f64),
    /// and one more step, 4 ESCAPE_LIMIT DERIVATIVE_LIMIT, stays finite.
    const DERIVATIVE_LIMIT: f64;
    /// 8 ulps: below `t` times this a sphere-tracing step no longer moves the ray (WGSL's
    /// RELATIVE_EPSILON for f32).
    const RELATIVE_EPSILON: f64;
    /// A literal or host-side value converted to this precision (rounded to nearest).
    fn lit(x: f64) -> Self;
    /// This value widened to f64.
    fn to_f64(self) -> f64;
}

impl Real for f32 {
    const NAME: &'static str = "f32";
    const ESCAPE_LIMIT: f64 = 1e8;
    const DERIVATIVE_LIMIT: f64 = 1e28;
    const RELATIVE_EPSILON: f64 = 8.0 * f32::EPSILON as f64;
    fn lit(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    const NAME: &'static str = "f64";
    const ESCAPE_LIMIT: f64 = 1e100;
    const DERIVATIVE_LIMIT: f64 = 1e200;
    const RELATIVE_EPSILON: f64 = 8.0 * f64::EPSILON;
    fn lit(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
}

/// A 2-vector, the twin of WGSL's `vec2<f32>`; as a complex number `x` is the real part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec2<F> {
    pub x: F,
    pub y: F,
}

/// A 3-vector, the twin of WGSL's `vec3<f32>`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3<F> {
    pub x: F,
    pub y: F,
    pub z: F,
}

/// A 4-vector, the twin of WGSL's `vec4<f32>`; as a quaternion `x` is the real part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec4<F> {
    pub x: F,
    pub y: F,
    pub z: F,
    pub w: F,
}

impl<F: Real> Vec2<F> {
    pub const fn new(x: F, y: F) -> Self {
        Self { x, y }
    }
    /// Converts a host-side f64 vector to this precision.
    pub fn from_f64(v: [f64; 2]) -> Self {
        Self::new(F::lit(v[0]), F::lit(v[1]))
    }
    pub fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y
    }
}

impl<F: Real> Vec3<F> {
    pub const fn new(x: F, y: F, z: F) -> Self {
        Self { x, y, z }
    }
    pub fn splat(v: F) -> Self {
        Self::new(v, v, v)
    }
    pub fn zero() -> Self {
        Self::splat(F::zero())
    }
    /// Converts a host-side f64 vector to this precision.
    pub fn from_f64(v: [f64; 3]) -> Self {
        Self::new(F::lit(v[0]), F::lit(v[1]), F::lit(v[2]))
    }
    pub fn to_f64(self) -> [f64; 3] {
        [self.x.to_f64(), self.y.to_f64(), self.z.to_f64()]
    }
    /// WGSL's `vec3<f32>(v)`: each component rounded to f32.
    pub fn to_f32(self) -> Vec3<f32> {
        let [x, y, z] = self.to_f64();
        Vec3::new(x as f32, y as f32, z as f32)
    }
    /// An f32 vector in this precision (exact): the kernels' f32 radiance in the CPU's `F`.
    pub fn from_f32(v: Vec3<f32>) -> Self {
        Self::from_f64(v.to_f64())
    }
    pub fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    pub fn length(self) -> F {
        self.dot(self).sqrt()
    }
    pub fn normalize(self) -> Self {
        self * (F::one() / self.length())
    }
    pub fn abs(self) -> Self {
        Self::new(self.x.abs(), self.y.abs(), self.z.abs())
    }
    /// Component-wise product, WGSL's `vec3 * vec3`.
    pub fn mul_elem(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
    pub fn min_elem(self, o: Self) -> Self {
        Self::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }
    pub fn max_elem(self, o: Self) -> Self {
        Self::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }
}

impl<F: Real> Vec4<F> {
    pub const fn new(x: F, y: F, z: F, w: F) -> Self {
        Self { x, y, z, w }
    }
    pub fn zero() -> Self {
        Self::new(F::zero(), F::zero(), F::zero(), F::zero())
    }
    /// A real quaternion `(r, 0, 0, 0)`.
    pub fn real(r: F) -> Self {
        Self::new(r, F::zero(), F::zero(), F::zero())
    }
    /// Builds `(x, v.x, v.y, v.z)`, WGSL's `vec4(x, v)`.
    pub fn from_parts(x: F, v: Vec3<F>) -> Self {
        Self::new(x, v.x, v.y, v.z)
    }
    /// Converts a host-side f64 vector to this precision.
    pub fn from_f64(v: [f64; 4]) -> Self {
        Self::new(F::lit(v[0]), F::lit(v[1]), F::lit(v[2]), F::lit(v[3]))
    }
    /// The imaginary part, WGSL's `q.yzw`.
    pub fn yzw(self) -> Vec3<F> {
        Vec3::new(self.y, self.z, self.w)
    }
    pub fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z + self.w * o.w
    }
    pub fn length(self) -> F {
        self.dot(self).sqrt()
    }
}

macro_rules! impl_vector_ops {
    ($ty:ident { $($f:ident),+ }) => {
        impl<F: Real> Add for $ty<F> {
            type Output = Self;
            fn add(self, o: Self) -> Self {
                Self { $($f: self.$f + o.$f),+ }
            }
        }
        impl<F: Real> AddAssign for $ty<F> {
            fn add_assign(&mut self, o: Self) {
                *self = *self + o;
            }
        }
        impl<F: Real> Sub for $ty<F> {
            type Output = Self;
            fn sub(self, o: Self) -> Self {
                Self { $($f: self.$f - o.$f),+ }
            }
        }
        impl<F: Real> Neg for $ty<F> {
            type Output = Self;
            fn neg(self) -> Self {
                Self { $($f: -self.$f),+ }
            }
        }
        impl<F: Real> Mul<F> for $ty<F> {
            type Output = Self;
            fn mul(self, s: F) -> Self {
                Self { $($f: self.$f * s),+ }
            }
        }
        impl<F: Real> Div<F> for $ty<F> {
            type Output = Self;
            fn div(self, s: F) -> Self {
                Self { $($f: self.$f / s),+ }
            }
        }
    };
}

impl_vector_ops!(Vec2 { x, y });
impl_vector_ops!(Vec3 { x, y, z });
impl_vector_ops!(Vec4 { x, y, z, w });

// ----- twins of shaders/algebra.wgsl -----

/// The quaternion product `a b` (not commutative). (The seed's quatMult.)
#[inline(always)]
pub fn quat_mul<F: Real>(a: Vec4<F>, b: Vec4<F>) -> Vec4<F> {
    Vec4::from_parts(
        a.x * b.x - a.yzw().dot(b.yzw()),
        b.yzw() * a.x + a.yzw() * b.x + a.yzw().cross(b.yzw()),
    )
}

/// The quaternion square `q q`, a cheaper special case of `quat_mul(q, q)`. (The seed's
/// quatSq.)
#[inline(always)]
pub fn quat_sq<F: Real>(q: Vec4<F>) -> Vec4<F> {
    Vec4::from_parts(
        q.x * q.x - q.yzw().dot(q.yzw()),
        q.yzw() * (F::lit(2.0) * q.x),
    )
}

#[inline(always)]
pub fn quat_conj<F: Real>(q: Vec4<F>) -> Vec4<F> {
    Vec4::from_parts(q.x, -q.yzw())
}

/// A number of the scene's algebra as quaternion parts: part 0 alone for a quaternion, parts
/// 0-1 for an octonion (a, b), all four for a sedenion ((p0, p1), (p2, p3)); unused parts are 0.
pub type Hyper<F> = [Vec4<F>; 4];

/// An octonion as its two quaternion halves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Octonion<F> {
    pub a: Vec4<F>,
    pub b: Vec4<F>,
}

/// The Cayley-Dickson product (a, b)(c, d) = (a c - conj(d) b, d a + b conj(c)).
#[inline(always)]
pub fn oct_mul<F: Real>(x: Octonion<F>, y: Octonion<F>) -> Octonion<F> {
    Octonion {
        a: quat_mul(x.a, y.a) - quat_mul(quat_conj(y.b), x.b),
        b: quat_mul(y.b, x.a) + quat_mul(x.b, quat_conj(y.a)),
    }
}

#[inline(always)]
pub fn oct_conj<F: Real>(x: Octonion<F>) -> Octonion<F> {
    Octonion {
        a: quat_conj(x.a),
        b: -x.b,
    }
}

/// The octonion square (a, b)^2 = (a^2 - |b|^2, 2 Re(a) b): conj(b) b = |b|^2 and
/// b a + b conj(a) = 2 Re(a) b, so no product is needed.
#[inline(always)]
pub fn oct_sq<F: Real>(x: Octonion<F>) -> Octonion<F> {
    Octonion {
        a: quat_sq(x.a) - Vec4::real(x.b.dot(x.b)),
        b: x.b * (F::lit(2.0) * x.a.x),
    }
}

/// The product x y of two numbers with `parts` quaternion parts (1, 2 or 4).
#[inline(always)]
pub fn hyper_mul<F: Real>(x: Hyper<F>, y: Hyper<F>, parts: u32) -> Hyper<F> {
    let zero = Vec4::zero();
    if parts == 1 {
        return [quat_mul(x[0], y[0]), zero, zero, zero];
    }
    let xa = Octonion { a: x[0], b: x[1] };
    let ya = Octonion { a: y[0], b: y[1] };
    if parts == 2 {
        let p = oct_mul(xa, ya);
        return [p.a, p.b, zero, zero];
    }
    // Sedenions: (A, B)(C, D) = (A C - conj(D) B, D A + B conj(C)) over octonions.
    let xb = Octonion { a: x[2], b: x[3] };
    let yb = Octonion { a: y[2], b: y[3] };
    let ac = oct_mul(xa, ya);
    let db = oct_mul(oct_conj(yb), xb);
    let da = oct_mul(yb, xa);
    let bc = oct_mul(xb, oct_conj(ya));
    [ac.a - db.a, ac.b - db.b, da.a + bc.a, da.b + bc.b]
}

/// The square x x, by (A, B)^2 = (A^2 - |B|^2, 2 Re(A) B) at each level of the construction.
#[inline(always)]
pub fn hyper_sq<F: Real>(x: Hyper<F>, parts: u32) -> Hyper<F> {
    let zero = Vec4::zero();
    if parts == 1 {
        return [quat_sq(x[0]), zero, zero, zero];
    }
    let a = oct_sq(Octonion { a: x[0], b: x[1] });
    if parts == 2 {
        return [a.a, a.b, zero, zero];
    }
    let b_squared = x[2].dot(x[2]) + x[3].dot(x[3]);
    let re = F::lit(2.0) * x[0].x;
    [a.a - Vec4::real(b_squared), a.b, x[2] * re, x[3] * re]
}

/// The Euclidean inner product of the first `parts` parts.
#[inline(always)]
pub fn hyper_dot<F: Real>(x: Hyper<F>, y: Hyper<F>, parts: u32) -> F {
    let mut sum = x[0].dot(y[0]);
    for k in 1..parts as usize {
        sum = sum + x[k].dot(y[k]);
    }
    sum
}

#[inline(always)]
pub fn hyper_add<F: Real>(x: Hyper<F>, y: Hyper<F>) -> Hyper<F> {
    [x[0] + y[0], x[1] + y[1], x[2] + y[2], x[3] + y[3]]
}

#[inline(always)]
pub fn hyper_scale<F: Real>(s: F, x: Hyper<F>) -> Hyper<F> {
    [x[0] * s, x[1] * s, x[2] * s, x[3] * s]
}

#[inline(always)]
pub fn hyper_sub<F: Real>(x: Hyper<F>, y: Hyper<F>) -> Hyper<F> {
    [x[0] - y[0], x[1] - y[1], x[2] - y[2], x[3] - y[3]]
}

/// The derivative of the square at z along j: z j + j z = 2 (Re(z) j + Re(j) z - <z, j>), the
/// same in every Cayley-Dickson algebra (the linear part of (z + j)^2 = 2 Re(z + j)(z + j) -
/// |z + j|^2), written so that for quaternions it is 2 (z.x j.x - z.yzw . j.yzw,
/// z.x j.yzw + j.x z.yzw).
#[inline(always)]
pub fn square_derivative<F: Real>(z: Hyper<F>, j: Hyper<F>, parts: u32) -> Hyper<F> {
    let mut inner = z[0].yzw().dot(j[0].yzw());
    for k in 1..parts as usize {
        inner = inner + z[k].dot(j[k]);
    }
    let mut out = [Vec4::zero(); 4];
    out[0] = Vec4::from_parts(
        z[0].x * j[0].x - inner,
        j[0].yzw() * z[0].x + z[0].yzw() * j[0].x,
    );
    for k in 1..parts as usize {
        out[k] = j[k] * z[0].x + z[k] * j[0].x;
    }
    hyper_scale(F::lit(2.0), out)
}

/// Up to 16 host-side f64 components (missing ones 0) as a [`Hyper`] in this precision. (CPU
/// only: the GPU gets its numbers from the uniform buffer.)
pub fn hyper_from_f64<F: Real>(v: &[f64]) -> Hyper<F> {
    let at = |k: usize| v.get(k).copied().unwrap_or(0.0);
    std::array::from_fn(|p| {
        Vec4::from_f64([at(4 * p), at(4 * p + 1), at(4 * p + 2), at(4 * p + 3)])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(x: f64, y: f64, z: f64, w: f64) -> Vec4<f64> {
        Vec4::new(x, y, z, w)
    }

    #[test]
    fn hamilton_units() {
        let (one, i, j, k) = (
            q(1., 0., 0., 0.),
            q(0., 1., 0., 0.),
            q(0., 0., 1., 0.),
            q(0., 0., 0., 1.),
        );
        assert_eq!(quat_mul(i, i), -one);
        assert_eq!(quat_mul(j, j), -one);
        assert_eq!(quat_mul(k, k), -one);
        assert_eq!(quat_mul(i, j), k);
        assert_eq!(quat_mul(j, k), i);
        assert_eq!(quat_mul(k, i), j);
        assert_eq!(quat_mul(j, i), -k);
    }

    #[test]
    fn square_matches_product_and_norm_is_multiplicative() {
        let a = q(0.3, -1.2, 0.7, 2.0);
        let b = q(-0.5, 0.25, 1.5, -0.75);
        let s = quat_sq(a);
        let p = quat_mul(a, a);
        assert!((s - p).length() < 1e-12);
        let ab = quat_mul(a, b);
        assert!((ab.length() - a.length() * b.length()).abs() < 1e-12);
    }

    /// A deterministic pseudo-random number of the algebra with `parts` parts.
    fn random(seed: &mut u64, parts: u32) -> Hyper<f64> {
        let mut next = || {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut x = [Vec4::zero(); 4];
        for part in x.iter_mut().take(parts as usize) {
            *part = q(next(), next(), next(), next());
        }
        x
    }

    fn norm(x: Hyper<f64>) -> f64 {
        hyper_dot(x, x, 4).sqrt()
    }

    fn distance(x: Hyper<f64>, y: Hyper<f64>) -> f64 {
        norm(hyper_sub(x, y))
    }

    #[test]
    fn octonion_norm_is_multiplicative_and_the_algebra_alternative() {
        let mut seed = 7;
        for _ in 0..200 {
            let (x, y) = (random(&mut seed, 2), random(&mut seed, 2));
            let xy = hyper_mul(x, y, 2);
            assert!((norm(xy) - norm(x) * norm(y)).abs() < 1e-12);
            // Alternative: x (x y) = (x x) y and (y x) x = y (x x).
            let xx = hyper_mul(x, x, 2);
            assert!(distance(hyper_mul(x, xy, 2), hyper_mul(xx, y, 2)) < 1e-12);
            let yx = hyper_mul(y, x, 2);
            assert!(distance(hyper_mul(yx, x, 2), hyper_mul(y, xx, 2)) < 1e-12);
            // The square is the product with itself.
            assert!(distance(hyper_sq(x, 2), xx) < 1e-14);
        }
    }

    #[test]
    fn octonions_are_not_associative() {
        let mut seed = 11;
        let (x, y, z) = (
            random(&mut seed, 2),
            random(&mut seed, 2),
            random(&mut seed, 2),
        );
        let left = hyper_mul(hyper_mul(x, y, 2), z, 2);
        let right = hyper_mul(x, hyper_mul(y, z, 2), 2);
        assert!(distance(left, right) > 1e-3);
    }

    #[test]
    fn sedenion_norm_is_not_multiplicative_and_has_zero_divisors() {
        let mut seed = 13;
        let mut worst = 0f64;
        for _ in 0..200 {
            let (x, y) = (random(&mut seed, 4), random(&mut seed, 4));
            let ratio = norm(hyper_mul(x, y, 4)) / (norm(x) * norm(y));
            worst = worst.max((ratio - 1.0).abs());
            // Still power-associative: the square is the product with itself.
            assert!(distance(hyper_sq(x, 4), hyper_mul(x, x, 4)) < 1e-14);
        }
        assert!(
            worst > 0.05,
            "the sedenion norm looked multiplicative: {worst}"
        );
        // A zero divisor pair of this construction: (e1 + e10)(e4 - e15) = 0.
        let unit = |k: usize| {
            let mut x = [Vec4::zero(); 4];
            let mut a = [x[k / 4].x, x[k / 4].y, x[k / 4].z, x[k / 4].w];
            a[k % 4] = 1.0;
            x[k / 4] = q(a[0], a[1], a[2], a[3]);
            x
        };
        let a = hyper_add(unit(1), unit(10));
        let b = hyper_sub(unit(4), unit(15));
        let ab = hyper_mul(a, b, 4);
        assert!(norm(ab) < 1e-15, "{ab:?}");
    }

    #[test]
    fn a_quaternion_multiplies_alike_in_every_algebra() {
        let mut seed = 17;
        for _ in 0..100 {
            let (x, y) = (random(&mut seed, 1), random(&mut seed, 1));
            let quat = [
                quat_mul(x[0], y[0]),
                Vec4::zero(),
                Vec4::zero(),
                Vec4::zero(),
            ];
            let sq = [quat_sq(x[0]), Vec4::zero(), Vec4::zero(), Vec4::zero()];
            for parts in [2, 4] {
                assert_eq!(hyper_mul(x, y, parts), quat);
                assert_eq!(hyper_sq(x, parts), sq);
            }
        }
    }

    #[test]
    fn square_derivative_is_the_derivative_of_the_square() {
        let mut seed = 19;
        for parts in [1, 2, 4] {
            let (z, j) = (random(&mut seed, parts), random(&mut seed, parts));
            let h = 1e-6;
            let ahead = hyper_sq(hyper_add(z, hyper_scale(h, j)), parts);
            let behind = hyper_sq(hyper_sub(z, hyper_scale(h, j)), parts);
            let numeric = hyper_scale(0.5 / h, hyper_sub(ahead, behind));
            let exact = square_derivative(z, j, parts);
            assert!(distance(numeric, exact) < 1e-8, "{parts}");
            // z j + j z by the products.
            let sum = hyper_add(hyper_mul(z, j, parts), hyper_mul(j, z, parts));
            assert!(distance(sum, exact) < 1e-13, "{parts}");
        }
    }
}
