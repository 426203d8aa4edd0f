//! The 2D Julia view on the GPU (shaders/julia2d.wgsl): its own pipeline, its `#[repr(C)]`
//! uniform, banded dispatch and readback for `qjulia render2d`, and the pieces the explorer uses
//! to draw into a texture.

use std::sync::mpsc;
use std::time::Instant;

use bytemuck::{Pod, Zeroable};

use super::GpuContext;
use super::shaders::JULIA2D_MODULE;
use super::{OUTPUTS, WORKGROUP};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::params::Julia2dParams;

/// Bytes per pixel per output array (colour u32, in-set marker f32, iterations u32).
const BYTES_PER_PIXEL: u64 = 4;

/// Keep in sync with `struct Julia2dParams` in shaders/julia2d.wgsl: same fields, same order.
/// The tests compare this layout with the one naga computes for the shader.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuJulia2dParams {
    pub c: [f32; 2],
    pub center: [f32; 2],
    pub half_extent: [f32; 2],
    pub max_iterations: u32,
    pub width: u32,
    pub height: u32,
    /// The band of rows this dispatch computes: [row_offset, row_offset + row_count).
    pub row_offset: u32,
    pub row_count: u32,
    /// Pixels per row of the output arrays (>= width; a multiple of 64 where the rows are
    /// copied into a texture).
    pub row_stride: u32,
    /// The output row that the band's first row lands in.
    pub out_row: u32,
    /// Fills the struct to WGSL's size (a multiple of its 8-byte alignment).
    pub pad: u32,
}

impl GpuJulia2dParams {
    /// The f32 parameters for a band of rows, written at the start of a band-sized output.
    pub fn new(p: &Julia2dParams<f32>, row_offset: u32, row_count: u32) -> Self {
        Self {
            c: [p.c.x, p.c.y],
            center: [p.center.x, p.center.y],
            half_extent: [p.half_extent.x, p.half_extent.y],
            max_iterations: p.max_iterations,
            width: p.width,
            height: p.height,
            row_offset,
            row_count,
            row_stride: p.width,
            out_row: 0,
            pad: 0,
        }
    }

    /// The same band written into a larger output: rows `row_stride` pixels apart, the band's
    /// first row at output row `out_row`.
    pub fn with_output(self, row_stride: u32, out_row: u32) -> Self {
        Self {
            row_stride,
            out_row,
            ..self
        }
    }
}

