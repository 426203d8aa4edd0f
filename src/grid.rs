//! The grid that `qjulia mesh` samples its level on: [`GridSpec`] in f64 as the mesh sees it,
//! and [`SampleGrid`], the same grid in the sampler's precision as both sampler twins
//! (shaders/sample.wgsl, src/cpu/sample.rs) read it.

use crate::algebra::{Real, Vec3};

/// A regular grid of points: the first (the low corner of its box), the spacing along x, y and
/// z, and the points per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    pub origin: [f64; 3],
    pub step: [f64; 3],
    pub size: [u32; 3],
}

impl GridSpec {
    /// The point at grid index (x, y, z).
    pub fn point(&self, x: f64, y: f64, z: f64) -> [f64; 3] {
        [
            self.origin[0] + x * self.step[0],
            self.origin[1] + y * self.step[1],
            self.origin[2] + z * self.step[2],
        ]
    }

    /// Points in the grid.
    pub fn points(&self) -> u64 {
        self.size.iter().map(|&n| n as u64).product()
    }

    /// The smallest spacing of its points: the cell, which plays a pixel's part in the
    /// precision rule.
    pub fn cell(&self) -> f64 {
        self.step.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The largest coordinate of its points, in absolute value.
    pub fn reach(&self) -> f64 {
        let far = [0, 1, 2].map(|k| {
            let end = self.origin[k] + self.step[k] * (self.size[k] - 1) as f64;
            self.origin[k].abs().max(end.abs())
        });
        far.iter().copied().fold(0.0, f64::max)
    }

    /// The grid in the sampler's precision, rows of rows.
    pub fn in_precision<F: Real>(&self) -> SampleGrid<F> {
        SampleGrid {
            origin: Vec3::from_f64(self.origin),
            step: Vec3::from_f64(self.step),
            width: self.size[0],
            rows: self.size[1],
        }
    }
}

/// The sampled grid in the working precision: its first point (the low corner of its box), the
/// spacing of its points along x, y and z, and its points per row and rows per layer. Row j of
/// the grid (rows of rows) is the row y = j % rows of layer z = j / rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleGrid<F> {
    pub origin: Vec3<F>,
    pub step: Vec3<F>,
    pub width: u32,
    pub rows: u32,
}
