//! The CPU twin of shaders/trace.wgsl: the same functions, with the same names, in the same
//! order, generic over the float type (tests/architecture/twins.rs checks names and order, and lists the
//! functions only one side has, each with its reason). WGSL's global `params` is `self` here; a
//! change to one file is a change to both, and the GPU-vs-CPU tests hold them together. The
//! kernel's `main` is cpu/mod.rs's `render_rows`.
//!
//! Why it passes 600 lines: it mirrors shaders/trace.wgsl function by function in the same
//! order (tests/architecture/twins.rs holds that order; issue 18 excepts the twins' bodies), so it is as long
//! as the kernel and stays one file as the shader is; a split must split both alike.

use super::light::mix3;
use crate::algebra::{
    Hyper, Real, Vec3, Vec4, hyper_add, hyper_dot, hyper_mul, hyper_scale, hyper_sq, hyper_sub,
    square_derivative,
};
use crate::params::TraceParams;
use crate::scene::{Colouring, NormalMethod};

/// Pixels a side of the blocks that share a cone (one workgroup on the GPU).
pub const CONE_BLOCK: u32 = 8;
/// The cone stops this many epsilons short: the estimate is about half the true distance near
/// the surface, so rays must start where it is still well above epsilon.
pub const CONE_MARGIN: f64 = 4.0;
/// Below this a squared length counts as zero: nothing is divided by it or normalised.
pub const TINY: f64 = 1e-30;
/// |z|^2 at which the normal's six orbits stop, long before they can overflow.
pub const NORMAL_LIMIT: f64 = 1e16;
/// Ambient occlusion samples the estimate at OCCLUSION_SAMPLES points p + k OCCLUSION_STEP n,
/// k = 1, 2, ...
pub const OCCLUSION_SAMPLES: u32 = 5;
pub const OCCLUSION_STEP: f64 = 0.04;

/// Where a ray meets the bounding ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval<F> {
    pub t_enter: F,
    pub t_exit: F,
    pub hit: bool,
}

/// A sphere-traced ray: the t reached, the estimates made, whether it hit, and the least
/// distance estimate along it (phong mode's glow: how close a miss came to the set;
/// [`NO_APPROACH`] for a ray not traced).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trace<F> {
    pub t: F,
    pub steps: u32,
    pub hit: bool,
    pub closest: F,
}

/// A [`Trace`]'s `closest` before any estimate.
pub const NO_APPROACH: f64 = 3.0e38;

impl<F: Real> Trace<F> {
    /// The outcome of a ray not traced: a miss of no steps at t = 0.
    pub fn untraced() -> Self {
        Trace {
            t: F::zero(),
            steps: 0,
            hit: false,
            closest: F::lit(NO_APPROACH),
        }
    }
}

/// One ray of an interleaved sphere trace (`sphere_trace_pair`): its ray and stretch,
/// `sphere_trace`'s variables, whether it is still being traced, and its outcome once it is not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct March<F> {
    pub origin: Vec3<F>,
    pub dir: Vec3<F>,
    pub t_end: F,
    pub eps_slope: F,
    pub t: F,
    pub omega: F,
    pub t_prev: F,
    pub prev_radius: F,
    pub closest: F,
    pub live: bool,
    pub trace: Trace<F>,
}

/// A sample's camera ray: its origin and direction and the stretch [t_start, t_end] of it that
/// sphere tracing covers, within the bounding ball; `hit` false where it misses the ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primary<F> {
    pub origin: Vec3<F>,
    pub dir: Vec3<F>,
    pub t_start: F,
    pub t_end: F,
    pub hit: bool,
}

/// A ray: its origin and its unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<F> {
    pub origin: Vec3<F>,
    pub dir: Vec3<F>,
}

/// One sample's outcome: its colour (unclamped), depth and steps, whether it hit, and where it
/// was shaded, the hit point and its shading normal (0 where it was not: a miss, or no
/// shading).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pixel<F> {
    pub colour: Vec3<F>,
    pub depth: F,
    pub steps: u32,
    pub hit: bool,
    pub point: Vec3<F>,
    pub normal: Vec3<F>,
}

