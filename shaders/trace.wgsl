// The quaternion Julia set ray tracer of Crane (2005), fixed as docs/CONTRACT.md defines it:
// one invocation per pixel, through the distance estimate, sphere tracing, the normal, Phong
// shading and the shadow ray.
//
// Why it passes 600 lines: it is one kernel's module, the tracer and its features, twinned
// function by function with src/cpu/trace.rs; a split must split both alike (issue 36 item 5).
//
// Twin: src/cpu/trace.rs, function by function, with the same names in the same order (checked
// by tests/architecture/twins.rs, which lists the functions only one side has); a change to one is a change to
// both. Written against the float type `Real` of shaders/real.wgsl: one source, an f32 and an f64
// kernel (the feature F64, shaders/kernels.json). Its uniform and switches are shaders/params.wgsl.
//
// WGSL may assume NaN and Inf never occur, so every guard comes before the operation it guards.
#import real
#import algebra
#import params
#import environment

// params.colouring: the diffuse colour (the seed), or the orbit's closest approach to the trap.
const COLOURING_FLAT: u32 = 0u;
const COLOURING_ORBIT_TRAP: u32 = 1u;

// params.tracing: the seed's sphere tracing of every ray, or a cone per 8x8 block first.
const TRACING_SEED: u32 = 0u;
const TRACING_CONE: u32 = 1u;
// Pixels a side of the blocks that share a cone (one workgroup).
const CONE_BLOCK: u32 = 8u;
// The cone stops this many epsilons short: the estimate is about half the true distance near
// the surface, so rays must start where it is still well above epsilon.
const CONE_MARGIN: Real = 4.0;

// The cone's start, shared by the workgroup's invocations.
var<workgroup> cone_t: Real;

// The band of rows [row_offset, row_offset + row_count) lands in the output arrays from row
// out_row on, row_stride pixels a row: pixel (i, row_offset + r) at (out_row + r) * row_stride + i.
// Colour as 0xFFBBGGRR (RGBA8, opaque).
@group(0) @binding(1) var<storage, read_write> out_colour: array<u32>;
// The hit's ray parameter t; -1 for a miss (the host turns it into NaN).
@group(0) @binding(2) var<storage, read_write> out_depth: array<Real>;
// Distance estimates along the primary ray.
@group(0) @binding(3) var<storage, read_write> out_steps: array<u32>;
// The work made for the pixel, every sample and every ray, summed across dispatches (add_work):
// its distance estimates and its quaternion iterations, each a 64-bit count as its low and
// high words (x and y the estimates, z and w the iterations).
@group(0) @binding(4) var<storage, read_write> out_work: array<vec4<u32>>;
// With several samples: the mean of the samples' clamped colours so far (rgb).
@group(0) @binding(5) var<storage, read_write> accumulated: array<vec4<f32>>;
// With AOVS: three vec4s a pixel, from index 3 * index on, the Aovs so far (store_aovs).
@group(0) @binding(6) var<storage, read_write> out_aovs: array<vec4<f32>>;

// Distance estimates this invocation has made for its pixel in this dispatch (the cone's are
// not counted), and the quaternion iterations (z <- z^2 + c) it has made for them, for the
// normals and for the orbit trap.
var<private> estimates: u32;
var<private> iterations: u32;

// DERIVATIVE_LIMIT, RELATIVE_EPSILON and MIN_NORMAL depend on the precision: the prelude
// (shaders/real32.wgsl or shaders/real64.wgsl) defines them.
// Below this a squared length counts as zero: nothing is divided by it or normalised.
const TINY: Real = 1e-30;
// |z|^2 at which the normal's six orbits stop, long before they can overflow.
const NORMAL_LIMIT: Real = 1e16;
// Ambient occlusion samples the estimate at OCCLUSION_SAMPLES points p + k OCCLUSION_STEP n,
// k = 1, 2, ... (Twin: cpu::trace's constants of the same names.)
const OCCLUSION_SAMPLES: u32 = 5u;
const OCCLUSION_STEP: Real = 0.04;

// Quaternion parts of the scene's algebra (1, 2 or 4): a constant when specialised.
fn algebra_parts() -> u32 {
    if SPECIALISED {
        return ALGEBRA_PARTS;
    }
    return params.algebra_parts;
}

