//! One runner for every compute kernel: a kernel is its WGSL, its `#[repr(C)]` uniform and a
//! description of its outputs ([`KernelSpec`]); [`Kernel`] does the rest. It caches a pipeline
//! per specialisation (override constants), binds the uniform and the output arrays, dispatches
//! a grid of any size in bands of bounded size, measures GPU time with timestamp queries, reads
//! back only the outputs asked for, and turns device and validation failures into errors.
//!
//! The grid is `width` x `height` items, one invocation each, in workgroups of
//! [`WORKGROUP_SIZE`]. A band is a run of whole rows; the kernel's uniform tells it which rows
//! (each kernel's params carry a row offset). Several dispatches may run on one band before it
//! is read back (an accumulation pass); a 3D grid (a voxel sampler) is rows of rows.
//!
//! This module owns the kernel's description ([`KernelSpec`], [`Run`] and what a run returns)
//! and building its module and layouts ([`Kernel::new`]). Its parts: `pipeline.rs`, the
//! pipelines built per specialisation, bind groups, one pass's encoding and the band size;
//! `cache.rs`, the pipelines held, bounded; `buffers.rs`, a band's device buffers;
//! `readback.rs`, making them and reading a band back through them; `stream.rs`, running bands
//! as a stream of steps, two in flight; `specialise.rs`, a specialisation's branches cut before
//! the driver sees them; `bake.rs`, a scene's values made constants of the module; `walk.rs`,
//! the statement walk both read the module with. The types of the kernel's state (`cache.rs`,
//! `buffers.rs`) use nothing of this module; the parts that add the kernel's methods use this
//! module, which uses none of theirs (no import cycle, tests/architecture/import_cycles.rs).

mod bake;
mod buffers;
mod cache;
mod pipeline;
mod readback;
mod specialise;
mod stream;
mod walk;

pub use cache::MAX_PIPELINES;
pub use stream::{Step, StepDone};

use std::sync::{Mutex, OnceLock};

use super::GpuContext;
use super::shaders::ShaderModuleSource;
use crate::error::{Error, Result};
use buffers::RunBuffers;

/// Invocations per workgroup in x and y, in every kernel's `@workgroup_size`: 8 wide, since
/// lavapipe packs 8 lanes along x. A test checks each shader against it.
pub const WORKGROUP_SIZE: (u32, u32) = (8, 8);

/// One storage array a kernel writes: binding 1 + its index in [`KernelSpec::outputs`].
#[derive(Clone, Copy, Debug)]
pub struct OutputSpec {
    pub name: &'static str,
    /// Bytes each grid item takes in it.
    pub bytes_per_item: u64,
    /// Allocated whole only for a run that reads it back; otherwise a placeholder of one item,
    /// which the kernel must not touch (the AOVs: the tracer writes them only under its AOVS
    /// override, which the host sets exactly when it reads them). The band's rows are sized
    /// without it where it is not read.
    pub on_demand: bool,
    /// Planes of `items` items each that the kernel keeps in it (the tracer's accumulator has
    /// four: what a pixel shows, then its halves and adaptive sampling's streams).
    pub planes: u64,
    /// The planes that come back, from the first: a band's readback of this output is these
    /// planes one after another, each `items` items (the accumulator's three: what a pixel
    /// shows, then its two halves).
    pub planes_back: u64,
}

impl OutputSpec {
    /// Bytes a grid item takes in a band's readback: its [`Self::planes_back`] planes.
    pub fn read_bytes(&self) -> u64 {
        self.bytes_per_item * self.planes_back
    }
}

/// What a compute kernel is: its module, entry point, uniform size and outputs. Binding 0 is the
/// uniform; bindings 1.. are the outputs, in order; a kernel may have a second uniform of its
/// own ([`SecondUniform`]).
#[derive(Clone, Copy, Debug)]
pub struct KernelSpec {
    pub name: &'static str,
    pub module: ShaderModuleSource,
    pub entry_point: &'static str,
    /// `size_of` the kernel's `#[repr(C)]` params.
    pub uniform_bytes: u64,
    pub outputs: &'static [OutputSpec],
    /// Bands start on multiples of this many rows (1: any row). Cone tracing shares one march
    /// per workgroup block, so the tracer's bands start on block rows.
    pub band_row_multiple: u32,
    /// Build the module without wgpu's runtime checks (bounds checks, loop bounding): only for a
    /// kernel that bounds its own loops (by its params) and checks its own indices.
    pub trusted: bool,
    /// A second uniform beside binding 0's (the sampler's grid, beside the tracer's `Params`).
    pub second_uniform: Option<SecondUniform>,
    /// The binding of a read-only storage array the scene gives (the environment map): each
    /// run's own ([`Run::input`]), a placeholder of a few words where it has none.
    pub input: Option<u32>,
    /// Whether a run may bake the scene's values into its pipeline ([`BAKE_VALUES`]): None
    /// where it may not; else the uniforms' members still read at run time (the per-dispatch
    /// ones: the band, where it lands, the samples it adds).
    pub bake_keeps: Option<&'static [&'static str]>,
}

