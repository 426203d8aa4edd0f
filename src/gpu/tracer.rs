//! The tracer kernel on the GPU: pipeline built once, then any number of renders, each traced in
//! bands of rows (bounded memory and bounded time per dispatch) and read back to host memory.

use std::collections::HashMap;
use std::sync::{Mutex, mpsc};
use std::time::Instant;

use wgpu::util::DeviceExt;

use super::GpuContext;
use super::params::GpuParams;
use super::shaders::TRACE_MODULE;
use super::variant::Variant;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::params::TraceParams;

/// The kernel's `@workgroup_size`: 8 wide, since lavapipe packs 8 lanes along x.
pub const WORKGROUP: (u32, u32) = (8, 8);
/// Bytes per pixel per output array (colour u32, depth f32, steps u32).
const BYTES_PER_PIXEL: u64 = 4;
/// Output arrays: colour, depth, steps.
pub const OUTPUTS: usize = 3;

/// The compute pipelines of shaders/trace.wgsl on one device: a generic one, and one per
/// scene [`Variant`] built on first use and cached.
pub struct GpuTracer {
    ctx: GpuContext,
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    layout: wgpu::BindGroupLayout,
    pipelines: Mutex<HashMap<Option<Variant>, wgpu::ComputePipeline>>,
    specialise: bool,
}

/// A GPU render: the frame and how long it took.
pub struct GpuRender {
    pub frame: Frame,
    /// From the first timed dispatch to the image in host memory.
    pub render_seconds: f64,
    /// The dispatches' GPU time by timestamp queries, where the device has them.
    pub gpu_seconds: Option<f64>,
}

/// Device-side buffers for one band of rows, reused across bands.
struct BandBuffers {
    uniform: wgpu::Buffer,
    storage: [wgpu::Buffer; OUTPUTS],
    readback: [wgpu::Buffer; OUTPUTS],
    bind_group: wgpu::BindGroup,
    timestamps: Option<Timestamps>,
}

struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl GpuTracer {
    /// Builds the pipeline; a shader the device rejects is an error, not a panic.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        let device = &ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(TRACE_MODULE.name),
            source: wgpu::ShaderSource::Wgsl(TRACE_MODULE.source().into()),
        });
        let storage_entry = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trace"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(size_of::<GpuParams>() as u64),
                    },
                    count: None,
                },
                storage_entry(1),
                storage_entry(2),
                storage_entry(3),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("trace"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!("the trace shader was rejected: {e}")));
        }
        let tracer = Self {
            ctx,
            module,
            pipeline_layout,
            layout,
            pipelines: Mutex::new(HashMap::new()),
            // QJULIA_SPECIALISE=0 runs every scene on the generic pipeline (to measure the gain).
            specialise: std::env::var_os("QJULIA_SPECIALISE").is_none_or(|v| v != "0"),
        };
        tracer.pipeline(None)?;
        Ok(tracer)
    }

    /// Whether scenes get their own specialised pipelines.
    pub fn set_specialise(&mut self, on: bool) {
        self.specialise = on;
    }

    /// The variant a scene runs on here: its own, or None (the generic pipeline) when
    /// specialisation is off.
    pub fn variant_for(&self, params: &TraceParams<f32>, shade: bool) -> Option<Variant> {
        self.specialise.then(|| Variant::of(params, shade))
    }

    /// The pipeline of a variant (None: generic), built on first use and cached.
    pub fn pipeline(&self, variant: Option<Variant>) -> Result<wgpu::ComputePipeline> {
        let mut cache = self.pipelines.lock().expect("pipeline cache");
        if let Some(p) = cache.get(&variant) {
            return Ok(p.clone());
        }
        let device = &self.ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let constants = variant.map(|v| v.constants()).unwrap_or_default();
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("trace"),
            layout: Some(&self.pipeline_layout),
            module: &self.module,
            entry_point: Some("main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            },
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!(
                "the trace pipeline {variant:?} was rejected: {e}"
            )));
        }
        cache.insert(variant, pipeline.clone());
        Ok(pipeline)
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Rows per dispatch for an image this wide: at most `band_pixels()` pixels (bounded memory,
    /// and bounded time per dispatch so that no driver watchdog fires on big images).
    fn band_rows(&self, width: u32, height: u32) -> u32 {
        let limit = self.ctx.device.limits();
        let max_binding = limit.max_storage_buffer_binding_size / BYTES_PER_PIXEL;
        let pixels = crate::band_pixels()
            .min(max_binding)
            .min(limit.max_buffer_size / BYTES_PER_PIXEL);
        // Whole workgroup rows, so that every band starts on a block row (cone tracing).
        let rows = ((pixels / width as u64) as u32 / WORKGROUP.1 * WORKGROUP.1).max(WORKGROUP.1);
        let max_groups = limit.max_compute_workgroups_per_dimension;
        rows.min(height).min(max_groups.saturating_mul(WORKGROUP.1))
    }

    /// Binds a uniform buffer (a [`GpuParams`]) and the colour, depth and steps arrays.
    pub fn create_bind_group(
        &self,
        uniform: &wgpu::Buffer,
        outputs: [&wgpu::Buffer; OUTPUTS],
    ) -> wgpu::BindGroup {
        super::output_bind_group(&self.ctx.device, ("trace", &self.layout), uniform, outputs)
    }

    /// Records one compute pass tracing `rows` rows of `width` pixels with the bound parameters.
    pub fn encode_band(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        (width, rows): (u32, u32),
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("trace"),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(width.div_ceil(WORKGROUP.0), rows.div_ceil(WORKGROUP.1), 1);
    }

    fn band_buffers(&self, band_pixels: u64) -> BandBuffers {
        let device = &self.ctx.device;
        let size = band_pixels * BYTES_PER_PIXEL;
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: size_of::<GpuParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (storage, readback) = super::output_buffers(device, size);
        let bind_group = self.create_bind_group(&uniform, [&storage[0], &storage[1], &storage[2]]);
        let timestamps = self.ctx.has_timestamps().then(|| Timestamps {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("trace time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("timestamps"),
                contents: &[0; 16],
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            }),
            readback: make_small(device, "timestamps readback"),
        });
        BandBuffers {
            uniform,
            storage,
            readback,
            bind_group,
            timestamps,
        }
    }

    /// Traces every pixel, band by band, after an untimed warm-up dispatch (lavapipe compiles
    /// the kernel at its first dispatch, not at pipeline creation).
    pub fn render(&self, params: &TraceParams<f32>) -> Result<GpuRender> {
        self.render_outputs(params, true)
    }

    /// As [`Self::render`]; with `shade` false only depth and steps are computed (the colour is
    /// the background), on a pipeline without the shading code.
    pub fn render_outputs(&self, params: &TraceParams<f32>, shade: bool) -> Result<GpuRender> {
        let mut frame = Frame {
            width: params.width,
            height: 0,
            colour: Vec::new(),
            depth: Vec::new(),
            steps: Vec::new(),
            non_finite: 0,
        };
        let (render_seconds, gpu_seconds) = self.render_bands(params, shade, &mut |band| {
            frame.append(&band);
            Ok(())
        })?;
        Ok(GpuRender {
            frame,
            render_seconds,
            gpu_seconds,
        })
    }

    /// Renders band by band (bounded memory and bounded time per dispatch, whatever the image
    /// size), handing each band of whole rows, top to bottom, to `sink` as a frame of its own.
    /// Returns the seconds spent rendering (the sink's time left out) and the GPU seconds.
    pub fn render_bands(
        &self,
        params: &TraceParams<f32>,
        shade: bool,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)> {
        let pipeline = self.pipeline(self.variant_for(params, shade))?;
        let (width, height) = (params.width, params.height);
        let band_rows = self.band_rows(width, height);
        let buffers = self.band_buffers(band_rows as u64 * width as u64);

        // Warm-up: one workgroup of the first band, same pipeline, results discarded.
        let warm_rows = band_rows.min(WORKGROUP.1);
        let warm = GpuParams::new(params, 0, warm_rows);
        self.dispatch(
            &pipeline,
            &buffers,
            &warm,
            (width.min(WORKGROUP.0), warm_rows),
            None,
        )?;

        let mut render_seconds = 0.0;
        let mut gpu_seconds = buffers.timestamps.as_ref().map(|_| 0.0);
        let mut row = 0;
        while row < height {
            let start = Instant::now();
            let rows = band_rows.min(height - row);
            let pixels = width as usize * rows as usize;
            let mut frame = Frame {
                width,
                height: rows,
                colour: Vec::with_capacity(pixels),
                depth: Vec::with_capacity(pixels),
                steps: Vec::with_capacity(pixels),
                non_finite: 0,
            };
            let band = GpuParams::new(params, row, rows);
            let seconds = self.dispatch(
                &pipeline,
                &buffers,
                &band,
                (width, rows),
                Some((&mut frame, rows)),
            )?;
            if let (Some(total), Some(s)) = (gpu_seconds.as_mut(), seconds) {
                *total += s;
            }
            render_seconds += start.elapsed().as_secs_f64();
            sink(frame)?;
            row += rows;
        }
        Ok((render_seconds, gpu_seconds))
    }

    /// One band of `size` (width, rows) pixels: upload its parameters, dispatch, copy out and
    /// wait. With `out`, appends the band's `rows` rows to the frame. Returns the GPU seconds
    /// where timestamps are on.
    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        buffers: &BandBuffers,
        band: &GpuParams,
        size: (u32, u32),
        out: Option<(&mut Frame, u32)>,
    ) -> Result<Option<f64>> {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        queue.write_buffer(&buffers.uniform, 0, bytemuck::bytes_of(band));
        let mut encoder = device.create_command_encoder(&Default::default());
        let timestamp_writes =
            buffers
                .timestamps
                .as_ref()
                .map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.queries,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                });
        self.encode_band(
            &mut encoder,
            pipeline,
            &buffers.bind_group,
            size,
            timestamp_writes,
        );
        let bytes = out.as_ref().map_or(0, |(_, rows)| {
            *rows as u64 * band.width as u64 * BYTES_PER_PIXEL
        });
        if bytes > 0 {
            for (src, dst) in buffers.storage.iter().zip(&buffers.readback) {
                encoder.copy_buffer_to_buffer(src, 0, dst, 0, bytes);
            }
        }
        if let Some(t) = &buffers.timestamps {
            encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, 16);
        }
        queue.submit([encoder.finish()]);

        let mut to_map: Vec<(&wgpu::Buffer, u64)> = Vec::new();
        if bytes > 0 {
            to_map.extend(buffers.readback.iter().map(|b| (b, bytes)));
        }
        if let Some(t) = &buffers.timestamps {
            to_map.push((&t.readback, 16));
        }
        self.map_all(&to_map)?;

        if let Some((frame, _)) = out {
            let view = |i: usize| buffers.readback[i].slice(..bytes).get_mapped_range();
            let mapped = [view(0), view(1), view(2)];
            let mapped: Vec<_> = mapped
                .into_iter()
                .collect::<Result<_, _>>()
                .map_err(|e| Error::Gpu(format!("reading back the image: {e}")))?;
            frame
                .colour
                .extend_from_slice(bytemuck::cast_slice(&mapped[0]));
            let depths = bytemuck::cast_slice::<u8, f32>(&mapped[1]);
            frame.non_finite += depths.iter().filter(|d| !d.is_finite()).count() as u64;
            frame
                .depth
                .extend(depths.iter().map(|&d| if d < 0.0 { f32::NAN } else { d }));
            frame
                .steps
                .extend_from_slice(bytemuck::cast_slice(&mapped[2]));
        }
        let seconds = match &buffers.timestamps {
            Some(t) => {
                let view = t
                    .readback
                    .slice(..16)
                    .get_mapped_range()
                    .map_err(|e| Error::Gpu(format!("reading timestamps: {e}")))?;
                let stamps: &[u64] = bytemuck::cast_slice(&view);
                let ticks = stamps[1].saturating_sub(stamps[0]);
                Some(ticks as f64 * queue.get_timestamp_period() as f64 * 1e-9)
            }
            None => None,
        };
        for (buffer, _) in to_map {
            buffer.unmap();
        }
        Ok(seconds)
    }

    /// Maps the buffers for reading and waits until all are mapped.
    fn map_all(&self, buffers: &[(&wgpu::Buffer, u64)]) -> Result<()> {
        let (sender, receiver) = mpsc::channel();
        for (buffer, bytes) in buffers {
            let sender = sender.clone();
            buffer
                .slice(..*bytes)
                .map_async(wgpu::MapMode::Read, move |r| drop(sender.send(r)));
        }
        self.ctx
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu(format!("waiting for the GPU: {e}")))?;
        for _ in buffers {
            receiver
                .recv()
                .map_err(|_| Error::Gpu("the device was lost".into()))?
                .map_err(|e| Error::Gpu(format!("mapping a result buffer: {e}")))?;
        }
        Ok(())
    }
}

fn make_small(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
