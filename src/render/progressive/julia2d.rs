//! The live 2D view: the Julia set of the current c, drawn by the same GPU kernel as
//! `qjulia render2d` (shaders/julia2d.wgsl) straight into the caller's [`Canvas`] (its full
//! quality's texture). One render in flight at a time, the whole image in one dispatch: when
//! the view changes during a render, the next one starts as soon as it is done, with the latest
//! values. In f32 or (deep) f64 by itself ([`PrecisionSwitch`], as [`Planner::for_view`]
//! decides).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::Quality;
use super::canvas::{Canvas, NewCanvas, Target};
use super::spans::span;
use super::switch::{Either, PrecisionSwitch};
use crate::gpu::{GpuJulia2d, GpuKernels, GpuReal};
use crate::params::Julia2dParams;
use crate::picture::Picture;
use crate::precision::Precision;
use crate::render::Planner;
use crate::scene::Scene;

/// The 2D view in one precision.
pub struct Julia2dView<F: GpuReal, C: Canvas> {
    julia: Arc<GpuJulia2d<F>>,
    /// Where its image is shown: the canvas's full quality.
    canvas: C,
    uniform: wgpu::Buffer,
    target: Option<Target>,
    /// The parameters of the render in flight, or of the last one done.
    submitted: Option<Julia2dParams<F>>,
    in_flight: Arc<AtomicBool>,
    started: Instant,
    /// When the render of the image shown began (a scene asked for before then is in it).
    shown_began: Option<Instant>,
    /// Seconds the last finished render took (submission to completion).
    pub render_seconds: f64,
    done_at: Arc<Mutex<Option<Instant>>>,
}

impl<F: GpuReal, C: Canvas> Julia2dView<F, C> {
    pub fn new(julia: Arc<GpuJulia2d<F>>, canvas: C) -> Self {
        let uniform = julia.kernel().uniform_buffer("view2d params");
        Self {
            julia,
            canvas,
            uniform,
            target: None,
            submitted: None,
            in_flight: Arc::new(AtomicBool::new(false)),
            started: Instant::now(),
            shown_began: None,
            render_seconds: 0.0,
            done_at: Arc::new(Mutex::new(None)),
        }
    }

    /// The size of the image shown (on the canvas's full quality), once there is one.
    pub fn shown(&self) -> Option<[u32; 2]> {
        let t = self.target.as_ref()?;
        self.submitted.as_ref().map(|_| [t.width, t.height])
    }

    /// When the render of the image shown began (a render done and not yet taken by
    /// [`Self::update`] is shown).
    pub fn shown_began(&self) -> Option<Instant> {
        if self.done_at.lock().unwrap().is_some() {
            return Some(self.started);
        }
        self.shown_began
    }

    pub fn canvas_mut(&mut self) -> &mut C {
        &mut self.canvas
    }

    /// The canvas the view shows its image on.
    pub fn canvas(&self) -> &C {
        &self.canvas
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
        if let Some(done) = self.done_at.lock().unwrap().take() {
            self.render_seconds = done.duration_since(self.started).as_secs_f64();
            self.shown_began = Some(self.started);
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
        let colour = (&t.outputs[0], t.row_stride);
        self.canvas
            .copy_rows(Quality::Full, &mut encoder, colour, (0, t.height));
        self.in_flight.store(true, Ordering::Release);
        self.started = Instant::now();
        queue.submit([encoder.finish()]);
        let (in_flight, done_at) = (self.in_flight.clone(), self.done_at.clone());
        queue.on_submitted_work_done(move || {
            *done_at.lock().unwrap() = Some(Instant::now());
            in_flight.store(false, Ordering::Release);
        });
        self.submitted = Some(params);
    }

    /// Gives back the memory of a view not shown: its target and its canvas's textures. Shown
    /// again, it renders afresh.
    pub fn release(&mut self) {
        if self.target.take().is_some() {
            self.canvas.release();
        }
        self.submitted = None;
        self.shown_began = None;
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
        let kernel = self.julia.kernel();
        self.target = Some(Target::new(kernel, &self.uniform, size, false, None));
        self.canvas.resize(Quality::Full, size);
    }
}

/// The live 2D view, in f32 or (deep) f64 by itself ([`PrecisionSwitch`]); `C` is the caller's
/// canvas, one for each precision's view, made by the function it gives.
pub struct Live2d<C: Canvas> {
    /// The device's kernels, shared with the explorer's exports.
    kernels: Arc<GpuKernels>,
    /// Makes the canvas of a new view.
    new_canvas: NewCanvas<C>,
    /// Decides the view's precision ([`Planner::for_view`]).
    planner: Planner,
    views: PrecisionSwitch<Julia2dView<f32, C>, Julia2dView<f64, C>>,
    /// Seconds the last finished render of the view shown took (submission to completion).
    pub render_seconds: f64,
}

impl<C: Canvas> Live2d<C> {
    /// The view on the f32 2D kernel of `kernels` (built now: a shader the device rejects is an
    /// error); the f64 one is taken from them at the first deep view. Each shows its image on
    /// a canvas of `new_canvas`.
    pub fn new(kernels: Arc<GpuKernels>, new_canvas: NewCanvas<C>) -> crate::Result<Self> {
        let view = Julia2dView::new(kernels.julia2d()?, new_canvas());
        Ok(Self {
            new_canvas,
            planner: Planner::for_view(kernels.clone()),
            kernels,
            views: PrecisionSwitch::new(view),
            render_seconds: 0.0,
        })
    }

    /// Asks for the 2D view of `scene` in the precision it needs; call once per UI frame.
    pub fn update(&mut self, scene: &Scene) {
        let (kernels, new_canvas) = (&self.kernels, &self.new_canvas);
        let build = |_: &Julia2dView<f32, C>| {
            Ok(Julia2dView::new(kernels.julia2d_in::<f64>()?, new_canvas()))
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

    /// The image shown, once there is one: the canvas it is on (its full quality) and its size
    /// in pixels.
    pub fn shown_image(&self) -> Option<(&C, [u32; 2])> {
        match self.views.shown() {
            Either::F32(view) => view.shown().map(|size| (view.canvas(), size)),
            Either::F64(view) => view.shown().map(|size| (view.canvas(), size)),
        }
    }

    /// When the render of the image shown began ([`Julia2dView::shown_began`]).
    pub fn shown_began(&self) -> Option<Instant> {
        match self.views.shown() {
            Either::F32(view) => view.shown_began(),
            Either::F64(view) => view.shown_began(),
        }
    }

    /// The canvas of the view shown, to change.
    pub fn shown_canvas_mut(&mut self) -> &mut C {
        match self.views.shown_mut() {
            Either::F32(view) => view.canvas_mut(),
            Either::F64(view) => view.canvas_mut(),
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
