// The distance estimate and the iteration: the 3D slice's axes and point, the orbit of z <- z^2 +
// c, the Julia set's estimate from it, estimate_distance (with the cut) that everything uses, and
// the fused pair versions of sphere_trace_pair; the work counts `estimates` and `iterations`.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/estimate.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import algebra
#import params
#import cut

// Distance estimates this invocation has made for its pixel in this dispatch (the cone's are
// not counted), and the quaternion iterations (z <- z^2 + c) it has made for them, for the
// normals and for the orbit trap.
var<private> estimates: u32;
var<private> iterations: u32;

// DERIVATIVE_LIMIT, RELATIVE_EPSILON and MIN_NORMAL depend on the precision: the prelude
// (shaders/real32.wgsl or shaders/real64.wgsl) defines them.
// Below this a squared length counts as zero: nothing is divided by it or normalised.
const TINY: Real = 1e-30;

// Quaternion parts of the scene's algebra (1, 2 or 4): the uniform's where the kernel has every
// algebra (the features QUATERNION and OCTONION both on), else the one algebra's constant
// (neither on: sedenions).
fn algebra_parts() -> u32 {
#if QUATERNION
#if OCTONION
    return params.algebra_parts;
#else
    return 1u;
#endif
#else
#if OCTONION
    return 2u;
#else
    return 4u;
#endif
#endif
}

#if SLICE
// The slice axes (the CPU twin reads them from its parameters). Without SLICE (the standard
// slice, x, y, z = 1, i, j) constants.
fn slice_axis_x() -> Hyper {
    return params.slice_x;
}

fn slice_axis_y() -> Hyper {
    return params.slice_y;
}

fn slice_axis_z() -> Hyper {
    return params.slice_z;
}

// Scene coordinates p in the 3D slice to the point offset + p.x x + p.y y + p.z z of the
// algebra.
fn slice_point(p: vec3<Real>) -> Hyper {
    var q = params.slice_offset;
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
#else
fn slice_axis_x() -> Hyper {
    return Hyper(vec4<Real>(1.0, 0.0, 0.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
}

fn slice_axis_y() -> Hyper {
    return Hyper(vec4<Real>(0.0, 1.0, 0.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
}

fn slice_axis_z() -> Hyper {
    return Hyper(vec4<Real>(0.0, 0.0, 1.0, 0.0), vec4<Real>(0.0), vec4<Real>(0.0), vec4<Real>(0.0));
}

// The standard slice: p is the first quaternion's 1, i, j.
fn slice_point(p: vec3<Real>) -> Hyper {
    var q = params.slice_offset;
    q[0] += vec4<Real>(p, 0.0);
    return q;
}
#endif

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

// The distance estimate everything uses (primary and shadow rays, the cone, occlusion): the
// set's, and with the cut on, the set intersected with the half-space cut_normal . p <= cut_offset,
// max(d, cut_normal . p - cut_offset) (still a lower bound of the distance to what is left).
fn estimate_distance(p: vec3<Real>) -> Real {
    let d = estimate_julia(p);
    if cut_on() {
        return max(d, cut_plane(p));
    }
    return d;
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
    if cut_on() {
        d = vec2<Real>(max(d.x, cut_plane(p1)), max(d.y, cut_plane(p2)));
    }
    return d;
}