/// The AOVs of a pixel's samples so far (`--hdr`, the denoiser): the mean of their unclamped
/// colours and the sum of the squared deviations of their luminances from the running mean
/// (Welford's M2: the denoiser's variance), and over the samples whose primary ray hit, how many
/// did and the means of their hits' base colours, shading normals and depths (0 while none has);
/// in path mode also the mean of their first hits' specular light
/// ([`crate::cpu::path::PathResult::specular`]; 0 in phong mode), and over the hits the mean
/// cosine of the view direction to the shading normal (the denoiser's specular reflectance).
/// In f32 in both precisions, as the shader keeps them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aovs {
    pub colour: Vec3<f32>,
    pub hits: f32,
    pub albedo: Vec3<f32>,
    pub normal: Vec3<f32>,
    pub m2: f32,
    pub depth: f32,
    pub specular: Vec3<f32>,
    pub cosine: f32,
}

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
    /// the same from the ALGEBRA_PARTS override).
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

    /// The cut's plane term cut_normal . p - cut_offset: the signed distance of p from the plane
    /// (cut_normal is of unit length), positive on the side the cut takes away.
    pub fn cut_plane(&self, p: Vec3<F>) -> F {
        self.cut_normal.dot(p) - self.cut_offset
    }

    /// The distance estimate everything uses (primary and shadow rays, the cone, occlusion): the
    /// set's, and with the cut on, the set intersected with the half-space
    /// cut_normal . p <= cut_offset, max(d, cut_normal . p - cut_offset) (still a lower bound of
    /// the distance to what is left).
    pub fn estimate_distance(&self, p: Vec3<F>) -> F {
        let d = self.estimate_julia(p);
        if self.cut {
            return d.max(self.cut_plane(p));
        }
        d
    }

    /// The ray origin + t dir (t >= 0) against the 3D ball the 4D bounding ball cuts from the
    /// slice. Starts at the origin when it is inside; a ray that misses, or a ball behind, gives
    /// no hit. (The seed's intersectSphere.)
    pub fn intersect_bounds(&self, origin: Vec3<F>, dir: Vec3<F>) -> Interval<F> {
        let zero = F::zero();
        let oc = origin - self.bounds_center;
        let b = oc.dot(dir);
        let cc = oc.dot(oc) - self.bounds_radius_squared;
        let disc = b * b - cc;
        if self.bounds_radius_squared <= zero || disc < zero {
            return Interval {
                t_enter: zero,
                t_exit: zero,
                hit: false,
            };
        }
        let t_exit = disc.sqrt() - b;
        if cc <= zero {
            return Interval {
                t_enter: zero,
                t_exit,
                hit: true,
            };
        }
        if t_exit <= zero {
            return Interval {
                t_enter: zero,
                t_exit: zero,
                hit: false,
            };
        }
        // The product of the roots is cc: the nearer one without cancellation.
        Interval {
            t_enter: cc / t_exit,
            t_exit,
            hit: true,
        }
    }

    /// Sphere tracing (the seed's intersectQJulia) from t_start: estimate d, advance by
    /// max(d, 0), stop with a hit when d is below the threshold: epsilon, or eps_slope t (epsilon
    /// proportional to the pixel footprint; 0 for shadow rays), or the float spacing at t
    /// (`Real::RELATIVE_EPSILON`) where steps stall. A miss when t passes t_end or after
    /// max_steps estimates. The hit is the point reached by the plain step, as in the seed.
    /// With step_scale > 1 steps are over-relaxed (omega d); when the unbounding spheres of two
    /// successive points stop overlapping the ray may have jumped the surface, so it goes back
    /// to the plain step from the last point and carries on without over-relaxation.
    pub fn sphere_trace(
        &self,
        origin: Vec3<F>,
        dir: Vec3<F>,
        t_start: F,
        t_end: F,
        eps_slope: F,
    ) -> Trace<F> {
        self.sphere_trace_by(origin, dir, t_start, t_end, eps_slope, self.step_scale)
    }

    /// `sphere_trace` with the over-relaxation omega given (path mode's secondary rays take
    /// theirs from `path.step_scale`).
    pub fn sphere_trace_by(
        &self,
        origin: Vec3<F>,
        dir: Vec3<F>,
        t_start: F,
        t_end: F,
        eps_slope: F,
        omega_start: F,
    ) -> Trace<F> {
        let mut t = t_start;
        let mut omega = omega_start;
        let mut t_prev = t_start;
        let mut prev_radius = F::zero();
        let mut closest = F::lit(NO_APPROACH);
        for steps in 1..=self.max_steps {
            let d = self.estimate_distance(origin + dir * t);
            closest = closest.min(d);
            let radius = d.max(F::zero());
            if omega > F::one() && t - t_prev > prev_radius + radius {
                t = t_prev + prev_radius;
                omega = F::one();
                continue;
            }
            let t_plain = t + radius;
            if d < self
                .epsilon
                .max(eps_slope * t_plain)
                .max(t_plain * F::lit(F::RELATIVE_EPSILON))
            {
                return Trace {
                    t: t_plain,
                    steps,
                    hit: true,
                    closest,
                };
            }
            t_prev = t;
            prev_radius = radius;
            t = t + omega * radius;
            if t > t_end {
                if t_plain > t_end {
                    return Trace {
                        t,
                        steps,
                        hit: false,
                        closest,
                    };
                }
                t = t_plain;
                omega = F::one();
            }
        }
        Trace {
            t,
            steps: self.max_steps,
            hit: false,
            closest,
        }
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
        if self.cut {
            return [d[0].max(self.cut_plane(p1)), d[1].max(self.cut_plane(p2))];
        }
        d
    }

    /// `sphere_trace`'s start for the ray origin + t dir over [t_start, t_end]; a ray not
    /// `live` is not traced (its outcome is a miss of no steps).
    pub fn march_start(
        &self,
        origin: Vec3<F>,
        dir: Vec3<F>,
        (t_start, t_end): (F, F),
        eps_slope: F,
        live: bool,
    ) -> March<F> {
        March {
            origin,
            dir,
            t_end,
            eps_slope,
            t: t_start,
            omega: self.step_scale,
            t_prev: t_start,
            prev_radius: F::zero(),
            closest: F::lit(NO_APPROACH),
            live,
            trace: Trace::untraced(),
        }
    }

    /// One step of `sphere_trace`, its `steps`-th, for the live ray m with the estimate d at its
    /// point: `sphere_trace`'s loop body, where a return ends the ray (live false, its outcome
    /// in trace).
    pub fn march_step(&self, m: &mut March<F>, d: F, steps: u32) {
        m.closest = m.closest.min(d);
        let radius = d.max(F::zero());
        if m.omega > F::one() && m.t - m.t_prev > m.prev_radius + radius {
            m.t = m.t_prev + m.prev_radius;
            m.omega = F::one();
            return;
        }
        let t_plain = m.t + radius;
        if d < self
            .epsilon
            .max(m.eps_slope * t_plain)
            .max(t_plain * F::lit(F::RELATIVE_EPSILON))
        {
            m.trace = Trace {
                t: t_plain,
                steps,
                hit: true,
                closest: m.closest,
            };
            m.live = false;
            return;
        }
        m.t_prev = m.t;
        m.prev_radius = radius;
        m.t = m.t + m.omega * radius;
        if m.t > m.t_end {
            if t_plain > m.t_end {
                m.trace = Trace {
                    t: m.t,
                    steps,
                    hit: false,
                    closest: m.closest,
                };
                m.live = false;
                return;
            }
            m.t = t_plain;
            m.omega = F::one();
        }
    }

    /// A marched ray's outcome: where it stopped, or, still live after max_steps, a miss there
    /// (`sphere_trace`'s last return).
    pub fn march_end(&self, m: &March<F>) -> Trace<F> {
        if m.live {
            return Trace {
                t: m.t,
                steps: self.max_steps,
                hit: false,
                closest: m.closest,
            };
        }
        m.trace
    }

    /// `sphere_trace` of two rays at once, step for step: both estimates of a step in one
    /// `estimate_distance_pair`, each ray stepped by `sphere_trace`'s rule and stopping on its
    /// own. Each outcome is `sphere_trace`'s of its ray bit for bit.
    pub fn sphere_trace_pair(&self, a: March<F>, b: March<F>) -> [Trace<F>; 2] {
        let mut m = [a, b];
        for steps in 1..=self.max_steps {
            if !(m[0].live || m[1].live) {
                break;
            }
            let p1 = m[0].origin + m[0].dir * m[0].t;
            let p2 = m[1].origin + m[1].dir * m[1].t;
            let d = self.estimate_distance_pair(p1, p2, [m[0].live, m[1].live]);
            for k in 0..2 {
                if m[k].live {
                    self.march_step(&mut m[k], d[k], steps);
                }
            }
        }
        [self.march_end(&m[0]), self.march_end(&m[1])]
    }
}

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
        if self.cut && self.cut_plane(p) + self.epsilon >= self.estimate_julia(p) {
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

    /// The orbit trap's distance for q: t = min over n = 0..N of | |z_n| - trap_radius |,
    /// z_0 = q, z_{n+1} = z_n^2 + c, N the first n with |z_n|^2 > escape_radius_squared, or
    /// max_iterations (iterate_orbit's count and escape; no derivative is carried, so its limit
    /// does not apply).
    pub fn orbit_trap(&self, q: Hyper<F>) -> F {
        let parts = self.algebra_parts;
        let mut z = q;
        let mut trap = (hyper_dot(z, z, parts).sqrt() - self.trap_radius).abs();
        for _ in 0..self.max_iterations {
            count(&super::ITERATIONS, 1);
            z = hyper_add(hyper_sq(z, parts), self.c);
            let z_norm2 = hyper_dot(z, z, parts);
            trap = trap.min((z_norm2.sqrt() - self.trap_radius).abs());
            if z_norm2 > self.escape_radius_squared {
                break;
            }
        }
        trap
    }

    /// The palette: 0.5 + 0.5 cos(2 pi x) per channel, x = fract(trap_scale t + palette_phase)
    /// (the fraction changes nothing but keeps cos's argument small).
    pub fn palette(&self, t: F) -> Vec3<F> {
        let half = F::lit(0.5);
        let channel = |phase: F| {
            let y = self.trap_scale * t + phase;
            let x = y - y.floor();
            half + half * (F::lit(6.2831855) * x).cos()
        };
        Vec3::new(
            channel(self.palette_phase.x),
            channel(self.palette_phase.y),
            channel(self.palette_phase.z),
        )
    }

    /// The base colour of a hit at p: the diffuse colour, or the palette's colour of the orbit
    /// trap. (shade_features's B, path mode's albedo, and the albedo AOV.)
    pub fn hit_albedo(&self, p: Vec3<F>) -> Vec3<F> {
        if self.colouring == Colouring::OrbitTrap {
            return self.palette(self.orbit_trap(self.slice_point(p)));
        }
        self.diffuse
    }

    /// Whether the hit is shaded by [`Self::shade_features`] (a light of some radius, ambient
    /// light, occlusion or orbit-trap colour) instead of the seed's phong and in_shadow.
    pub fn shading_features(&self) -> bool {
        let soft = self.shadows && self.light_radius > F::zero();
        let trap = self.colouring == Colouring::OrbitTrap;
        soft || self.occlusion > F::zero() || trap || self.ambient > F::zero()
    }

    /// The shading with the picture's features, the README's formula: with base colour B
    /// (diffuse, or the palette's colour of the orbit trap), the occlusion factor A and V the light's visibility (1 lit, 0 in shadow, between
    /// in a penumbra): ambient A B + (shadow_factor + (1 - shadow_factor) V)
    /// (A (B + normal_tint |n|) max(N.L, 0) + highlight), the highlight as in phong. With
    /// ambient 0, A 1 and a point light it is phong's colour, shadowed as trace_pixel does.
    /// The viewer is at `eye`: the ray's origin (the camera's eye, or a point of the lens).
    pub fn shade_features(&self, p: Vec3<F>, n: Vec3<F>, eye: Vec3<F>) -> Vec3<F> {
        let base = self.hit_albedo(p);
        let mut a = F::one();
        if self.occlusion > F::zero() {
            a = self.occlusion(p, n);
        }
        let mut ambient = base * (self.ambient * a);
        if self.environment_on() && self.env_light {
            ambient = ambient.mul_elem(Vec3::from_f32(self.env_irradiance(n.to_f32())));
        }
        let l = safe_normalize(self.light - p, n);
        let e = safe_normalize(eye - p, n);
        let n_dot_l = n.dot(l);
        if n_dot_l <= F::zero() {
            return ambient;
        }
        let r = n * (F::lit(2.0) * n_dot_l) - l;
        let e_dot_r = e.dot(r);
        let mut highlight = F::zero();
        if e_dot_r > F::zero() {
            highlight = self.specular * e_dot_r.powf(self.shininess);
        }
        let mut light = (base + n.abs() * self.normal_tint) * a * n_dot_l + Vec3::splat(highlight);
        // As in trace_pixel: no shadow ray for an unlit point.
        let lit = light.x > F::zero() || light.y > F::zero() || light.z > F::zero();
        if self.shadows && lit {
            if self.light_radius > F::zero() {
                let sf = self.shadow_factor;
                light = light * (sf + (F::one() - sf) * self.soft_shadow(p, n));
            } else if self.in_shadow(p, n) {
                light = light * self.shadow_factor;
            }
        }
        ambient + light
    }

    /// What a ray along `dir` that hits nothing shows: the environment map's radiance where
    /// the scene has one (phong mode clamps it as any colour), else the flat background.
    pub fn background(&self, dir: Vec3<F>) -> Vec3<F> {
        if self.environment_on() {
            return Vec3::from_f32(self.env_radiance(dir.to_f32()));
        }
        self.background
    }

    /// The ray through the point (x, y) of the image plane in pixel units, (0, 0) the top left
    /// corner.
    pub fn camera_ray_at(&self, x: F, y: F) -> Vec3<F> {
        let (one, two) = (F::one(), F::lit(2.0));
        let px = (two * x / F::lit(self.width as f64) - one) * self.tan_half_fov_y * self.aspect;
        let py = (one - two * y / F::lit(self.height as f64)) * self.tan_half_fov_y;
        (self.cam_forward + self.cam_right * px + self.cam_up * py).normalize()
    }

    /// The primary ray's direction through sample `sample` of pixel (i, j), row 0 at the top
    /// (docs/CONTRACT.md's camera); sample 0 goes through the pixel's centre.
    pub fn camera_ray(&self, i: u32, j: u32, sample: u32) -> Vec3<F> {
        let (sx, sy) = self.stream_position(sample);
        self.camera_ray_at(F::lit(i as f64) + sx, F::lit(j as f64) + sy)
    }

    /// Whether the camera's samples go through the thin lens: aperture > 0. Every sample does
    /// then, sample 0 too; the depth and the steps stay the pinhole's ray's through the pixel's
    /// centre (`pinhole_ray`), traced for them alone.
    pub fn lens_open(&self) -> bool {
        self.aperture > F::zero()
    }

    /// The thin lens's ray of sample `sample` of pixel (i, j) in phong mode: through the
    /// sample's image-plane point (`stream_position`) and the aperture's point at its lens
    /// position (`lens_point`).
    pub fn lens_ray(&self, i: u32, j: u32, sample: u32) -> Ray<F> {
        let (sx, sy) = self.stream_position(sample);
        let x = F::lit(i as f64) + sx;
        let y = F::lit(j as f64) + sy;
        self.thin_lens_ray(x, y, self.lens_point(sample))
    }

    /// The thin lens's ray through the image-plane point (x, y) (in pixels) and the point `lens`
    /// of the unit aperture: the pinhole ray through (x, y), direction f + px r + py u, meets
    /// the focus plane (at focus_distance along f) at eye + focus_distance (f + px r + py u);
    /// the ray leaves the lens at eye + aperture (lens.x r + lens.y u), toward that point.
    pub fn thin_lens_ray(&self, x: F, y: F, lens: (f32, f32)) -> Ray<F> {
        let (one, two) = (F::one(), F::lit(2.0));
        let px = (two * x / F::lit(self.width as f64) - one) * self.tan_half_fov_y * self.aspect;
        let py = (one - two * y / F::lit(self.height as f64)) * self.tan_half_fov_y;
        let (lx, ly) = (
            self.aperture * F::lit(lens.0 as f64),
            self.aperture * F::lit(lens.1 as f64),
        );
        let offset = self.cam_right * lx + self.cam_up * ly;
        let focus =
            (self.cam_forward + self.cam_right * px + self.cam_up * py) * self.focus_distance;
        Ray {
            origin: self.eye + offset,
            dir: (focus - offset).normalize(),
        }
    }

    /// Sample k's point on the unit aperture in phong mode: the aperture's point at its
    /// stream's lens position (`stream_lens_position`: the Halton point of index 0 is the
    /// lens's centre, which would make a stream's first sample a pinhole sample).
    pub fn lens_point(&self, k: u32) -> (f32, f32) {
        self.aperture_point(self.stream_lens_position(k))
    }

    /// The point of the unit aperture at (u, v) in [0, 1)^2, in f32 (its trigonometry too, as
    /// the f64 kernels do), turned by rotation = blade_rotation: for a round aperture (blades 0)
    /// the polar map sqrt(u) (cos phi, sin phi), phi = 2 pi v + rotation (uniform over the
    /// disc); for n blades the regular n-gon inscribed in the unit circle with corners
    /// c_m = (cos a_m, sin a_m), a_m = 2 pi m / n + rotation, uniform over it: the triangle
    /// (0, c_m, c_m+1) with m = floor(n u), then with a = n u - m and b = v the point
    /// sqrt(a) ((1 - b) c_m + b c_m+1).
    pub fn aperture_point(&self, (u, v): (f32, f32)) -> (f32, f32) {
        let rotation = self.blade_rotation.to_f64() as f32;
        if self.blades == 0 {
            let phi = 6.283_185_5_f32 * v + rotation;
            let r = u.sqrt();
            return (r * phi.cos(), r * phi.sin());
        }
        let n = self.blades as f32;
        let m = (n * u).floor().min(n - 1.0);
        let a = n * u - m;
        let a0 = 6.283_185_5_f32 * (m / n) + rotation;
        let a1 = 6.283_185_5_f32 * ((m + 1.0) / n) + rotation;
        let r = a.sqrt();
        (
            r * ((1.0 - v) * a0.cos() + v * a1.cos()),
            r * ((1.0 - v) * a0.sin() + v * a1.sin()),
        )
    }

    /// Cone tracing's start for the block (bi, bj) of CONE_BLOCK x CONE_BLOCK pixels: march the
    /// ray through the block's centre, shrinking each unbounding sphere by the cone's radius at
    /// that distance (t times the tangent of the widest angle to a corner ray), so that the whole
    /// cone is known to be at least epsilon from the set up to the t returned. Every ray of the
    /// block may start there. Bounded by max_steps; 0 where the centre ray misses the ball.
    pub fn cone_start(&self, bi: u32, bj: u32) -> F {
        let x0 = F::lit((bi * CONE_BLOCK) as f64);
        let y0 = F::lit((bj * CONE_BLOCK) as f64);
        let size = F::lit(CONE_BLOCK as f64);
        let half = F::lit(0.5);
        let centre = self.camera_ray_at(x0 + half * size, y0 + half * size);
        let mut spread = F::zero();
        for k in 0..4u32 {
            let corner = self.camera_ray_at(
                x0 + size * F::lit((k & 1) as f64),
                y0 + size * F::lit((k >> 1) as f64),
            );
            let cos_angle = centre.dot(corner).max(F::lit(0.1));
            spread = spread.max(centre.cross(corner).length() / cos_angle);
        }
        let bounds = self.intersect_bounds(self.eye, centre);
        if !bounds.hit {
            return F::zero();
        }
        let mut t = bounds.t_enter;
        for _ in 0..self.max_steps {
            let free = self.estimate_distance(self.eye + centre * t) - spread * t;
            if free < F::lit(CONE_MARGIN) * self.epsilon || t > bounds.t_exit {
                return t;
            }
            t = t + free;
        }
        t
    }

    /// Sample `sample`'s pinhole ray of pixel (i, j), from the eye, against the bounds, from
    /// t_min on (the cone's start, or 0): the camera ray where the lens is closed, and with
    /// sample 0 the ray that gives the depth and the steps.
    pub fn pinhole_ray(&self, i: u32, j: u32, sample: u32, t_min: F) -> Primary<F> {
        let dir = self.camera_ray(i, j, sample);
        let bounds = self.intersect_bounds(self.eye, dir);
        Primary {
            origin: self.eye,
            dir,
            t_start: bounds.t_enter.max(t_min),
            t_end: bounds.t_exit,
            hit: bounds.hit,
        }
    }

    /// Sample `sample`'s camera ray of pixel (i, j): the pinhole's (`pinhole_ray`), or where
    /// the lens is open the thin lens's, against the bounds. A lens ray starts from the ball:
    /// the cone covers the block's rays from the eye, not rays from elsewhere on the lens.
    pub fn primary_ray(&self, i: u32, j: u32, sample: u32, t_min: F) -> Primary<F> {
        if !self.lens_open() {
            return self.pinhole_ray(i, j, sample, t_min);
        }
        let ray = self.lens_ray(i, j, sample);
        let bounds = self.intersect_bounds(ray.origin, ray.dir);
        Primary {
            origin: ray.origin,
            dir: ray.dir,
            t_start: bounds.t_enter,
            t_end: bounds.t_exit,
            hit: bounds.hit,
        }
    }

    /// A camera ray's sphere trace, with the pixel epsilon; a miss of no steps where it misses
    /// the ball.
    pub fn trace_primary(&self, ray: &Primary<F>) -> Trace<F> {
        if !ray.hit {
            return Trace::untraced();
        }
        let eps_slope = self.pixel_epsilon * self.pixel_angle;
        self.sphere_trace(ray.origin, ray.dir, ray.t_start, ray.t_end, eps_slope)
    }

    /// Two camera rays' sphere traces at once (`sphere_trace_pair`): each `trace_primary`'s
    /// bit for bit.
    pub fn trace_primary_pair(&self, a: &Primary<F>, b: &Primary<F>) -> [Trace<F>; 2] {
        let eps_slope = self.pixel_epsilon * self.pixel_angle;
        let m1 = self.march_start(a.origin, a.dir, (a.t_start, a.t_end), eps_slope, a.hit);
        let m2 = self.march_start(b.origin, b.dir, (b.t_start, b.t_end), eps_slope, b.hit);
        self.sphere_trace_pair(m1, m2)
    }

    /// Whether the scene has fog (`fog.density` > 0, either model).
    pub fn fog_on(&self) -> bool {
        self.fog_density > F::zero()
    }

    /// Whether phong mode's halo is on (`glow.strength` > 0).
    pub fn glow_on(&self) -> bool {
        self.glow_strength > F::zero()
    }

    /// The fog's transmittance along origin + t dir over t in [0, t_stop]: exp(-fog_density L),
    /// L the length of that stretch within the bounding ball (the fog fills the ball); 1
    /// without fog. In f32, as path mode's radiance is.
    pub fn fog_transmittance(&self, origin: Vec3<F>, dir: Vec3<F>, t_stop: F) -> f32 {
        if !self.fog_on() {
            return 1.0;
        }
        let bounds = self.intersect_bounds(origin, dir);
        if !bounds.hit {
            return 1.0;
        }
        let length = (bounds.t_exit.min(t_stop) - bounds.t_enter).max(F::zero());
        (-((self.fog_density * length).to_f64() as f32)).exp()
    }

    /// Phong mode's halo for a ray that missed: glow_strength glow_colour exp(-closest /
    /// glow_radius), closest the least distance estimate along the ray ([`Trace`]'s `closest`;
    /// a ray that missed the ball gets exp(-3e38 / r) = 0).
    pub fn glow(&self, closest: F) -> Vec3<F> {
        let fall = (-((closest.max(F::zero()) / self.glow_radius).to_f64() as f32)).exp();
        self.glow_colour * (self.glow_strength * F::lit(fall as f64))
    }

    /// Phong mode's atmosphere over a camera ray's colour (docs/book/atmosphere.md): a miss
    /// gains the halo ([`Self::glow`]); then the colour is blended toward fog_colour by the
    /// fog's transmittance T from the eye to the hit (through the whole ball on a miss),
    /// mix(fog_colour, colour, T). Without fog and glow the colour unchanged.
    pub fn atmosphere(&self, colour: Vec3<F>, ray: &Primary<F>, trace: Trace<F>) -> Vec3<F> {
        let mut c = colour;
        if !trace.hit && self.glow_on() {
            c += self.glow(trace.closest);
        }
        if self.fog_on() {
            let t_stop = if trace.hit { trace.t } else { F::lit(3.0e38) };
            let transmittance = F::lit(self.fog_transmittance(ray.origin, ray.dir, t_stop) as f64);
            c = mix3(self.fog_colour, c, transmittance);
        }
        c
    }

    /// A sample's outcome from its camera ray and the ray's trace: normal, Phong, shadow, and
    /// the atmosphere over them. `shade` is the kernel's SHADE override (false: depth and steps only, as a specialised
    /// pipeline without the shading code): the colour is the background.
    pub fn shade_pixel(&self, ray: &Primary<F>, trace: Trace<F>, shade: bool) -> Pixel<F> {
        let none = Vec3::zero();
        if !trace.hit {
            return Pixel {
                colour: self.atmosphere(self.background(ray.dir), ray, trace),
                depth: -F::one(),
                steps: trace.steps,
                hit: false,
                point: none,
                normal: none,
            };
        }
        if !shade {
            return Pixel {
                colour: self.background,
                depth: trace.t,
                steps: trace.steps,
                hit: true,
                point: none,
                normal: none,
            };
        }
        let (origin, dir) = (ray.origin, ray.dir);
        let p = origin + dir * trace.t;
        let n = self.estimate_normal(p, dir);
        if self.shading_features() {
            return Pixel {
                colour: self.atmosphere(self.shade_features(p, n, origin), ray, trace),
                depth: trace.t,
                steps: trace.steps,
                hit: true,
                point: p,
                normal: n,
            };
        }
        let mut colour = self.phong(self.light, origin, p, n);
        // An unlit point (black: the light is behind its surface) stays black in shadow: no ray.
        let lit = colour.x > F::zero() || colour.y > F::zero() || colour.z > F::zero();
        if self.shadows && lit && self.in_shadow(p, n) {
            colour = colour * self.shadow_factor;
        }
        Pixel {
            colour: self.atmosphere(colour, ray, trace),
            depth: trace.t,
            steps: trace.steps,
            hit: true,
            point: p,
            normal: n,
        }
    }

    /// Everything for one sample of pixel (i, j): its camera ray (`primary_ray`), sphere
    /// tracing, and shading (`shade_pixel`).
    pub fn trace_pixel(&self, i: u32, j: u32, sample: u32, t_min: F, shade: bool) -> Pixel<F> {
        let ray = self.primary_ray(i, j, sample, t_min);
        self.shade_pixel(&ray, self.trace_primary(&ray), shade)
    }
}