/// The constant that asks a kernel to bake the scene's values (its uniforms' members, but
/// those of [`KernelSpec::bake_keeps`]) into the run's pipeline as constants of its module
/// ([`bake`]): a pipeline per scene's values, held in the kernel's bounded cache. No override
/// of a shader's: the kernel takes it out of the constants before it specialises, and bakes
/// the values of the step's first dispatch (every dispatch of the step must agree on them).
pub const BAKE_VALUES: (&str, f64) = ("qjulia_bake_values", 1.0);

/// The members of the tracer's and the path tracer's uniforms (`Params`, `PathParams`) read at
/// run time in a pipeline with the scene's values baked: `Params`' per-dispatch members (a
/// test holds them to the uniform's layout), and the path sampler's seed, which an animation's
/// frames change (path.animated_seed) while the rest of the scene stays.
pub const TRACE_BAKE_KEEPS: &[&str] = &[
    "row_offset",
    "row_count",
    "row_stride",
    "out_row",
    "sample_start",
    "sample_end",
    "seed",
];

/// As [`TRACE_BAKE_KEEPS`], for the 2D view's `Julia2dParams`.
pub const JULIA2D_BAKE_KEEPS: &[&str] = &["row_offset", "row_count", "row_stride", "out_row"];

/// A kernel's second uniform: its binding and the `size_of` its `#[repr(C)]` struct. It rides
/// in the same buffer as the first, from [`Kernel::second_uniform_offset`] on: a dispatch's
/// uniform bytes are the first uniform's, zeros up to there, then the second's
/// ([`Kernel::pack_uniforms`]).
#[derive(Clone, Copy, Debug)]
pub struct SecondUniform {
    pub binding: u32,
    pub bytes: u64,
}

/// The rows one dispatch covers, and which of the band's dispatches it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Band {
    pub row: u32,
    pub rows: u32,
    /// 0 to `dispatches_per_band - 1`.
    pub dispatch: u32,
}

/// One run of a kernel over a grid.
pub struct Run<'a> {
    pub constants: &'a [(&'static str, f64)],
    /// Items per row, rows.
    pub size: (u32, u32),
    /// Which outputs come back to the host (by index); the others stay on the device.
    pub read: &'a [bool],
    /// Dispatches on each band before it is read back.
    pub dispatches_per_band: u32,
    /// The uniform's bytes for one dispatch.
    pub params: &'a dyn Fn(Band) -> Vec<u8>,
    /// The scene's input array ([`KernelSpec::input`]; None where the kernel has none or the
    /// scene gives none).
    pub input: InputData,
}

/// One band read back: its rows, and the bytes of each output asked for (None for the others).
pub struct BandOutput<'a> {
    pub row: u32,
    pub rows: u32,
    pub outputs: &'a [Option<&'a [u8]>],
}

/// How long a run took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunTimes {
    /// From the first timed dispatch to the last band decoded in host memory, the sink's time
    /// left out (the pipeline's first use is warmed up untimed).
    pub seconds: f64,
    /// GPU time of the dispatches by timestamp queries, where the device has them.
    pub gpu_seconds: Option<f64>,
}

