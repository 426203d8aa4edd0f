//! The CPU twin of shaders/normal.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). The normal: safe_normalize, the
//! seed's central differences, the tetrahedral and the analytic normals, and estimate_normal, which
//! picks one.

use super::estimate::{TINY, count};
use crate::algebra::{
    Hyper, Real, Vec3, hyper_add, hyper_dot, hyper_scale, hyper_sq, hyper_sub, square_derivative,
};
use crate::params::TraceParams;
use crate::scene::NormalMethod;

/// |z|^2 at which the normal's six orbits stop, long before they can overflow.
pub const NORMAL_LIMIT: f64 = 1e16;

/// v normalised, or the fallback where v is too short to have a direction. Scaled by its
/// largest component first, so that a long v (an analytic gradient can reach 1e30) cannot
/// overflow.
pub fn safe_normalize<F: Real>(v: Vec3<F>, fallback: Vec3<F>) -> Vec3<F> {
    let m = v.x.abs().max(v.y.abs()).max(v.z.abs());
    if m * m <= F::lit(TINY) {
        return fallback;
    }
    let w = v / m;
    w / w.dot(w).sqrt()
}

impl<F: Real> TraceParams<F> {
    /// The seed's normal (its normEstimate): central differences of |z_N| along the slice axes
    /// with normal_delta, max_iterations iterations of z <- z^2 + c. All six orbits stop
    /// together once any |z|^2 passes NORMAL_LIMIT: from there z_N ~ z_n^(2^(N-n)), so
    /// grad |z_N| is parallel to grad |z_n| and the direction is already known, and nothing
    /// overflows.
    pub fn normal_central(&self, q: Hyper<F>) -> Vec3<F> {
        let parts = self.algebra_parts;
        let dx = hyper_scale(self.normal_delta, self.slice_x);
        let dy = hyper_scale(self.normal_delta, self.slice_y);
        let dz = hyper_scale(self.normal_delta, self.slice_z);
        let mut x_minus = hyper_sub(q, dx);
        let mut x_plus = hyper_add(q, dx);
        let mut y_minus = hyper_sub(q, dy);
        let mut y_plus = hyper_add(q, dy);
        let mut z_minus = hyper_sub(q, dz);
        let mut z_plus = hyper_add(q, dz);
        let norm2 = |g: Hyper<F>| hyper_dot(g, g, parts);
        for _ in 0..self.max_iterations {
            let largest = (norm2(x_minus).max(norm2(x_plus)))
                .max(norm2(y_minus).max(norm2(y_plus)))
                .max(norm2(z_minus).max(norm2(z_plus)));
            if largest > F::lit(NORMAL_LIMIT) {
                break;
            }
            count(&super::ITERATIONS, 6);
            x_minus = hyper_add(hyper_sq(x_minus, parts), self.c);
            x_plus = hyper_add(hyper_sq(x_plus, parts), self.c);
            y_minus = hyper_add(hyper_sq(y_minus, parts), self.c);
            y_plus = hyper_add(hyper_sq(y_plus, parts), self.c);
            z_minus = hyper_add(hyper_sq(z_minus, parts), self.c);
            z_plus = hyper_add(hyper_sq(z_plus, parts), self.c);
        }
        Vec3::new(
            norm2(x_plus).sqrt() - norm2(x_minus).sqrt(),
            norm2(y_plus).sqrt() - norm2(y_minus).sqrt(),
            norm2(z_plus).sqrt() - norm2(z_minus).sqrt(),
        )
    }