// The slice axes: constants for the standard slice when specialised (the CPU twin reads them
// from its parameters).
fn slice_axis_x() -> Hyper {
    if SPECIALISED && STANDARD_SLICE {
        return Hyper(vec4<Real>(1.0, 0.0, 0.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    }
    return params.slice_x;
}

fn slice_axis_y() -> Hyper {
    if SPECIALISED && STANDARD_SLICE {
        return Hyper(vec4<Real>(0.0, 1.0, 0.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    }
    return params.slice_y;
}

fn slice_axis_z() -> Hyper {
    if SPECIALISED && STANDARD_SLICE {
        return Hyper(vec4<Real>(0.0, 0.0, 1.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    }
    return params.slice_z;
}

// Scene coordinates p in the 3D slice to the point offset + p.x x + p.y y + p.z z of the
// algebra.
fn slice_point(p: vec3<Real>) -> Hyper {
    var q = params.slice_offset;
    if SPECIALISED && STANDARD_SLICE {
        q[0] += vec4<Real>(p, 0.0);
        return q;
    }
    let x = params.slice_x;
    let y = params.slice_y;
    let z = params.slice_z;
    q[0] += p.x * x[0] + p.y * y[0] + p.z * z[0];
    if algebra_parts() >= 2u {
        q[1] += p.x * x[1] + p.y * y[1] + p.z * z[1];
    }
    if algebra_parts() >= 4u {
        q[2] += p.x * x[2] + p.y * y[2] + p.z * z[2];
        q[3] += p.x * x[3] + p.y * y[3] + p.z * z[3];
    }
    return q;
}

// The orbit of z: z <- z^2 + c with z' <- 2 z z' (z'_0 = 1), until |z|^2 > escape_radius_squared
// or max_iterations (or |z'|^2 > DERIVATIVE_LIMIT); leaves the last z in z and returns |z'|^2.
// (The seed's iterateIntersect.) Quaternions and octonions are composition algebras,
// |a b| = |a| |b|, so |z'|^2 <- 4 |z|^2 |z'|^2 gives the same |z'| without the product (half the
// arithmetic of an iteration). Sedenions are not: there z' is carried whole.
fn iterate_orbit(z: ptr<function, Hyper>) -> Real {
    let parts = algebra_parts();
    var z_norm2 = hyper_dot(*z, *z, parts);
    var dz_norm2: Real = 1.0;
    var dz = Hyper(vec4<Real>(1.0, 0.0, 0.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    // The loop's counter is the iterations made (counted once, after it).
    var i = 0u;
    for (; i < params.max_iterations; i++) {
        if parts == 4u {
            dz = hyper_scale(2.0, hyper_mul(*z, dz, parts));
            dz_norm2 = hyper_dot(dz, dz, parts);
        } else {
            dz_norm2 *= 4.0 * z_norm2;
        }
        *z = hyper_add(hyper_sq(*z, parts), params.c);
        z_norm2 = hyper_dot(*z, *z, parts);
        if z_norm2 > params.escape_radius_squared || dz_norm2 > DERIVATIVE_LIMIT {
            i++;
            break;
        }
    }
    iterations += i;
    return dz_norm2;
}

// The seed's distance estimate d = 0.5 |z| log|z| / |z'|, written as
// 0.25 sqrt(|z|^2 / |z'|^2) log(|z|^2) so that no root or log is taken of zero.
// Negative inside the set (|z| < 1); 0 where it cannot be formed: |z| = 0 (below the smallest
// normal float), |z'| = 0 (below TINY |z|, which keeps the ratio finite) or |z'| huge.
// The set alone, without the cut (estimate_distance adds it).
fn estimate_julia(p: vec3<Real>) -> Real {
    estimates += 1u;
    var z = slice_point(p);
    let dz_norm2 = iterate_orbit(&z);
    return orbit_distance(z, dz_norm2);
}

// The estimate from an orbit's last z and its |z'|^2 (estimate_julia's formula and guards).
fn orbit_distance(z: Hyper, dz_norm2: Real) -> Real {
    let z_norm2 = hyper_dot(z, z, algebra_parts());
    if z_norm2 < MIN_NORMAL || dz_norm2 > DERIVATIVE_LIMIT || dz_norm2 <= z_norm2 * TINY {
        return 0.0;
    }
    return 0.25 * real_sqrt(z_norm2 / dz_norm2) * real_log(z_norm2);
}

// The cut's plane term cut_normal . p - cut_offset: the signed distance of p from the plane
// (cut_normal is of unit length), positive on the side the cut takes away.
fn cut_plane(p: vec3<Real>) -> Real {
    return dot(params.cut_normal, p) - params.cut_offset;
}

// The distance estimate everything uses (primary and shadow rays, the cone, occlusion): the
// set's, and with the cut on, the set intersected with the half-space cut_normal . p <= cut_offset,
// max(d, cut_normal . p - cut_offset) (still a lower bound of the distance to what is left).
fn estimate_distance(p: vec3<Real>) -> Real {
    let d = estimate_julia(p);
    if (!SPECIALISED || CUT) && params.cut != 0u {
        return max(d, cut_plane(p));
    }
    return d;
}

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

// Sphere tracing (the seed's intersectQJulia) from t_start: estimate d, advance by max(d, 0),
// stop with a hit when d is below the threshold: epsilon, or eps_slope t (epsilon proportional to
// the pixel footprint; 0 for shadow rays), or the float spacing at t where steps stall. A miss
// when t passes t_end or after max_steps estimates. The hit is the point reached by the plain
// step, as in the seed.
// With step_scale > 1 steps are over-relaxed (omega d); when the unbounding spheres of two
// successive points stop overlapping the ray may have jumped the surface, so it goes back to the
// plain step from the last point and carries on without over-relaxation.
fn sphere_trace(origin: vec3<Real>, dir: vec3<Real>, t_start: Real, t_end: Real, eps_slope: Real) -> Trace {
    var omega = params.step_scale;
    if SPECIALISED && !OVER_RELAXED {
        omega = 1.0;
    }
    return sphere_trace_by(origin, dir, t_start, t_end, eps_slope, omega);
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
        if !SPECIALISED || PIXEL_EPSILON {
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

// iterate_orbit of two numbers at once (interleaving): both orbits in one loop, each stopping
// on its own, so that the two chains of dependent arithmetic overlap; an orbit not `live` is not
// iterated. Returns the two |z'|^2; each z and |z'|^2 is iterate_orbit's bit for bit.
fn iterate_orbit_pair(z1: ptr<function, Hyper>, z2: ptr<function, Hyper>, live: vec2<bool>) -> vec2<Real> {
    let parts = algebra_parts();
    var z1_norm2 = hyper_dot(*z1, *z1, parts);
    var z2_norm2 = hyper_dot(*z2, *z2, parts);
    var dz1_norm2: Real = 1.0;
    var dz2_norm2: Real = 1.0;
    var dz1 = Hyper(vec4<Real>(1.0, 0.0, 0.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
    var dz2 = dz1;
    var on1 = live.x;
    var on2 = live.y;
    for (var i = 0u; i < params.max_iterations; i++) {
        if !(on1 || on2) {
            break;
        }
        if on1 {
            iterations += 1u;
            if parts == 4u {
                dz1 = hyper_scale(2.0, hyper_mul(*z1, dz1, parts));
                dz1_norm2 = hyper_dot(dz1, dz1, parts);
            } else {
                dz1_norm2 *= 4.0 * z1_norm2;
            }
            *z1 = hyper_add(hyper_sq(*z1, parts), params.c);
            z1_norm2 = hyper_dot(*z1, *z1, parts);
            on1 = !(z1_norm2 > params.escape_radius_squared || dz1_norm2 > DERIVATIVE_LIMIT);
        }
        if on2 {
            iterations += 1u;
            if parts == 4u {
                dz2 = hyper_scale(2.0, hyper_mul(*z2, dz2, parts));
                dz2_norm2 = hyper_dot(dz2, dz2, parts);
            } else {
                dz2_norm2 *= 4.0 * z2_norm2;
            }
            *z2 = hyper_add(hyper_sq(*z2, parts), params.c);
            z2_norm2 = hyper_dot(*z2, *z2, parts);
            on2 = !(z2_norm2 > params.escape_radius_squared || dz2_norm2 > DERIVATIVE_LIMIT);
        }
    }
    return vec2<Real>(dz1_norm2, dz2_norm2);
}

// estimate_julia at two points at once (iterate_orbit_pair); a point not `live` is not estimated
// (its estimate is 0, and not counted).
fn estimate_julia_pair(p1: vec3<Real>, p2: vec3<Real>, live: vec2<bool>) -> vec2<Real> {
    estimates += select(0u, 1u, live.x) + select(0u, 1u, live.y);
    var z1 = slice_point(p1);
    var z2 = slice_point(p2);
    let dz_norm2 = iterate_orbit_pair(&z1, &z2, live);
    return vec2<Real>(orbit_distance(z1, dz_norm2.x), orbit_distance(z2, dz_norm2.y));
}

// estimate_distance at two points at once: estimate_julia_pair, and the cut as
// estimate_distance adds it.
fn estimate_distance_pair(p1: vec3<Real>, p2: vec3<Real>, live: vec2<bool>) -> vec2<Real> {
    var d = estimate_julia_pair(p1, p2, live);
    if (!SPECIALISED || CUT) && params.cut != 0u {
        d = vec2<Real>(max(d.x, cut_plane(p1)), max(d.y, cut_plane(p2)));
    }
    return d;
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
    var omega = params.step_scale;
    if SPECIALISED && !OVER_RELAXED {
        omega = 1.0;
    }
    return March(origin, dir, t_end, eps_slope, t_start, omega, t_start, 0.0, NO_APPROACH, live, Trace(0.0, 0u, false, NO_APPROACH));
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
    if !SPECIALISED || PIXEL_EPSILON {
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

// v normalised, or the fallback where v is too short to have a direction. Scaled by its largest
// component first, so that a long v (an analytic gradient can reach 1e30) cannot overflow.
fn safe_normalize(v: vec3<Real>, fallback: vec3<Real>) -> vec3<Real> {
    let m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    if m * m <= TINY {
        return fallback;
    }
    let w = v / m;
    return w / real_sqrt(dot(w, w));
}

// The seed's normal (its normEstimate): central differences of |z_N| along the slice axes with
// normal_delta, max_iterations iterations of z <- z^2 + c. All six orbits stop together once
// any |z|^2 passes NORMAL_LIMIT: from there z_N ~ z_n^(2^(N-n)), so grad |z_N| is parallel to
// grad |z_n| and the direction is already known, and nothing overflows.
fn normal_central(q: Hyper) -> vec3<Real> {
    let parts = algebra_parts();
    let dx = hyper_scale(params.normal_delta, slice_axis_x());
    let dy = hyper_scale(params.normal_delta, slice_axis_y());
    let dz = hyper_scale(params.normal_delta, slice_axis_z());
    var x_minus = hyper_sub(q, dx);
    var x_plus = hyper_add(q, dx);
    var y_minus = hyper_sub(q, dy);
    var y_plus = hyper_add(q, dy);
    var z_minus = hyper_sub(q, dz);
    var z_plus = hyper_add(q, dz);
    for (var i = 0u; i < params.max_iterations; i++) {
        let largest = max(
            max(
                max(hyper_dot(x_minus, x_minus, parts), hyper_dot(x_plus, x_plus, parts)),
                max(hyper_dot(y_minus, y_minus, parts), hyper_dot(y_plus, y_plus, parts)),
            ),
            max(hyper_dot(z_minus, z_minus, parts), hyper_dot(z_plus, z_plus, parts)),
        );
        if largest > NORMAL_LIMIT {
            break;
        }
        iterations += 6u;
        x_minus = hyper_add(hyper_sq(x_minus, parts), params.c);
        x_plus = hyper_add(hyper_sq(x_plus, parts), params.c);
        y_minus = hyper_add(hyper_sq(y_minus, parts), params.c);
        y_plus = hyper_add(hyper_sq(y_plus, parts), params.c);
        z_minus = hyper_add(hyper_sq(z_minus, parts), params.c);
        z_plus = hyper_add(hyper_sq(z_plus, parts), params.c);
    }
    return vec3<Real>(
        real_sqrt(hyper_dot(x_plus, x_plus, parts)) - real_sqrt(hyper_dot(x_minus, x_minus, parts)),
        real_sqrt(hyper_dot(y_plus, y_plus, parts)) - real_sqrt(hyper_dot(y_minus, y_minus, parts)),
        real_sqrt(hyper_dot(z_plus, z_plus, parts)) - real_sqrt(hyper_dot(z_minus, z_minus, parts)),
    );
}

// Four samples at the corners of a tetrahedron, (1,-1,-1), (-1,-1,1), (-1,1,-1), (1,1,1) times
// normal_delta: sum of v_k |z_N(p + delta v_k)|, two thirds the work of central differences.
fn normal_tetrahedral(q: Hyper) -> vec3<Real> {
    let parts = algebra_parts();
    let h = params.normal_delta;
    let x = slice_axis_x();
    let y = slice_axis_y();
    let z = slice_axis_z();
    var a = hyper_add(q, hyper_scale(h, hyper_sub(hyper_sub(x, y), z)));
    var b = hyper_add(q, hyper_scale(h, hyper_add(hyper_sub(hyper_scale(-1.0, x), y), z)));
    var c = hyper_add(q, hyper_scale(h, hyper_sub(hyper_add(hyper_scale(-1.0, x), y), z)));
    var d = hyper_add(q, hyper_scale(h, hyper_add(hyper_add(x, y), z)));
    for (var i = 0u; i < params.max_iterations; i++) {
        let largest = max(
            max(hyper_dot(a, a, parts), hyper_dot(b, b, parts)),
            max(hyper_dot(c, c, parts), hyper_dot(d, d, parts)),
        );
        if largest > NORMAL_LIMIT {
            break;
        }
        iterations += 4u;
        a = hyper_add(hyper_sq(a, parts), params.c);
        b = hyper_add(hyper_sq(b, parts), params.c);
        c = hyper_add(hyper_sq(c, parts), params.c);
        d = hyper_add(hyper_sq(d, parts), params.c);
    }
    let la = real_sqrt(hyper_dot(a, a, parts));
    let lb = real_sqrt(hyper_dot(b, b, parts));
    let lc = real_sqrt(hyper_dot(c, c, parts));
    let ld = real_sqrt(hyper_dot(d, d, parts));
    return vec3<Real>(la - lb - lc + ld, -la - lb + lc + ld, -la + lb - lc + ld);
}

// The exact gradient of |z_N|: the derivatives of z along the three slice axes, carried through
// the iteration (d(z^2) = z dz + dz z, square_derivative), then grad_i |z| = z . dz_i / |z| (the
// 1/|z| does not change the direction).
fn normal_analytic(q: Hyper) -> vec3<Real> {
    let parts = algebra_parts();
    var z = q;
    var jx = slice_axis_x();
    var jy = slice_axis_y();
    var jz = slice_axis_z();
    for (var i = 0u; i < params.max_iterations; i++) {
        let largest = max(max(hyper_dot(jx, jx, parts), hyper_dot(jy, jy, parts)), hyper_dot(jz, jz, parts));
        if hyper_dot(z, z, parts) > NORMAL_LIMIT || largest > DERIVATIVE_LIMIT {
            break;
        }
        iterations += 1u;
        jx = square_derivative(z, jx, parts);
        jy = square_derivative(z, jy, parts);
        jz = square_derivative(z, jz, parts);
        z = hyper_add(hyper_sq(z, parts), params.c);
    }
    return vec3<Real>(hyper_dot(z, jx, parts), hyper_dot(z, jy, parts), hyper_dot(z, jz, parts));
}

// The shading normal by params.normal_method; where no gradient can be formed it points back
// along the ray. On the cut face, the cut's normal.
fn estimate_normal(p: vec3<Real>, dir: vec3<Real>) -> vec3<Real> {
    // On the cut face the normal is the plane's: where the plane's term is within epsilon of
    // the set's estimate or above it (inside the set the estimate can be 0, where it cannot be
    // formed, against a plane term rounded a little below 0).
    if (!SPECIALISED || CUT) && params.cut != 0u && cut_plane(p) + params.epsilon >= estimate_julia(p) {
        return params.cut_normal;
    }
    let q = slice_point(p);
    var grad: vec3<Real>;
    var method = params.normal_method;
    if SPECIALISED {
        method = NORMAL_METHOD;
    }
    switch method {
        case NORMAL_TETRAHEDRAL: {
            grad = normal_tetrahedral(q);
        }
        case NORMAL_ANALYTIC: {
            grad = normal_analytic(q);
        }
        default: {
            grad = normal_central(q);
        }
    }
    return safe_normalize(grad, -dir);
}

// Phong shading at pt with normal n, a point light and the viewer at eye:
// (diffuse + normal_tint |n|) max(N.L, 0) + specular max(E.R, 0)^shininess, R = 2 (N.L) N - L,
// no highlight where N.L <= 0. (The seed negates R and passes the ray direction as the eye.)
fn phong(light: vec3<Real>, eye: vec3<Real>, pt: vec3<Real>, n: vec3<Real>) -> vec3<Real> {
    let l = safe_normalize(light - pt, n);
    let e = safe_normalize(eye - pt, n);
    let n_dot_l = dot(n, l);
    if n_dot_l <= 0.0 {
        return vec3<Real>(0.0);
    }
    let r = 2.0 * n_dot_l * n - l;
    let e_dot_r = dot(e, r);
    var highlight: Real = 0.0;
    if e_dot_r > 0.0 {
        highlight = params.specular * real_pow(e_dot_r, params.shininess);
    }
    return (params.diffuse + params.normal_tint * abs(n)) * n_dot_l + vec3<Real>(highlight);
}

// The shadow ray: from p + 2 epsilon n toward the light, traced like a primary ray, stopping
// at the light or where it leaves the bounding ball, whichever comes first.
fn in_shadow(p: vec3<Real>, n: vec3<Real>) -> bool {
    let origin = p + 2.0 * params.epsilon * n;
    let to_light = params.light - origin;
    let dist_squared = dot(to_light, to_light);
    if dist_squared <= TINY {
        return false;
    }
    let dist = real_sqrt(dist_squared);
    let dir = to_light / dist;
    let bounds = intersect_bounds(origin, dir);
    let t_end = min(bounds.t_exit, dist);
    if !bounds.hit || bounds.t_enter >= t_end {
        return false;
    }
    return sphere_trace(origin, dir, bounds.t_enter, t_end, 0.0).hit;
}

// The shadow of a spherical light (centre light, radius light_radius > 0), soft: from
// p + 2 epsilon n toward the centre, marched like in_shadow's ray with plain steps (the same t
// at every step, so it hits exactly where in_shadow's does with step_scale 1); a hit gives 0,
// else the visibility is min(1, min over the steps with t > 0 of 2 d / (t tan)), tan =
// light_radius / (distance from the origin to the centre): the closest approach relative to the
// cone towards the light, with 2 d for the true distance (the estimate is about half of it near
// the surface).
fn soft_shadow(p: vec3<Real>, n: vec3<Real>) -> Real {
    let origin = p + 2.0 * params.epsilon * n;
    let to_light = params.light - origin;
    let dist_squared = dot(to_light, to_light);
    if dist_squared <= TINY {
        return 1.0;
    }
    let dist = real_sqrt(dist_squared);
    let dir = to_light / dist;
    let bounds = intersect_bounds(origin, dir);
    let t_end = min(bounds.t_exit, dist);
    if !bounds.hit || bounds.t_enter >= t_end {
        return 1.0;
    }
    let tan_size = params.light_radius / dist;
    var visibility: Real = 1.0;
    var t = bounds.t_enter;
    for (var steps = 1u; steps <= params.max_steps; steps++) {
        let d = estimate_distance(origin + t * dir);
        let t_plain = t + max(d, 0.0);
        if d < max(params.epsilon, t_plain * RELATIVE_EPSILON) {
            return 0.0;
        }
        if t > 0.0 {
            visibility = min(visibility, 2.0 * d / (t * tan_size));
        }
        t = t_plain;
        if t > t_end {
            break;
        }
    }
    return visibility;
}

// The ambient occlusion factor A in [1 - occlusion, 1]: at h_k = k OCCLUSION_STEP along the
// normal (k = 1..OCCLUSION_SAMPLES) an open surface has the set at least h_k away, and 2 d (the
// estimate is about half the true distance near the surface) at least h_k; what falls short
// occludes: A = 1 - occlusion (1 / K) sum_k clamp(1 - 2 d(p + h_k n) / h_k, 0, 1).
fn occlusion(p: vec3<Real>, n: vec3<Real>) -> Real {
    var sum: Real = 0.0;
    for (var k = 1u; k <= OCCLUSION_SAMPLES; k++) {
        let h = Real(k) * OCCLUSION_STEP;
        let d = estimate_distance(p + h * n);
        sum += clamp(1.0 - 2.0 * d / h, 0.0, 1.0);
    }
    return 1.0 - params.occlusion * (sum / Real(OCCLUSION_SAMPLES));
}

// The orbit trap's distance for q: t = min over n = 0..N of | |z_n| - trap_radius |, z_0 = q,
// z_{n+1} = z_n^2 + c, N the first n with |z_n|^2 > escape_radius_squared, or max_iterations
// (iterate_orbit's count and escape; no derivative is carried, so its limit does not apply).
fn orbit_trap(q: Hyper) -> Real {
    let parts = algebra_parts();
    var z = q;
    var trap = abs(real_sqrt(hyper_dot(z, z, parts)) - params.trap_radius);
    for (var i = 0u; i < params.max_iterations; i++) {
        iterations += 1u;
        z = hyper_add(hyper_sq(z, parts), params.c);
        let z_norm2 = hyper_dot(z, z, parts);
        trap = min(trap, abs(real_sqrt(z_norm2) - params.trap_radius));
        if z_norm2 > params.escape_radius_squared {
            break;
        }
    }
    return trap;
}

// The palette: 0.5 + 0.5 cos(2 pi x) per channel, x = fract(trap_scale t + palette_phase) (the
// fraction changes nothing but keeps cos's argument small).
fn palette(t: Real) -> vec3<Real> {
    let x = fract(params.trap_scale * t + params.palette_phase);
    return 0.5 + 0.5 * real_cos(6.2831855 * x);
}

// The base colour of a hit at p: the diffuse colour, or the palette's colour of the orbit trap.
// (shade_features's B, path mode's albedo, and the albedo AOV.)
fn hit_albedo(p: vec3<Real>) -> vec3<Real> {
    if (!SPECIALISED || ORBIT_TRAP) && params.colouring == COLOURING_ORBIT_TRAP {
        return palette(orbit_trap(slice_point(p)));
    }
    return params.diffuse;
}

// Whether the hit is shaded by shade_features (a light of some radius, ambient light, occlusion
// or orbit-trap colour) instead of the seed's phong and in_shadow.
fn shading_features() -> bool {
    var shadows = params.shadows != 0u;
    if SPECIALISED {
        shadows = SHADOWS;
    }
    let soft = (!SPECIALISED || SOFT_SHADOWS) && shadows && params.light_radius > 0.0;
    let occluded = (!SPECIALISED || OCCLUSION) && params.occlusion > 0.0;
    let trap = (!SPECIALISED || ORBIT_TRAP) && params.colouring == COLOURING_ORBIT_TRAP;
    return soft || occluded || trap || params.ambient > 0.0;
}

// The shading with the picture's features, the book's formula (docs/book/scene-file.md): with
// base colour B (diffuse, or the palette's colour of the orbit trap),
// the occlusion factor A and V the light's visibility (1 lit, 0 in shadow, between in a penumbra):
// ambient A B + (shadow_factor + (1 - shadow_factor) V) (A (B + normal_tint |n|) max(N.L, 0)
// + highlight), the highlight as in phong. With ambient 0, A 1 and a point light it is
// phong's colour, shadowed as shade_pixel does. The viewer is at eye: the ray's origin (the
// camera's eye, or a point of the lens).
fn shade_features(p: vec3<Real>, n: vec3<Real>, eye: vec3<Real>) -> vec3<Real> {
    let base = hit_albedo(p);
    var a: Real = 1.0;
    if (!SPECIALISED || OCCLUSION) && params.occlusion > 0.0 {
        a = occlusion(p, n);
    }
    var ambient = params.ambient * a * base;
    if (!SPECIALISED || ENVIRONMENT) && environment_on() && params.env_light != 0u {
        ambient *= vec3<Real>(env_irradiance(vec3<f32>(n)));
    }
    let l = safe_normalize(params.light - p, n);
    let e = safe_normalize(eye - p, n);
    let n_dot_l = dot(n, l);
    if n_dot_l <= 0.0 {
        return ambient;
    }
    let r = 2.0 * n_dot_l * n - l;
    let e_dot_r = dot(e, r);
    var highlight: Real = 0.0;
    if e_dot_r > 0.0 {
        highlight = params.specular * real_pow(e_dot_r, params.shininess);
    }
    var light = a * (base + params.normal_tint * abs(n)) * n_dot_l + vec3<Real>(highlight);
    var shadows = params.shadows != 0u;
    if SPECIALISED {
        shadows = SHADOWS;
    }
    // As in shade_pixel: no shadow ray for an unlit point.
    if shadows && any(light > vec3<Real>(0.0)) {
        if (!SPECIALISED || SOFT_SHADOWS) && params.light_radius > 0.0 {
            light *= params.shadow_factor + (1.0 - params.shadow_factor) * soft_shadow(p, n);
        } else if in_shadow(p, n) {
            light *= params.shadow_factor;
        }
    }
    return ambient + light;
}

// What a ray along dir that hits nothing shows: the environment map's radiance where the scene
// has one (phong mode clamps it as any colour), else the flat background.
fn background(dir: vec3<Real>) -> vec3<Real> {
    if (!SPECIALISED || ENVIRONMENT) && environment_on() {
        return vec3<Real>(env_radiance(vec3<f32>(dir)));
    }
    return params.background;
}

// The ray through the point (x, y) of the image plane in pixel units, (0, 0) the top left corner.
fn camera_ray_at(x: Real, y: Real) -> vec3<Real> {
    let px = (2.0 * x / Real(params.width) - 1.0) * params.tan_half_fov_y * params.aspect;
    let py = (1.0 - 2.0 * y / Real(params.height)) * params.tan_half_fov_y;
    return real_normalize(params.cam_forward + px * params.cam_right + py * params.cam_up);
}

// The primary ray's direction through sample `sample` of pixel (i, j), row 0 at the top
// (docs/CONTRACT.md's camera); sample 0 goes through the pixel's centre.
fn camera_ray(i: u32, j: u32, sample: u32) -> vec3<Real> {
    let s = stream_position(sample);
    return camera_ray_at(Real(i) + s.x, Real(j) + s.y);
}

// Whether the camera's samples go through the thin lens: aperture > 0. Every sample does then,
// sample 0 too; the depth and the steps stay the pinhole's ray's through the pixel's centre
// (pinhole_ray), traced for them alone.
fn lens_open() -> bool {
    if SPECIALISED && !LENS {
        return false;
    }
    return params.aperture > 0.0;
}

// A ray: its origin and its unit direction.
struct Ray {
    origin: vec3<Real>,
    dir: vec3<Real>,
}

// The thin lens's ray of sample `sample` of pixel (i, j) in phong mode: through the sample's
// image-plane point (stream_position) and the aperture's point at its lens position
// (lens_point).
fn lens_ray(i: u32, j: u32, sample: u32) -> Ray {
    let s = stream_position(sample);
    return thin_lens_ray(Real(i) + s.x, Real(j) + s.y, lens_point(sample));
}

// The thin lens's ray through the image-plane point (x, y) (in pixels) and the point `lens` of
// the unit aperture: the pinhole ray through (x, y), direction f + px r + py u, meets the focus
// plane (at focus_distance along f) at eye + focus_distance (f + px r + py u); the ray leaves the
// lens at eye + aperture (lens.x r + lens.y u), toward that point.
fn thin_lens_ray(x: Real, y: Real, lens_unit: vec2<f32>) -> Ray {
    let px = (2.0 * x / Real(params.width) - 1.0) * params.tan_half_fov_y * params.aspect;
    let py = (1.0 - 2.0 * y / Real(params.height)) * params.tan_half_fov_y;
    let lens = params.aperture * vec2<Real>(lens_unit);
    let offset = lens.x * params.cam_right + lens.y * params.cam_up;
    let focus = params.focus_distance * (params.cam_forward + px * params.cam_right + py * params.cam_up);
    return Ray(params.eye + offset, real_normalize(focus - offset));
}

// Sample k's point on the unit aperture in phong mode: the aperture's point at its stream's lens
// position (stream_lens_position: the Halton point of index 0 is the lens's centre, which
// would make a stream's first sample a pinhole sample).
fn lens_point(k: u32) -> vec2<f32> {
    return aperture_point(stream_lens_position(k));
}

// The point of the unit aperture at (u, v) in [0, 1)^2, in f32 (its trigonometry too: the f64
// kernels take no f64 sin or cos), turned by rotation = blade_rotation: for a round aperture
// (blades 0) the polar map sqrt(u) (cos phi, sin phi), phi = 2 pi v + rotation (uniform over the
// disc); for n blades the regular n-gon inscribed in the unit circle with corners
// c_m = (cos a_m, sin a_m), a_m = 2 pi m / n + rotation, uniform over it: the triangle
// (0, c_m, c_m+1) with m = floor(n u), then with a = n u - m and b = v the point
// sqrt(a) ((1 - b) c_m + b c_m+1).
fn aperture_point(uv: vec2<f32>) -> vec2<f32> {
    let rotation = f32(params.blade_rotation);
    if params.blades == 0u {
        let phi = 6.2831855 * uv.y + rotation;
        return sqrt(uv.x) * vec2<f32>(cos(phi), sin(phi));
    }
    let n = f32(params.blades);
    let m = min(floor(n * uv.x), n - 1.0);
    let a = n * uv.x - m;
    let a0 = 6.2831855 * (m / n) + rotation;
    let a1 = 6.2831855 * ((m + 1.0) / n) + rotation;
    let c0 = vec2<f32>(cos(a0), sin(a0));
    let c1 = vec2<f32>(cos(a1), sin(a1));
    return sqrt(a) * ((1.0 - uv.y) * c0 + uv.y * c1);
}

// Cone tracing's start for the block (bi, bj) of CONE_BLOCK x CONE_BLOCK pixels: march the ray
// through the block's centre, shrinking each unbounding sphere by the cone's radius at that
// distance (t times the tangent of the widest angle to a corner ray), so that the whole cone is
// known to be at least epsilon from the set up to the t returned. Every ray of the block may
// start there. Bounded by max_steps; 0 where the centre ray misses the ball.
fn cone_start(bi: u32, bj: u32) -> Real {
    let x0 = Real(bi * CONE_BLOCK);
    let y0 = Real(bj * CONE_BLOCK);
    let size = Real(CONE_BLOCK);
    let centre = camera_ray_at(x0 + 0.5 * size, y0 + 0.5 * size);
    var spread: Real = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let corner = camera_ray_at(x0 + size * Real(k & 1u), y0 + size * Real(k >> 1u));
        let cos_angle = max(dot(centre, corner), 0.1);
        let side = cross(centre, corner);
        spread = max(spread, real_sqrt(dot(side, side)) / cos_angle);
    }
    let bounds = intersect_bounds(params.eye, centre);
    if !bounds.hit {
        return 0.0;
    }
    var t = bounds.t_enter;
    for (var step = 0u; step < params.max_steps; step++) {
        let free = estimate_distance(params.eye + t * centre) - spread * t;
        if free < CONE_MARGIN * params.epsilon || t > bounds.t_exit {
            return t;
        }
        t += free;
    }
    return t;
}

// One sample's outcome: its colour (unclamped), depth and steps, whether it hit, and where
// it was shaded, the hit point and its shading normal (0 where it was not: a miss, or no
// shading).
struct Pixel {
    colour: vec3<Real>,
    depth: Real,
    steps: u32,
    hit: bool,
    point: vec3<Real>,
    normal: vec3<Real>,
}

// A sample's camera ray: its origin and direction and the stretch [t_start, t_end] of it that
// sphere tracing covers, within the bounding ball; `hit` false where it misses the ball.
struct Primary {
    origin: vec3<Real>,
    dir: vec3<Real>,
    t_start: Real,
    t_end: Real,
    hit: bool,
}

// Sample `sample`'s pinhole ray of pixel (i, j), from the eye, against the bounds, from t_min on
// (the cone's start, or 0): the camera ray where the lens is closed, and with sample 0 the ray
// that gives the depth and the steps.
fn pinhole_ray(i: u32, j: u32, sample: u32, t_min: Real) -> Primary {
    let dir = camera_ray(i, j, sample);
    let bounds = intersect_bounds(params.eye, dir);
    return Primary(params.eye, dir, max(bounds.t_enter, t_min), bounds.t_exit, bounds.hit);
}

// Sample `sample`'s camera ray of pixel (i, j): the pinhole's (pinhole_ray), or where the lens is
// open the thin lens's, against the bounds. A lens ray starts from the ball: the cone covers the
// block's rays from the eye, not rays from elsewhere on the lens.
fn primary_ray(i: u32, j: u32, sample: u32, t_min: Real) -> Primary {
    if !lens_open() {
        return pinhole_ray(i, j, sample, t_min);
    }
    let ray = lens_ray(i, j, sample);
    let bounds = intersect_bounds(ray.origin, ray.dir);
    return Primary(ray.origin, ray.dir, bounds.t_enter, bounds.t_exit, bounds.hit);
}

// A camera ray's sphere trace, with the pixel epsilon; a miss of no steps where it misses the
// ball.
fn trace_primary(ray: Primary) -> Trace {
    if !ray.hit {
        return Trace(0.0, 0u, false, NO_APPROACH);
    }
    return sphere_trace(ray.origin, ray.dir, ray.t_start, ray.t_end, params.pixel_epsilon * params.pixel_angle);
}

// Two camera rays' sphere traces at once (sphere_trace_pair): each trace_primary's bit for bit.
fn trace_primary_pair(a: Primary, b: Primary) -> TracePair {
    let eps_slope = params.pixel_epsilon * params.pixel_angle;
    let m1 = march_start(a.origin, a.dir, a.t_start, a.t_end, eps_slope, a.hit);
    let m2 = march_start(b.origin, b.dir, b.t_start, b.t_end, eps_slope, b.hit);
    return sphere_trace_pair(m1, m2);
}

// Whether the scene has fog (fog.density > 0, either model).
fn fog_on() -> bool {
    return (!SPECIALISED || FOG) && params.fog_density > 0.0;
}

// Whether phong mode's halo is on (glow.strength > 0).
fn glow_on() -> bool {
    return (!SPECIALISED || GLOW) && params.glow_strength > 0.0;
}

// The fog's transmittance along origin + t dir over t in [0, t_stop]: exp(-fog_density L), L the
// length of that stretch within the bounding ball (the fog fills the ball); 1 without fog. In
// f32, as path mode's radiance is.
fn fog_transmittance(origin: vec3<Real>, dir: vec3<Real>, t_stop: Real) -> f32 {
    if !((!SPECIALISED || FOG) && fog_on()) {
        return 1.0;
    }
    let bounds = intersect_bounds(origin, dir);
    if !bounds.hit {
        return 1.0;
    }
    let length = max(min(bounds.t_exit, t_stop) - bounds.t_enter, 0.0);
    return exp(-f32(params.fog_density * length));
}

// Phong mode's halo for a ray that missed: glow_strength glow_colour exp(-closest / glow_radius),
// closest the least distance estimate along the ray (Trace's closest; a ray that missed the
// ball gets exp(-3e38 / r) = 0).
fn glow(closest: Real) -> vec3<Real> {
    let fall = exp(-f32(max(closest, 0.0) / params.glow_radius));
    return params.glow_strength * params.glow_colour * Real(fall);
}

// Phong mode's atmosphere over a camera ray's colour (docs/book/atmosphere.md): a miss gains the
// halo (glow); then the colour is blended toward fog_colour by the fog's transmittance T from
// the eye to the hit (through the whole ball on a miss), mix(fog_colour, colour, T) (Mandelbulber's
// basic fog). Without fog and glow the colour unchanged.
fn atmosphere(colour: vec3<Real>, ray: Primary, trace: Trace) -> vec3<Real> {
    var c = colour;
    if !trace.hit && (!SPECIALISED || GLOW) && glow_on() {
        c += glow(trace.closest);
    }
    if (!SPECIALISED || FOG) && fog_on() {
        let t_stop = select(Real(3.0e38), trace.t, trace.hit);
        let transmittance = Real(fog_transmittance(ray.origin, ray.dir, t_stop));
        c = mix(params.fog_colour, c, vec3<Real>(transmittance));
    }
    return c;
}

// A sample's outcome from its camera ray and the ray's trace: normal, Phong, shadow, and the
// atmosphere over them.
fn shade_pixel(ray: Primary, trace: Trace) -> Pixel {
    let none = vec3<Real>(0.0);
    if !trace.hit {
        return Pixel(atmosphere(background(ray.dir), ray, trace), -1.0, trace.steps, false, none, none);
    }
    if SPECIALISED && !SHADE {
        return Pixel(params.background, trace.t, trace.steps, true, none, none);
    }
    let origin = ray.origin;
    let dir = ray.dir;
    let p = origin + trace.t * dir;
    let n = estimate_normal(p, dir);
    if shading_features() {
        return Pixel(atmosphere(shade_features(p, n, origin), ray, trace), trace.t, trace.steps, true, p, n);
    }
    var colour = phong(params.light, origin, p, n);
    var shadows = params.shadows != 0u;
    if SPECIALISED {
        shadows = SHADOWS;
    }
    // An unlit point (black: the light is behind its surface) stays black in shadow: no ray.
    let lit = any(colour > vec3<Real>(0.0));
    if shadows && lit && in_shadow(p, n) {
        colour *= params.shadow_factor;
    }
    return Pixel(atmosphere(colour, ray, trace), trace.t, trace.steps, true, p, n);
}

// Everything for one sample of pixel (i, j): its camera ray (primary_ray), sphere tracing,
// and shading (shade_pixel).
fn trace_pixel(i: u32, j: u32, sample: u32, t_min: Real) -> Pixel {
    let ray = primary_ray(i, j, sample, t_min);
    return shade_pixel(ray, trace_primary(ray));
}

// Where sample k lies in its pixel, (x, y) in [0, 1)^2 from the pixel's top left corner:
// (0.5, 0.5), the centre, for sample 0; else the Halton point of index k in bases 2 and 3
// (k < 4096: its 12 binary and 8 ternary digits, so both coordinates are exact in f32).
fn sample_position(k: u32) -> vec2<Real> {
    if k == 0u {
        return vec2<Real>(0.5, 0.5);
    }
    let base2 = reverseBits(k) >> 20u;
    var base3 = 0u;
    var rest = k;
    for (var digit = 0u; digit < 8u; digit++) {
        base3 = base3 * 3u + rest % 3u;
        rest /= 3u;
    }
    return vec2<Real>(Real(base2) * (1.0 / 4096.0), Real(base3) * (1.0 / 6561.0));
}

// Where sample k (>= 1) lies on the lens before the aperture's map, (u, v) in [0, 1)^2: the
// Halton point of index k in bases 5 and 7 (the sub-pixel positions take 2 and 3), from k's
// first 6 quinary and 5 septenary digits as integers over 15625 and 16807 (k < 4096 has no more).
fn lens_position(k: u32) -> vec2<f32> {
    var base5 = 0u;
    var rest = k;
    for (var digit = 0u; digit < 6u; digit++) {
        base5 = base5 * 5u + rest % 5u;
        rest /= 5u;
    }
    var base7 = 0u;
    rest = k;
    for (var digit = 0u; digit < 5u; digit++) {
        base7 = base7 * 7u + rest % 7u;
        rest /= 7u;
    }
    return vec2<f32>(f32(base5) * (1.0 / 15625.0), f32(base7) * (1.0 / 16807.0));
}

// Adaptive sampling's two streams (docs/book/adaptive.md): sample k of an adaptive pixel is
// sample k / 2 of stream k % 2, as (stream, index). Each stream's stop is decided by its own
// samples and applied to the other's mean (add_to_streams), so that no half of what the pixel
// shows depends on its own stop. Without adaptive sampling every sample is stream 0's: (0, k)
// (phong mode; path mode has both streams anyway: path.wgsl's path_stream).
fn sample_stream(k: u32) -> vec2<u32> {
    if adaptive() {
        return vec2<u32>(k & 1u, k >> 1u);
    }
    return vec2<u32>(0u, k);
}

// Stream 1's points in phong mode are stream 0's turned by this Cranley-Patterson shift (modulo
// 1, in the pixel and on the lens alike): R2's (0.7549, 0.5698) rounded to 11 bits, exact in
// f32. The streams' points are then apart, each stream as well spread as the Halton points.
const STREAM_SHIFT: vec2<f32> = vec2<f32>(1545.0 / 2048.0, 1167.0 / 2048.0);

// Where sample k lies in its pixel in phong mode: its stream's index's sample_position, shifted
// by STREAM_SHIFT in stream 1.
fn stream_position(k: u32) -> vec2<Real> {
    let s = sample_stream(k);
    let p = sample_position(s.y);
    if s.x == 0u {
        return p;
    }
    return fract(p + vec2<Real>(STREAM_SHIFT));
}

// Where sample k lies on the lens before the aperture's map in phong mode: lens_position of its
// stream's index + 1, shifted by STREAM_SHIFT in stream 1.
fn stream_lens_position(k: u32) -> vec2<f32> {
    let s = sample_stream(k);
    let p = lens_position(s.y + 1u);
    if s.x == 0u {
        return p;
    }
    return fract(p + STREAM_SHIFT);
}

// Colour clamped to [0, 1], times 255, rounded half up, packed as RGBA8 0xFFBBGGRR (opaque).
// (In f32 whatever the precision: a colour needs no more.)
fn pack_colour(colour: vec3<Real>) -> u32 {
    let c = vec3<f32>(colour);
    let v = vec3<u32>(floor(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)) * 255.0 + 0.5));
    return v.x | (v.y << 8u) | (v.z << 16u) | 0xff000000u;
}

// The AOVs of a pixel's samples so far (`--hdr`, the denoiser): the mean of their unclamped
// colours and the sum of the squared deviations of their luminances from the running mean
// (Welford's M2: the denoiser's variance), and over the samples whose primary ray hit, how many
// did and the means of their hits' base colours, shading normals and depths (0 while none has);
// in path mode also the mean of their first hits' specular light (path.wgsl's
// PathResult.specular; 0 in phong mode), and over the hits the mean cosine of the view
// direction to the shading normal (the denoiser's specular reflectance). In f32 in both
// precisions, as the accumulator is.
struct Aovs {
    colour: vec3<f32>,
    hits: f32,
    albedo: vec3<f32>,
    normal: vec3<f32>,
    m2: f32,
    depth: f32,
    specular: vec3<f32>,
    cosine: f32,
}

// Rec. 709 luminance of a linear colour, as shaders/bsdf.wgsl's `luminance` (the phong module
// has no bsdf.wgsl).
fn sample_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// Welford's rule: the sum of squared deviations from the mean m2 of luminances, with one more
// luminance l, given the mean's luminance before it (before) and after (after),
// M2_k = M2_(k-1) + (l_k - L(m_(k-1))) (l_k - L(m_k)).
fn add_m2(m2: f32, l: f32, before: f32, after: f32) -> f32 {
    return m2 + (l - before) * (l - after);
}

// Adds sample k (0-based) to the AOVs: its colour and its specular light to the running means
// over the samples, m_k = m_(k-1) + (c_k - m_(k-1)) / (k + 1), and its luminance l_k to M2
// (add_m2); where it hit, its albedo, normal, depth and view cosine to the running means over
// the hits, by the same rule with the hits counted so far.
fn add_aovs(a: Aovs, k: u32, colour: vec3<f32>, hit: bool, albedo: vec3<f32>, normal: vec3<f32>, depth: f32, specular: vec3<f32>, cosine: f32) -> Aovs {
    var out = a;
    out.colour = a.colour + (colour - a.colour) / f32(k + 1u);
    out.specular = a.specular + (specular - a.specular) / f32(k + 1u);
    let l = sample_luminance(colour);
    out.m2 = add_m2(a.m2, l, sample_luminance(a.colour), sample_luminance(out.colour));
    if hit {
        out.hits = a.hits + 1.0;
        out.albedo = a.albedo + (albedo - a.albedo) / out.hits;
        out.normal = a.normal + (normal - a.normal) / out.hits;
        out.depth = a.depth + (depth - a.depth) / out.hits;
        out.cosine = a.cosine + (cosine - a.cosine) / out.hits;
    }
    return out;
}

// Adds sample k's pixel to the AOVs: its colour, and where it hit, the base colour of its hit
// (hit_albedo), its shading normal and its depth. (The host sets AOVS only with SHADE: every hit
// is shaded.)
fn add_pixel_aovs(a: Aovs, k: u32, pixel: Pixel) -> Aovs {
    var albedo = vec3<f32>(0.0);
    if pixel.hit {
        albedo = vec3<f32>(hit_albedo(pixel.point));
    }
    return add_aovs(a, k, vec3<f32>(pixel.colour), pixel.hit, albedo, vec3<f32>(pixel.normal), f32(pixel.depth), vec3<f32>(0.0), 0.0);
}

// The AOVs pixel `index` holds in out_aovs: colour and hits, albedo and M2, normal and depth,
// specular light and view cosine.
fn load_aovs(index: u32) -> Aovs {
    let a = out_aovs[4u * index];
    let b = out_aovs[4u * index + 1u];
    let c = out_aovs[4u * index + 2u];
    let d = out_aovs[4u * index + 3u];
    return Aovs(a.xyz, a.w, b.xyz, c.xyz, b.w, c.w, d.xyz, d.w);
}

fn store_aovs(index: u32, a: Aovs) {
    out_aovs[4u * index] = vec4<f32>(a.colour, a.hits);
    out_aovs[4u * index + 1u] = vec4<f32>(a.albedo, a.m2);
    out_aovs[4u * index + 2u] = vec4<f32>(a.normal, a.depth);
    out_aovs[4u * index + 3u] = vec4<f32>(a.specular, a.cosine);
}

// Adaptive sampling (params.noise_target > 0; the book's chapter "Adaptive sampling"), by
// cross-fitting. Each pixel decides alone, after each of its samples, so any split of the image
// into bands, tiles or dispatches gives the same pixels. Its samples alternate between two
// streams (sample_stream), A (stream 0) and B (stream 1). Each stream's own rule (stream_fires)
// sees that stream's samples alone and stops it after its draw tau_A, tau_B. The pixel shows
// half the mean of B's first tau_A samples plus half the mean of A's first tau_B (streams_mean),
// so that neither half depends on its own stream's stop, and it samples both streams until both
// rules have fired and each stream has the draws the other's stop asks of it (sampling_done).
override ADAPTIVE: bool = true;

// A pixel's noise is taken relative to its mean luminance or to this, whichever is larger (the
// floor for dark pixels, in linear luminance: 1 is phong mode's white).
const NOISE_LUMINANCE_FLOOR: f32 = 0.01;

// Whether this pipeline samples adaptively.
fn adaptive() -> bool {
    if SPECIALISED {
        return ADAPTIVE;
    }
    return params.noise_target > 0.0 && params.samples > 1u;
}

// A pixel's noise after n >= 2 samples whose luminances' M2 is m2: the standard error of its
// mean luminance, sqrt(m2 / (n (n - 1))), relative to that mean (at least the floor).
fn pixel_noise(m2: f32, n: u32, mean_luminance: f32) -> f32 {
    let k = f32(n);
    let variance = max(m2 / (k * (k - 1.0)), 0.0);
    return sqrt(variance) / max(abs(mean_luminance), NOISE_LUMINANCE_FLOOR);
}

// A pixel's adaptive state, the accumulator's four planes (load_streams):
//   a      = (A's mean colour, tau_A: 0 until A's rule fires),
//   b      = (B's mean colour, the samples in it),
//   rule_a = (A's mean luminance, its M2 (add_m2), its samples kept, the samples in A's colour),
//   rule_b = (B's mean luminance, its M2, its samples kept, tau_B: 0 until B's rule fires).
// A's mean colour takes A's draws while B's rule has not fired, which are A's first tau_B; B's
// takes B's first tau_A. Each stream's luminances are counted until its own rule fires. The
// counts are exact in f32. A sample that is not valid (path mode's sample_valid) is a draw of its
// stream but joins nothing. Once the pixel is done the first plane holds what it shows
// (streams_mean) and minus the samples it took, and the next two its halves (store_streams).
struct Streams {
    a: vec4<f32>,
    b: vec4<f32>,
    rule_a: vec4<f32>,
    rule_b: vec4<f32>,
}

// A stream's luminance statistics (rule: mean, M2, samples kept) with one more luminance l, by
// Welford's rule (add_m2, at least 0); the fourth float is kept.
fn add_luminance(rule: vec4<f32>, l: f32) -> vec4<f32> {
    var out = rule;
    out.z = rule.z + 1.0;
    out.x = rule.x + (l - rule.x) / out.z;
    out.y = max(add_m2(rule.y, l, rule.x, out.x), 0.0);
    return out;
}

// Whether a stream's rule fires after its draw `draws` (from 1), its luminances' statistics being
// `rule` (add_luminance): at its cap of samples / 2 draws, or from half the floor
// max(min(min_samples, samples), 4) (rounded up) on, with at least 2 samples kept and a noise
// (pixel_noise) at most the target.
fn stream_fires(rule: vec4<f32>, draws: u32) -> bool {
    if draws >= params.samples / 2u {
        return true;
    }
    let floor = (max(min(params.min_samples, params.samples), 4u) + 1u) / 2u;
    if draws < floor || rule.z < 2.0 {
        return false;
    }
    return pixel_noise(rule.y, u32(rule.z), rule.x) <= f32(params.noise_target);
}

// A pixel's streams with its sample k taken (draw k / 2 + 1 of stream k % 2), of colour `colour`
// where it is valid.
fn add_to_streams(s: Streams, k: u32, valid: bool, colour: vec3<f32>) -> Streams {
    var out = s;
    let draws = k / 2u + 1u;
    let l = sample_luminance(colour);
    if k % 2u == 0u {
        // A's draw joins A's colour while B's rule has not fired.
        if valid && s.rule_b.w == 0.0 {
            out.rule_a.w = s.rule_a.w + 1.0;
            out.a = vec4<f32>(s.a.xyz + (colour - s.a.xyz) / out.rule_a.w, s.a.w);
        }
        if s.a.w == 0.0 {
            if valid {
                out.rule_a = vec4<f32>(add_luminance(s.rule_a, l).xyz, out.rule_a.w);
            }
            if stream_fires(out.rule_a, draws) {
                out.a.w = f32(draws);
            }
        }
    } else {
        // B's draw joins B's colour while A's rule has not fired, or up to A's stop.
        if valid && (s.a.w == 0.0 || f32(draws) <= s.a.w) {
            out.b.w = s.b.w + 1.0;
            out.b = vec4<f32>(s.b.xyz + (colour - s.b.xyz) / out.b.w, out.b.w);
        }
        if s.rule_b.w == 0.0 {
            if valid {
                out.rule_b = vec4<f32>(add_luminance(s.rule_b, l).xyz, 0.0);
            }
            if stream_fires(out.rule_b, draws) {
                out.rule_b.w = f32(draws);
            }
        }
    }
    return out;
}

// Whether a pixel whose streams are s is done once it has taken `taken` samples: both rules have
// fired and B has its first tau_A draws (A has its first tau_B whenever B's rule has fired), or
// it has taken every sample.
fn sampling_done(s: Streams, taken: u32) -> bool {
    if taken >= params.samples {
        return true;
    }
    return s.a.w > 0.0 && s.rule_b.w > 0.0 && f32(taken / 2u) >= s.a.w;
}

// A pixel's two halves (path mode, and an adaptive pixel once it is done): each stream's mean
// colour and the samples in it, a = (A's mean colour, n_A), b = (B's mean colour, n_B). The
// streams are drawn independently, so the halves' disagreement estimates the error of what the
// pixel shows (docs/CONTRACT.md's `estimated_rmse`): E[(a - b)^2] / 4 = Var((a + b) / 2).
struct Halves {
    a: vec4<f32>,
    b: vec4<f32>,
}

// A pixel's halves with its valid sample k (of stream k % 2) of colour `colour` joined to its
// stream's running mean, m_n = m_(n-1) + (c - m_(n-1)) / n.
fn add_to_halves(h: Halves, k: u32, colour: vec3<f32>) -> Halves {
    var out = h;
    if k % 2u == 0u {
        let n = h.a.w + 1.0;
        out.a = vec4<f32>(h.a.xyz + (colour - h.a.xyz) / n, n);
    } else {
        let n = h.b.w + 1.0;
        out.b = vec4<f32>(h.b.xyz + (colour - h.b.xyz) / n, n);
    }
    return out;
}

// What a pixel whose halves are h shows: half A's mean colour plus half B's, or the one half's
// where the other has no sample in it (black where neither has).
fn halves_mean(h: Halves) -> vec3<f32> {
    if h.a.w == 0.0 {
        return h.b.xyz;
    }
    if h.b.w == 0.0 {
        return h.a.xyz;
    }
    return 0.5 * (h.a.xyz + h.b.xyz);
}

// An adaptive pixel's halves: A's mean of its first tau_B draws, B's of its first tau_A.
fn streams_halves(s: Streams) -> Halves {
    return Halves(vec4<f32>(s.a.xyz, s.rule_a.w), s.b);
}

// What a pixel whose streams are s shows: its halves' mean (halves_mean).
fn streams_mean(s: Streams) -> vec3<f32> {
    return halves_mean(streams_halves(s));
}

// A done pixel's AOVs with their hits and M2 taken to the `taken` samples it took, which the host
// divides by (denoise::mean_variance, denoise::hit_fraction): hits / taken is then the fraction of the n = n_A + n_B
// samples in its colours that hit, and M2 / (taken (taken - 1)) the variance of what it shows,
// M2 / (n - 1) (1 / n_A + 1 / n_B) / 4 (1 / n with one stream empty).
fn finish_aovs(a: Aovs, s: Streams, taken: u32) -> Aovs {
    var out = a;
    let n = s.rule_a.w + s.b.w;
    let t = f32(taken);
    if n == 0.0 {
        return out;
    }
    out.hits = a.hits * t / n;
    var spread = 1.0 / n;
    if s.rule_a.w > 0.0 && s.b.w > 0.0 {
        spread = 0.25 * (1.0 / s.rule_a.w + 1.0 / s.b.w);
    }
    out.m2 = 0.0;
    if n >= 2.0 && t >= 2.0 {
        out.m2 = a.m2 / (n - 1.0) * spread * (t * (t - 1.0));
    }
    return out;
}

// A pixel's streams (Streams), from the accumulator's four planes: plane p of pixel `index` is
// element p arrayLength / 4 + index (the host allocates accumulated four times the pixels).
fn load_streams(index: u32) -> Streams {
    let plane = arrayLength(&accumulated) / 4u;
    return Streams(
        accumulated[index],
        accumulated[plane + index],
        accumulated[2u * plane + index],
        accumulated[3u * plane + index],
    );
}

// Keeps a pixel's streams after a dispatch: once it is done (after `taken` samples; 0 while it
// samples), what it shows and minus its samples in the first plane and its halves in the next
// two (store_halves); else all four planes (load_streams).
fn store_streams(index: u32, s: Streams, taken: u32) {
    if taken > 0u {
        accumulated[index] = vec4<f32>(streams_mean(s), -f32(taken));
        store_halves(index, streams_halves(s));
        return;
    }
    let plane = arrayLength(&accumulated) / 4u;
    accumulated[index] = s.a;
    accumulated[plane + index] = s.b;
    accumulated[2u * plane + index] = s.rule_a;
    accumulated[3u * plane + index] = s.rule_b;
}

// A pixel's halves (Halves) from the accumulator's second and third planes, where path mode
// keeps them (and an adaptive pixel once done: store_streams).
fn load_halves(index: u32) -> Halves {
    let plane = arrayLength(&accumulated) / 4u;
    return Halves(accumulated[plane + index], accumulated[2u * plane + index]);
}

fn store_halves(index: u32, h: Halves) {
    let plane = arrayLength(&accumulated) / 4u;
    accumulated[plane + index] = h.a;
    accumulated[2u * plane + index] = h.b;
}

// A pixel's work counts `held` (out_work) with this dispatch's estimates and iterations added,
// each carried into its high word where its low word wraps.
fn add_work(held: vec4<u32>) -> vec4<u32> {
    let e = held.x + estimates;
    let n = held.z + iterations;
    return vec4<u32>(e, held.y + select(0u, 1u, e < estimates), n, held.w + select(0u, 1u, n < iterations));
}

// The workgroup's live pixels (compacted_pixel): how many, and each one's local index.
var<workgroup> live_count: atomic<u32>;
var<workgroup> live_lanes: array<u32, 64>;

// The pixel, as (column, row of the band), that invocation `lid` of workgroup `wid` samples:
// its own (gid.xy), or with COMPACT in a later dispatch of adaptive sampling the lid-th live
// pixel of its 8 x 8 block (in no fixed order: a pixel's samples do not depend on the lane that
// takes them); (width, 0), none, where the block has fewer live pixels. Every invocation of the
// workgroup calls it, before any returns (it holds a barrier).
fn compacted_pixel(gid: vec3<u32>, wid: vec3<u32>, lid: u32) -> vec2<u32> {
    if !(COMPACT && adaptive() && params.sample_start > 0u) {
        return gid.xy;
    }
    if gid.x < params.width && gid.y < params.row_count {
        let index = (params.out_row + gid.y) * params.row_stride + gid.x;
        if accumulated[index].w >= 0.0 {
            live_lanes[atomicAdd(&live_count, 1u)] = lid;
        }
    }
    workgroupBarrier();
    if lid >= atomicLoad(&live_count) {
        return vec2<u32>(params.width, 0u);
    }
    let own = live_lanes[lid];
    return vec2<u32>(wid.x * 8u + own % 8u, wid.y * 8u + own / 8u);
}

// Whether this pipeline traces a cone per block first.
fn cone_tracing() -> bool {
    if SPECIALISED {
        return CONE_TRACING;
    }
    return params.tracing == TRACING_CONE;
}

// One workgroup is one CONE_BLOCK x CONE_BLOCK block (bands start on block rows).
@compute @workgroup_size(8, 8, 1)
fn main(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let cone = cone_tracing();
    if cone {
        if lid == 0u {
            cone_t = cone_start(wid.x, params.row_offset / CONE_BLOCK + wid.y);
        }
        workgroupBarrier();
    }
    let t_min = select(0.0, cone_t, cone);
    // With compaction the block's live pixels, packed (the cone is the block's either way).
    let pixel = compacted_pixel(gid, wid, lid);
    let i = pixel.x;
    let row = pixel.y;
    if i >= params.width || row >= params.row_count {
        return;
    }
    let j = params.row_offset + row;
    let index = (params.out_row + row) * params.row_stride + i;
    estimates = 0u;
    iterations = 0u;
    var samples = params.samples;
    if SPECIALISED && !SAMPLES {
        samples = 1u;
    }
    let no_aovs = Aovs(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, vec3<f32>(0.0), 0.0);
    // Where the lens is open, the depth and the steps are the pinhole ray's, traced for them.
    if params.sample_start == 0u && lens_open() {
        let pinhole = trace_primary(pinhole_ray(i, j, 0u, t_min));
        out_depth[index] = select(-1.0, pinhole.t, pinhole.hit);
        out_steps[index] = pinhole.steps;
    }
    if samples <= 1u {
        let pixel = trace_pixel(i, j, 0u, t_min);
        out_colour[index] = pack_colour(pixel.colour);
        if !lens_open() {
            out_depth[index] = select(-1.0, pixel.depth, pixel.hit);
            out_steps[index] = pixel.steps;
        }
        out_work[index] = add_work(vec4<u32>(0u));
        if AOVS {
            store_aovs(index, add_pixel_aovs(no_aovs, 0u, pixel));
        }
        return;
    }
    // This dispatch adds the samples [sample_start, sample_end) to the running mean of their
    // clamped colours, m_k = m_(k-1) + (c_k - m_(k-1)) / (k + 1), exact where every sample
    // has the same colour (adaptively, to the pixel's streams instead: add_to_streams); sample 0
    // gives the depth and the steps (where the lens is open, the pinhole ray's, traced above).
    var mean = vec3<Real>(0.0);
    var made = vec4<u32>(0u);
    var aovs = no_aovs;
    var streams = Streams(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    if params.sample_start > 0u {
        let held = accumulated[index];
        if adaptive() && held.w < 0.0 {
            return;
        }
        mean = vec3<Real>(held.xyz);
        made = out_work[index];
        if adaptive() {
            streams = load_streams(index);
        }
        if AOVS {
            aovs = load_aovs(index);
        }
    }
    // With INTERLEAVE 2 samples k and k + 1 are traced as a pair at k (trace_primary_pair), and
    // k + 1's trace kept for it; an odd sample left over is traced alone.
    var second = Trace(0.0, 0u, false, NO_APPROACH);
    var paired = false;
    var taken = 0u;
    for (var k = params.sample_start; k < params.sample_end; k++) {
        let ray = primary_ray(i, j, k, t_min);
        var trace: Trace;
        if paired {
            trace = second;
            paired = false;
        } else if INTERLEAVE >= 2u && k + 1u < params.sample_end {
            let pair = trace_primary_pair(ray, primary_ray(i, j, k + 1u, t_min));
            trace = pair.first;
            second = pair.second;
            paired = true;
        } else {
            trace = trace_primary(ray);
        }
        let pixel = shade_pixel(ray, trace);
        let c = clamp(pixel.colour, vec3<Real>(0.0), vec3<Real>(1.0));
        if k == 0u && !lens_open() {
            out_depth[index] = select(-1.0, pixel.depth, pixel.hit);
            out_steps[index] = pixel.steps;
        }
        if adaptive() {
            // The samples the pixel's colours hold, and whether this one joined them.
            let before = streams.rule_a.w + streams.b.w;
            streams = add_to_streams(streams, k, true, vec3<f32>(c));
            let n = streams.rule_a.w + streams.b.w;
            if AOVS && n > before {
                aovs = add_pixel_aovs(aovs, u32(n) - 1u, pixel);
            }
            if sampling_done(streams, k + 1u) {
                taken = k + 1u;
                break;
            }
        } else {
            mean += (c - mean) / Real(k + 1u);
            if AOVS {
                aovs = add_pixel_aovs(aovs, k, pixel);
            }
        }
    }
    if adaptive() {
        if AOVS && taken > 0u {
            aovs = finish_aovs(aovs, streams, taken);
        }
        store_streams(index, streams, taken);
        mean = vec3<Real>(streams_mean(streams));
    } else {
        accumulated[index] = vec4<f32>(vec3<f32>(mean), 0.0);
    }
    if AOVS {
        store_aovs(index, aovs);
    }
    out_work[index] = add_work(made);
    out_colour[index] = pack_colour(mean);
}
