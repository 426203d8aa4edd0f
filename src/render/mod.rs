//! One decision, one render path. [`Planner::plan`] (in `plan.rs`) is the one place that decides how a work is
//! made of a scene (a [`Picture`], or a mesh's levels): the precision by the scene
//! ([`crate::precision`]), then the backend, and returns the [`Renderer`] with the decision, its
//! reason and the warnings of the precision that runs. A [`Renderer`] can be had no other way.
//! It then renders any [`Picture`] of a scene in bands of whole rows handed to a sink, or
//! samples a mesh's grid, and returns its [`RenderStats`]. `render`, `render2d`, `animate`,
//! `mesh`, the reports, the bench and the explorer all go through it.
//!
//! ```compile_fail
//! // Outside this module a renderer is only made by a plan: no constructor, no fields.
//! let renderer = qjulia::Renderer::cpu(qjulia::Precision::F32);
//! ```
//!
//! ```compile_fail
//! let renderer = qjulia::Renderer { gpu: None, precision: qjulia::Precision::F32, reason: String::new() };
//! ```

mod banded;
mod plan;
pub mod progressive;
pub mod target;

pub use banded::{BandedRender, Cpu};
use banded::{InPrecision, PreciseWork};

pub use crate::gpu::Readback;
pub use crate::memory::band_pixels;
pub use crate::picture::{Picture, Work};
pub use plan::{Backend, GPU_F64_UNSUPPORTED, Plan, Planner};

use std::marker::PhantomData;
use std::sync::Arc;

use crate::denoise::Denoiser;
use crate::display::Display;
use crate::error::Result;
use crate::frame::Frame;
use crate::gpu::GpuKernels;
use crate::grid::GridSpec;
use crate::precision::Precision;
use crate::scene::Scene;
use crate::stats::{RenderStats, SummaryBuilder};

/// Where renders run: the GPU or the CPU, in a precision (f64 on the GPU only where the device
/// passed the start-up check), made by [`Planner::plan`] alone.
#[derive(Clone)]
pub struct Renderer {
    gpu: Option<Arc<GpuKernels>>,
    precision: Precision,
    /// Why this precision (`precision_reason` of its stats).
    reason: String,
}

impl Renderer {
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// Why the render runs in its precision.
    pub fn reason(&self) -> &str {
        &self.reason
    }

