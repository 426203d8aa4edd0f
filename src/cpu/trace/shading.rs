//! The CPU twin of shaders/shading.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). Phong shading, the shadow ray (hard
//! and soft) and ambient occlusion.

use super::estimate::TINY;
use super::normal::safe_normalize;
use crate::algebra::{Real, Vec3};
use crate::params::TraceParams;

/// Ambient occlusion samples the estimate at OCCLUSION_SAMPLES points p + k OCCLUSION_STEP n,
/// k = 1, 2, ...
pub const OCCLUSION_SAMPLES: u32 = 5;
pub const OCCLUSION_STEP: f64 = 0.04;

impl<F: Real> TraceParams<F> {
    /// Phong shading at pt with normal n, a point light and the viewer at eye:
    /// (diffuse + normal_tint |n|) max(N.L, 0) + specular max(E.R, 0)^shininess,
    /// R = 2 (N.L) N - L, no highlight where N.L <= 0.
    /// (The seed negates R and passes the ray direction as the eye.)
    pub fn phong(&self, light: Vec3<F>, eye: Vec3<F>, pt: Vec3<F>, n: Vec3<F>) -> Vec3<F> {
        let l = safe_normalize(light - pt, n);
        let e = safe_normalize(eye - pt, n);
        let n_dot_l = n.dot(l);
        if n_dot_l <= F::zero() {
            return Vec3::zero();
        }
        let r = n * (F::lit(2.0) * n_dot_l) - l;
        let e_dot_r = e.dot(r);
        let mut highlight = F::zero();
        if e_dot_r > F::zero() {
            highlight = self.specular * e_dot_r.powf(self.shininess);
        }
        (self.diffuse + n.abs() * self.normal_tint) * n_dot_l + Vec3::splat(highlight)
    }

    /// Whether the light casts shadows (light.shadows).
    pub fn shadows_on(&self) -> bool {
        self.shadows
    }

    /// The shadow ray: from p + 2 epsilon n toward the light, traced like a primary ray,
    /// stopping at the light or where it leaves the bounding ball, whichever comes first.
    pub fn in_shadow(&self, p: Vec3<F>, n: Vec3<F>) -> bool {
        let origin = p + n * (F::lit(2.0) * self.epsilon);
        let to_light = self.light - origin;
        let dist_squared = to_light.dot(to_light);
        if dist_squared <= F::lit(TINY) {
            return false;
        }
        let dist = dist_squared.sqrt();
        let dir = to_light / dist;
        let bounds = self.intersect_bounds(origin, dir);
        let t_end = bounds.t_exit.min(dist);
        if !bounds.hit || bounds.t_enter >= t_end {
            return false;
        }
        self.sphere_trace(origin, dir, bounds.t_enter, t_end, F::zero())
            .hit
    }

    /// Whether the light has a radius (light.radius > 0): the shadows are
    /// [`Self::soft_shadow`]'s.
    pub fn soft_shadows_on(&self) -> bool {
        self.light_radius > F::zero()
    }

    /// The shadow of a spherical light (centre light, radius light_radius > 0), soft: from
    /// p + 2 epsilon n toward the centre, marched like [`Self::in_shadow`]'s ray with plain
    /// steps (the same t at every step, so it hits exactly where in_shadow's does with
    /// step_scale 1); a hit gives 0, else the visibility is min(1, min over the steps with t > 0
    /// of 2 d / (t tan)), tan = light_radius / (distance from the origin to the centre): the
    /// closest approach relative to the cone towards the light, with 2 d for the true distance
    /// (the estimate is about half of it near the surface).
    pub fn soft_shadow(&self, p: Vec3<F>, n: Vec3<F>) -> F {
        let one = F::one();
        let origin = p + n * (F::lit(2.0) * self.epsilon);
        let to_light = self.light - origin;
        let dist_squared = to_light.dot(to_light);
        if dist_squared <= F::lit(TINY) {
            return one;
        }
        let dist = dist_squared.sqrt();
        let dir = to_light / dist;
        let bounds = self.intersect_bounds(origin, dir);
        let t_end = bounds.t_exit.min(dist);
        if !bounds.hit || bounds.t_enter >= t_end {
            return one;
        }
        let tan_size = self.light_radius / dist;
        let mut visibility = one;
        let mut t = bounds.t_enter;
        for _ in 0..self.max_steps {
            let d = self.estimate_distance(origin + dir * t);
            let t_plain = t + d.max(F::zero());
            if d < self.epsilon.max(t_plain * F::lit(F::RELATIVE_EPSILON)) {
                return F::zero();
            }
            if t > F::zero() {
                visibility = visibility.min(F::lit(2.0) * d / (t * tan_size));
            }
            t = t_plain;
            if t > t_end {
                break;
            }
        }
        visibility
    }

    /// Whether the scene has ambient occlusion (shading.occlusion > 0).
    pub fn occlusion_on(&self) -> bool {
        self.occlusion > F::zero()
    }

    /// The ambient occlusion factor A in [1 - occlusion, 1]: at h_k = k OCCLUSION_STEP along
    /// the normal (k = 1..OCCLUSION_SAMPLES) an open surface has the set at least h_k away, and
    /// 2 d (the estimate is about half the true distance near the surface) at least h_k; what
    /// falls short occludes: A = 1 - occlusion (1 / K) sum_k clamp(1 - 2 d(p + h_k n) / h_k, 0, 1).
    pub fn occlusion(&self, p: Vec3<F>, n: Vec3<F>) -> F {
        let (zero, one, two) = (F::zero(), F::one(), F::lit(2.0));
        let mut sum = zero;
        for k in 1..=OCCLUSION_SAMPLES {
            let h = F::lit(k as f64) * F::lit(OCCLUSION_STEP);
            let d = self.estimate_distance(p + n * h);
            sum = sum + (one - two * d / h).max(zero).min(one);
        }
        one - self.occlusion * (sum / F::lit(OCCLUSION_SAMPLES as f64))
    }
}
