//! The 2D Julia set's texture, which the explorer's viewport shows in 2D mode: the set of the
//! current c, drawn by the same GPU kernel as `qjulia render2d` (shaders/julia2d.wgsl) straight
//! into a texture egui shows. One render in flight at a time, whole image in one dispatch: when
//! the view changes during a render, the next one starts as soon as it is done, with the latest
//! values.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use super::frame_spans::span;
use super::kernel_texture::KernelTarget;
use super::precision_switch::{Either, PrecisionSwitch};
use crate::gpu::{GpuJulia2d, GpuKernels, GpuReal};
use crate::params::Julia2dParams;
use crate::precision::Precision;
use crate::render::{Picture, Planner};
use crate::scene::Scene;

/// The 2D view in one precision.
pub struct Julia2dView<F: GpuReal = f32> {
    julia: Arc<GpuJulia2d<F>>,
    renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
    uniform: wgpu::Buffer,
    target: Option<KernelTarget>,
    /// The parameters of the render in flight, or of the last one done.
    submitted: Option<Julia2dParams<F>>,
    in_flight: Arc<AtomicBool>,
    started: Instant,
    /// Seconds the last finished render took (submission to completion).
    pub render_seconds: f64,
    done_at: Arc<egui::mutex::Mutex<Option<Instant>>>,
}

impl<F: GpuReal> Julia2dView<F> {
    pub fn new(
        julia: Arc<GpuJulia2d<F>>,
        renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
    ) -> Self {
        let uniform = julia.kernel().uniform_buffer("view2d params");
        Self {
            julia,
            renderer,
            uniform,
            target: None,
            submitted: None,
            in_flight: Arc::new(AtomicBool::new(false)),
            started: Instant::now(),
            render_seconds: 0.0,
            done_at: Arc::new(egui::mutex::Mutex::new(None)),
        }
    }

    pub fn julia(&self) -> &Arc<GpuJulia2d<F>> {
        &self.julia
    }

    /// The texture to draw and its size in pixels, once there is one.
    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        let t = self.target.as_ref()?;
        self.submitted
            .as_ref()
            .map(|_| (t.texture_id, [t.width, t.height]))
    }

    /// Whether a render is still running (the caller should keep repainting).
    pub fn busy(&self) -> bool {
        self.in_flight.load(Ordering::Acquire)
    }

    /// Whether the texture holds exactly this scene's 2D view (its `image` size).
    pub fn is_refined(&self, scene: &Scene) -> bool {
        !self.busy() && self.submitted.as_ref() == Some(&Julia2dParams::new(scene))
    }

    /// Asks for the 2D view of `scene` at its image size; call once per UI frame.
    pub fn update(&mut self, scene: &Scene) {
        self.julia.context().device.poll(wgpu::PollType::Poll).ok();
        if let Some(done) = self.done_at.lock().take() {
            self.render_seconds = done.duration_since(self.started).as_secs_f64();
        }
        let params = Julia2dParams::<F>::new(scene);
        if self.busy() || self.submitted.as_ref() == Some(&params) {
            return;
        }
        let size = [params.width.clamp(1, 8192), params.height.clamp(1, 8192)];
        if [params.width, params.height] != size {
            return;
        }
        span("target", || self.ensure_target(size));
        let Some(t) = &self.target else { return };
        let device = &self.julia.context().device;
        let band = F::julia2d_view_uniform(&params, t.row_stride);
        let queue = &self.julia.context().queue;
        queue.write_buffer(&self.uniform, 0, &band);
        let Ok(pipeline) = span("pipeline", || self.julia.pipeline()) else {
            return;
        };
        let mut encoder = device.create_command_encoder(&Default::default());
        self.julia.kernel().encode(
            &mut encoder,
            &pipeline,
            &t.bind_group,
            (t.width, t.height),
            None,
        );
        t.copy_rows(&mut encoder, 0, t.height);
        self.in_flight.store(true, Ordering::Release);
        self.started = Instant::now();
        queue.submit([encoder.finish()]);
        let (in_flight, done_at) = (self.in_flight.clone(), self.done_at.clone());
        queue.on_submitted_work_done(move || {
            *done_at.lock() = Some(Instant::now());
            in_flight.store(false, Ordering::Release);
        });
        self.submitted = Some(params);
    }

    /// Gives back the memory of a view not shown: its target (its egui texture freed). Shown
    /// again, it renders afresh.
    pub fn release(&mut self) {
        if let Some(target) = self.target.take() {
            self.renderer.write().free_texture(&target.texture_id);
        }
        self.submitted = None;
    }

    /// Makes sure the target has this size, re-creating it if not.
    fn ensure_target(&mut self, size: [u32; 2]) {
        if self
            .target
            .as_ref()
            .is_some_and(|t| [t.width, t.height] == size)
        {
            return;
        }
        let old = self.target.take();
        self.target = Some(KernelTarget::new(
            self.julia.kernel(),
            &self.renderer,
            ("view2d", &self.uniform),
            (size, false),
            old.map(|t| t.texture_id),
        ));
    }
}

