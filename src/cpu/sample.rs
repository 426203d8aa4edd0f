//! The CPU twin of shaders/sample.wgsl, the voxel sampler of `qjulia mesh`: the same functions
//! with the same names in the same order (tests/architecture/twins.rs), generic over the float type. WGSL's
//! `params` is `self` (the tracer's parameters) and its grid fields are a [`SampleGrid`] here
//! (src/grid.rs, shared with the GPU sampler); the kernel's entry point `sample` is
//! [`sample_rows`] (rows in parallel).

use rayon::prelude::*;

use crate::algebra::{Real, Vec3};
use crate::grid::SampleGrid;
use crate::params::TraceParams;

impl<F: Real> TraceParams<F> {
    /// The grid point at column i of the grid's row j (rows of rows), in slice coordinates.
    pub fn grid_point(&self, grid: &SampleGrid<F>, i: u32, j: u32) -> Vec3<F> {
        let y = j % grid.rows;
        let z = j / grid.rows;
        let index = Vec3::new(F::lit(i as f64), F::lit(y as f64), F::lit(z as f64));
        grid.origin + index.mul_elem(grid.step)
    }

    /// The level whose zero set is the mesh's surface: d(p) - epsilon inside the bounding ball
    /// (negative inside the shell the renderer's rays stop in), and outside it the distance to
    /// the ball, so that the surface is cut by the ball as the renderer's rays are:
    /// max(d(p) - epsilon, |p - centre| - radius), the estimate not made where the second term
    /// is positive. An empty bounding region is outside everywhere (1).
    pub fn sample_level(&self, p: Vec3<F>) -> F {
        if self.bounds_radius_squared <= F::zero() {
            return F::one();
        }
        let ball = (p - self.bounds_center).length() - self.bounds_radius_squared.sqrt();
        if ball > F::zero() {
            return ball;
        }
        (self.estimate_distance(p) - self.epsilon).max(ball)
    }
}

/// The levels of the grid's rows [rows.start, rows.end), row by row (the GPU's `sample`
/// dispatch), the rows in parallel.
pub fn sample_rows<F: Real>(
    params: &TraceParams<F>,
    grid: &SampleGrid<F>,
    rows: std::ops::Range<u32>,
) -> Vec<F> {
    let width = grid.width as usize;
    let mut out = vec![F::zero(); rows.len() * width];
    out.par_chunks_mut(width).zip(rows).for_each(|(row, j)| {
        for (i, level) in row.iter_mut().enumerate() {
            *level = params.sample_level(params.grid_point(grid, i as u32, j));
        }
    });
    out
}