/// A compute kernel on one device.
pub struct Kernel {
    ctx: GpuContext,
    spec: KernelSpec,
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Pipelines by their constants, whether each has run once (warmed up), and the least
    /// recently used dropped past [`MAX_PIPELINES`].
    pipelines: Mutex<cache::Pipelines>,
    /// Held while a pipeline is built ([`Kernel::pipeline`]).
    building: Mutex<()>,
    /// The source parsed once, for specialisations ([`specialise`]); built at the first, or
    /// at [`Kernel::new`] where the params are bound as storage.
    parsed: OnceLock<Option<specialise::Parsed>>,
    /// The text composed for a set of scene features and parsed, for the pipelines of those
    /// features ([`crate::gpu::shaders::split_constants`]): the last [`MAX_PARSED`] sets.
    parsed_scenes: Mutex<Vec<ParsedScene>>,
    /// The byte ranges of a dispatch's uniform bytes that a baked pipeline still reads at run
    /// time ([`KernelSpec::bake_keeps`]): zeroed in the key of a baked pipeline.
    kept_ranges: OnceLock<Vec<std::ops::Range<usize>>>,
    /// Whether the params (binding 0 and the second uniform) are bound as read-only storage
    /// ([`GpuContext::uniforms_as_storage`]).
    uniforms_as_storage: bool,
    /// The input arrays uploaded ([`Kernel::input_buffer`]), by the data they hold.
    inputs: Mutex<Vec<(InputData, wgpu::Buffer)>>,
    /// The last run's buffers, kept for the next run of the same band size and readback (an
    /// animation's frames, the explorer's views): allocating and clearing them anew each time
    /// costs more than a fast GPU's whole render (a 4 Mpixel band is 128 MiB of outputs).
    spare: Mutex<Vec<RunBuffers>>,
}

impl Kernel {
    /// Builds the module and layouts; a shader the device rejects is an error, not a panic.
    pub fn new(ctx: GpuContext, spec: KernelSpec) -> Result<Self> {
        let device = &ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        // Where the params go in as storage, the source is parsed here (the base of every
        // specialisation too), and the plain module made of it.
        let parsed = OnceLock::new();
        if ctx.uniforms_as_storage() {
            let _ = parsed.set(specialise::Parsed::new(&spec.module.source(), true));
        }
        let uniforms_as_storage = matches!(parsed.get(), Some(Some(_)));
        let source = match parsed.get() {
            Some(Some(p)) => wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(p.module().clone())),
            _ => wgpu::ShaderSource::Wgsl(spec.module.source().into()),
        };
        let module = create_module(device, &spec, source);
        let params = match uniforms_as_storage {
            true => wgpu::BufferBindingType::Storage { read_only: true },
            false => wgpu::BufferBindingType::Uniform,
        };
        let entry = |binding, ty, min_binding_size| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size,
            },
            count: None,
        };
        let storage = wgpu::BufferBindingType::Storage { read_only: false };
        let input = wgpu::BufferBindingType::Storage { read_only: true };
        let entries: Vec<_> =
            std::iter::once(entry(0, params, wgpu::BufferSize::new(spec.uniform_bytes)))
                .chain((1..=spec.outputs.len() as u32).map(|b| entry(b, storage, None)))
                .chain(
                    spec.second_uniform
                        .map(|u| entry(u.binding, params, wgpu::BufferSize::new(u.bytes))),
                )
                .chain(spec.input.map(|b| entry(b, input, None)))
                .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(spec.name),
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(spec.name),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!(
                "the {} shader was rejected: {e}",
                spec.name
            )));
        }
        Ok(Self {
            ctx,
            spec,
            module,
            layout,
            pipeline_layout,
            pipelines: Mutex::new(cache::Pipelines::default()),
            building: Mutex::new(()),
            parsed,
            parsed_scenes: Mutex::new(Vec::new()),
            kept_ranges: OnceLock::new(),
            uniforms_as_storage,
            inputs: Mutex::new(Vec::new()),
            spare: Mutex::new(Vec::new()),
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    pub fn spec(&self) -> &KernelSpec {
        &self.spec
    }
}

/// The scene's input array a run binds ([`KernelSpec::input`]): the environment map, or None.
pub type InputData = Option<std::sync::Arc<crate::envmap::EnvironmentData>>;

/// Where a run's input is among the buffers uploaded: the address of its data (0: none).
pub(crate) fn input_source(data: &InputData) -> usize {
    data.as_ref()
        .map_or(0, |d| std::sync::Arc::as_ptr(d) as usize)
}

/// Maps kept uploaded ([`Kernel::input_buffer`]): the last few, each held alive so that its
/// address stays its own (and the placeholder).
const INPUTS_KEPT: usize = 2;

/// A set of scene features and the kernel's text composed for it, parsed (None where naga
/// refuses it).
type ParsedScene = (
    Vec<&'static str>,
    std::sync::Arc<Option<specialise::Parsed>>,
);

/// Texts composed for a set of scene features and parsed that a kernel keeps
/// ([`Kernel::parsed_scenes`]): a process that renders one scene needs one; the tests and the
/// explorer go from scene to scene, and a parse is cheap beside the driver's build.
pub(super) const MAX_PARSED: usize = 4;

impl Kernel {
    /// The buffer holding `data` on the device, uploaded at its first use and kept for the
    /// next runs ([`INPUTS_KEPT`] of them); sixteen bytes of zeros for None, where the kernel
    /// reads nothing of it.
    pub fn input_buffer(&self, data: &InputData) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        let mut inputs = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
        let source = input_source(data);
        if let Some((_, buffer)) = inputs.iter().find(|(d, _)| input_source(d) == source) {
            return buffer.clone();
        }
        let placeholder = [0.0f32; 4];
        let contents: &[f32] = data.as_ref().map_or(&placeholder, |d| &d.packed);
        let buffer = self
            .ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("input"),
                contents: bytemuck::cast_slice(contents),
                usage: wgpu::BufferUsages::STORAGE,
            });
        // The oldest map goes past INPUTS_KEPT of them; a placeholder costs nothing and stays.
        let maps = inputs.iter().filter(|(d, _)| d.is_some()).count();
        if data.is_some()
            && maps >= INPUTS_KEPT
            && let Some(oldest) = inputs.iter().position(|(d, _)| d.is_some())
        {
            inputs.remove(oldest);
        }
        inputs.push((data.clone(), buffer.clone()));
        buffer
    }
}

