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

use std::collections::HashMap;
use std::sync::{Mutex, mpsc};
use std::time::{Duration, Instant};

use super::GpuContext;
use super::shaders::ShaderModuleSource;
use crate::error::{Error, Result};

/// Invocations per workgroup in x and y, in every kernel's `@workgroup_size`: 8 wide, since
/// lavapipe packs 8 lanes along x. A test checks each shader against it.
pub const WORKGROUP_SIZE: (u32, u32) = (8, 8);

/// Override constants as a hash key (the values' bits).
type ConstantsKey = Vec<(&'static str, u64)>;

fn constants_key(constants: &[(&'static str, f64)]) -> ConstantsKey {
    constants.iter().map(|&(n, v)| (n, v.to_bits())).collect()
}

/// One storage array a kernel writes: binding 1 + its index in [`KernelSpec::outputs`].
#[derive(Clone, Copy, Debug)]
pub struct OutputSpec {
    pub name: &'static str,
    /// Bytes each grid item takes in it.
    pub bytes_per_item: u64,
}

/// What a compute kernel is: its module, entry point, uniform size and outputs. Binding 0 is the
/// uniform; bindings 1.. are the outputs, in order.
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
    /// Pipelines by their constants, and whether each has run once (warmed up).
    pipelines: Mutex<HashMap<ConstantsKey, (wgpu::ComputePipeline, bool)>>,
    /// The last run's buffers, kept for the next run of the same band size and readback (an
    /// animation's frames, the explorer's views): allocating and clearing them anew each time
    /// costs more than a fast GPU's whole render (a 4 Mpixel band is 128 MiB of outputs).
    spare: Mutex<Vec<RunBuffers>>,
}

/// Steps a stream keeps on the device at once on a GPU: one being read back, one running.
const STEPS_IN_FLIGHT: usize = 2;

/// One band of a stream ([`Kernel::run_stream`]): its pipeline's constants, the grid's width,
/// its rows, the uniform of each of its dispatches and the outputs to read back.
pub struct Step {
    pub constants: Vec<(&'static str, f64)>,
    pub width: u32,
    /// The grid's rows: the step with `row + rows == height` is its last band.
    pub height: u32,
    pub row: u32,
    pub rows: u32,
    /// The grid's rows per band (the buffers are sized for it; the last band may be shorter).
    pub band_rows: u32,
    pub uniforms: Vec<Vec<u8>>,
    pub read: Vec<bool>,
}

/// A step done: what `decode` made of it, when it was submitted and decoded, and its GPU time
/// (timestamp queries, where the device has them).
pub struct StepDone<T> {
    pub made: T,
    pub submitted: Instant,
    pub decoded: Instant,
    pub gpu_seconds: Option<f64>,
}

type MapResult = std::result::Result<(), wgpu::BufferAsyncError>;

/// A step submitted and not yet read back.
struct InFlight {
    step: Step,
    buffers: RunBuffers,
    submitted: Instant,
    index: wgpu::SubmissionIndex,
    mapped: Vec<mpsc::Receiver<MapResult>>,
}

/// Device-side buffers of one band, reused across bands, runs and frames.
struct RunBuffers {
    /// Items they hold.
    items: u64,
    /// Which outputs have readback buffers.
    read: Vec<bool>,
    uniform: wgpu::Buffer,
    storage: Vec<wgpu::Buffer>,
    /// Readback copies of the outputs asked for.
    readback: Vec<Option<wgpu::Buffer>>,
    bind_group: wgpu::BindGroup,
    timestamps: Option<Timestamps>,
}

struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl RunBuffers {
    /// Whether these buffers serve a band of `items` reading back `read` (larger ones would
    /// do, but a step of another size is another grid: allocate it its own).
    fn fits(&self, items: u64, read: &[bool]) -> bool {
        self.items == items && self.read == read
    }
}

/// Bytes of the two timestamps a band writes.
const TIMESTAMP_BYTES: u64 = 16;

impl Kernel {
    /// Builds the module and layouts; a shader the device rejects is an error, not a panic.
    pub fn new(ctx: GpuContext, spec: KernelSpec) -> Result<Self> {
        let device = &ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let descriptor = wgpu::ShaderModuleDescriptor {
            label: Some(spec.module.name),
            source: wgpu::ShaderSource::Wgsl(spec.module.source().into()),
        };
        let module = if spec.trusted {
            // SAFETY: a trusted kernel bounds every loop by its uniform's counts and checks
            // every index against the grid before it writes (KernelSpec::trusted), so wgpu's
            // injected bounds checks and loop bounding would only repeat its own.
            unsafe {
                device.create_shader_module_trusted(
                    descriptor,
                    wgpu::ShaderRuntimeChecks::unchecked(),
                )
            }
        } else {
            device.create_shader_module(descriptor)
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
        let entries: Vec<_> = std::iter::once(entry(
            0,
            wgpu::BufferBindingType::Uniform,
            wgpu::BufferSize::new(spec.uniform_bytes),
        ))
        .chain((1..=spec.outputs.len() as u32).map(|b| entry(b, storage, None)))
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
            pipelines: Mutex::new(HashMap::new()),
            spare: Mutex::new(Vec::new()),
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    pub fn spec(&self) -> &KernelSpec {
        &self.spec
    }

    /// The pipeline for these override constants (empty: generic), built on first use and
    /// cached.
    pub fn pipeline(&self, constants: &[(&'static str, f64)]) -> Result<wgpu::ComputePipeline> {
        let key = constants_key(constants);
        let mut cache = self.pipelines.lock().expect("pipeline cache");
        if let Some((p, _)) = cache.get(&key) {
            return Ok(p.clone());
        }
        let device = &self.ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(self.spec.name),
            layout: Some(&self.pipeline_layout),
            module: &self.module,
            entry_point: Some(self.spec.entry_point),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            },
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!(
                "the {} pipeline {constants:?} was rejected: {e}",
                self.spec.name
            )));
        }
        cache.insert(key, (pipeline.clone(), false));
        Ok(pipeline)
    }

    /// A uniform buffer for this kernel's params.
    pub fn uniform_buffer(&self, label: &str) -> wgpu::Buffer {
        self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: self.spec.uniform_bytes,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Storage buffers for the outputs, `items` each, usable as copy sources (for readback or
    /// a texture).
    pub fn output_buffers(&self, items: u64, label: &str) -> Vec<wgpu::Buffer> {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        self.spec
            .outputs
            .iter()
            .map(|o| {
                buffer(
                    &self.ctx.device,
                    &format!("{label} {}", o.name),
                    items * o.bytes_per_item,
                    usage,
                )
            })
            .collect()
    }

    /// Binds a uniform buffer (binding 0) and the output arrays (bindings 1..).
    pub fn bind_group(&self, uniform: &wgpu::Buffer, outputs: &[wgpu::Buffer]) -> wgpu::BindGroup {
        assert_eq!(
            outputs.len(),
            self.spec.outputs.len(),
            "one buffer per output"
        );
        let entries: Vec<_> = std::iter::once(uniform)
            .chain(outputs)
            .enumerate()
            .map(|(binding, b)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        self.ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(self.spec.name),
                layout: &self.layout,
                entries: &entries,
            })
    }

    /// Records one compute pass over `width` x `rows` items with the bound parameters.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        (width, rows): (u32, u32),
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.spec.name),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(
            width.div_ceil(WORKGROUP_SIZE.0),
            rows.div_ceil(WORKGROUP_SIZE.1),
            1,
        );
    }

    /// Rows per band for a grid this wide: at most `band_pixels()` items (bounded memory, and
    /// bounded time per dispatch so that no driver watchdog fires on big grids), within the
    /// device's buffer and dispatch limits, a multiple of `band_row_multiple`.
    pub fn band_rows(&self, width: u32, height: u32) -> u32 {
        let limit = self.ctx.device.limits();
        let widest = self
            .spec
            .outputs
            .iter()
            .map(|o| o.bytes_per_item)
            .max()
            .unwrap_or(1);
        let items = crate::band_pixels()
            .min(limit.max_storage_buffer_binding_size / widest)
            .min(limit.max_buffer_size / widest);
        let multiple = self.spec.band_row_multiple.max(1);
        let rows = ((items / width.max(1) as u64) as u32 / multiple * multiple).max(multiple);
        let max_groups = limit.max_compute_workgroups_per_dimension;
        rows.min(height)
            .min(max_groups.saturating_mul(WORKGROUP_SIZE.1))
    }

    /// Runs the kernel over the whole grid, band by band, top to bottom. Each band's outputs
    /// are handed to `decode` (timed) and what it makes to `sink` (not timed). The first use of
    /// a pipeline is preceded by an untimed warm-up dispatch of one workgroup (lavapipe compiles
    /// a kernel at its first dispatch, not at pipeline creation). The bands are pipelined as in
    /// [`Self::run_stream`].
    pub fn run<T>(
        &self,
        run: &Run<'_>,
        mut decode: impl FnMut(BandOutput<'_>) -> T,
        mut sink: impl FnMut(T) -> Result<()>,
    ) -> Result<RunTimes> {
        assert_eq!(
            run.read.len(),
            self.spec.outputs.len(),
            "read: one flag per output"
        );
        let mut steps = self.steps(run);
        let mut times = RunTimes::default();
        let mut first_submitted = None;
        // The sink's time is left out, though the device may have run the next band meanwhile.
        let mut in_sink = Duration::ZERO;
        self.run_stream(
            &mut steps,
            |_, out| decode(out),
            |_, done| {
                let start = *first_submitted.get_or_insert(done.submitted);
                times.seconds = (done.decoded - start).saturating_sub(in_sink).as_secs_f64();
                times.gpu_seconds = done
                    .gpu_seconds
                    .map(|s| s + times.gpu_seconds.unwrap_or(0.0));
                let sink_start = Instant::now();
                let sunk = sink(done.made);
                in_sink += sink_start.elapsed();
                sunk
            },
        )?;
        Ok(times)
    }

    /// The bands of a run as [`Step`]s, each with its dispatches' uniforms.
    pub fn steps<'r>(&self, run: &'r Run<'_>) -> impl Iterator<Item = Step> + 'r {
        let (width, height) = run.size;
        let band_rows = self.band_rows(width, height).max(1);
        let dispatches = run.dispatches_per_band.max(1);
        let constants = run.constants.to_vec();
        let read = run.read.to_vec();
        (0..height).step_by(band_rows as usize).map(move |row| {
            let rows = band_rows.min(height - row);
            Step {
                constants: constants.clone(),
                width,
                height,
                row,
                rows,
                band_rows,
                read: read.clone(),
                uniforms: (0..dispatches)
                    .map(|dispatch| {
                        (run.params)(Band {
                            row,
                            rows,
                            dispatch,
                        })
                    })
                    .collect(),
            }
        })
    }

    /// Runs a stream of bands (of one grid or of many: an animation's frames), two at a time:
    /// while the host waits for, reads back and decodes one band, the device already runs the
    /// next, so a fast GPU is not left idle between frames. Each step's outputs go to `decode`
    /// and then, with its times, to `sink`, in the order of the steps. Memory stays bounded:
    /// two sets of buffers, each of one band.
    pub fn run_stream<T>(
        &self,
        steps: &mut dyn Iterator<Item = Step>,
        mut decode: impl FnMut(&Step, BandOutput<'_>) -> T,
        mut sink: impl FnMut(Step, StepDone<T>) -> Result<()>,
    ) -> Result<()> {
        let mut free: Vec<RunBuffers> = self
            .spare
            .lock()
            .expect("spare buffers")
            .drain(..)
            .collect();
        let mut in_flight: std::collections::VecDeque<InFlight> = Default::default();
        let mut finish_oldest = |in_flight: &mut std::collections::VecDeque<InFlight>,
                                 free: &mut Vec<RunBuffers>|
         -> Result<()> {
            let flight = in_flight.pop_front().expect("a step in flight");
            let (step, done, buffers) = self.finish(flight, &mut decode)?;
            free.push(buffers);
            sink(step, done)
        };
        let depth = self.steps_in_flight();
        for step in steps {
            assert_eq!(
                step.read.len(),
                self.spec.outputs.len(),
                "one flag per output"
            );
            if in_flight.len() == depth {
                finish_oldest(&mut in_flight, &mut free)?;
            }
            let items = step.band_rows as u64 * step.width as u64;
            let buffers = match free.iter().position(|b| b.fits(items, &step.read)) {
                Some(k) => free.swap_remove(k),
                None => self.run_buffers(items, &step.read),
            };
            in_flight.push_back(self.submit(step, buffers)?);
        }
        while !in_flight.is_empty() {
            finish_oldest(&mut in_flight, &mut free)?;
        }
        free.truncate(STEPS_IN_FLIGHT);
        *self.spare.lock().expect("spare buffers") = free;
        Ok(())
    }

    /// Steps in flight on this device: [`STEPS_IN_FLIGHT`] on a GPU; one on a CPU adapter
    /// (lavapipe, llvmpipe), whose "device" is the host's own cores: there the host's work on
    /// one band would only take cores from the next, and lavapipe's threads, which wait for
    /// each other within a dispatch, lose more than the overlap gains (measured: docs/PERFORMANCE.md).
    /// `QJULIA_STEPS_IN_FLIGHT` (1 or 2) overrides it, to measure.
    pub fn steps_in_flight(&self) -> usize {
        let default = match self.ctx.info.device_type {
            wgpu::DeviceType::Cpu => 1,
            _ => STEPS_IN_FLIGHT,
        };
        std::env::var("QJULIA_STEPS_IN_FLIGHT")
            .ok()
            .and_then(|v| v.parse::<usize>().ok())
            .map_or(default, |n| n.clamp(1, STEPS_IN_FLIGHT))
    }

    /// Submits a step's dispatches and the copies of its outputs, and asks for them to be
    /// mapped; does not wait. A pipeline's first use is warmed up first, untimed.
    fn submit(&self, step: Step, buffers: RunBuffers) -> Result<InFlight> {
        let pipeline = self.pipeline(&step.constants)?;
        if !self.warmed(&step.constants) {
            let rows = step.rows.min(WORKGROUP_SIZE.1);
            let size = (step.width.min(WORKGROUP_SIZE.0), rows);
            for uniform in &step.uniforms {
                // The warm-up's uniform is the band's own: only its first rows run.
                self.dispatch(&pipeline, &buffers, uniform, size, None)?;
            }
            self.ctx
                .device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Gpu(format!("waiting for the GPU: {e}")))?;
        }
        let submitted = Instant::now();
        let dispatches = step.uniforms.len();
        for (dispatch, uniform) in step.uniforms.iter().enumerate() {
            // The band's time: from the start of its first dispatch to the end of its last.
            let (first, last) = (dispatch == 0, dispatch + 1 == dispatches);
            let timestamps = buffers
                .timestamps
                .as_ref()
                .filter(|_| first || last)
                .map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.queries,
                    beginning_of_pass_write_index: first.then_some(0),
                    end_of_pass_write_index: last.then_some(1),
                });
            self.dispatch(
                &pipeline,
                &buffers,
                uniform,
                (step.width, step.rows),
                timestamps,
            )?;
        }
        let items = step.rows as u64 * step.width as u64;
        let (index, mapped) = self.copy_out(&buffers, items);
        Ok(InFlight {
            step,
            buffers,
            submitted,
            index,
            mapped,
        })
    }

    /// Waits for a step's outputs, decodes them and frees its buffers for the next step.
    fn finish<T>(
        &self,
        flight: InFlight,
        decode: &mut impl FnMut(&Step, BandOutput<'_>) -> T,
    ) -> Result<(Step, StepDone<T>, RunBuffers)> {
        let InFlight {
            step,
            buffers,
            submitted,
            index,
            mapped,
        } = flight;
        self.ctx
            .device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            })
            .map_err(|e| Error::Gpu(format!("waiting for the GPU: {e}")))?;
        for result in mapped {
            result
                .recv()
                .map_err(|_| Error::Gpu("the device was lost".into()))?
                .map_err(|e| Error::Gpu(format!("mapping a result buffer: {e}")))?;
        }
        let items = step.rows as u64 * step.width as u64;
        let made = {
            let views = self.read_mapped(&buffers, items)?;
            let slices: Vec<Option<&[u8]>> = views.iter().map(|m| m.as_deref()).collect();
            let output = BandOutput {
                row: step.row,
                rows: step.rows,
                outputs: &slices,
            };
            decode(&step, output)
        };
        let gpu_seconds = match &buffers.timestamps {
            Some(t) => Some(self.read_timestamps(t)?),
            None => None,
        };
        self.unmap(&buffers);
        let done = StepDone {
            made,
            submitted,
            decoded: Instant::now(),
            gpu_seconds,
        };
        Ok((step, done, buffers))
    }

    /// Whether the pipeline of these constants has run once; marks it so.
    fn warmed(&self, constants: &[(&'static str, f64)]) -> bool {
        let key = constants_key(constants);
        let mut cache = self.pipelines.lock().expect("pipeline cache");
        let entry = cache.get_mut(&key).expect("built before it runs");
        std::mem::replace(&mut entry.1, true)
    }

    fn run_buffers(&self, items: u64, read: &[bool]) -> RunBuffers {
        let device = &self.ctx.device;
        let uniform = self.uniform_buffer(&format!("{} params", self.spec.name));
        let storage = self.output_buffers(items, self.spec.name);
        let read_usage = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let readback = self
            .spec
            .outputs
            .iter()
            .zip(read)
            .map(|(o, &wanted)| {
                let label = format!("{} {} readback", self.spec.name, o.name);
                wanted.then(|| buffer(device, &label, items * o.bytes_per_item, read_usage))
            })
            .collect();
        let bind_group = self.bind_group(&uniform, &storage);
        let timestamps = self.ctx.has_timestamps().then(|| Timestamps {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("kernel time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer(
                device,
                "timestamps",
                TIMESTAMP_BYTES,
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(device, "timestamps readback", TIMESTAMP_BYTES, read_usage),
        });
        RunBuffers {
            items,
            read: read.to_vec(),
            uniform,
            storage,
            readback,
            bind_group,
            timestamps,
        }
    }

    /// Uploads one dispatch's params and submits it.
    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        buffers: &RunBuffers,
        params: &[u8],
        size: (u32, u32),
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<()> {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        queue.write_buffer(&buffers.uniform, 0, params);
        let mut encoder = device.create_command_encoder(&Default::default());
        self.encode(
            &mut encoder,
            pipeline,
            &buffers.bind_group,
            size,
            timestamps,
        );
        queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Copies the band's outputs asked for (and its timestamps) to the readback buffers and asks
    /// for them to be mapped: the submission to wait for, and one report per buffer mapped.
    fn copy_out(
        &self,
        buffers: &RunBuffers,
        items: u64,
    ) -> (wgpu::SubmissionIndex, Vec<mpsc::Receiver<MapResult>>) {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        let mut encoder = device.create_command_encoder(&Default::default());
        let mut to_map: Vec<(&wgpu::Buffer, u64)> = Vec::new();
        for ((src, dst), spec) in buffers
            .storage
            .iter()
            .zip(&buffers.readback)
            .zip(self.spec.outputs)
        {
            let bytes = items * spec.bytes_per_item;
            if let Some(dst) = dst
                && bytes > 0
            {
                encoder.copy_buffer_to_buffer(src, 0, dst, 0, bytes);
                to_map.push((dst, bytes));
            }
        }
        if let Some(t) = &buffers.timestamps {
            encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, TIMESTAMP_BYTES);
            to_map.push((&t.readback, TIMESTAMP_BYTES));
        }
        let index = queue.submit([encoder.finish()]);
        let mapped = to_map
            .into_iter()
            .map(|(buffer, bytes)| {
                let (sender, receiver) = mpsc::channel();
                buffer
                    .slice(..bytes)
                    .map_async(wgpu::MapMode::Read, move |r| drop(sender.send(r)));
                receiver
            })
            .collect();
        (index, mapped)
    }

    /// The mapped bytes of each output asked for.
    fn read_mapped(
        &self,
        buffers: &RunBuffers,
        items: u64,
    ) -> Result<Vec<Option<wgpu::BufferView>>> {
        buffers
            .readback
            .iter()
            .zip(self.spec.outputs)
            .map(|(b, spec)| {
                let bytes = items * spec.bytes_per_item;
                match b {
                    Some(b) if bytes > 0 => b
                        .slice(..bytes)
                        .get_mapped_range()
                        .map(Some)
                        .map_err(|e| Error::Gpu(format!("reading back the image: {e}"))),
                    _ => Ok(None),
                }
            })
            .collect()
    }

    /// Seconds between the band's two timestamps.
    fn read_timestamps(&self, t: &Timestamps) -> Result<f64> {
        let view = t
            .readback
            .slice(..TIMESTAMP_BYTES)
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("reading timestamps: {e}")))?;
        let stamps: &[u64] = bytemuck::cast_slice(&view);
        let ticks = stamps[1].saturating_sub(stamps[0]);
        Ok(ticks as f64 * self.ctx.queue.get_timestamp_period() as f64 * 1e-9)
    }

    fn unmap(&self, buffers: &RunBuffers) {
        for b in buffers.readback.iter().flatten() {
            b.unmap();
        }
        if let Some(t) = &buffers.timestamps {
            t.readback.unmap();
        }
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
