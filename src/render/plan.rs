//! The one decision: [`Planner::plan`] takes the precision of a work by the scene
//! ([`crate::precision::decide`]), then its backend, and makes the [`Renderer`] (only here:
//! its fields are its module's) with the decision, its reason and the warnings of the
//! precision that runs. A planner keeps the device it opened (or was given) and the renderers
//! it made, so that the frames of an animation share them.

use std::sync::Arc;

use super::Renderer;
use super::banded::SAMPLER_F32_ONLY;
use crate::error::{Error, Result};
use crate::gpu::{GpuContext, GpuKernels};
use crate::picture::{Picture, Work};
use crate::precision::{self, Decision, Precision, PrecisionChoice, Warning};
use crate::scene::Scene;

/// Which tracer renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// The GPU when wgpu finds an adapter that can do what is asked, else the CPU.
    Auto,
    Gpu,
    Cpu,
}

/// The kernel a work needs: renderers are made once per kernel and precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kernel {
    Slice,
    /// The slice path traced (`shading.model = "path"`).
    Path,
    Julia2d,
    Sampler,
}

impl Work {
    fn kernel(&self, scene: &Scene) -> Kernel {
        match self {
            Work::Picture(picture) if picture.path_traced(scene) => Kernel::Path,
            Work::Picture(Picture::Slice { .. }) => Kernel::Slice,
            Work::Picture(Picture::Julia2d) => Kernel::Julia2d,
            Work::Mesh(_) => Kernel::Sampler,
        }
    }
}

/// Why f64 is refused on a GPU (docs/CONTRACT.md: only where the adapter has SHADER_F64 and the
/// start-up check passes); the check's reason follows it.
pub const GPU_F64_UNSUPPORTED: &str = "--precision f64 is not available on the GPU";

/// How a work is made: the renderer, the precision decided and why, and what that precision
/// cannot resolve in the scene.
#[derive(Clone)]
pub struct Plan {
    pub renderer: Renderer,
    pub decision: Decision,
    pub warnings: Vec<Warning>,
}

/// A renderer made for one kernel in one precision, kept for the next work that needs it.
struct Made {
    kernel: Kernel,
    /// The precision the decision asked for (the renderer's may differ: see `fell_back`).
    asked: Precision,
    renderer: Renderer,
    /// f64 was wanted on `--backend gpu` by auto, and the device has none: f32 on the GPU.
    fell_back: bool,
}

/// The backend and precision asked for, and the device they run on, opened on first need (or
/// given: the explorer's, the report's); [`Self::plan`] makes the decision for each work.
pub struct Planner {
    backend: Backend,
    choice: PrecisionChoice,
    /// None: not opened yet. Some(Err): with `Backend::Auto`, why there is no GPU.
    device: Option<std::result::Result<Arc<GpuKernels>, String>>,
    made: Vec<Made>,
}

impl Planner {
    /// A planner that opens the GPU (wgpu's choice of adapter) when a work first needs it.
    pub fn new(backend: Backend, choice: PrecisionChoice) -> Self {
        Self {
            backend,
            choice,
            device: None,
            made: Vec::new(),
        }
    }

    /// A planner on a device already open, whose kernels it shares (`Backend::Auto`: this
    /// device where it can do the work, else the CPU).
    pub fn on_device(kernels: Arc<GpuKernels>, backend: Backend, choice: PrecisionChoice) -> Self {
        Self {
            device: Some(Ok(kernels)),
            ..Self::new(backend, choice)
        }
    }

    /// The planner of the explorer's live views, on its device: `auto`, and `Backend::Gpu`'s
    /// rule where auto wants f64 and the device has none, which keeps the view on the GPU in
    /// f32 (the view says "f64 unavailable" and why), where `render`'s default
    /// (`Backend::Auto`) goes to the CPU in f64. A view that fell to the CPU would not keep
    /// its frame rate.
    pub fn for_view(kernels: Arc<GpuKernels>) -> Self {
        Self::on_device(kernels, Backend::Gpu, PrecisionChoice::Auto)
    }

    /// The precision [`Self::plan`] decides for `work` on `scene`, and why, without making a
    /// renderer (the explorer's views make their own kernels' views of it).
    pub fn decide(&self, scene: &Scene, work: &Work) -> Decision {
        precision::decide(self.choice, scene, work)
    }

    /// The one decision: the precision of `work` on `scene` (`auto`: by the scene), then its
    /// renderer on the backend asked for. `notice` hears, the first time a renderer is made for
    /// a kernel and precision, what the user should know: why f64 runs where auto chose it,
    /// which backend was chosen and why, and the warnings of the precision that runs.
    pub fn plan(
        &mut self,
        scene: &Scene,
        work: Work,
        notice: &mut dyn FnMut(&str),
    ) -> Result<Plan> {
        let mut decision = precision::decide(self.choice, scene, &work);
        let kernel = work.kernel(scene);
        let asked = decision.precision;
        let found = self
            .made
            .iter()
            .position(|m| m.kernel == kernel && m.asked == asked);
        let index = match found {
            Some(index) => index,
            None => {
                let made = self.make(kernel, &decision, notice)?;
                self.made.push(made);
                self.made.len() - 1
            }
        };
        let made = &self.made[index];
        if made.fell_back {
            decision = Decision {
                precision: Precision::F32,
                reason: format!(
                    "{}; the adapter has no f64, so f32 on the GPU (--backend gpu)",
                    decision.reason
                ),
            };
        }
        let warnings = precision::warnings(scene, &work, decision.precision);
        if found.is_none() {
            for warning in &warnings {
                notice(&format!("warning: {warning}"));
            }
            if scene.camera.aperture > 0.0 && scene.image.samples == 1 {
                notice(
                    "camera.aperture > 0 with image.samples = 1 takes one point of the lens: set \
                     image.samples > 1 for depth of field",
                );
            }
        }
        let renderer = Renderer {
            reason: decision.reason.clone(),
            ..made.renderer.clone()
        };
        Ok(Plan {
            renderer,
            decision,
            warnings,
        })
    }

