// The cut: the plane term of the half-space a scene's cut takes away, which the distance estimate
// applies (estimate_distance).
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/cut.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params

#if CUT
// Whether the scene has a cut (cut.enabled). Without CUT (shaders/kernels.json) false, and the
// plane is not in the kernel.
fn cut_on() -> bool {
    return params.cut != 0u;
}

// The cut's plane term cut_normal . p - cut_offset: the signed distance of p from the plane
// (cut_normal is of unit length), positive on the side the cut takes away.
fn cut_plane(p: vec3<Real>) -> Real {
    return dot(params.cut_normal, p) - params.cut_offset;
}
#else
fn cut_on() -> bool {
    return false;
}

// Never called: cut_on() is false.
fn cut_plane(p: vec3<Real>) -> Real {
    return 0.0;
}
#endif