/// Where sample k lies in its pixel, (x, y) in [0, 1)^2 from the pixel's top left corner:
/// (0.5, 0.5), the centre, for sample 0; else the Halton point of index k in bases 2 and 3
/// (k < 4096: its 12 binary and 8 ternary digits, so both coordinates are exact in f32).
pub fn sample_position<F: Real>(k: u32) -> (F, F) {
    if k == 0 {
        return (F::lit(0.5), F::lit(0.5));
    }
    let base2 = k.reverse_bits() >> 20;
    let mut base3 = 0u32;
    let mut rest = k;
    for _ in 0..8 {
        base3 = base3 * 3 + rest % 3;
        rest /= 3;
    }
    (
        F::lit(base2 as f64) * F::lit(1.0 / 4096.0),
        F::lit(base3 as f64) * F::lit(1.0 / 6561.0),
    )
}

/// Where sample k (>= 1) lies on the lens before the aperture's map, (u, v) in [0, 1)^2: the
/// Halton point of index k in bases 5 and 7 (the sub-pixel positions take 2 and 3), from k's
/// first 6 quinary and 5 septenary digits as integers over 15625 and 16807 (k < 4096 has no
/// more).
pub fn lens_position(k: u32) -> (f32, f32) {
    let mut base5 = 0u32;
    let mut rest = k;
    for _ in 0..6 {
        base5 = base5 * 5 + rest % 5;
        rest /= 5;
    }
    let mut base7 = 0u32;
    rest = k;
    for _ in 0..5 {
        base7 = base7 * 7 + rest % 7;
        rest /= 7;
    }
    (
        base5 as f32 * (1.0 / 15625.0_f64) as f32,
        base7 as f32 * (1.0 / 16807.0_f64) as f32,
    )
}

