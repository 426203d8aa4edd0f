//! Small vector and quaternion arithmetic, generic over the float type (f32 or f64).
//!
//! The CPU tracer is written against these types so that it reads like the WGSL shader:
//! `Vec3` and `Vec4` play the parts of `vec3<f32>` and `vec4<f32>`, and a quaternion is a
//! `Vec4` with `x` the real part and `(y, z, w)` the i, j, k parts, exactly as in
//! `shaders/quaternion.wgsl`, whose twin this file is for `quat_mul` and `quat_sq`.

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

// ----- twins of shaders/quaternion.wgsl -----

/// The quaternion product `a b` (not commutative).
pub fn quat_mul<F: Real>(a: Vec4<F>, b: Vec4<F>) -> Vec4<F> {
    Vec4::from_parts(
        a.x * b.x - a.yzw().dot(b.yzw()),
        b.yzw() * a.x + a.yzw() * b.x + a.yzw().cross(b.yzw()),
    )
}

/// The quaternion square `q q`, a cheaper special case of `quat_mul(q, q)`.
pub fn quat_sq<F: Real>(q: Vec4<F>) -> Vec4<F> {
    Vec4::from_parts(
        q.x * q.x - q.yzw().dot(q.yzw()),
        q.yzw() * (F::lit(2.0) * q.x),
    )
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
}
