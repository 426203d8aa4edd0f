//! The live view of the 3D slice: the sessions of the tracer and the path tracer, each in f32
//! and, where the view is deep, f64 ([`PrecisionSwitch`], as [`Planner::for_view`] decides),
//! the one shown chosen by the scene at each frame, the others' memory given back.

use std::sync::Arc;

use super::Quality;
use super::canvas::{Canvas, NewCanvas};
use super::session::{KeptRadiance, Session, TextureStats, ViewKernel};
use super::switch::{Either, PrecisionSwitch};
use crate::gpu::GpuKernels;
use crate::picture::Picture;
use crate::precision::Precision;
use crate::render::Planner;
use crate::scene::Scene;

/// A view in f32 and, by itself, f64.
type Views<C> = PrecisionSwitch<Session<f32, C>, Session<f64, C>>;

/// Calls `$body` with `$view` bound to the shown view of `$views`, in its precision.
macro_rules! on_shown {
    ($views:expr, $view:ident => $body:expr) => {
        match $views.shown() {
            Either::F32($view) => $body,
            Either::F64($view) => $body,
        }
    };
}

/// The live view of the 3D slice, in f32 or (deep) f64 by itself ([`PrecisionSwitch`]): the
/// tracer's session (Phong, and the step views), or in path mode the path tracer's. `C` is the
/// caller's canvas, one for each session, made by the function it gives.
pub struct LiveView<C: Canvas> {
    /// The device's kernels, shared with the explorer's exports.
    kernels: Arc<GpuKernels>,
    /// Makes the canvas of a new session.
    new_canvas: NewCanvas<C>,
    /// Decides the views' precision ([`Planner::for_view`]).
    planner: Planner,
    views: Views<C>,
    /// The path tracer's views, built at the first path-traced view; Err: it cannot run here,
    /// and why (the tracer's view stands in).
    path_views: Option<Result<Views<C>, String>>,
    /// Whether the path tracer's view is the one shown.
    path_shown: bool,
}

impl<C: Canvas> LiveView<C> {
    /// The view on the f32 tracer of `kernels` (built now: a shader the device rejects is an
    /// error); the f64 one is taken from them at the first deep view, the path tracer's at the
    /// first path-traced view. Each session shows its images on a canvas of `new_canvas`.
    pub fn new(kernels: Arc<GpuKernels>, new_canvas: NewCanvas<C>) -> crate::Result<Self> {
        let view = Session::new(
            ViewKernel::Phong(kernels.tracer()?),
            new_canvas(),
            kernels.clone(),
        );
        Ok(Self {
            new_canvas,
            planner: Planner::for_view(kernels.clone()),
            kernels,
            views: PrecisionSwitch::new(view),
            path_views: None,
            path_shown: false,
        })
    }

    /// Renders `scene` at `size` in the precision it needs, with the path tracer where it is
    /// path traced (`shading.model = "path"`, the shaded view), as [`Session::update`].
    pub fn update(&mut self, scene: &Scene, size: [u32; 2], interacting: bool) {
        let kernels = &self.kernels;
        let picture = Picture::Slice {
            shade: scene.image.view.needs_shading(),
        };
        self.path_shown = false;
        if picture.path_traced(scene) {
            let new_canvas = &self.new_canvas;
            let slot = self.path_views.get_or_insert_with(|| {
                let tracer = kernels.path().map_err(|e| e.to_string())?;
                let view = Session::new(ViewKernel::Path(tracer), new_canvas(), kernels.clone());
                Ok(PrecisionSwitch::new(view))
            });
            if let Ok(views) = slot {
                self.path_shown = true;
                let build = |_: &Session<f32, C>| {
                    let path64 = ViewKernel::Path(kernels.path_in::<f64>()?);
                    Ok(Session::new(path64, new_canvas(), kernels.clone()))
                };
                match views.pick(&self.planner, scene, Picture::SHADED, build) {
                    Either::F32(view) => view.update(scene, size, interacting),
                    Either::F64(view) => view.update(scene, size, interacting),
                }
                self.release_hidden();
                return;
            }
        }
        let new_canvas = &self.new_canvas;
        let build = |_: &Session<f32, C>| {
            let tracer64 = ViewKernel::Phong(kernels.tracer_in::<f64>()?);
            Ok(Session::new(tracer64, new_canvas(), kernels.clone()))
        };
        match self
            .views
            .pick(&self.planner, scene, Picture::SHADED, build)
        {
            Either::F32(view) => view.update(scene, size, interacting),
            Either::F64(view) => view.update(scene, size, interacting),
        }
        self.release_hidden();
    }

