//! The pure-Rust reference tracer: shaders/*.wgsl written again in Rust, generic over f32 and
//! f64, parallel over rows with rayon. The tests hold the GPU to it.

pub mod trace;

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use crate::algebra::Real;
use crate::frame::Frame;
use crate::params::TraceParams;

/// Renders every pixel of the scene the parameters describe; returns the frame and the seconds
/// it took.
pub fn render<F: Real>(params: &TraceParams<F>) -> (Frame, f64) {
    let start = Instant::now();
    let (w, h) = (params.width as usize, params.height as usize);
    let mut colour = vec![0u32; w * h];
    let mut depth = vec![0f32; w * h];
    let mut steps = vec![0u32; w * h];
    let non_finite = AtomicU64::new(0);
    colour
        .par_chunks_mut(w)
        .zip(depth.par_chunks_mut(w))
        .zip(steps.par_chunks_mut(w))
        .enumerate()
        .for_each(|(j, ((colour_row, depth_row), steps_row))| {
            for i in 0..w {
                let pixel = params.trace_pixel(i as u32, j as u32);
                let c = pixel.colour;
                let bad = [c.x, c.y, c.z, pixel.depth]
                    .iter()
                    .filter(|v| !v.is_finite())
                    .count();
                if bad > 0 {
                    non_finite.fetch_add(bad as u64, Ordering::Relaxed);
                }
                colour_row[i] = trace::pack_colour(pixel.colour);
                depth_row[i] = if pixel.hit {
                    pixel.depth.to_f64() as f32
                } else {
                    f32::NAN
                };
                steps_row[i] = pixel.steps;
            }
        });
    let frame = Frame {
        width: params.width,
        height: params.height,
        colour,
        depth,
        steps,
        non_finite: non_finite.into_inner(),
    };
    (frame, start.elapsed().as_secs_f64())
}
