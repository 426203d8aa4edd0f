// The march: where a ray meets the bounding ball (intersect_bounds), sphere tracing with the seed's
// epsilon and over-relaxation (sphere_trace, sphere_trace_by), and the march of two rays in step
// (March, march_start, march_step, march_end, sphere_trace_pair).
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/march.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params
#import estimate

// Where a ray meets the bounding ball.
struct Interval {
    t_enter: Real,
    t_exit: Real,
    hit: bool,
}

// The ray origin + t dir (t >= 0) against the 3D ball the 4D bounding ball cuts from the slice.
// Starts at the origin when it is inside; a ray that misses, or a ball behind, gives no hit.
// (The seed's intersectSphere.)
fn intersect_bounds(origin: vec3<Real>, dir: vec3<Real>) -> Interval {
    let oc = origin - params.bounds_center;
    let b = dot(oc, dir);
    let cc = dot(oc, oc) - params.bounds_radius_squared;
    let disc = b * b - cc;
    if params.bounds_radius_squared <= 0.0 || disc < 0.0 {
        return Interval(0.0, 0.0, false);
    }
    let t_exit = real_sqrt(disc) - b;
    if cc <= 0.0 {
        return Interval(0.0, t_exit, true);
    }
    if t_exit <= 0.0 {
        return Interval(0.0, 0.0, false);
    }
    // The product of the roots is cc: the nearer one without cancellation.
    return Interval(cc / t_exit, t_exit, true);
}

// A sphere-traced ray: the t reached, the estimates made, whether it hit, and the least
// distance estimate along it (phong mode's glow: how close a miss came to the set; NO_APPROACH
// for a ray not traced).
struct Trace {
    t: Real,
    steps: u32,
    hit: bool,
    closest: Real,
}

// A Trace's `closest` before any estimate.
const NO_APPROACH: Real = 3.0e38;

#if OVER_RELAXED
// The over-relaxation's omega at a march's start: step_scale. Without OVER_RELAXED
// (shaders/kernels.json: step_scale <= 1) 1, plain steps.
fn over_relaxation() -> Real {
    return params.step_scale;
}
#else
fn over_relaxation() -> Real {
    return 1.0;
}
#endif

#if PIXEL_EPSILON
// Whether a hit's threshold grows with the pixel's footprint (eps_slope t). Without
// PIXEL_EPSILON (pixel_epsilon = 0: eps_slope is 0 for every ray) false, and the term is not in
// the kernel.
fn pixel_epsilon_on() -> bool {
    return true;
}
#else
fn pixel_epsilon_on() -> bool {
    return false;
}
#endif

// Sphere tracing (the seed's intersectQJulia) from t_start: estimate d, advance by max(d, 0),
// stop with a hit when d is below the threshold: epsilon, or eps_slope t (epsilon proportional to
// the pixel footprint; 0 for shadow rays), or the float spacing at t where steps stall. A miss
// when t passes t_end or after max_steps estimates. The hit is the point reached by the plain
// step, as in the seed.
// With step_scale > 1 steps are over-relaxed (omega d); when the unbounding spheres of two
// successive points stop overlapping the ray may have jumped the surface, so it goes back to the
// plain step from the last point and carries on without over-relaxation.
fn sphere_trace(origin: vec3<Real>, dir: vec3<Real>, t_start: Real, t_end: Real, eps_slope: Real) -> Trace {
    return sphere_trace_by(origin, dir, t_start, t_end, eps_slope, over_relaxation());
}

// sphere_trace with the over-relaxation omega given (path mode's secondary rays take theirs
// from path.step_scale).
fn sphere_trace_by(origin: vec3<Real>, dir: vec3<Real>, t_start: Real, t_end: Real, eps_slope: Real, omega_start: Real) -> Trace {
    var t = t_start;
    var omega = omega_start;
    var t_prev = t_start;
    var prev_radius: Real = 0.0;
    var closest = NO_APPROACH;
    for (var steps = 1u; steps <= params.max_steps; steps++) {
        let d = estimate_distance(origin + t * dir);
        closest = min(closest, d);
        let radius = max(d, 0.0);
        if omega > 1.0 && t - t_prev > prev_radius + radius {
            t = t_prev + prev_radius;
            omega = 1.0;
            continue;
        }
        let t_plain = t + radius;
        var threshold = max(params.epsilon, t_plain * RELATIVE_EPSILON);
        if pixel_epsilon_on() {
            threshold = max(threshold, eps_slope * t_plain);
        }
        if d < threshold {
            return Trace(t_plain, steps, true, closest);
        }
        t_prev = t;
        prev_radius = radius;
        t += omega * radius;
        if t > t_end {
            if t_plain > t_end {
                return Trace(t, steps, false, closest);
            }
            t = t_plain;
            omega = 1.0;
        }
    }
    return Trace(t, params.max_steps, false, closest);
}

