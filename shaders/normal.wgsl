// The normal: safe_normalize, the seed's central differences, the tetrahedral and the analytic
// normals, and estimate_normal, which picks one.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/normal.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import algebra
#import params
#import cut
#import estimate

// |z|^2 at which the normal's six orbits stop, long before they can overflow.
const NORMAL_LIMIT: Real = 1e16;

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

#if CENTRAL_NORMAL
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
#else
// Never called: normal_method() is another method.
fn normal_central(q: Hyper) -> vec3<Real> {
    return vec3<Real>(0.0);
}
#endif

#if TETRAHEDRAL_NORMAL
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
#else
// Never called: normal_method() is another method.
fn normal_tetrahedral(q: Hyper) -> vec3<Real> {
    return vec3<Real>(0.0);
}
#endif

#if ANALYTIC_NORMAL
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
#else
// Never called: normal_method() is another method.
fn normal_analytic(q: Hyper) -> vec3<Real> {
    return vec3<Real>(0.0);
}
#endif

// The normal's method: a constant where the scene's kernel has one (one of the features
// CENTRAL_NORMAL, TETRAHEDRAL_NORMAL and ANALYTIC_NORMAL on), params.normal_method where it has
// every one.
fn normal_method() -> u32 {
#if CENTRAL_NORMAL
#if TETRAHEDRAL_NORMAL
    return params.normal_method;
#else
    return NORMAL_CENTRAL;
#endif
#else
#if TETRAHEDRAL_NORMAL
    return NORMAL_TETRAHEDRAL;
#else
    return NORMAL_ANALYTIC;
#endif
#endif
}

// The shading normal by params.normal_method; where no gradient can be formed it points back
// along the ray. On the cut face, the cut's normal.
fn estimate_normal(p: vec3<Real>, dir: vec3<Real>) -> vec3<Real> {
    // On the cut face the normal is the plane's: where the plane's term is within epsilon of
    // the set's estimate or above it (inside the set the estimate can be 0, where it cannot be
    // formed, against a plane term rounded a little below 0).
    if cut_on() && cut_plane(p) + params.epsilon >= estimate_julia(p) {
        return params.cut_normal;
    }
    let q = slice_point(p);
    var grad: vec3<Real>;
    switch normal_method() {
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
