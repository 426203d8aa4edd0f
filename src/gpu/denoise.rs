//! The denoiser's passes on the GPU (shaders/denoise.wgsl; its CPU twin is src/cpu/denoise.rs):
//! the image and its guides uploaded once, every a-trous pass recorded in one submission (each
//! with its own uniform), the last pass's image read back. [`crate::denoise`] prepares the
//! image and finishes it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

use bytemuck::{Pod, Zeroable};

use super::GpuContext;
use super::kernel::{Kernel, KernelSpec, OutputSpec};
use super::shaders::DENOISE_MODULE;
use crate::cpu::denoise::DenoiseParams;
use crate::error::{Error, Result};

/// One pass's uniform, as shaders/denoise.wgsl's `DenoiseParams` (keep in sync).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuDenoiseParams {
    pub width: u32,
    pub height: u32,
    pub step: u32,
    /// 0: the pass reads image_a and writes image_b; 1: the other way.
    pub source: u32,
    pub sigma_luminance: f32,
    pub sigma_normal: f32,
    pub sigma_depth: f32,
    pub pad: u32,
}

impl GpuDenoiseParams {
    /// The uniform of a pass of `p` that reads `source` (0: image_a).
    pub fn new(p: &DenoiseParams, source: u32) -> Self {
        Self {
            width: p.width,
            height: p.height,
            step: p.step,
            source,
            sigma_luminance: p.sigma_luminance,
            sigma_normal: p.sigma_normal,
            sigma_depth: p.sigma_depth,
            pad: 0,
        }
    }
}