impl<F: Real> TraceParams<F> {
    /// Adaptive sampling's two streams (docs/book/adaptive.md): sample k of an adaptive pixel
    /// is sample k / 2 of stream k % 2, as (stream, index). Each stream's stop is decided by its
    /// own samples and applied to the other's mean ([`TraceParams::add_to_streams`]), so that no
    /// half of what the pixel shows depends on its own stop. Without adaptive sampling every
    /// sample is stream 0's: (0, k) (phong mode; path mode has both streams anyway:
    /// [`TraceParams::path_stream`]).
    pub fn sample_stream(&self, k: u32) -> (u32, u32) {
        if self.adaptive() {
            return (k & 1, k >> 1);
        }
        (0, k)
    }
}

/// Stream 1's points in phong mode are stream 0's turned by this Cranley-Patterson shift
/// (modulo 1, in the pixel and on the lens alike): R2's (0.7549, 0.5698) rounded to 11 bits,
/// exact in f32. The streams' points are then apart, each stream as well spread as the Halton
/// points.
pub const STREAM_SHIFT: (f32, f32) = (1545.0 / 2048.0, 1167.0 / 2048.0);

impl<F: Real> TraceParams<F> {
    /// Where sample k lies in its pixel in phong mode: its stream's index's `sample_position`,
    /// shifted by [`STREAM_SHIFT`] in stream 1.
    pub fn stream_position(&self, k: u32) -> (F, F) {
        let (stream, index) = self.sample_stream(k);
        let (x, y) = sample_position::<F>(index);
        if stream == 0 {
            return (x, y);
        }
        let fract = |v: F| v - v.floor();
        (
            fract(x + F::lit(STREAM_SHIFT.0 as f64)),
            fract(y + F::lit(STREAM_SHIFT.1 as f64)),
        )
    }