    /// Four samples at the corners of a tetrahedron, (1,-1,-1), (-1,-1,1), (-1,1,-1), (1,1,1)
    /// times normal_delta: sum of v_k |z_N(p + delta v_k)|, two thirds the work of central
    /// differences.
    pub fn normal_tetrahedral(&self, q: Hyper<F>) -> Vec3<F> {
        let parts = self.algebra_parts;
        let h = self.normal_delta;
        let (x, y, z) = (self.slice_x, self.slice_y, self.slice_z);
        let minus_x = hyper_scale(-F::one(), x);
        let mut a = hyper_add(q, hyper_scale(h, hyper_sub(hyper_sub(x, y), z)));
        let mut b = hyper_add(q, hyper_scale(h, hyper_add(hyper_sub(minus_x, y), z)));
        let mut c = hyper_add(q, hyper_scale(h, hyper_sub(hyper_add(minus_x, y), z)));
        let mut d = hyper_add(q, hyper_scale(h, hyper_add(hyper_add(x, y), z)));
        let norm2 = |g: Hyper<F>| hyper_dot(g, g, parts);
        for _ in 0..self.max_iterations {
            let largest = (norm2(a).max(norm2(b))).max(norm2(c).max(norm2(d)));
            if largest > F::lit(NORMAL_LIMIT) {
                break;
            }
            count(&super::ITERATIONS, 4);
            a = hyper_add(hyper_sq(a, parts), self.c);
            b = hyper_add(hyper_sq(b, parts), self.c);
            c = hyper_add(hyper_sq(c, parts), self.c);
            d = hyper_add(hyper_sq(d, parts), self.c);
        }
        let (la, lb, lc, ld) = (
            norm2(a).sqrt(),
            norm2(b).sqrt(),
            norm2(c).sqrt(),
            norm2(d).sqrt(),
        );
        Vec3::new(la - lb - lc + ld, -la - lb + lc + ld, -la + lb - lc + ld)
    }

    /// The exact gradient of |z_N|: the derivatives of z along the three slice axes, carried
    /// through the iteration (d(z^2) = z dz + dz z, `square_derivative`), then
    /// grad_i |z| = z . dz_i / |z| (the 1/|z| does not change the direction).
    pub fn normal_analytic(&self, q: Hyper<F>) -> Vec3<F> {
        let parts = self.algebra_parts;
        let mut z = q;
        let (mut jx, mut jy, mut jz) = (self.slice_x, self.slice_y, self.slice_z);
        let norm2 = |g: Hyper<F>| hyper_dot(g, g, parts);
        for _ in 0..self.max_iterations {
            let largest = norm2(jx).max(norm2(jy)).max(norm2(jz));
            if norm2(z) > F::lit(NORMAL_LIMIT) || largest > F::lit(F::DERIVATIVE_LIMIT) {
                break;
            }
            count(&super::ITERATIONS, 1);
            jx = square_derivative(z, jx, parts);
            jy = square_derivative(z, jy, parts);
            jz = square_derivative(z, jz, parts);
            z = hyper_add(hyper_sq(z, parts), self.c);
        }
        Vec3::new(
            hyper_dot(z, jx, parts),
            hyper_dot(z, jy, parts),
            hyper_dot(z, jz, parts),
        )
    }

    /// The shading normal by normal_method; where no gradient can be formed it points back
    /// along the ray. On the cut face, the cut's normal.
    pub fn estimate_normal(&self, p: Vec3<F>, dir: Vec3<F>) -> Vec3<F> {
        // On the cut face the normal is the plane's: where the plane's term is within epsilon
        // of the set's estimate or above it (inside the set the estimate can be 0, where it
        // cannot be formed, against a plane term rounded a little below 0).
        if self.cut_on() && self.cut_plane(p) + self.epsilon >= self.estimate_julia(p) {
            return self.cut_normal;
        }
        let q = self.slice_point(p);
        let grad = match self.normal_method {
            NormalMethod::Tetrahedral => self.normal_tetrahedral(q),
            NormalMethod::Analytic => self.normal_analytic(q),
            NormalMethod::Central => self.normal_central(q),
        };
        safe_normalize(grad, -dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn safe_normalize_survives_long_and_short_vectors() {
        let fallback = Vec3::new(0.0f32, 0.0, 1.0);
        let long = safe_normalize(Vec3::new(3e30f32, 4e30, 0.0), fallback);
        assert!(
            (long.x - 0.6).abs() < 1e-6 && (long.y - 0.8).abs() < 1e-6,
            "{long:?}"
        );
        assert_eq!(
            safe_normalize(Vec3::new(1e-20f32, 0.0, 0.0), fallback),
            fallback
        );
        let plain = safe_normalize(Vec3::new(0.0f64, -2.0, 0.0), Vec3::zero());
        assert_eq!(plain, Vec3::new(0.0, -1.0, 0.0));
    }
}
