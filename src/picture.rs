//! What is made of a scene: a [`Picture`] (the 3D slice, the 2D Julia set), or a mesh's
//! levels; together a [`Work`], which the precision rule ([`crate::precision`]) and the one
//! decision ([`crate::render::Planner::plan`]) take.

use crate::grid::GridSpec;

/// What is rendered of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Picture {
    /// The 3D slice (`qjulia render`). `shade` false asks for depth and steps only: the GPU runs
    /// a pipeline without the shading code, the CPU skips it too, and the colour is the
    /// background.
    Slice { shade: bool },
    /// The 2D Julia set of `c[0] + c[1] i` (`qjulia render2d`): colour the grey, depth 0 in the
    /// set and NaN outside it, steps the iterations made. Its stats count points in the set as
    /// hits and iterations as steps.
    Julia2d,
}

impl Picture {
    /// The shaded 3D slice.
    pub const SHADED: Picture = Picture::Slice { shade: true };

    /// Whether this picture of `scene` is path traced: the shaded slice of a scene in
    /// `shading.model = "path"`. Depth and steps alone (`shade` false) are the tracer's: a
    /// path's depth and steps are the pinhole's camera ray's through the pixel's centre, traced
    /// as the tracer traces it.
    pub fn path_traced(&self, scene: &crate::scene::Scene) -> bool {
        matches!(self, Picture::Slice { shade: true })
            && scene.shading.model == crate::scene::ShadingModel::Path
    }
}

/// What a plan is for: a picture, or the levels of a mesh's grid (`qjulia mesh`; None: the
/// bounding region is empty and there is nothing to sample). The grid's cell plays the part of
/// the pixel in the precision rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Work {
    Picture(Picture),
    Mesh(Option<GridSpec>),
}

impl From<Picture> for Work {
    fn from(picture: Picture) -> Self {
        Work::Picture(picture)
    }
}