    /// Where sample k lies on the lens before the aperture's map in phong mode: `lens_position`
    /// of its stream's index + 1, shifted by [`STREAM_SHIFT`] in stream 1.
    pub fn stream_lens_position(&self, k: u32) -> (f32, f32) {
        let (stream, index) = self.sample_stream(k);
        let (u, v) = lens_position(index + 1);
        if stream == 0 {
            return (u, v);
        }
        let fract = |x: f32| x - x.floor();
        (fract(u + STREAM_SHIFT.0), fract(v + STREAM_SHIFT.1))
    }
}

/// Colour clamped to [0, 1], times 255, rounded half up, packed as RGBA8 0xFFBBGGRR (opaque).
pub fn pack_colour<F: Real>(colour: Vec3<F>) -> u32 {
    let channel = |c: F| {
        let c = c.max(F::zero()).min(F::one());
        (c * F::lit(255.0) + F::lit(0.5)).floor().to_f64() as u32
    };
    channel(colour.x) | (channel(colour.y) << 8) | (channel(colour.z) << 16) | 0xff00_0000
}

/// Rec. 709 luminance of a linear colour, as [`super::bsdf::luminance`] (the shader's phong
/// module has no bsdf.wgsl).
pub fn sample_luminance(c: Vec3<f32>) -> f32 {
    super::bsdf::luminance(c)
}