    /// "gpu" or "cpu".
    pub fn backend_name(&self) -> &'static str {
        if self.gpu.is_some() { "gpu" } else { "cpu" }
    }

    /// The adapter, "name / Backend", or "cpu".
    pub fn adapter(&self) -> String {
        match &self.gpu {
            Some(k) => k.context().adapter_label(),
            None => "cpu".into(),
        }
    }

    /// Whether two renderers are the same tracer in the same precision on the same device: the
    /// frames of one may share a stream.
    pub fn same_tracer(&self, other: &Renderer) -> bool {
        let same_device = match (&self.gpu, &other.gpu) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        same_device && self.precision == other.precision
    }

    /// Renders a validated scene, handing the image to `sink` in bands of whole rows, top to
    /// bottom, as they are done: any image size renders in bounded memory.
    pub fn render(
        &self,
        scene: &Scene,
        picture: Picture,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
    ) -> Result<RenderStats> {
        self.render_with(scene, picture, Readback::All, sink)
    }

    /// As [`Self::render`], reading back only `readback`'s outputs ([`Readback::Hdr`]: a shaded
    /// slice only, with its AOVs). With a denoiser (`image.denoise`) the shaded slice is
    /// rendered whole with its AOVs, denoised ([`crate::denoise`]) and handed to `sink` as one
    /// band: the filter reaches across bands.
    pub fn render_with(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
    ) -> Result<RenderStats> {
        let all = 0..scene.image.height;
        if picture == Picture::SHADED && scene.targets_error() {
            return self.render_to_target(scene, readback, sink);
        }
        if picture != Picture::SHADED || scene.image.denoise == Denoiser::None {
            return self.render_rows(scene, picture, readback, all, sink);
        }
        let (width, height) = (scene.image.width, scene.image.height);
        crate::memory::check(
            &format!("the denoised {width}x{height} image"),
            u64::from(width)
                * u64::from(height)
                * (crate::memory::FRAME_BYTES_PER_PIXEL + crate::memory::DENOISE_BYTES_PER_PIXEL),
        )?;
        let mut whole = Frame::empty(scene.image.width);
        let mut stats = self.render_rows(scene, picture, Readback::Hdr, all, &mut |band| {
            whole.append(band);
            Ok(())
        })?;
        self.denoise(scene, &mut whole, &mut stats)?;
        sink(&whole)?;
        Ok(stats)
    }

    /// Runs `scene`'s denoiser (`image.denoise`, [`crate::denoise`]) over a whole shaded
    /// `frame` rendered with its AOVs, on this renderer's GPU where it has one: the frame's
    /// linear image becomes the denoised one (the mean kept in [`Frame::noisy`]) and its colour
    /// that image's display; the denoiser's figures go in `stats`. `render` and `merge` both
    /// come here, so that their bytes agree.
    pub fn denoise(&self, scene: &Scene, frame: &mut Frame, stats: &mut RenderStats) -> Result<()> {
        // Path mode's estimate of the denoised image, timed with the denoiser.
        let (denoised, estimate) =
            crate::denoise::denoise_estimated(frame, scene, self.gpu.as_deref())?;
        stats.summary.estimated_rmse = estimate.map(|e| e.rmse);
        stats.summary.estimated_relative_rmse = estimate.map(|e| e.relative);
        let colour = match Picture::SHADED.path_traced(scene) {
            true => Display::of(scene).pack_all(&denoised.linear),
            false => crate::denoise::pack_phong(&denoised.linear),
        };
        frame.set_denoised(denoised.linear, colour);
        stats.denoise = Some(crate::stats::DenoiseStats {
            seconds: denoised.seconds,
            gpu_seconds: denoised.gpu_seconds,
            backend: denoised.backend.into(),
        });
        Ok(())
    }

    /// As [`Self::render_with`] without the denoiser, the image's rows `rows` alone (`render
    /// --tile`, a slice only): every pixel exactly as a render of the whole image makes it (the
    /// GPU's bands of the whole image's size, starting on a cone block's row and cropped; the
    /// CPU's pixels depend on their own row alone). The stats are those of these rows (width x
    /// their count).
    pub fn render_rows(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        rows: std::ops::Range<u32>,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
    ) -> Result<RenderStats> {
        let height = scene.image.height;
        assert!(
            rows.start < rows.end && rows.end <= height,
            "rows {rows:?} of an image of {height}"
        );
        assert!(
            rows == (0..height) || picture != Picture::Julia2d,
            "the 2D view renders whole"
        );
        let size = (scene.image.width, rows.end - rows.start);
        if readback.aovs() {
            assert!(
                picture == Picture::SHADED,
                "the AOVs are made of a shaded slice"
            );
        }
        let mut summary = SummaryBuilder::new(scene.image.width);
        // A slice's bands say the samples each pixel took (the kernels return them where
        // adaptive sampling stopped some pixels early).
        let slice = picture != Picture::Julia2d;
        let samples = scene.image.samples.max(1);
        let mut counted = |mut band: Frame| {
            if slice {
                band.fill_samples(samples);
            }
            if readback.maps() {
                summary.add(&band);
            }
            sink(&band)
        };
        let banded = self.in_precision().banded(scene, picture)?;
        let times = match picture.path_traced(scene) {
            // Each band's colour is the display transform of its mean radiance.
            true => {
                let display = Display::of(scene);
                let mut displayed = |mut band: Frame| {
                    band.take_path_counters();
                    display.show(&mut band);
                    counted(band)
                };
                banded.render_bands(scene, picture, readback, rows, &mut displayed)?
            }
            false => banded.render_bands(scene, picture, readback, rows, &mut counted)?,
        };
        let mut stats = self.stats(size, times, summary.finish());
        stats.kernel = self.kernel_stats(scene, picture);
        stats.environment_seconds = scene.loaded.environment.as_ref().map(|e| e.seconds);
        Ok(stats)
    }

    /// The stats of a render of this renderer.
    fn stats(
        &self,
        (width, height): (u32, u32),
        (render_seconds, gpu_seconds): (f64, Option<f64>),
        summary: crate::stats::Summary,
    ) -> RenderStats {
        RenderStats {
            backend: self.backend_name().into(),
            adapter: self.adapter(),
            precision: self.precision.name().into(),
            precision_reason: self.reason.clone(),
            width,
            height,
            render_seconds,
            gpu_seconds,
            environment_seconds: None,
            denoise: None,
            target: None,
            kernel: None,
            summary,
        }
    }

    /// The kernel that draws `picture` of `scene` here, on the GPU; nothing on the CPU.
    fn kernel_stats(&self, scene: &Scene, picture: Picture) -> Option<crate::stats::KernelStats> {
        self.gpu.as_ref()?;
        Some(crate::gpu::scene_kernel::kernel_stats(
            scene,
            picture,
            self.precision,
        ))
    }

    /// Renders a picture of each of `scenes` (validated, of one size) one after another and
    /// hands each whole to `sink` with its stats, in order. On the GPU the frames stream: the
    /// device renders the next while the host reads back and hands out this one
    /// ([`crate::gpu::Kernel::run_stream`]); a frame's `render_seconds` then runs from its
    /// submission to its decoding, and may overlap the one before.
    pub fn render_frames(
        &self,
        scenes: &mut dyn Iterator<Item = Scene>,
        picture: Picture,
        readback: Readback,
        sink: &mut dyn FnMut(Frame, RenderStats) -> Result<()>,
    ) -> Result<()> {
        // Path-traced, denoised and adaptively sampled frames go one by one (the choice of
        // model, of denoiser and of adaptive sampling is not animated: the first frame's is
        // every frame's).
        let mut scenes = scenes.peekable();
        let one_by_one = scenes.peek().is_some_and(|s| {
            picture.path_traced(s)
                || (picture == Picture::SHADED && s.image.denoise != Denoiser::None)
                || s.adaptive()
        });
        let samples = scenes.peek().map_or(1, |s| s.image.samples.max(1));
        let (Some(kernels), Picture::Slice { shade }, false) = (&self.gpu, picture, one_by_one)
        else {
            for scene in scenes {
                let mut frame = Frame::empty(scene.image.width);
                let stats = self.render_with(&scene, picture, readback, &mut |band| {
                    frame.append(band);
                    Ok(())
                })?;
                sink(frame, stats)?;
            }
            return Ok(());
        };
        let kernel = scenes.peek().and_then(|s| self.kernel_stats(s, picture));
        let mut sink = |mut frame: Frame, times: crate::gpu::kernel::RunTimes| {
            frame.fill_samples(samples);
            let summary = match readback.maps() {
                true => crate::stats::Summary::of(&frame),
                false => SummaryBuilder::new(frame.width).finish(),
            };
            let mut stats = self.stats(
                (frame.width, frame.height),
                (times.seconds, times.gpu_seconds),
                summary,
            );
            stats.kernel = kernel.clone();
            sink(frame, stats)
        };
        self.in_precision()
            .stream_frames(kernels, &mut scenes, shade, readback, &mut sink)
    }

    /// As [`Self::render`], the whole image in host memory.
    pub fn render_frame(&self, scene: &Scene, picture: Picture) -> Result<(Frame, RenderStats)> {
        let mut frame = Frame::empty(scene.image.width);
        let stats = self.render(scene, picture, &mut |band| {
            frame.append(band);
            Ok(())
        })?;
        Ok((frame, stats))
    }

    /// Samples the level of `qjulia mesh`'s surface at every point of `grid` (shaders/sample.wgsl
    /// or its CPU twin), handing the levels to `sink` in order (row after row, layer after
    /// layer) in pieces of any length, as f32 with their sign kept; returns the seconds spent
    /// sampling (the sink's time left out).
    pub fn sample_levels(
        &self,
        scene: &Scene,
        grid: &GridSpec,
        sink: &mut dyn FnMut(&[f32]) -> Result<()>,
    ) -> Result<f64> {
        self.in_precision().sample_levels(scene, grid, sink)
    }

    /// This renderer's work in its precision: the one place it matches on the precision.
    fn in_precision(&self) -> Box<dyn PreciseWork + '_> {
        let gpu = self.gpu.as_deref();
        match self.precision {
            Precision::F32 => Box::new(InPrecision::<f32> {
                gpu,
                precision: PhantomData,
            }),
            Precision::F64 => Box::new(InPrecision::<f64> {
                gpu,
                precision: PhantomData,
            }),
        }
    }
}