    /// A renderer for `work` in the precision decided, telling `notice` what it chose (the
    /// warnings of the precision that runs follow, from [`Self::plan`]).
    fn make(
        &mut self,
        kernel: Kernel,
        decision: &Decision,
        notice: &mut dyn FnMut(&str),
    ) -> Result<Made> {
        if self.choice == PrecisionChoice::Auto && decision.precision == Precision::F64 {
            let doing = match kernel {
                Kernel::Sampler => "sampling",
                Kernel::Slice | Kernel::Path | Kernel::Julia2d => "rendering",
            };
            notice(&format!("{doing} in f64: {}", decision.reason));
        }
        let wants_f64 = decision.precision == Precision::F64;
        let mut fell_back = false;
        let renderer = if wants_f64
            && self.backend == Backend::Gpu
            && self.choice == PrecisionChoice::Auto
        {
            // Auto on `--backend gpu`: an adapter without f64 keeps the work on the GPU in f32.
            match self.choose(Backend::Gpu, Precision::F64, kernel, notice) {
                Err(Error::Unsupported(why)) => {
                    notice(&format!(
                        "f64 would resolve this scene, but {why}; staying on the GPU in f32 as --backend gpu asks"
                    ));
                    fell_back = true;
                    self.choose(Backend::Gpu, Precision::F32, kernel, notice)?
                }
                chosen => chosen?,
            }
        } else {
            self.choose(self.backend, decision.precision, kernel, notice)?
        };
        Ok(Made {
            kernel,
            asked: decision.precision,
            renderer,
            fell_back,
        })
    }

    /// The renderer of `kernel` in `precision` on `backend`: `Auto` goes to the CPU where the
    /// GPU cannot do it (no adapter, a shader the device rejects, f64 failing its check).
    fn choose(
        &mut self,
        backend: Backend,
        precision: Precision,
        kernel: Kernel,
        notice: &mut dyn FnMut(&str),
    ) -> Result<Renderer> {
        let cpu = Renderer {
            gpu: None,
            precision,
            reason: String::new(),
        };
        match backend {
            Backend::Cpu => Ok(cpu),
            Backend::Gpu => self.on_gpu(precision, kernel),
            Backend::Auto => match self.on_gpu(precision, kernel) {
                Ok(renderer) => {
                    let f64_note = match precision {
                        Precision::F64 => " in f64",
                        Precision::F32 => "",
                    };
                    notice(&format!(
                        "rendering on the GPU{f64_note}: {}",
                        renderer.adapter()
                    ));
                    Ok(renderer)
                }
                Err(e) => {
                    notice(&format!("{e}; rendering on the CPU"));
                    Ok(cpu)
                }
            },
        }
    }

    /// The GPU renderer of `kernel` in `precision`, its kernel built now (so that a shader the
    /// device rejects, or f64 failing its check, shows up here).
    fn on_gpu(&mut self, precision: Precision, kernel: Kernel) -> Result<Renderer> {
        let kernels = self.device()?;
        let built = match (kernel, precision) {
            (Kernel::Slice, Precision::F32) => kernels.tracer().map(drop),
            (Kernel::Path, Precision::F32) => kernels.path().map(drop),
            (Kernel::Path, Precision::F64) => kernels.path_in::<f64>().map(drop),
            (Kernel::Julia2d, Precision::F32) => kernels.julia2d().map(drop),
            (Kernel::Sampler, Precision::F32) => kernels.sampler().map(drop),
            (Kernel::Slice, Precision::F64) => kernels.tracer_in::<f64>().map(drop),
            (Kernel::Julia2d, Precision::F64) => kernels.julia2d_in::<f64>().map(drop),
            (Kernel::Sampler, Precision::F64) => Err(Error::Unsupported(SAMPLER_F32_ONLY.into())),
        };
        built.map_err(|e| match precision {
            Precision::F64 => Error::Unsupported(format!("{GPU_F64_UNSUPPORTED}: {e}")),
            Precision::F32 => e,
        })?;
        Ok(Renderer {
            gpu: Some(kernels),
            precision,
            reason: String::new(),
        })
    }

    /// The device, opened on first need. With `Backend::Auto` a failure to open one is kept
    /// (the CPU is used from then on); otherwise it is the error.
    fn device(&mut self) -> Result<Arc<GpuKernels>> {
        match &self.device {
            Some(Ok(kernels)) => return Ok(kernels.clone()),
            Some(Err(why)) if self.backend == Backend::Auto => {
                return Err(Error::Unsupported(why.clone()));
            }
            _ => {}
        }
        match GpuContext::new() {
            Ok(ctx) => {
                let kernels = Arc::new(GpuKernels::new(ctx));
                self.device = Some(Ok(kernels.clone()));
                Ok(kernels)
            }
            Err(e) => {
                self.device = Some(Err(e.to_string()));
                Err(e)
            }
        }
    }
}
