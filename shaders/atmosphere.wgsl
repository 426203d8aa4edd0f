// The atmosphere: fog's transmittance along the primary ray and the glow of its closest approach,
// laid over a pixel's colour.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/atmosphere.rs, function
// by function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params
#import march
#import camera

#if FOG
// Whether the scene has fog (fog.density > 0, either model). Without FOG (shaders/kernels.json)
// false, and the fog's transmittance is 1 (path mode's free flight is not in the kernel either:
// shaders/path_vertex.wgsl, shaders/medium.wgsl).
fn fog_on() -> bool {
    return params.fog_density > 0.0;
}
#else
fn fog_on() -> bool {
    return false;
}
#endif

#if GLOW
// Whether phong mode's halo is on (glow.strength > 0). Without GLOW false, and the halo is not in
// the kernel.
fn glow_on() -> bool {
    return params.glow_strength > 0.0;
}
#else
fn glow_on() -> bool {
    return false;
}
#endif

#if FOG
// The fog's transmittance along origin + t dir over t in [0, t_stop]: exp(-fog_density L), L the
// length of that stretch within the bounding ball (the fog fills the ball); 1 without fog. In
// f32, as path mode's radiance is.
fn fog_transmittance(origin: vec3<Real>, dir: vec3<Real>, t_stop: Real) -> f32 {
    if !fog_on() {
        return 1.0;
    }
    let bounds = intersect_bounds(origin, dir);
    if !bounds.hit {
        return 1.0;
    }
    let length = max(min(bounds.t_exit, t_stop) - bounds.t_enter, 0.0);
    return exp(-f32(params.fog_density * length));
}
#else
// No fog: nothing is lost.
fn fog_transmittance(origin: vec3<Real>, dir: vec3<Real>, t_stop: Real) -> f32 {
    return 1.0;
}
#endif

#if GLOW
// Phong mode's halo for a ray that missed: glow_strength glow_colour exp(-closest / glow_radius),
// closest the least distance estimate along the ray (Trace's closest; a ray that missed the
// ball gets exp(-3e38 / r) = 0).
fn glow(closest: Real) -> vec3<Real> {
    let fall = exp(-f32(max(closest, 0.0) / params.glow_radius));
    return params.glow_strength * params.glow_colour * Real(fall);
}
#else
// Never called: glow_on() is false.
fn glow(closest: Real) -> vec3<Real> {
    return vec3<Real>(0.0);
}
#endif

// Phong mode's atmosphere over a camera ray's colour (docs/book/atmosphere.md): a miss gains the
// halo (glow); then the colour is blended toward fog_colour by the fog's transmittance T from
// the eye to the hit (through the whole ball on a miss), mix(fog_colour, colour, T) (Mandelbulber's
// basic fog). Without fog and glow the colour unchanged.
fn atmosphere(colour: vec3<Real>, ray: Primary, trace: Trace) -> vec3<Real> {
    var c = colour;
    if !trace.hit && glow_on() {
        c += glow(trace.closest);
    }
    if fog_on() {
        let t_stop = select(Real(3.0e38), trace.t, trace.hit);
        let transmittance = Real(fog_transmittance(ray.origin, ray.dir, t_stop));
        c = mix(params.fog_colour, c, vec3<Real>(transmittance));
    }
    return c;
}
