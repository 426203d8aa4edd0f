//! The kernels of one device, each built on first use and then shared: the tracer, the path
//! tracer and the 2D view in f32 and (where the device passes the start-up check) f64, the mesh's
//! sampler and the denoiser.
//! The explorer's views, its exports and the renders of a command all take their kernels from
//! one of these, so a kernel is built once per device.

use std::any::Any;
use std::sync::{Arc, Mutex};

use super::denoise::GpuDenoiser;
use super::path::GpuPathTracer;
use super::{GpuContext, GpuJulia2d, GpuReal, GpuSampler, GpuTracer};
use crate::error::Result;

/// A kernel slot: empty until the kernel is first asked for.
type Slot<T> = Mutex<Option<Arc<T>>>;

/// One precision's kernels, each built on first use.
struct Slots<R: GpuReal> {
    tracer: Slot<GpuTracer<R>>,
    path: Slot<GpuPathTracer<R>>,
    julia2d: Slot<GpuJulia2d<R>>,
}

impl<R: GpuReal> Default for Slots<R> {
    fn default() -> Self {
        Self {
            tracer: Mutex::new(None),
            path: Mutex::new(None),
            julia2d: Mutex::new(None),
        }
    }
}

/// The GPU kernels of one device, each built on first use: those of a precision through the
/// accessors generic over it ([`Self::tracer_in`], [`Self::path_in`], [`Self::julia2d_in`];
/// [`Self::tracer`], [`Self::path`] and [`Self::julia2d`] are f32's), the f32-only sampler and
/// denoiser through their own.
pub struct GpuKernels {
    ctx: GpuContext,
    f32: Slots<f32>,
    f64: Slots<f64>,
    sampler: Slot<GpuSampler>,
    denoiser: Slot<GpuDenoiser>,
}

impl GpuKernels {
    /// No kernel built yet.
    pub fn new(ctx: GpuContext) -> Self {
        Self {
            ctx,
            f32: Slots::default(),
            f64: Slots::default(),
            sampler: Mutex::new(None),
            denoiser: Mutex::new(None),
        }
    }

    /// On a tracer already built (a bench's generic one, say): its device, with it as the f32
    /// tracer; the other kernels are built on use.
    pub fn with_tracer(tracer: Arc<GpuTracer>) -> Self {
        let kernels = Self::new(tracer.context().clone());
        *kernels.f32.tracer.lock().expect("kernel slot") = Some(tracer);
        kernels
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The kernels of precision `R`: f32's or f64's (GpuReal has no other impl).
    fn slots<R: GpuReal>(&self) -> &Slots<R> {
        let f32: &dyn Any = &self.f32;
        let f64: &dyn Any = &self.f64;
        f32.downcast_ref()
            .or_else(|| f64.downcast_ref())
            .expect("GpuReal is f32 or f64")
    }

    /// The tracer in `R`; in f64 where the device passes the start-up check of f64
    /// ([`GpuContext::f64_support`]; Err saying why not).
    pub fn tracer_in<R: GpuReal>(&self) -> Result<Arc<GpuTracer<R>>> {
        built(&self.slots::<R>().tracer, || {
            GpuTracer::build(self.ctx.clone())
        })
    }

    /// The path tracer (`shading.model = "path"`) in `R`, as [`Self::tracer_in`].
    pub fn path_in<R: GpuReal>(&self) -> Result<Arc<GpuPathTracer<R>>> {
        built(&self.slots::<R>().path, || {
            GpuPathTracer::build(self.ctx.clone())
        })
    }

    /// The 2D view in `R`, as [`Self::tracer_in`].
    pub fn julia2d_in<R: GpuReal>(&self) -> Result<Arc<GpuJulia2d<R>>> {
        built(&self.slots::<R>().julia2d, || {
            GpuJulia2d::build(self.ctx.clone())
        })
    }

    /// The f32 tracer.
    pub fn tracer(&self) -> Result<Arc<GpuTracer>> {
        self.tracer_in()
    }

    /// The f32 2D view.
    pub fn julia2d(&self) -> Result<Arc<GpuJulia2d>> {
        self.julia2d_in()
    }

    /// The f32 path tracer.
    pub fn path(&self) -> Result<Arc<GpuPathTracer>> {
        self.path_in()
    }

    pub fn sampler(&self) -> Result<Arc<GpuSampler>> {
        built(&self.sampler, || GpuSampler::new(self.ctx.clone()))
    }

    /// The denoiser's a-trous pass (`image.denoise = "atrous"`).
    pub fn denoiser(&self) -> Result<Arc<GpuDenoiser>> {
        built(&self.denoiser, || GpuDenoiser::new(self.ctx.clone()))
    }

    /// The pipelines each built kernel holds, as `tracer 3, path64 1, …` (each at most
    /// [`super::kernel::MAX_PIPELINES`]; a kernel not built yet is left out): what the device
    /// holds of compiled code, which the explorer's memory is bounded by.
    pub fn pipelines_held(&self) -> String {
        fn count<T>(slot: &Slot<T>, held: impl Fn(&T) -> usize) -> Option<usize> {
            slot.lock().expect("kernel slot").as_deref().map(held)
        }
        [
            ("tracer", count(&self.f32.tracer, GpuTracer::pipelines_held)),
            (
                "tracer64",
                count(&self.f64.tracer, GpuTracer::pipelines_held),
            ),
            ("path", count(&self.f32.path, GpuPathTracer::pipelines_held)),
            (
                "path64",
                count(&self.f64.path, GpuPathTracer::pipelines_held),
            ),
            (
                "julia2d",
                count(&self.f32.julia2d, GpuJulia2d::pipelines_held),
            ),
            (
                "julia2d64",
                count(&self.f64.julia2d, GpuJulia2d::pipelines_held),
            ),
        ]
        .into_iter()
        .filter_map(|(name, n)| n.map(|n| format!("{name} {n}")))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// Whether f64 runs on this device: SHADER_F64 and the start-up check
    /// ([`GpuContext::f64_support`], run once per device).
    pub fn has_f64(&self) -> bool {
        self.ctx.f64_support().is_ok()
    }
}

fn built<T>(slot: &Slot<T>, make: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
    let mut slot = slot.lock().expect("kernel slot");
    if let Some(k) = slot.as_ref() {
        return Ok(k.clone());
    }
    let k = Arc::new(make()?);
    *slot = Some(k.clone());
    Ok(k)
}
