//! The renderer, held to its CPU twin and to answers known without it: every picture feature
//! and both models on the GPU against the twin in f32 and f64, the samplers, BSDF, lights and
//! display transform against their definitions, and the GPU runtime under them (the kernel
//! runner, its pipelines, the uniforms' layout, memory over many renders).
//!
//! One test crate (as Cargo's own testsuite is): each file a module, tests/common compiled once.
//! Tests that need a GPU fail without an adapter unless `QJULIA_SKIP_GPU_TESTS=1`; a part that
//! needs a capability the adapter lacks (f64 on the GPU) is skipped with a `skipped:` line,
//! except under CI on a backend that has it (`common::Capability`). The tests that need a
//! process of their own (a process-wide variable, resident memory) run themselves in a child
//! process (`common::own_process`).

mod adaptive;
mod adaptive_bias;
mod algebra;
mod atmosphere;
mod baked_pipelines;
mod bsdf;
#[path = "../common/mod.rs"]
mod common;
mod cut;
mod denoise;
mod display;
mod environment;
mod error_estimate;
mod exact;
mod gpu_f64;
mod gpu_params;
mod gpu_vs_cpu;
mod interleave;
mod julia2d;
mod kernel;
mod kernel_fuzz;
mod light;
mod multiscatter;
mod path;
mod path_convergence;
mod path_extremes;
mod path_mode;
mod path_regularize;
mod pipeline_bound;
mod repeated_renders;
mod samples;
mod shading;
mod sobol;
mod stability;
mod thin_lens;