/// Welford's rule: the sum of squared deviations from the mean `m2` of luminances, with one
/// more luminance `l`, given the mean's luminance before it (`before`) and after (`after`),
/// M2_k = M2_(k-1) + (l_k - L(m_(k-1))) (l_k - L(m_k)).
pub fn add_m2(m2: f32, l: f32, before: f32, after: f32) -> f32 {
    m2 + (l - before) * (l - after)
}

/// Adds sample k (0-based) to the AOVs: its colour and its specular light to the running means
/// over the samples, m_k = m_(k-1) + (c_k - m_(k-1)) / (k + 1), and its luminance l_k to M2
/// ([`add_m2`]); where it hit, its albedo, normal, depth and view cosine to the running means
/// over the hits, by the same rule with the hits counted so far.
#[allow(clippy::too_many_arguments)]
pub fn add_aovs(
    a: Aovs,
    k: u32,
    colour: Vec3<f32>,
    hit: bool,
    albedo: Vec3<f32>,
    normal: Vec3<f32>,
    depth: f32,
    (specular, cosine): (Vec3<f32>, f32),
) -> Aovs {
    let mut out = a;
    out.colour = a.colour + (colour - a.colour) / (k + 1) as f32;
    out.specular = a.specular + (specular - a.specular) / (k + 1) as f32;
    let l = sample_luminance(colour);
    out.m2 = add_m2(
        a.m2,
        l,
        sample_luminance(a.colour),
        sample_luminance(out.colour),
    );
    if hit {
        out.hits = a.hits + 1.0;
        out.albedo = a.albedo + (albedo - a.albedo) / out.hits;
        out.normal = a.normal + (normal - a.normal) / out.hits;
        out.depth = a.depth + (depth - a.depth) / out.hits;
        out.cosine = a.cosine + (cosine - a.cosine) / out.hits;
    }
    out
}

