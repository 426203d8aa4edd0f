//! The CPU twin of shaders/march.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). The march: where a ray meets the
//! bounding ball (intersect_bounds), sphere tracing with the seed's epsilon and over-relaxation
//! (sphere_trace, sphere_trace_by), and the march of two rays in step (March, march_start,
//! march_step, march_end, sphere_trace_pair).

use crate::algebra::{Real, Vec3};
use crate::params::TraceParams;

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

impl<F: Real> TraceParams<F> {
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
