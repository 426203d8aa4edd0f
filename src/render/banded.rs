//! One precision's band-by-band work. [`BandedRender`] is what the tracer, the path tracer, the
//! 2D view's kernel and the CPU's functions ([`Cpu`]) all are: a picture of a scene rendered
//! in bands of whole rows. [`InPrecision`] is the renderer's work in one precision, behind the
//! object-safe [`PreciseWork`], so that [`super::Renderer`] matches on its precision once
//! (`Renderer::in_precision`) and names no kernel of a precision.

use std::marker::PhantomData;
use std::ops::Range;
use std::sync::Arc;

use crate::algebra::Real;
use crate::cpu;
use crate::cpu::path::PathParams;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::gpu::kernel::RunTimes;
use crate::gpu::path::GpuPathTracer;
use crate::gpu::{GpuJulia2d, GpuKernels, GpuReal, GpuTracer, Readback};
use crate::grid::GridSpec;
use crate::memory::band_pixels;
use crate::params::{Julia2dParams, TraceParams};
use crate::picture::Picture;
use crate::scene::Scene;

/// What renders a picture of a scene band by band, in its own precision.
pub trait BandedRender {
    /// Renders the rows `rows` of `scene`'s `picture` (the 2D view: whole) band by band into
    /// `sink`, with the outputs `readback` asks for; returns (render seconds, GPU seconds).
    /// Path mode's bands come with their counter words where the colour goes (the renderer's
    /// display transform takes them).
    fn render_bands(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        rows: Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)>;
}

impl<T: BandedRender + ?Sized> BandedRender for Arc<T> {
    fn render_bands(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        rows: Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)> {
        (**self).render_bands(scene, picture, readback, rows, sink)
    }
}

fn times(t: RunTimes) -> (f64, Option<f64>) {
    (t.seconds, t.gpu_seconds)
}

/// The tracer: a slice, shaded (phong mode) or not (the maps).
impl<R: GpuReal> BandedRender for GpuTracer<R> {
    fn render_bands(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        rows: Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)> {
        let Picture::Slice { shade } = picture else {
            unreachable!("the tracer renders slices")
        };
        let p = TraceParams::<R>::new(scene);
        self.render_band_rows(&p, shade, readback, rows, sink)
            .map(times)
    }
}

/// The path tracer: a shaded slice in path mode.
impl<R: GpuReal> BandedRender for GpuPathTracer<R> {
    fn render_bands(
        &self,
        scene: &Scene,
        _: Picture,
        readback: Readback,
        rows: Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)> {
        let (p, path) = (TraceParams::<R>::new(scene), PathParams::<R>::new(scene));
        self.render_band_rows(&p, &path, readback, rows, sink)
            .map(times)
    }
}

/// The 2D view, whole.
impl<R: GpuReal> BandedRender for GpuJulia2d<R> {
    fn render_bands(
        &self,
        scene: &Scene,
        _: Picture,
        readback: Readback,
        _: Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)> {
        GpuJulia2d::render_bands(self, &Julia2dParams::<R>::new(scene), readback, sink).map(times)
    }
}

/// The CPU's functions in precision `R` (cpu/: the twins of the kernels).
pub struct Cpu<R>(PhantomData<R>);

impl<R: Real> BandedRender for Cpu<R> {
    fn render_bands(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        rows: Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<(f64, Option<f64>)> {
        let aovs = readback.aovs();
        let seconds = match picture.path_traced(scene) {
            true => path_cpu::<R>(scene, aovs, rows, sink)?,
            false => render_cpu::<R>(scene, picture, aovs, rows, sink)?,
        };
        Ok((seconds, None))
    }
}

/// The renderer's work in precision `R`: on `gpu`'s kernels in `R` where there is a GPU, else
/// on the CPU's functions in `R`.
pub struct InPrecision<'a, R> {
    pub gpu: Option<&'a GpuKernels>,
    pub precision: PhantomData<R>,
}

/// What the renderer does in its precision ([`InPrecision`]'s, object safe).
pub trait PreciseWork {
    /// What renders `picture` of `scene` band by band: the path tracer, the tracer or the 2D
    /// view's kernel, or the CPU's functions.
    fn banded(&self, scene: &Scene, picture: Picture) -> Result<Box<dyn BandedRender>>;
    /// Streams the frames of these slices (`shade`: shaded or the maps) on the GPU's tracer
    /// ([`GpuTracer::render_frames`]), each to `sink` with its times.
    fn stream_frames(
        &self,
        kernels: &GpuKernels,
        scenes: &mut dyn Iterator<Item = Scene>,
        shade: bool,
        readback: Readback,
        sink: &mut dyn FnMut(Frame, RunTimes) -> Result<()>,
    ) -> Result<()>;
    /// Samples the level at every point of `grid` (see `Renderer::sample_levels`).
    fn sample_levels(
        &self,
        scene: &Scene,
        grid: &GridSpec,
        sink: &mut dyn FnMut(&[f32]) -> Result<()>,
    ) -> Result<f64>;
}