// One ray of an interleaved sphere trace (sphere_trace_pair): its ray and stretch, sphere_trace's
// variables, whether it is still being traced, and its outcome once it is not.
struct March {
    origin: vec3<Real>,
    dir: vec3<Real>,
    t_end: Real,
    eps_slope: Real,
    t: Real,
    omega: Real,
    t_prev: Real,
    prev_radius: Real,
    closest: Real,
    live: bool,
    trace: Trace,
}

// sphere_trace's start for the ray origin + t dir over [t_start, t_end]; a ray not `live` is
// not traced (its outcome is a miss of no steps).
fn march_start(origin: vec3<Real>, dir: vec3<Real>, t_start: Real, t_end: Real, eps_slope: Real, live: bool) -> March {
    return March(origin, dir, t_end, eps_slope, t_start, over_relaxation(), t_start, 0.0, NO_APPROACH, live, Trace(0.0, 0u, false, NO_APPROACH));
}

// One step of sphere_trace, its `steps`-th, for the live ray m with the estimate d at its point:
// sphere_trace's loop body, where a return ends the ray (live false, its outcome in trace).
fn march_step(m: ptr<function, March>, d: Real, steps: u32) {
    (*m).closest = min((*m).closest, d);
    let radius = max(d, 0.0);
    if (*m).omega > 1.0 && (*m).t - (*m).t_prev > (*m).prev_radius + radius {
        (*m).t = (*m).t_prev + (*m).prev_radius;
        (*m).omega = 1.0;
        return;
    }
    let t_plain = (*m).t + radius;
    var threshold = max(params.epsilon, t_plain * RELATIVE_EPSILON);
    if pixel_epsilon_on() {
        threshold = max(threshold, (*m).eps_slope * t_plain);
    }
    if d < threshold {
        (*m).trace = Trace(t_plain, steps, true, (*m).closest);
        (*m).live = false;
        return;
    }
    (*m).t_prev = (*m).t;
    (*m).prev_radius = radius;
    (*m).t += (*m).omega * radius;
    if (*m).t > (*m).t_end {
        if t_plain > (*m).t_end {
            (*m).trace = Trace((*m).t, steps, false, (*m).closest);
            (*m).live = false;
            return;
        }
        (*m).t = t_plain;
        (*m).omega = 1.0;
    }
}

// A marched ray's outcome: where it stopped, or, still live after max_steps, a miss there
// (sphere_trace's last return).
fn march_end(m: March) -> Trace {
    if m.live {
        return Trace(m.t, params.max_steps, false, m.closest);
    }
    return m.trace;
}

// Two sphere traces.
struct TracePair {
    first: Trace,
    second: Trace,
}

// sphere_trace of two rays at once, step for step: both estimates of a step in one
// estimate_distance_pair, each ray stepped by sphere_trace's rule and stopping on its own. Each
// outcome is sphere_trace's of its ray bit for bit.
fn sphere_trace_pair(a: March, b: March) -> TracePair {
    var m1 = a;
    var m2 = b;
    for (var steps = 1u; steps <= params.max_steps; steps++) {
        if !(m1.live || m2.live) {
            break;
        }
        let d = estimate_distance_pair(m1.origin + m1.t * m1.dir, m2.origin + m2.t * m2.dir, vec2<bool>(m1.live, m2.live));
        if m1.live {
            march_step(&m1, d.x, steps);
        }
        if m2.live {
            march_step(&m2, d.y, steps);
        }
    }
    return TracePair(march_end(m1), march_end(m2));
}
