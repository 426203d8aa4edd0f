// The voxel sampler of `qjulia mesh`: one invocation per grid point, the level of the mesh's
// surface there, through the tracer's own estimate (estimate_distance, with the cut). Imports
// shaders/trace.wgsl, whose `Params` uniform (binding 0: the scene's, as a render's) and first output (binding 1) it
// shares; the grid is a uniform of its own (binding 7: binding 6 is the tracer's AOV output).
//
// Twin: src/cpu/sample.rs, function by function, with the same names in the same order
// (tests/architecture/twins.rs).
#import trace
//
// The sampled grid (keep in sync with GpuSampleGrid in src/gpu/sampler.rs; its CPU twin is
// src/grid.rs's SampleGrid): its first point (the low corner of its box), the spacing of its
// points along x, y and z, its points per row and rows per layer. The grid is rows of rows: its
// row j is the row y = j % rows of the layer z = j / rows, and this dispatch samples the rows
// [row_offset, row_offset + row_count), point (i, row_offset + r) written at r * width + i.
struct SampleGrid {
    origin: vec3<f32>,
    width: u32,
    step: vec3<f32>,
    rows: u32,
    row_offset: u32,
    row_count: u32,
}

@group(0) @binding(7) var<uniform> grid: SampleGrid;

// The grid point at column i of the grid's row j (rows of rows), in slice coordinates.
fn grid_point(i: u32, j: u32) -> vec3<f32> {
    let y = j % grid.rows;
    let z = j / grid.rows;
    return grid.origin + vec3<f32>(f32(i), f32(y), f32(z)) * grid.step;
}

// The level whose zero set is the mesh's surface: d(p) - epsilon inside the bounding ball
// (negative inside the shell the renderer's rays stop in), and outside it the distance to the
// ball, so that the surface is cut by the ball as the renderer's rays are:
// max(d(p) - epsilon, |p - centre| - radius), the estimate not made where the second term is
// positive. An empty bounding region is outside everywhere (1).
fn sample_level(p: vec3<f32>) -> f32 {
    if params.bounds_radius_squared <= 0.0 {
        return 1.0;
    }
    let ball = length(p - params.bounds_center) - sqrt(params.bounds_radius_squared);
    if ball > 0.0 {
        return ball;
    }
    return max(estimate_distance(p) - params.epsilon, ball);
}

// One grid point's level, as its bits in the first output (`out_colour`, an array of u32).
@compute @workgroup_size(8, 8, 1)
fn sample(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    let row = gid.y;
    if i >= grid.width || row >= grid.row_count {
        return;
    }
    let level = sample_level(grid_point(i, grid.row_offset + row));
    out_colour[row * grid.width + i] = bitcast<u32>(level);
}
