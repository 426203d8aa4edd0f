// Traps and colour: the orbit trap, the palette, a hit's base colour, the shading features (the
// environment's light, shadows and occlusion) and the background.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/colour.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import algebra
#import params
#import environment
#import estimate
#import normal
#import shading

// params.colouring: the diffuse colour (the seed), or the orbit's closest approach to the trap.
const COLOURING_FLAT: u32 = 0u;
const COLOURING_ORBIT_TRAP: u32 = 1u;

#if ORBIT_TRAP
// Whether the scene colours by the orbit trap (shading.colouring = "orbit_trap"). Without
// ORBIT_TRAP (shaders/kernels.json) false, and the trap and its palette are not in the kernel.
fn trap_on() -> bool {
    return params.colouring == COLOURING_ORBIT_TRAP;
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
#else
fn trap_on() -> bool {
    return false;
}

// Never called: trap_on() is false.
fn orbit_trap(q: Hyper) -> Real {
    return 0.0;
}

// Never called: trap_on() is false.
fn palette(t: Real) -> vec3<Real> {
    return params.diffuse;
}
#endif

// The base colour of a hit at p: the diffuse colour, or the palette's colour of the orbit trap.
// (shade_features's B, path mode's albedo, and the albedo AOV.)
fn hit_albedo(p: vec3<Real>) -> vec3<Real> {
    if trap_on() {
        return palette(orbit_trap(slice_point(p)));
    }
    return params.diffuse;
}

// Whether the hit is shaded by shade_features (a light of some radius, ambient light, occlusion
// or orbit-trap colour) instead of the seed's phong and in_shadow.
fn shading_features() -> bool {
    let soft = shadows_on() && soft_shadows_on();
    return soft || occlusion_on() || trap_on() || params.ambient > 0.0;
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
    if occlusion_on() {
        a = occlusion(p, n);
    }
    var ambient = params.ambient * a * base;
    if environment_on() && params.env_light != 0u {
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
    // As in shade_pixel: no shadow ray for an unlit point.
    if shadows_on() && any(light > vec3<Real>(0.0)) {
        if soft_shadows_on() {
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
    if environment_on() {
        return vec3<Real>(env_radiance(vec3<f32>(dir)));
    }
    return params.background;
}