impl<R: GpuReal> PreciseWork for InPrecision<'_, R> {
    fn banded(&self, scene: &Scene, picture: Picture) -> Result<Box<dyn BandedRender>> {
        let Some(kernels) = self.gpu else {
            return Ok(Box::new(Cpu::<R>(PhantomData)));
        };
        Ok(match picture {
            _ if picture.path_traced(scene) => Box::new(kernels.path_in::<R>()?),
            Picture::Slice { .. } => Box::new(kernels.tracer_in::<R>()?),
            Picture::Julia2d => Box::new(kernels.julia2d_in::<R>()?),
        })
    }

    fn stream_frames(
        &self,
        kernels: &GpuKernels,
        scenes: &mut dyn Iterator<Item = Scene>,
        shade: bool,
        readback: Readback,
        sink: &mut dyn FnMut(Frame, RunTimes) -> Result<()>,
    ) -> Result<()> {
        let mut params = scenes.map(|scene| (TraceParams::<R>::new(&scene), shade));
        kernels
            .tracer_in::<R>()?
            .render_frames(&mut params, readback, sink)
    }

    fn sample_levels(
        &self,
        scene: &Scene,
        grid: &GridSpec,
        sink: &mut dyn FnMut(&[f32]) -> Result<()>,
    ) -> Result<f64> {
        match self.gpu {
            // The sampler is f32's alone.
            Some(kernels) if R::NAME == f32::NAME => {
                let times = kernels.sampler()?.sample(
                    &TraceParams::<f32>::new(scene),
                    &grid.in_precision(),
                    grid.size[1] * grid.size[2],
                    &mut |_, levels| sink(levels),
                )?;
                Ok(times.seconds)
            }
            Some(_) => Err(Error::Unsupported(SAMPLER_F32_ONLY.into())),
            None => sample_cpu::<R>(scene, grid, sink),
        }
    }
}

/// A picture on the CPU in `F`, band by band, with the AOVs where `aovs` asks; returns the
/// seconds spent rendering (the sink's time left out).
fn render_cpu<F: Real>(
    scene: &Scene,
    picture: Picture,
    aovs: bool,
    rows: Range<u32>,
    sink: &mut dyn FnMut(Frame) -> Result<()>,
) -> Result<f64> {
    match picture {
        Picture::Slice { shade } => {
            let p = TraceParams::<F>::new(scene);
            let rows_of = |rows| cpu::render_rows(&p, shade, aovs, rows);
            cpu_bands(p.width, rows, &rows_of, sink)
        }
        Picture::Julia2d => {
            let p = Julia2dParams::<F>::new(scene);
            let rows = |rows| cpu::julia2d::render_rows(&p, rows);
            cpu_bands(p.width, 0..p.height, &rows, sink)
        }
    }
}

/// A path-traced picture on the CPU in `F`, band by band (each band's colour still to be
/// made), with the AOVs where `aovs` asks; returns the seconds spent rendering.
fn path_cpu<F: Real>(
    scene: &Scene,
    aovs: bool,
    rows: Range<u32>,
    sink: &mut dyn FnMut(Frame) -> Result<()>,
) -> Result<f64> {
    let p = TraceParams::<F>::new(scene);
    let path = PathParams::<F>::new(scene);
    let render = |rows| cpu::path::render_path_rows(&p, &path, aovs, rows);
    cpu_bands(p.width, rows, &render, sink)
}

/// Samples the grid on the CPU in `F`, a layer at a time; the seconds spent sampling.
fn sample_cpu<F: Real>(
    scene: &Scene,
    grid: &GridSpec,
    sink: &mut dyn FnMut(&[f32]) -> Result<()>,
) -> Result<f64> {
    let params = TraceParams::<F>::new(scene);
    let sample_grid = grid.in_precision::<F>();
    let (rows, layers) = (grid.size[1], grid.size[2]);
    let mut seconds = 0.0;
    for z in 0..layers {
        let start = std::time::Instant::now();
        let levels = cpu::sample::sample_rows(&params, &sample_grid, z * rows..(z + 1) * rows);
        let layer: Vec<f32> = levels.into_iter().map(to_f32_level).collect();
        seconds += start.elapsed().as_secs_f64();
        sink(&layer)?;
    }
    Ok(seconds)
}

/// A level in f32 with its sign kept: a negative level too small for f32 stays negative.
fn to_f32_level<F: Real>(level: F) -> f32 {
    let l = level.to_f64();
    let r = l as f32;
    if l < 0.0 && r == 0.0 {
        -f32::MIN_POSITIVE
    } else {
        r
    }
}

/// Why a mesh in f64 is not sampled on the GPU (it samples on the CPU instead).
pub(super) const SAMPLER_F32_ONLY: &str = "the mesh sampler runs in f32 on the GPU";

/// Renders the rows `rows` of an image `width` wide on the CPU band by band with
/// `render_rows`, handing each band to `sink`; returns the seconds spent rendering (the sink's
/// time left out). A pixel depends on its own row alone, so any rows can be rendered.
fn cpu_bands(
    width: u32,
    rows: Range<u32>,
    render_rows: &dyn Fn(Range<u32>) -> Frame,
    sink: &mut dyn FnMut(Frame) -> Result<()>,
) -> Result<f64> {
    let band_rows = (band_pixels() / width.max(1) as u64).clamp(1, u32::MAX as u64) as u32;
    let mut seconds = 0.0;
    let (mut row, end) = (rows.start, rows.end);
    while row < end {
        let rows = band_rows.min(end - row);
        let start = std::time::Instant::now();
        let band = render_rows(row..row + rows);
        seconds += start.elapsed().as_secs_f64();
        sink(band)?;
        row += rows;
    }
    Ok(seconds)
}
