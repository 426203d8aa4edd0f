//! The CPU twin of shaders/cut.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). The cut: the plane term of the
//! half-space a scene's cut takes away, which the distance estimate applies (estimate_distance).

use crate::algebra::{Real, Vec3};
use crate::params::TraceParams;

impl<F: Real> TraceParams<F> {
    /// Whether the scene has a cut (cut.enabled).
    pub fn cut_on(&self) -> bool {
        self.cut
    }

    /// The cut's plane term cut_normal . p - cut_offset: the signed distance of p from the plane
    /// (cut_normal is of unit length), positive on the side the cut takes away.
    pub fn cut_plane(&self, p: Vec3<F>) -> F {
        self.cut_normal.dot(p) - self.cut_offset
    }
}
