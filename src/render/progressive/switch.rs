//! The live views in two precisions: f32 wherever f32 resolves the view, and f64 on the GPU
//! where it does not (the rule of `--precision auto`, as the planner for views decides it:
//! [`crate::render::Planner::for_view`]), switched by itself as the view zooms in and out. The
//! f64 view is built on the first deep view, on the same device; where the device has no f64
//! (or fails its start-up check), the view stays in f32 and the reason says why. The 3D view
//! ([`super::live::LiveView`]) and the explorer's 2D view both switch through it.

use crate::precision::Precision;
use crate::render::{Picture, Planner};
use crate::scene::Scene;

/// One of the two views.
pub enum Either<A, B> {
    F32(A),
    F64(B),
}

/// An f32 view, and the f64 view beside it once one was needed.
pub struct PrecisionSwitch<A, B> {
    f32_view: A,
    /// Built on first need; Err: f64 cannot run on this device, and why.
    f64_view: Option<Result<B, String>>,
    /// The precision of the view shown, and why (for the status line).
    active: Precision,
    reason: String,
}

impl<A, B> PrecisionSwitch<A, B> {
    pub fn new(f32_view: A) -> Self {
        Self {
            f32_view,
            f64_view: None,
            active: Precision::F32,
            reason: String::new(),
        }
    }

    /// The f32 view (on whose device the f64 one is built).
    pub fn f32_view(&self) -> &A {
        &self.f32_view
    }

    /// The f64 view, once built.
    pub fn f64_view(&self) -> Option<&B> {
        self.f64_view.as_ref()?.as_ref().ok()
    }

    /// The view `picture` of `scene` needs, as `planner` decides ([`Planner::for_view`]: the
    /// auto rule, and f32 on the GPU where f64 cannot run); the f64 one built with `build`
    /// (from the f32 one) the first time it is needed.
    pub fn pick(
        &mut self,
        planner: &Planner,
        scene: &Scene,
        picture: Picture,
        build: impl FnOnce(&A) -> crate::Result<B>,
    ) -> Either<&mut A, &mut B> {
        let decision = planner.decide(scene, &picture.into());
        self.reason = decision.reason;
        self.active = Precision::F32;
        if decision.precision == Precision::F64 {
            let f32_view = &self.f32_view;
            let built = self
                .f64_view
                .get_or_insert_with(|| build(f32_view).map_err(|e| e.to_string()));
            match built {
                Ok(view) => {
                    self.active = Precision::F64;
                    return Either::F64(view);
                }
                Err(why) => self.reason = format!("{}; f64 unavailable: {why}", self.reason),
            }
        }
        Either::F32(&mut self.f32_view)
    }

    /// Calls `release` on each view built that is not the one shown (`all`: on every view).
    pub fn release_hidden(
        &mut self,
        all: bool,
        release_f32: impl FnOnce(&mut A),
        release_f64: impl FnOnce(&mut B),
    ) {
        let active = self.active;
        if all || active != Precision::F32 {
            release_f32(&mut self.f32_view);
        }
        if let Some(Ok(view)) = &mut self.f64_view
            && (all || active != Precision::F64)
        {
            release_f64(view);
        }
    }

    /// The view shown now.
    pub fn shown(&self) -> Either<&A, &B> {
        match (&self.active, &self.f64_view) {
            (Precision::F64, Some(Ok(view))) => Either::F64(view),
            _ => Either::F32(&self.f32_view),
        }
    }

    /// The view shown now, to change.
    pub fn shown_mut(&mut self) -> Either<&mut A, &mut B> {
        match (&self.active, &mut self.f64_view) {
            (Precision::F64, Some(Ok(view))) => Either::F64(view),
            _ => Either::F32(&mut self.f32_view),
        }
    }

    /// The precision of the view shown.
    pub fn precision(&self) -> Precision {
        self.active
    }

    /// Why the view runs in its precision (the status line's hover text).
    pub fn reason(&self) -> &str {
        &self.reason
    }
}
