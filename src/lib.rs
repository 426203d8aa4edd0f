//! qjulia: ray tracing quaternion Julia sets after Keenan Crane (2005), on the GPU with wgpu
//! compute and on the CPU with a pure-Rust twin of the shader that the GPU is held to.
//!
//! The flow: a [`Scene`] (plain data) becomes [`TraceParams`]; a [`Renderer`] (the [`gpu`] or
//! [`cpu`] tracer, chosen in one place: [`Planner::plan`]) turns those into a [`Frame`] and its
//! [`RenderStats`]; [`output`] writes them.

pub mod algebra;
#[cfg(feature = "gpu")]
pub mod animate;
pub mod compare;
pub mod cpu;
pub mod denoise;
pub mod display;
pub mod envmap;
pub mod error;
pub mod estimate;
#[cfg(feature = "gpu")]
pub mod explore;
pub mod frame;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod grid;
pub mod hdr;
pub mod heatmap;
pub mod memory;
pub mod mesh;
pub mod output;
pub mod params;
pub mod picture;
pub mod precision;
#[cfg(feature = "gpu")]
pub mod render;
#[cfg(feature = "gpu")]
pub mod report;
pub mod scene;
pub mod stats;
pub mod tile;
pub mod uniform;
pub mod video;
#[cfg(feature = "gpu")]
pub mod web;

pub use error::{Error, Result};
pub use frame::Frame;
pub use params::{Julia2dParams, TraceParams};
pub use precision::{Precision, PrecisionChoice};
#[cfg(feature = "gpu")]
pub use render::{
    Backend, GPU_F64_UNSUPPORTED, Picture, Plan, Planner, Readback, Renderer, Work, band_pixels,
};
pub use scene::Scene;
/// The `[animation]` table, a part of the scene model ([`scene::animation`]).
pub use scene::animation;
pub use stats::{RenderStats, Summary};
