//! The CPU twin of shaders/estimate.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). The distance estimate and the
//! iteration: the 3D slice's axes and point, the orbit of z <- z^2 + c, the Julia set's estimate
//! from it, estimate_distance (with the cut) that everything uses, and the fused pair versions of
//! sphere_trace_pair; the work counts `estimates` and `iterations`.

use crate::algebra::{
    Hyper, Real, Vec3, Vec4, hyper_add, hyper_dot, hyper_mul, hyper_scale, hyper_sq,
};
use crate::params::TraceParams;

/// Below this a squared length counts as zero: nothing is divided by it or normalised.
pub const TINY: f64 = 1e-30;

impl<F: Real> TraceParams<F> {
    /// Scene coordinates p in the 3D slice to the point offset + p.x x + p.y y + p.z z of the
    /// algebra.
    pub fn slice_point(&self, p: Vec3<F>) -> Hyper<F> {
        let mut q = self.slice_offset;
        for (k, qk) in q.iter_mut().enumerate().take(self.algebra_parts as usize) {
            *qk += self.slice_x[k] * p.x + self.slice_y[k] * p.y + self.slice_z[k] * p.z;
        }
        q
    }

    /// The orbit of z: z <- z^2 + c with z' <- 2 z z' (z'_0 = 1), until
    /// |z|^2 > escape_radius_squared or max_iterations (or |z'|^2 > `Real::DERIVATIVE_LIMIT`,
    /// WGSL's DERIVATIVE_LIMIT in f32); leaves the last z in z and returns |z'|^2. (The seed's
    /// iterateIntersect.) Quaternions and octonions are composition algebras, |a b| = |a| |b|,
    /// so |z'|^2 <- 4 |z|^2 |z'|^2 gives the same |z'| without the product (half the arithmetic
    /// of an iteration). Sedenions are not: there z' is carried whole.
    pub fn iterate_orbit(&self, z: &mut Hyper<F>) -> F {
        // The loop compiled once per algebra, so that its arithmetic skips the unused parts.
        match self.algebra_parts {
            1 => self.iterate_orbit_parts::<1>(z),
            2 => self.iterate_orbit_parts::<2>(z),
            _ => self.iterate_orbit_parts::<4>(z),
        }
    }

    /// [`Self::iterate_orbit`] for a number of parts known at compile time (CPU only: WGSL gets
    /// the same from algebra_parts() composed for one algebra).
    #[inline(always)]
    fn iterate_orbit_parts<const PARTS: u32>(&self, z: &mut Hyper<F>) -> F {
        let parts = PARTS;
        let mut z_norm2 = hyper_dot(*z, *z, parts);
        let mut dz_norm2 = F::one();
        let mut dz = [
            Vec4::real(F::one()),
            Vec4::zero(),
            Vec4::zero(),
            Vec4::zero(),
        ];
        for _ in 0..self.max_iterations {
            count(&super::ITERATIONS, 1);
            if parts == 4 {
                dz = hyper_scale(F::lit(2.0), hyper_mul(*z, dz, parts));
                dz_norm2 = hyper_dot(dz, dz, parts);
            } else {
                dz_norm2 = dz_norm2 * (F::lit(4.0) * z_norm2);
            }
            *z = hyper_add(hyper_sq(*z, parts), self.c);
            z_norm2 = hyper_dot(*z, *z, parts);
            if z_norm2 > self.escape_radius_squared || dz_norm2 > F::lit(F::DERIVATIVE_LIMIT) {
                break;
            }
        }
        dz_norm2
    }

    /// The seed's distance estimate d = 0.5 |z| log|z| / |z'|, written as
    /// 0.25 sqrt(|z|^2 / |z'|^2) log(|z|^2) so that no root or log is taken of zero.
    /// Negative inside the set (|z| < 1); 0 where it cannot be formed: |z| = 0 (below the
    /// smallest normal float, WGSL's MIN_NORMAL), |z'| = 0 (below TINY |z|, which keeps the
    /// ratio finite) or |z'| huge. The set alone, without the cut (`estimate_distance` adds it).
    pub fn estimate_julia(&self, p: Vec3<F>) -> F {
        count(&super::ESTIMATES, 1);
        let mut z = self.slice_point(p);
        let dz_norm2 = self.iterate_orbit(&mut z);
        self.orbit_distance(z, dz_norm2)
    }

    /// The estimate from an orbit's last z and its |z'|^2 (`estimate_julia`'s formula and
    /// guards).
    pub fn orbit_distance(&self, z: Hyper<F>, dz_norm2: F) -> F {
        let z_norm2 = hyper_dot(z, z, self.algebra_parts);
        if z_norm2 < F::min_positive_value()
            || dz_norm2 > F::lit(F::DERIVATIVE_LIMIT)
            || dz_norm2 <= z_norm2 * F::lit(TINY)
        {
            return F::zero();
        }
        F::lit(0.25) * (z_norm2 / dz_norm2).sqrt() * z_norm2.ln()
    }

