//! The animation timeline, in three: the keyframed animation as the explorer edits it, with no
//! egui in it ([`model`]); the strip under the view and the "Render animation…" window that
//! edit it ([`panel`]); and the render job that runs its frames through `qjulia animate`'s own
//! code on a thread ([`job`]).

pub mod job;
pub mod model;
pub mod panel;

pub use model::Timeline;