impl<F: Real> TraceParams<F> {
    /// Adds sample k's pixel to the AOVs: its colour, and where it hit, the base colour of its
    /// hit (hit_albedo), its shading normal and its depth. (AOVs are made only of shaded
    /// pictures: every hit is shaded.)
    pub fn add_pixel_aovs(&self, a: Aovs, k: u32, pixel: &Pixel<F>) -> Aovs {
        let mut albedo = Vec3::zero();
        if pixel.hit {
            albedo = self.hit_albedo(pixel.point).to_f32();
        }
        let (colour, normal) = (pixel.colour.to_f32(), pixel.normal.to_f32());
        let depth = pixel.depth.to_f64() as f32;
        add_aovs(
            a,
            k,
            colour,
            pixel.hit,
            albedo,
            normal,
            depth,
            (Vec3::zero(), 0.0),
        )
    }

    /// Whether this render samples adaptively (the shader's `adaptive`: `noise_target` > 0 with
    /// samples > 1; the book's chapter "Adaptive sampling"). Each pixel decides alone, after
    /// each of its samples, whether it is done, so any split of the image gives the same pixels.
    pub fn adaptive(&self) -> bool {
        self.noise_target > F::zero() && self.samples > 1
    }
}

/// A pixel's noise is taken relative to its mean luminance or to this, whichever is larger (the
/// floor for dark pixels, in linear luminance: 1 is phong mode's white), so that a black
/// pixel's noise is not a division by zero.
pub const NOISE_LUMINANCE_FLOOR: f32 = 0.01;

/// A pixel's noise after n >= 2 samples whose luminances' M2 is `m2`: the standard error of
/// its mean luminance, sqrt(m2 / (n (n - 1))), relative to that mean (at least
/// [`NOISE_LUMINANCE_FLOOR`]).
pub fn pixel_noise(m2: f32, n: u32, mean_luminance: f32) -> f32 {
    let k = n as f32;
    let variance = (m2 / (k * (k - 1.0))).max(0.0);
    variance.sqrt() / mean_luminance.abs().max(NOISE_LUMINANCE_FLOOR)
}

/// A pixel's adaptive state (the kernels' `Streams`, kept on the GPU in the accumulator's four
/// planes): `a` = (A's mean colour, tau_A: 0 until A's rule fires), `b` = (B's mean colour, the
/// samples in it), `rule_a` = (A's mean luminance, its M2 ([`add_m2`]), its samples kept, the
/// samples in A's colour), `rule_b` = (B's mean luminance, its M2, its samples kept, tau_B: 0
/// until B's rule fires). Streams A and B are stream 0 and 1 of
/// [`TraceParams::sample_stream`]. A's colour takes A's draws while B's rule has not fired (A's
/// first tau_B), B's takes B's first tau_A; each stream's luminances are counted until its own
/// rule fires. The counts are exact in f32. All in f32 in both precisions, as the accumulator is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Streams {
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub rule_a: [f32; 4],
    pub rule_b: [f32; 4],
}

/// A stream's luminance statistics (`rule`: mean, M2, samples kept) with one more luminance `l`,
/// by Welford's rule ([`add_m2`], at least 0); the fourth float is kept.
pub fn add_luminance(rule: [f32; 4], l: f32) -> [f32; 4] {
    let mut out = rule;
    out[2] = rule[2] + 1.0;
    out[0] = rule[0] + (l - rule[0]) / out[2];
    out[1] = add_m2(rule[1], l, rule[0], out[0]).max(0.0);
    out
}

impl<F: Real> TraceParams<F> {
    /// Whether a stream's rule fires after its draw `draws` (from 1), its luminances' statistics
    /// being `rule` ([`add_luminance`]): at its cap of samples / 2 draws, or from half the floor
    /// max(min(min_samples, samples), 4) (rounded up) on, with at least 2 samples kept and a
    /// noise ([`pixel_noise`]) at most the target.
    pub fn stream_fires(&self, rule: [f32; 4], draws: u32) -> bool {
        if draws >= self.samples / 2 {
            return true;
        }
        let floor = self.min_samples.min(self.samples).max(4).div_ceil(2);
        if draws < floor || rule[2] < 2.0 {
            return false;
        }
        pixel_noise(rule[1], rule[2] as u32, rule[0]) <= self.noise_target.to_f64() as f32
    }

