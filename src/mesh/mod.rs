//! `qjulia mesh`: the set as a closed triangle mesh, for 3D printing and other tools.
//!
//! The surface is the zero set of the level
//! `L(p) = max(d(p) - epsilon, |p - centre| - radius)`: the shell d(p) = epsilon that the
//! renderer's rays stop in (d the tracer's own distance estimate, `estimate_distance`, the cut
//! included), cut by the bounding ball as the rays are. L is sampled on a grid of N points per
//! axis over the cube around the bounding ball (faces included), or over `--box`; by the GPU's
//! sampling kernel (shaders/sample.wgsl) or its CPU twin ([`crate::cpu::sample`]), a grid layer
//! at a time in bands of bounded size, and meshed slab by slab as the layers arrive
//! ([`extract`]). Vertex normals are the gradient of L (tetrahedral differences of the CPU's
//! f64 estimate); triangles wind counter-clockwise seen from outside.

pub mod extract;
pub mod write;

use std::path::Path;

use serde::Serialize;

pub use extract::{GridSpec, Mesh};
pub use write::Format;

use crate::algebra::Vec3;
use crate::error::{FlagError, Result};
use crate::params::TraceParams;
use crate::picture::Work;
#[cfg(feature = "gpu")]
use crate::render::Renderer;
use crate::scene::Scene;

/// Grid points per axis: the default, and the range `--resolution` accepts.
pub const DEFAULT_RESOLUTION: u32 = 256;
pub const MIN_RESOLUTION: u32 = 8;
pub const MAX_RESOLUTION: u32 = 4096;

/// What to mesh: the grid's points per axis, and the box (min, max corners in slice
/// coordinates; None: the cube around the bounding ball).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshOptions {
    pub resolution: u32,
    pub region: Option<[[f64; 3]; 2]>,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self {
            resolution: DEFAULT_RESOLUTION,
            region: None,
        }
    }
}

impl MeshOptions {
    /// Checks `--resolution`.
    pub fn check_resolution(n: u32) -> Result<u32, FlagError> {
        if (MIN_RESOLUTION..=MAX_RESOLUTION).contains(&n) {
            return Ok(n);
        }
        Err(FlagError::new(
            format!("--resolution {n}"),
            format!("must be from {MIN_RESOLUTION} to {MAX_RESOLUTION} (grid points per axis)"),
        ))
    }

    /// Parses `--box X0,Y0,Z0,X1,Y1,Z1`: six finite numbers, each min below its max.
    pub fn parse_box(text: &str) -> Result<[[f64; 3]; 2], FlagError> {
        let bad = |why: &str| FlagError::new(format!("--box {text}"), why);
        let numbers: Vec<f64> = text
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad("expected six numbers X0,Y0,Z0,X1,Y1,Z1"))?;
        let [x0, y0, z0, x1, y1, z1] = numbers[..] else {
            return Err(bad("expected six numbers X0,Y0,Z0,X1,Y1,Z1"));
        };
        if numbers.iter().any(|v| !v.is_finite()) {
            return Err(bad("every number must be finite"));
        }
        if !(x0 < x1 && y0 < y1 && z0 < z1) {
            return Err(bad(
                "each minimum must be below its maximum (X0 < X1, Y0 < Y1, Z0 < Z1)",
            ));
        }
        Ok([[x0, y0, z0], [x1, y1, z1]])
    }

    /// Checks `--scale`: finite and > 0.
    pub fn check_scale(s: f64) -> Result<f64, FlagError> {
        if s.is_finite() && s > 0.0 {
            return Ok(s);
        }
        Err(FlagError::new(
            format!("--scale {s}"),
            "must be finite and > 0",
        ))
    }
}

/// The grid of a scene: N points per axis over the box, or the cube around the bounding ball;
/// None when there is no box and the bounding region is empty.
pub fn grid_for(scene: &Scene, options: &MeshOptions) -> Option<GridSpec> {
    let [min, max] = match options.region {
        Some(b) => b,
        None => {
            let bounds = scene.slice_bounds();
            if bounds.radius_squared <= 0.0 {
                return None;
            }
            let r = bounds.radius_squared.sqrt();
            [bounds.center.map(|c| c - r), bounds.center.map(|c| c + r)]
        }
    };
    let n = options.resolution.max(2);
    Some(GridSpec {
        origin: min,
        step: [0, 1, 2].map(|k| (max[k] - min[k]) / (n - 1) as f64),
        size: [n; 3],
    })
}

/// What `mesh --stats` writes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshStats {
    /// "gpu" or "cpu".
    pub backend: String,
    /// The adapter ("name / Backend"), or "cpu".
    pub adapter: String,
    /// The sampling's precision, "f32" or "f64".
    pub precision: String,
    /// Grid points per axis.
    pub resolution: u32,
    /// The grid's box: min and max corners, slice coordinates.
    pub box_min: [f64; 3],
    pub box_max: [f64; 3],
    pub grid_points: u64,
    pub vertices: u64,
    pub triangles: u64,
    /// The whole mesh: sampling, extraction and normals (not writing).
    pub seconds: f64,
    /// The sampling alone (on the GPU: from its first dispatch to its last band in host
    /// memory, extraction left out).
    pub sample_seconds: f64,
    /// grid_points / sample_seconds.
    pub grid_points_per_second: f64,
}