/// The explorer's 2D view, in f32 or (deep) f64 by itself ([`PrecisionSwitch`]).
pub struct Julia2dTexture {
    /// The device's kernels, shared with the explorer's exports.
    kernels: Arc<GpuKernels>,
    /// Decides the view's precision ([`Planner::for_view`]).
    planner: Planner,
    views: PrecisionSwitch<Julia2dView<f32>, Julia2dView<f64>>,
    /// Seconds the last finished render of the view shown took (submission to completion).
    pub render_seconds: f64,
}

impl Julia2dTexture {
    /// The view on the f32 2D kernel of `kernels` (built now: a shader the device rejects is an
    /// error); the f64 one is taken from them at the first deep view.
    pub fn new(
        kernels: Arc<GpuKernels>,
        renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
    ) -> crate::Result<Self> {
        let view = Julia2dView::new(kernels.julia2d()?, renderer);
        Ok(Self {
            planner: Planner::for_view(kernels.clone()),
            kernels,
            views: PrecisionSwitch::new(view),
            render_seconds: 0.0,
        })
    }

    /// Asks for the 2D view of `scene` in the precision it needs; call once per UI frame.
    pub fn update(&mut self, scene: &Scene) {
        let kernels = &self.kernels;
        let build = |view: &Julia2dView<f32>| {
            Ok(Julia2dView::new(
                kernels.julia2d_in::<f64>()?,
                view.renderer.clone(),
            ))
        };
        self.render_seconds = match self
            .views
            .pick(&self.planner, scene, Picture::Julia2d, build)
        {
            Either::F32(view) => {
                view.update(scene);
                view.render_seconds
            }
            Either::F64(view) => {
                view.update(scene);
                view.render_seconds
            }
        };
        self.views
            .release_hidden(false, Julia2dView::release, Julia2dView::release);
    }

    /// Gives back the memory of both views (3D mode shows neither).
    pub fn release(&mut self) {
        self.views
            .release_hidden(true, Julia2dView::release, Julia2dView::release);
    }

    /// The precision of the view shown.
    pub fn precision(&self) -> Precision {
        self.views.precision()
    }

    /// Why the view runs in its precision (the status line's hover text).
    pub fn precision_note(&self) -> &str {
        self.views.reason()
    }

    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        match self.views.shown() {
            Either::F32(view) => view.texture(),
            Either::F64(view) => view.texture(),
        }
    }

    pub fn busy(&self) -> bool {
        match self.views.shown() {
            Either::F32(view) => view.busy(),
            Either::F64(view) => view.busy(),
        }
    }

    pub fn is_refined(&self, scene: &Scene) -> bool {
        match self.views.shown() {
            Either::F32(view) => view.is_refined(scene),
            Either::F64(view) => view.is_refined(scene),
        }
    }
}