    /// Gives back the memory of every view but the one shown ([`Session::release`]).
    fn release_hidden(&mut self) {
        let path = self.path_shown;
        self.views
            .release_hidden(path, Session::release, Session::release);
        if let Some(Ok(views)) = &mut self.path_views {
            views.release_hidden(!path, Session::release, Session::release);
        }
    }

    /// Gives back the memory of every view (2D mode shows none of them).
    pub fn release(&mut self) {
        self.views
            .release_hidden(true, Session::release, Session::release);
        if let Some(Ok(views)) = &mut self.path_views {
            views.release_hidden(true, Session::release, Session::release);
        }
    }

    /// The views shown: the path tracer's or the tracer's.
    fn shown(&self) -> &Views<C> {
        match (&self.path_views, self.path_shown) {
            (Some(Ok(views)), true) => views,
            _ => &self.views,
        }
    }

    /// The canvas of the view shown, to change.
    pub fn shown_canvas_mut(&mut self) -> &mut C {
        let views = match (&mut self.path_views, self.path_shown) {
            (Some(Ok(views)), true) => views,
            _ => &mut self.views,
        };
        match views.shown_mut() {
            Either::F32(view) => view.canvas_mut(),
            Either::F64(view) => view.canvas_mut(),
        }
    }

    /// Whether the view shown is path traced.
    pub fn path_traced(&self) -> bool {
        self.path_shown
    }

    /// Why path mode cannot run here, if it was asked for and cannot.
    pub fn path_unavailable(&self) -> Option<&str> {
        self.path_views.as_ref()?.as_ref().err().map(String::as_str)
    }

    /// The precision of the view shown.
    pub fn precision(&self) -> Precision {
        self.shown().precision()
    }

    /// Why the view runs in its precision (the status line's hover text).
    pub fn precision_note(&self) -> &str {
        self.shown().reason()
    }

    pub fn stats(&self) -> &TextureStats {
        on_shown!(self.shown(), view => view.stats())
    }

    /// Whether the view shown waits for its pipeline to be built.
    pub fn building_pipeline(&self) -> bool {
        on_shown!(self.shown(), view => view.building_pipeline())
    }

    /// The image shown, once there is one: the canvas it is on, its quality (which of the
    /// canvas's textures) and its size in pixels.
    pub fn shown_image(&self) -> Option<(&C, Quality, [u32; 2])> {
        on_shown!(self.shown(), view => view.shown().map(|(q, size)| (view.canvas(), q, size)))
    }

    /// When the render of the image shown began ([`Session::shown_began`]).
    pub fn shown_began(&self) -> Option<std::time::Instant> {
        on_shown!(self.shown(), view => view.shown_began())
    }

    pub fn busy(&self) -> bool {
        on_shown!(self.shown(), view => view.busy())
    }

    pub fn is_refined(&self, scene: &Scene, size: [u32; 2]) -> bool {
        on_shown!(self.shown(), view => view.is_refined(scene, size))
    }

    /// Tiles dispatched by every view since they were made (a trace of any of them adds to it).
    pub fn dispatches(&self) -> u64 {
        let mut all = vec![&self.views];
        all.extend(self.path_views.as_ref().and_then(|v| v.as_ref().ok()));
        all.iter()
            .map(|v| on_both(v, |d, e| d + e, Session::dispatches, Session::dispatches))
            .sum()
    }

    /// Path mode: images the shown view encoded on the host from radiance.
    pub fn encodes(&self) -> u64 {
        on_shown!(self.shown(), view => view.encodes())
    }

    /// Path mode: the radiance of the image shown, its size and its samples.
    pub fn kept_radiance(&self) -> Option<&KeptRadiance> {
        on_shown!(self.shown(), view => view.kept_radiance())
    }
}

/// `f32(view)` and, where the f64 view was built, `f64(view)`, joined by `join`.
fn on_both<R: Default, C: Canvas>(
    views: &Views<C>,
    join: impl Fn(R, R) -> R,
    f32: impl Fn(&Session<f32, C>) -> R,
    f64: impl Fn(&Session<f64, C>) -> R,
) -> R {
    let deep = views.f64_view().map_or_else(R::default, f64);
    join(f32(views.f32_view()), deep)
}
