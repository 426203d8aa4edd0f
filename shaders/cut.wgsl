// The cut: the plane term of the half-space a scene's cut takes away, which the distance estimate
// applies (estimate_distance).
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/cut.rs, function by
// function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params

// The cut's plane term cut_normal . p - cut_offset: the signed distance of p from the plane
// (cut_normal is of unit length), positive on the side the cut takes away.
fn cut_plane(p: vec3<Real>) -> Real {
    return dot(params.cut_normal, p) - params.cut_offset;
}