/// A shader module of the kernel's, from WGSL or from a specialised naga module.
fn create_module(
    device: &wgpu::Device,
    spec: &KernelSpec,
    source: wgpu::ShaderSource,
) -> wgpu::ShaderModule {
    let descriptor = wgpu::ShaderModuleDescriptor {
        label: Some(spec.module.name),
        source,
    };
    if spec.trusted {
        // SAFETY: a trusted kernel bounds every loop by its uniform's counts and checks
        // every index against the grid before it writes (KernelSpec::trusted), so wgpu's
        // injected bounds checks and loop bounding would only repeat its own.
        unsafe {
            device.create_shader_module_trusted(descriptor, wgpu::ShaderRuntimeChecks::unchecked())
        }
    } else {
        device.create_shader_module(descriptor)
    }
}

fn buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::shaders::ALL_MODULES;

    /// A baked pipeline reads at run time exactly the members a dispatch sets (the uniforms'
    /// per-dispatch fields), and the path sampler's seed, which animation frames change.
    #[test]
    fn baked_pipelines_keep_the_per_dispatch_members() {
        use crate::gpu::params::{GpuJulia2dParams, GpuJulia2dParams64, GpuParams, GpuParams64};
        let per_dispatch = |layout: crate::uniform::Layout| -> Vec<&str> {
            let fields = layout.fields.iter().filter(|f| f.per_dispatch);
            fields.map(|f| f.name).collect()
        };
        for layout in [GpuParams::LAYOUT, GpuParams64::LAYOUT] {
            let mut keeps = per_dispatch(layout);
            keeps.push("seed");
            assert_eq!(keeps, TRACE_BAKE_KEEPS);
        }
        let path = crate::gpu::path::GpuPathParams::LAYOUT;
        assert!(path.field("seed").is_some() && per_dispatch(path).is_empty());
        for layout in [GpuJulia2dParams::LAYOUT, GpuJulia2dParams64::LAYOUT] {
            assert_eq!(per_dispatch(layout), JULIA2D_BAKE_KEEPS);
        }
    }

    /// Every kernel's `@workgroup_size` is [`WORKGROUP_SIZE`]: the runner dispatches by it, the
    /// cone tracer shares one march per workgroup block, and the divergence statistics count
    /// the lanes of one workgroup (`stats::DIVERGENCE_BLOCK`).
    #[test]
    fn every_kernel_has_the_workgroup_size_the_runner_dispatches() {
        for m in ALL_MODULES {
            let module = crate::gpu::shaders::validate_wgsl(&m.source()).expect(m.name);
            assert!(
                !module.entry_points.is_empty(),
                "{}: no entry point",
                m.name
            );
            for entry in &module.entry_points {
                assert_eq!(
                    entry.workgroup_size,
                    [WORKGROUP_SIZE.0, WORKGROUP_SIZE.1, 1],
                    "{} {}",
                    m.name,
                    entry.name
                );
            }
        }
        let cone = crate::cpu::trace::CONE_BLOCK;
        assert_eq!((cone, cone), WORKGROUP_SIZE, "a cone block is a workgroup");
    }
}