/// How far a mesh has got: grid layers sampled and meshed, of the total.
pub type Progress<'a> = &'a mut dyn FnMut(u32, u32);

/// Meshes a validated scene on `renderer`'s backend and precision (a plan of [`work`]).
#[cfg(feature = "gpu")]
pub fn make_mesh(
    renderer: &Renderer,
    scene: &Scene,
    options: &MeshOptions,
    progress: Progress<'_>,
) -> Result<(Mesh, MeshStats)> {
    let start = std::time::Instant::now();
    let mut stats = MeshStats {
        backend: renderer.backend_name().into(),
        adapter: renderer.adapter(),
        precision: renderer.precision().name().into(),
        resolution: options.resolution,
        box_min: [0.0; 3],
        box_max: [0.0; 3],
        grid_points: 0,
        vertices: 0,
        triangles: 0,
        seconds: 0.0,
        sample_seconds: 0.0,
        grid_points_per_second: 0.0,
    };
    let Some(grid) = grid_for(scene, options) else {
        return Ok((Mesh::default(), stats));
    };
    stats.box_min = grid.origin;
    stats.box_max = grid.point(
        (grid.size[0] - 1) as f64,
        (grid.size[1] - 1) as f64,
        (grid.size[2] - 1) as f64,
    );
    stats.grid_points = grid.points();
    let exact = TraceParams::<f64>::new(scene);
    let h = 0.1 * grid.cell();
    let gradient = |p: [f64; 3]| level_gradient(&exact, p, h);
    let mut extractor = extract::Extractor::new(grid, &gradient);
    let layers = grid.size[2];
    let layer_points = grid.size[0] as usize * grid.size[1] as usize;
    // The levels come in pieces of any length: whole layers go to the extractor.
    let mut partial: Vec<f32> = Vec::with_capacity(layer_points);
    let mut done = 0;
    let sample_seconds = renderer.sample_levels(scene, &grid, &mut |mut levels| {
        while !levels.is_empty() {
            let take = (layer_points - partial.len()).min(levels.len());
            partial.extend_from_slice(&levels[..take]);
            levels = &levels[take..];
            if partial.len() == layer_points {
                let layer = std::mem::replace(&mut partial, Vec::with_capacity(layer_points));
                extractor.push_layer(layer);
                done += 1;
                progress(done, layers);
            }
        }
        Ok(())
    })?;
    let mesh = extractor.finish();
    stats.vertices = mesh.positions.len() as u64;
    stats.triangles = mesh.triangles.len() as u64;
    stats.seconds = start.elapsed().as_secs_f64();
    stats.sample_seconds = sample_seconds;
    stats.grid_points_per_second = stats.grid_points as f64 / sample_seconds.max(1e-9);
    Ok((mesh, stats))
}

/// The work of meshing `scene` with `options`, for [`crate::render::Planner::plan`]: the grid's cell plays
/// the pixel's part in the precision rule.
pub fn work(scene: &Scene, options: &MeshOptions) -> Work {
    Work::Mesh(grid_for(scene, options))
}

/// The gradient of the level at p by tetrahedral differences of step h (four estimates), in
/// f64 on the CPU: the vertex normal's direction (outward: the level grows outward).
pub fn level_gradient(params: &TraceParams<f64>, p: [f64; 3], h: f64) -> [f64; 3] {
    const CORNERS: [[f64; 3]; 4] = [
        [1.0, -1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, 1.0, 1.0],
    ];
    let mut g = [0.0; 3];
    for v in CORNERS {
        let q = Vec3::new(p[0] + h * v[0], p[1] + h * v[1], p[2] + h * v[2]);
        let level = params.sample_level(q);
        (0..3).for_each(|k| g[k] += v[k] * level);
    }
    g
}

/// Writes the mesh (and the stats, when asked) whole or not at all: each to a temporary file
/// beside its target, renamed into place only when both are written.
pub fn write_outputs(
    mesh_path: &Path,
    mesh: &Mesh,
    scale: f64,
    stats: Option<(&Path, &MeshStats)>,
) -> Result<()> {
    let format = Format::for_path(mesh_path)?;
    let mesh_file = crate::output::stage(mesh_path, |w| write::write_mesh(w, mesh, format, scale))?;
    let stats_file = match stats {
        Some((path, stats)) => Some((
            path,
            crate::output::stage(path, |w| {
                serde_json::to_writer_pretty(&mut *w, stats)?;
                w.write_all(b"\n")
            })?,
        )),
        None => None,
    };
    mesh_file
        .persist(mesh_path)
        .map_err(|e| crate::output::io_error(mesh_path, e.error))?;
    if let Some((path, file)) = stats_file {
        file.persist(path)
            .map_err(|e| crate::output::io_error(path, e.error))?;
    }
    Ok(())
}
