// The camera and the lens: the camera rays of a sample, the thin lens and its aperture, the cone's
// start for a block of pixels, the primary ray (pinhole or lens, clipped to the bounds) and its
// sphere tracing, alone or as a fused pair.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/camera.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params
#import estimate
#import march
#import accumulate

// Pixels a side of the blocks that share a cone (one workgroup).
const CONE_BLOCK: u32 = 8u;
// The cone stops this many epsilons short: the estimate is about half the true distance near
// the surface, so rays must start where it is still well above epsilon.
const CONE_MARGIN: Real = 4.0;

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

// A ray: its origin and its unit direction.
struct Ray {
    origin: vec3<Real>,
    dir: vec3<Real>,
}

#if LENS
// Whether the camera's samples go through the thin lens: aperture > 0. Every sample does then,
// sample 0 too; the depth and the steps stay the pinhole's ray's through the pixel's centre
// (pinhole_ray), traced for them alone. Without LENS (shaders/kernels.json) false, and the lens
// is not in the kernel.
fn lens_open() -> bool {
    return params.aperture > 0.0;
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
#else
fn lens_open() -> bool {
    return false;
}

// Never called: lens_open() is false.
fn lens_ray(i: u32, j: u32, sample: u32) -> Ray {
    return Ray(params.eye, params.cam_forward);
}

// Never called: lens_open() is false.
fn thin_lens_ray(x: Real, y: Real, lens_unit: vec2<f32>) -> Ray {
    return Ray(params.eye, params.cam_forward);
}

// Never called: lens_open() is false.
fn aperture_point(uv: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(0.0);
}
#endif

#if CONE_TRACING
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
#else
// Never called: cone_tracing() is false.
fn cone_start(bi: u32, bj: u32) -> Real {
    return 0.0;
}
#endif

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