/// The 2D Julia pipeline on one device.
pub struct GpuJulia2d {
    ctx: GpuContext,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl GpuJulia2d {
    /// Builds the pipeline; a shader the device rejects is an error, not a panic.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        let device = &ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(JULIA2D_MODULE.name),
            source: wgpu::ShaderSource::Wgsl(JULIA2D_MODULE.source().into()),
        });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let storage = wgpu::BufferBindingType::Storage { read_only: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("julia2d"),
            entries: &[
                entry(0, wgpu::BufferBindingType::Uniform),
                entry(1, storage),
                entry(2, storage),
                entry(3, storage),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("julia2d"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("julia2d"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!("the julia2d shader was rejected: {e}")));
        }
        Ok(Self {
            ctx,
            pipeline,
            layout,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Binds a uniform buffer (a [`GpuJulia2dParams`]) and the colour, depth and steps arrays.
    pub fn create_bind_group(
        &self,
        uniform: &wgpu::Buffer,
        outputs: [&wgpu::Buffer; OUTPUTS],
    ) -> wgpu::BindGroup {
        super::output_bind_group(
            &self.ctx.device,
            ("julia2d", &self.layout),
            uniform,
            outputs,
        )
    }

    /// Records one compute pass over `rows` rows of `width` pixels with the bound parameters.
    pub fn encode_band(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        (width, rows): (u32, u32),
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("julia2d"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(width.div_ceil(WORKGROUP.0), rows.div_ceil(WORKGROUP.1), 1);
    }

    /// Rows per dispatch: at most `band_pixels()` pixels, within the device's limits.
    fn band_rows(&self, width: u32, height: u32) -> u32 {
        let limit = self.ctx.device.limits();
        let pixels = crate::band_pixels()
            .min(limit.max_storage_buffer_binding_size / BYTES_PER_PIXEL)
            .min(limit.max_buffer_size / BYTES_PER_PIXEL);
        let rows = ((pixels / width as u64) as u32).max(1);
        let max_groups = limit.max_compute_workgroups_per_dimension;
        rows.min(height).min(max_groups.saturating_mul(WORKGROUP.1))
    }

    /// The whole image in host memory.
    pub fn render(&self, params: &Julia2dParams<f32>) -> Result<(Frame, f64)> {
        let mut frame = Frame {
            width: params.width,
            height: 0,
            colour: Vec::new(),
            depth: Vec::new(),
            steps: Vec::new(),
            non_finite: 0,
        };
        let seconds = self.render_bands(params, &mut |band| {
            frame.append(&band);
            Ok(())
        })?;
        Ok((frame, seconds))
    }

    /// Renders band by band (bounded memory and time per dispatch), handing each band of whole
    /// rows, top to bottom, to `sink`: colour the grey, depth 0 in the set and NaN outside it,
    /// steps the iterations made. Returns the seconds spent rendering after an untimed warm-up
    /// dispatch (the sink's time left out).
    pub fn render_bands(
        &self,
        params: &Julia2dParams<f32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<f64> {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        let (width, height) = (params.width, params.height);
        let band_rows = self.band_rows(width, height);
        let bytes = band_rows as u64 * width as u64 * BYTES_PER_PIXEL;
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("julia2d params"),
            size: size_of::<GpuJulia2dParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (storage, readback) = super::output_buffers(device, bytes);
        let bind_group = self.create_bind_group(&uniform, [&storage[0], &storage[1], &storage[2]]);

        // One band: upload, dispatch, and (unless warming up) copy out, wait and append.
        let run = |band: GpuJulia2dParams, size: (u32, u32), read_rows: u32| -> Result<Frame> {
            queue.write_buffer(&uniform, 0, bytemuck::bytes_of(&band));
            let mut encoder = device.create_command_encoder(&Default::default());
            self.encode_band(&mut encoder, &bind_group, size);
            let n = read_rows as u64 * width as u64 * BYTES_PER_PIXEL;
            if n > 0 {
                for (src, dst) in storage.iter().zip(&readback) {
                    encoder.copy_buffer_to_buffer(src, 0, dst, 0, n);
                }
            }
            queue.submit([encoder.finish()]);
            let mut frame = Frame {
                width,
                height: read_rows,
                colour: Vec::new(),
                depth: Vec::new(),
                steps: Vec::new(),
                non_finite: 0,
            };
            if n == 0 {
                device
                    .poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| Error::Gpu(format!("waiting for the GPU: {e}")))?;
                return Ok(frame);
            }
            let (sender, receiver) = mpsc::channel();
            for buffer in &readback {
                let sender = sender.clone();
                buffer
                    .slice(..n)
                    .map_async(wgpu::MapMode::Read, move |r| drop(sender.send(r)));
            }
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Gpu(format!("waiting for the GPU: {e}")))?;
            for _ in &readback {
                receiver
                    .recv()
                    .map_err(|_| Error::Gpu("the device was lost".into()))?
                    .map_err(|e| Error::Gpu(format!("mapping a result buffer: {e}")))?;
            }
            {
                let view = |i: usize| {
                    readback[i]
                        .slice(..n)
                        .get_mapped_range()
                        .map_err(|e| Error::Gpu(format!("reading back the image: {e}")))
                };
                let (colour, depth, steps) = (view(0)?, view(1)?, view(2)?);
                frame.colour = bytemuck::cast_slice(&colour).to_vec();
                frame.depth = bytemuck::cast_slice::<u8, f32>(&depth)
                    .iter()
                    .map(|&d| if d < 0.0 { f32::NAN } else { d })
                    .collect();
                frame.steps = bytemuck::cast_slice(&steps).to_vec();
            }
            for buffer in &readback {
                buffer.unmap();
            }
            Ok(frame)
        };

        // Warm-up: one workgroup, results discarded (lavapipe compiles at the first dispatch).
        let warm_rows = band_rows.min(WORKGROUP.1);
        run(
            GpuJulia2dParams::new(params, 0, warm_rows),
            (width.min(WORKGROUP.0), warm_rows),
            0,
        )?;
        let mut seconds = 0.0;
        let mut row = 0;
        while row < height {
            let start = Instant::now();
            let rows = band_rows.min(height - row);
            let frame = run(
                GpuJulia2dParams::new(params, row, rows),
                (width, rows),
                rows,
            )?;
            seconds += start.elapsed().as_secs_f64();
            sink(frame)?;
            row += rows;
        }
        Ok(seconds)
    }
}
