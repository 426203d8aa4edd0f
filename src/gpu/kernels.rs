//! The kernels of one device, each built on first use and then shared: the tracer, the path
//! tracer and the 2D view in f32 and (where the device passes the start-up check) f64, the mesh's
//! sampler and the denoiser.
//! The explorer's views, its exports and the renders of a command all take their kernels from
//! one of these, so a kernel is built once per device.

use std::sync::{Arc, Mutex};

use super::denoise::GpuDenoiser;
use super::path::GpuPathTracer;
use super::{GpuContext, GpuJulia2d, GpuSampler, GpuTracer};
use crate::error::Result;

/// The GPU kernels of one device, each built on first use.
pub struct GpuKernels {
    ctx: GpuContext,
    tracer: Mutex<Option<Arc<GpuTracer>>>,
    julia2d: Mutex<Option<Arc<GpuJulia2d>>>,
    tracer64: Mutex<Option<Arc<GpuTracer<f64>>>>,
    julia2d64: Mutex<Option<Arc<GpuJulia2d<f64>>>>,
    sampler: Mutex<Option<Arc<GpuSampler>>>,
    path: Mutex<Option<Arc<GpuPathTracer>>>,
    path64: Mutex<Option<Arc<GpuPathTracer<f64>>>>,
    denoiser: Mutex<Option<Arc<GpuDenoiser>>>,
}

impl GpuKernels {
    /// No kernel built yet.
    pub fn new(ctx: GpuContext) -> Self {
        Self {
            ctx,
            tracer: Mutex::new(None),
            julia2d: Mutex::new(None),
            tracer64: Mutex::new(None),
            julia2d64: Mutex::new(None),
            sampler: Mutex::new(None),
            path: Mutex::new(None),
            path64: Mutex::new(None),
            denoiser: Mutex::new(None),
        }
    }

    /// On a tracer already built (a bench's generic one, say): its device, with it as the f32
    /// tracer; the other kernels are built on use.
    pub fn with_tracer(tracer: Arc<GpuTracer>) -> Self {
        let kernels = Self::new(tracer.context().clone());
        *kernels.tracer.lock().expect("kernel slot") = Some(tracer);
        kernels
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    pub fn tracer(&self) -> Result<Arc<GpuTracer>> {
        built(&self.tracer, || GpuTracer::new(self.ctx.clone()))
    }

    pub fn julia2d(&self) -> Result<Arc<GpuJulia2d>> {
        built(&self.julia2d, || GpuJulia2d::new(self.ctx.clone()))
    }

    pub fn sampler(&self) -> Result<Arc<GpuSampler>> {
        built(&self.sampler, || GpuSampler::new(self.ctx.clone()))
    }

    /// The path tracer (`shading.model = "path"`).
    pub fn path(&self) -> Result<Arc<GpuPathTracer>> {
        built(&self.path, || GpuPathTracer::new(self.ctx.clone()))
    }

    /// The f64 path tracer, where the device passes the start-up check of f64.
    pub fn path64(&self) -> Result<Arc<GpuPathTracer<f64>>> {
        built(&self.path64, || GpuPathTracer::new_f64(self.ctx.clone()))
    }

    /// The denoiser's a-trous pass (`image.denoise = "atrous"`).
    pub fn denoiser(&self) -> Result<Arc<GpuDenoiser>> {
        built(&self.denoiser, || GpuDenoiser::new(self.ctx.clone()))
    }

    /// The f64 tracer, where the device passes the start-up check of f64.
    pub fn tracer64(&self) -> Result<Arc<GpuTracer<f64>>> {
        built(&self.tracer64, || GpuTracer::new_f64(self.ctx.clone()))
    }

    /// The f64 2D view, where the device passes the start-up check of f64.
    pub fn julia2d64(&self) -> Result<Arc<GpuJulia2d<f64>>> {
        built(&self.julia2d64, || GpuJulia2d::new_f64(self.ctx.clone()))
    }

    /// Whether f64 runs on this device: SHADER_F64 and the start-up check
    /// ([`GpuContext::f64_support`], run once per device).
    pub fn has_f64(&self) -> bool {
        self.ctx.f64_support().is_ok()
    }
}

fn built<T>(slot: &Mutex<Option<Arc<T>>>, make: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
    let mut slot = slot.lock().expect("kernel slot");
    if let Some(k) = slot.as_ref() {
        return Ok(k.clone());
    }
    let k = Arc::new(make()?);
    *slot = Some(k.clone());
    Ok(k)
}