    /// The distance estimate everything uses (primary and shadow rays, the cone, occlusion): the
    /// set's, and with the cut on, the set intersected with the half-space
    /// cut_normal . p <= cut_offset, max(d, cut_normal . p - cut_offset) (still a lower bound of
    /// the distance to what is left).
    pub fn estimate_distance(&self, p: Vec3<F>) -> F {
        let d = self.estimate_julia(p);
        if self.cut_on() {
            return d.max(self.cut_plane(p));
        }
        d
    }

    /// `iterate_orbit` of two numbers at once (interleaving): both orbits in one loop, each
    /// stopping on its own; an orbit not `live` is not iterated. Returns the two |z'|^2; each z
    /// and |z'|^2 is `iterate_orbit`'s bit for bit.
    pub fn iterate_orbit_pair(
        &self,
        z1: &mut Hyper<F>,
        z2: &mut Hyper<F>,
        live: [bool; 2],
    ) -> [F; 2] {
        match self.algebra_parts {
            1 => self.iterate_orbit_pair_parts::<1>(z1, z2, live),
            2 => self.iterate_orbit_pair_parts::<2>(z1, z2, live),
            _ => self.iterate_orbit_pair_parts::<4>(z1, z2, live),
        }
    }

    /// [`Self::iterate_orbit_pair`] for a number of parts known at compile time (CPU only, as
    /// `iterate_orbit_parts`).
    #[inline(always)]
    fn iterate_orbit_pair_parts<const PARTS: u32>(
        &self,
        z1: &mut Hyper<F>,
        z2: &mut Hyper<F>,
        live: [bool; 2],
    ) -> [F; 2] {
        let parts = PARTS;
        let one = [
            Vec4::real(F::one()),
            Vec4::zero(),
            Vec4::zero(),
            Vec4::zero(),
        ];
        let mut z = [*z1, *z2];
        let mut z_norm2 = [hyper_dot(z[0], z[0], parts), hyper_dot(z[1], z[1], parts)];
        let mut dz_norm2 = [F::one(); 2];
        let mut dz = [one; 2];
        let mut on = live;
        for _ in 0..self.max_iterations {
            if !(on[0] || on[1]) {
                break;
            }
            for k in 0..2 {
                if !on[k] {
                    continue;
                }
                count(&super::ITERATIONS, 1);
                if parts == 4 {
                    dz[k] = hyper_scale(F::lit(2.0), hyper_mul(z[k], dz[k], parts));
                    dz_norm2[k] = hyper_dot(dz[k], dz[k], parts);
                } else {
                    dz_norm2[k] = dz_norm2[k] * (F::lit(4.0) * z_norm2[k]);
                }
                z[k] = hyper_add(hyper_sq(z[k], parts), self.c);
                z_norm2[k] = hyper_dot(z[k], z[k], parts);
                on[k] = !(z_norm2[k] > self.escape_radius_squared
                    || dz_norm2[k] > F::lit(F::DERIVATIVE_LIMIT));
            }
        }
        (*z1, *z2) = (z[0], z[1]);
        dz_norm2
    }

    /// `estimate_julia` at two points at once (`iterate_orbit_pair`); a point not `live` is
    /// not estimated (its estimate is 0, and not counted).
    pub fn estimate_julia_pair(&self, p1: Vec3<F>, p2: Vec3<F>, live: [bool; 2]) -> [F; 2] {
        count(
            &super::ESTIMATES,
            live.iter().filter(|&&l| l).count() as u64,
        );
        let mut z1 = self.slice_point(p1);
        let mut z2 = self.slice_point(p2);
        let dz_norm2 = self.iterate_orbit_pair(&mut z1, &mut z2, live);
        [
            self.orbit_distance(z1, dz_norm2[0]),
            self.orbit_distance(z2, dz_norm2[1]),
        ]
    }

    /// `estimate_distance` at two points at once: `estimate_julia_pair`, and the cut as
    /// `estimate_distance` adds it.
    pub fn estimate_distance_pair(&self, p1: Vec3<F>, p2: Vec3<F>, live: [bool; 2]) -> [F; 2] {
        let d = self.estimate_julia_pair(p1, p2, live);
        if self.cut_on() {
            return [d[0].max(self.cut_plane(p1)), d[1].max(self.cut_plane(p2))];
        }
        d
    }
}

/// Adds to one of the work counters (see `cpu::count_work`); not part of the twin.
pub(super) fn count(counter: &'static std::thread::LocalKey<std::cell::Cell<u64>>, n: u64) {
    counter.with(|c| c.set(c.get() + n));
}