    /// A pixel's streams with its sample `k` taken (draw k / 2 + 1 of stream k % 2), of colour
    /// `colour` where it is `valid`.
    pub fn add_to_streams(&self, s: Streams, k: u32, valid: bool, colour: Vec3<f32>) -> Streams {
        let mut out = s;
        let draws = k / 2 + 1;
        let l = sample_luminance(colour);
        let c = [colour.x, colour.y, colour.z];
        let joined = |mean: [f32; 4], n: f32| [0, 1, 2].map(|k| mean[k] + (c[k] - mean[k]) / n);
        if k.is_multiple_of(2) {
            // A's draw joins A's colour while B's rule has not fired.
            if valid && s.rule_b[3] == 0.0 {
                out.rule_a[3] = s.rule_a[3] + 1.0;
                let [r, g, b] = joined(s.a, out.rule_a[3]);
                out.a = [r, g, b, s.a[3]];
            }
            if s.a[3] == 0.0 {
                if valid {
                    let [m, m2, kept, _] = add_luminance(s.rule_a, l);
                    out.rule_a = [m, m2, kept, out.rule_a[3]];
                }
                if self.stream_fires(out.rule_a, draws) {
                    out.a[3] = draws as f32;
                }
            }
        } else {
            // B's draw joins B's colour while A's rule has not fired, or up to A's stop.
            if valid && (s.a[3] == 0.0 || draws as f32 <= s.a[3]) {
                let n = s.b[3] + 1.0;
                let [r, g, b] = joined(s.b, n);
                out.b = [r, g, b, n];
            }
            if s.rule_b[3] == 0.0 {
                if valid {
                    let [m, m2, kept, _] = add_luminance(s.rule_b, l);
                    out.rule_b = [m, m2, kept, 0.0];
                }
                if self.stream_fires(out.rule_b, draws) {
                    out.rule_b[3] = draws as f32;
                }
            }
        }
        out
    }

    /// Whether a pixel whose streams are `s` is done once it has taken `taken` samples: both
    /// rules have fired and B has its first tau_A draws (A has its first tau_B whenever B's rule
    /// has fired), or it has taken every sample.
    pub fn sampling_done(&self, s: &Streams, taken: u32) -> bool {
        if taken >= self.samples {
            return true;
        }
        s.a[3] > 0.0 && s.rule_b[3] > 0.0 && (taken / 2) as f32 >= s.a[3]
    }
}

/// A pixel's two halves (the kernels' `Halves`; path mode, and an adaptive pixel once it is
/// done): each stream's mean colour and the samples in it, `a` = (A's mean colour, n_A), `b` =
/// (B's mean colour, n_B). The streams are drawn independently, so the halves' disagreement
/// estimates the error of what the pixel shows: E[(a - b)^2] / 4 = Var((a + b) / 2).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Halves {
    pub a: [f32; 4],
    pub b: [f32; 4],
}

/// A pixel's halves with its valid sample `k` (of stream k % 2) of colour `colour` joined to its
/// stream's running mean, m_n = m_(n-1) + (c - m_(n-1)) / n.
pub fn add_to_halves(h: Halves, k: u32, colour: Vec3<f32>) -> Halves {
    let c = [colour.x, colour.y, colour.z];
    let joined = |m: [f32; 4]| {
        let n = m[3] + 1.0;
        [
            m[0] + (c[0] - m[0]) / n,
            m[1] + (c[1] - m[1]) / n,
            m[2] + (c[2] - m[2]) / n,
            n,
        ]
    };
    let mut out = h;
    if k.is_multiple_of(2) {
        out.a = joined(h.a);
    } else {
        out.b = joined(h.b);
    }
    out
}

/// What a pixel whose halves are `h` shows: half A's mean colour plus half B's, or the one
/// half's where the other has no sample in it (black where neither has).
pub fn halves_mean(h: &Halves) -> Vec3<f32> {
    let [a, b] = [h.a, h.b].map(|m| Vec3::new(m[0], m[1], m[2]));
    if h.a[3] == 0.0 {
        return b;
    }
    if h.b[3] == 0.0 {
        return a;
    }
    (a + b) * 0.5
}

/// An adaptive pixel's halves: A's mean of its first tau_B draws, B's of its first tau_A.
pub fn streams_halves(s: &Streams) -> Halves {
    Halves {
        a: [s.a[0], s.a[1], s.a[2], s.rule_a[3]],
        b: s.b,
    }
}

/// What a pixel whose streams are `s` shows: its halves' mean ([`halves_mean`]).
pub fn streams_mean(s: &Streams) -> Vec3<f32> {
    halves_mean(&streams_halves(s))
}

/// A done pixel's AOVs with their hits and M2 taken to the `taken` samples it took, which the
/// host divides by ([`crate::denoise::mean_variance`], [`crate::denoise::hit_fraction`]):
/// hits / taken is then the fraction of the n = n_A + n_B samples in its colours that hit, and
/// M2 / (taken (taken - 1)) the variance of what it shows, M2 / (n - 1) (1 / n_A + 1 / n_B) / 4
/// (1 / n with one stream empty).
pub fn finish_aovs(a: Aovs, s: &Streams, taken: u32) -> Aovs {
    let mut out = a;
    let n = s.rule_a[3] + s.b[3];
    let t = taken as f32;
    if n == 0.0 {
        return out;
    }
    out.hits = a.hits * t / n;
    let mut spread = 1.0 / n;
    if s.rule_a[3] > 0.0 && s.b[3] > 0.0 {
        spread = 0.25 * (1.0 / s.rule_a[3] + 1.0 / s.b[3]);
    }
    out.m2 = 0.0;
    if n >= 2.0 && t >= 2.0 {
        out.m2 = a.m2 / (n - 1.0) * spread * (t * (t - 1.0));
    }
    out
}

/// Adds to one of the work counters (see `cpu::count_work`); not part of the twin.
fn count(counter: &'static std::thread::LocalKey<std::cell::Cell<u64>>, n: u64) {
    counter.with(|c| c.set(c.get() + n));
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
