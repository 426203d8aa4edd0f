// A test-support kernel (src/gpu/sobol_probe.rs): the sampler of shaders/sobol.wgsl evaluated
// over a grid of (pixel, sample, dimension), its bits written as they are, so that the tests
// can hold them to the CPU twin's bit for bit. Item
// (x, row) of the grid is pixel `pixel_base + row_offset + row`, sample `x / dims`, dimension
// `x % dims`, written at row * width + x.
#import sobol
struct ProbeParams {
    row_offset: u32,
    rows: u32,
    width: u32,
    dims: u32,
    pixel_base: u32,
    sampler: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> probe: ProbeParams;
@group(0) @binding(1) var<storage, read_write> out_bits: array<u32>;

@compute @workgroup_size(8, 8, 1)
fn sobol_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= probe.width || gid.y >= probe.rows {
        return;
    }
    let pixel = probe.pixel_base + probe.row_offset + gid.y;
    let bits = sample_bits(probe.sampler, pixel, gid.x / probe.dims, gid.x % probe.dims);
    out_bits[gid.y * probe.width + gid.x] = bits;
}