const OUTPUTS: [OutputSpec; 3] = [
    OutputSpec {
        name: "image_a",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "image_b",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "guide",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
];

const DENOISE_KERNEL: KernelSpec = KernelSpec {
    name: "denoise",
    module: DENOISE_MODULE,
    entry_point: "atrous_main",
    uniform_bytes: size_of::<GpuDenoiseParams>() as u64,
    outputs: &OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
    input: None,
    bake_keeps: None,
};

/// The denoiser's kernel on one device.
pub struct GpuDenoiser {
    kernel: Kernel,
    /// Whether the pipeline has run once (lavapipe compiles it at its first dispatch, which
    /// the timed passes leave out).
    warmed: AtomicBool,
}

/// What the passes made: the filtered image, and their GPU time where the device has
/// timestamps.
pub struct DenoiseRun {
    pub image: Vec<[f32; 4]>,
    pub gpu_seconds: Option<f64>,
}

impl GpuDenoiser {
    pub fn new(ctx: GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: Kernel::new(ctx, DENOISE_KERNEL)?,
            warmed: AtomicBool::new(false),
        })
    }

    /// Whether an image of `pixels` fits the device's buffers (the whole image is one
    /// binding: every pass reads across it).
    pub fn fits(&self, pixels: u64) -> bool {
        let limits = self.kernel.context().device.limits();
        let bytes = pixels * 16;
        bytes <= limits.max_storage_buffer_binding_size && bytes <= limits.max_buffer_size
    }

    /// Runs the passes `passes` (their parameters, in order) over `image` with `guide`: the
    /// image after the last.
    pub fn run(
        &self,
        passes: &[DenoiseParams],
        image: &[[f32; 4]],
        guide: &[[f32; 4]],
    ) -> Result<DenoiseRun> {
        let ctx = self.kernel.context();
        let (device, queue) = (&ctx.device, &ctx.queue);
        let (width, height) = match passes.first() {
            Some(p) => (p.width, p.height),
            None => {
                return Ok(DenoiseRun {
                    image: image.to_vec(),
                    gpu_seconds: Some(0.0),
                });
            }
        };
        let bytes = image.len() as u64 * 16;
        if !self.fits(image.len() as u64) {
            return Err(Error::Unsupported(format!(
                "the denoiser's image of {width}x{height} exceeds the device's storage buffers"
            )));
        }
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let storage = |label: &str| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let buffers = [
            storage("denoise a"),
            storage("denoise b"),
            storage("denoise guide"),
        ];
        queue.write_buffer(&buffers[0], 0, bytemuck::cast_slice(image));
        queue.write_buffer(&buffers[2], 0, bytemuck::cast_slice(guide));
        let pipeline = self.kernel.pipeline(&[])?;
        let timestamps = ctx.has_timestamps().then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("denoise time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            })
        });
        if !self.warmed.swap(true, Ordering::Relaxed) {
            // One invocation of one pixel, untimed: the pipeline's compilation.
            let uniform = self.kernel.uniform_buffer("denoise warm-up");
            let one = DenoiseParams {
                width: 1,
                height: 1,
                ..passes[0]
            };
            queue.write_buffer(
                &uniform,
                0,
                bytemuck::bytes_of(&GpuDenoiseParams::new(&one, 0)),
            );
            let bind_group = self.kernel.bind_group(&uniform, &buffers, &None);
            let mut encoder = device.create_command_encoder(&Default::default());
            self.kernel
                .encode(&mut encoder, &pipeline, &bind_group, (1, 1), None);
            queue.submit([encoder.finish()]);
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Gpu(format!("waiting for the denoiser: {e}")))?;
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        let last = passes.len() - 1;
        for (k, p) in passes.iter().enumerate() {
            let uniform = self.kernel.uniform_buffer("denoise params");
            let params = GpuDenoiseParams::new(p, (k % 2) as u32);
            queue.write_buffer(&uniform, 0, bytemuck::bytes_of(&params));
            let bind_group = self.kernel.bind_group(&uniform, &buffers, &None);
            // The first pass's start and the last's end (no writes for the passes between).
            let writes = timestamps
                .as_ref()
                .filter(|_| k == 0 || k == last)
                .map(|q| wgpu::ComputePassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: (k == 0).then_some(0),
                    end_of_pass_write_index: (k == last).then_some(1),
                });
            self.kernel.encode(
                &mut encoder,
                &pipeline,
                &bind_group,
                (width, height),
                writes,
            );
        }
        // After an even number of passes the image is back in image_a.
        let result = &buffers[passes.len() % 2];
        let read_usage = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("denoise readback"),
            size: bytes,
            usage: read_usage,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(result, 0, &readback, 0, bytes);
        let stamps = timestamps.as_ref().map(|q| {
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("denoise timestamps"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("denoise timestamps readback"),
                size: 16,
                usage: read_usage,
                mapped_at_creation: false,
            });
            encoder.resolve_query_set(q, 0..2, &resolve, 0);
            encoder.copy_buffer_to_buffer(&resolve, 0, &read, 0, 16);
            read
        });
        queue.submit([encoder.finish()]);
        let map = |buffer: &wgpu::Buffer| {
            let (sender, receiver) = mpsc::channel();
            buffer
                .slice(..)
                .map_async(wgpu::MapMode::Read, move |r| drop(sender.send(r)));
            receiver
        };
        let mapped = map(&readback);
        let stamps_mapped = stamps.as_ref().map(map);
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu(format!("waiting for the denoiser: {e}")))?;
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!("the denoiser failed: {e}")));
        }
        let mapped_ok = |r: mpsc::Receiver<_>| -> Result<()> {
            match r.recv() {
                Ok(Ok(())) => Ok(()),
                _ => Err(Error::Gpu("reading back the denoised image".into())),
            }
        };
        mapped_ok(mapped)?;
        let image = {
            let view = readback
                .slice(..)
                .get_mapped_range()
                .map_err(|e| Error::Gpu(format!("reading back the denoised image: {e}")))?;
            bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&view)
        };
        let gpu_seconds = match (stamps, stamps_mapped) {
            (Some(read), Some(r)) => {
                mapped_ok(r)?;
                let view = read
                    .slice(..)
                    .get_mapped_range()
                    .map_err(|e| Error::Gpu(format!("reading timestamps: {e}")))?;
                let t: &[u64] = bytemuck::cast_slice(&view);
                let ticks = t[1].saturating_sub(t[0]);
                Some(ticks as f64 * queue.get_timestamp_period() as f64 * 1e-9)
            }
            _ => None,
        };
        Ok(DenoiseRun { image, gpu_seconds })
    }
}
