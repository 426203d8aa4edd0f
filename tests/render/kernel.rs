//! The kernel runner on its own: a small test kernel that accumulates over several dispatches
//! per band, in bands far smaller than the grid, reading back one output of two. The expected
//! values are written down from the kernel's definition, not computed by the runner.

use crate::common;

use qjulia::gpu::kernel::{Band, BandOutput, Kernel, KernelSpec, OutputSpec, Run};
use qjulia::gpu::shaders::ShaderModuleSource;

/// Each item (x, row) of the grid holds `row * 1000 + x`, added once per dispatch; `scratch`
/// is written but never asked for.
const ACCUMULATE_WGSL: &str = "
struct Params { row_offset: u32, rows: u32, width: u32, dispatch: u32 }
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> sum: array<u32>;
@group(0) @binding(2) var<storage, read_write> scratch: array<u32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.rows {
        return;
    }
    let i = gid.y * params.width + gid.x;
    let value = (params.row_offset + gid.y) * 1000u + gid.x;
    if params.dispatch == 0u {
        sum[i] = value;
    } else {
        sum[i] = sum[i] + value;
    }
    scratch[i] = 7u;
}
";

const ACCUMULATE: KernelSpec = KernelSpec {
    name: "accumulate",
    module: ShaderModuleSource::text("accumulate", ACCUMULATE_WGSL),
    entry_point: "main",
    uniform_bytes: 16,
    outputs: &[
        OutputSpec {
            name: "sum",
            bytes_per_item: 4,
            on_demand: false,
            planes: 1,
            planes_back: 1,
        },
        OutputSpec {
            name: "scratch",
            bytes_per_item: 4,
            on_demand: false,
            planes: 1,
            planes_back: 1,
        },
    ],
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
    input: None,
    bake_keeps: None,
};

#[test]
fn the_runner_accumulates_dispatches_band_by_band_and_reads_back_what_is_asked() {
    // 64 items per band: a 13-wide grid runs in bands of 4 rows. The variable is read once a
    // process, so the test runs in a process of its own that starts with it.
    let name = "the_runner_accumulates_dispatches_band_by_band_and_reads_back_what_is_asked";
    if !common::own_process(module_path!(), name, &[("QJULIA_BAND_PIXELS", "64")]) {
        return;
    }
    let Some(tracer) = common::gpu("kernel runner") else {
        return;
    };
    let kernel = Kernel::new(tracer.context().clone(), ACCUMULATE).expect("the test kernel");
    let (width, height, dispatches) = (13u32, 11u32, 3u32);
    assert_eq!(kernel.band_rows(width, height), 4);
    let params =
        |b: Band| bytemuck::cast::<[u32; 4], [u8; 16]>([b.row, b.rows, width, b.dispatch]).to_vec();
    let run = Run {
        constants: &[],
        size: (width, height),
        read: &[true, false],
        dispatches_per_band: dispatches,
        params: &params,
        input: None,
    };
    let mut bands = Vec::new();
    let mut sums = Vec::new();
    let times = kernel
        .run(
            &run,
            |out: BandOutput<'_>| {
                assert!(out.outputs[1].is_none(), "scratch was not asked for");
                let sum: &[u32] = bytemuck::cast_slice(out.outputs[0].expect("sum"));
                (out.row, out.rows, sum.to_vec())
            },
            |(row, rows, sum)| {
                bands.push((row, rows));
                sums.extend(sum);
                Ok(())
            },
        )
        .expect("the run");
    assert_eq!(bands, [(0, 4), (4, 4), (8, 3)]);
    let expected: Vec<u32> = (0..height)
        .flat_map(|row| (0..width).map(move |x| dispatches * (row * 1000 + x)))
        .collect();
    assert_eq!(sums, expected);
    assert!(times.seconds > 0.0);
    if tracer.context().has_timestamps() {
        assert!(times.gpu_seconds.is_some_and(|s| s >= 0.0));
    }
}
