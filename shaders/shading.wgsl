// Phong shading, the shadow ray (hard and soft) and ambient occlusion.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/shading.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params
#import estimate
#import march
#import normal

#if OCCLUSION
// Ambient occlusion samples the estimate at OCCLUSION_SAMPLES points p + k OCCLUSION_STEP n,
// k = 1, 2, ... (Twin: cpu::trace's constants of the same names.)
const OCCLUSION_SAMPLES: u32 = 5u;
const OCCLUSION_STEP: Real = 0.04;
#endif

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

#if SHADOWS
// Whether the light casts shadows (light.shadows). Without SHADOWS (shaders/kernels.json) false,
// and in_shadow is not in the kernel.
fn shadows_on() -> bool {
    return params.shadows != 0u;
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
#else
fn shadows_on() -> bool {
    return false;
}

// Never called: shadows_on() is false.
fn in_shadow(p: vec3<Real>, n: vec3<Real>) -> bool {
    return false;
}
#endif

#if SOFT_SHADOWS
// Whether the light has a radius (light.radius > 0): the shadows are soft_shadow's. Without
// SOFT_SHADOWS (shaders/kernels.json) false, and soft_shadow is not in the kernel.
fn soft_shadows_on() -> bool {
    return params.light_radius > 0.0;
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
#else
fn soft_shadows_on() -> bool {
    return false;
}

// Never called: soft_shadows_on() is false.
fn soft_shadow(p: vec3<Real>, n: vec3<Real>) -> Real {
    return 1.0;
}
#endif

#if OCCLUSION
// Whether the scene has ambient occlusion (shading.occlusion > 0). Without OCCLUSION false, and
// occlusion is not in the kernel.
fn occlusion_on() -> bool {
    return params.occlusion > 0.0;
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
#else
fn occlusion_on() -> bool {
    return false;
}

// Never called: occlusion_on() is false. Nothing occluded.
fn occlusion(p: vec3<Real>, n: vec3<Real>) -> Real {
    return 1.0;
}
#endif
