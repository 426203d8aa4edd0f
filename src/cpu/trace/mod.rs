//! The CPU twin of shaders/trace.wgsl and of the parts it imports, one module each with the
//! part's name (estimate, cut, march, normal, shading, colour, camera, atmosphere, accumulate):
//! the same functions, with the same names, in the same order, generic over the float type
//! (tests/architecture/twins.rs checks names and order, and lists the functions only one side
//! has, each with its reason). WGSL's global `params` is `self` here; a change to one file is a
//! change to both, and the GPU-vs-CPU tests hold them together. This module is the root's twin
//! (`shade_pixel`, `trace_pixel`) and re-exports the parts' items, so that they are all
//! `cpu::trace::X`; the kernel's `main` is cpu/mod.rs's `render_rows`.

mod accumulate;
mod atmosphere;
mod camera;
mod colour;
mod cut;
mod estimate;
mod march;
mod normal;
mod shading;

pub use accumulate::{
    Aovs, Halves, NOISE_LUMINANCE_FLOOR, Pixel, STREAM_SHIFT, Streams, add_aovs, add_luminance,
    add_m2, add_to_halves, finish_aovs, halves_mean, lens_position, pack_colour, pixel_noise,
    sample_luminance, sample_position, streams_halves, streams_mean,
};
pub use camera::{CONE_BLOCK, CONE_MARGIN, Primary, Ray};
pub use estimate::TINY;
pub use march::{Interval, March, NO_APPROACH, Trace};
pub use normal::{NORMAL_LIMIT, safe_normalize};
pub use shading::{OCCLUSION_SAMPLES, OCCLUSION_STEP};

use super::{ESTIMATES, ITERATIONS, bsdf};
use crate::algebra::{Real, Vec3};
use crate::params::TraceParams;

impl<F: Real> TraceParams<F> {
    /// A sample's outcome from its camera ray and the ray's trace: normal, Phong, shadow, and
    /// the atmosphere over them. `shade` is the kernel's SHADE override (false: depth and steps only, as a specialised
    /// pipeline without the shading code): the colour is the background.
    pub fn shade_pixel(&self, ray: &Primary<F>, trace: Trace<F>, shade: bool) -> Pixel<F> {
        let none = Vec3::zero();
        if !trace.hit {
            return Pixel {
                colour: self.atmosphere(self.background(ray.dir), ray, trace),
                depth: -F::one(),
                steps: trace.steps,
                hit: false,
                point: none,
                normal: none,
            };
        }
        if !shade {
            return Pixel {
                colour: self.background,
                depth: trace.t,
                steps: trace.steps,
                hit: true,
                point: none,
                normal: none,
            };
        }
        let (origin, dir) = (ray.origin, ray.dir);
        let p = origin + dir * trace.t;
        let n = self.estimate_normal(p, dir);
        if self.shading_features() {
            return Pixel {
                colour: self.atmosphere(self.shade_features(p, n, origin), ray, trace),
                depth: trace.t,
                steps: trace.steps,
                hit: true,
                point: p,
                normal: n,
            };
        }
        let mut colour = self.phong(self.light, origin, p, n);
        // An unlit point (black: the light is behind its surface) stays black in shadow: no ray.
        let lit = colour.x > F::zero() || colour.y > F::zero() || colour.z > F::zero();
        if self.shadows_on() && lit && self.in_shadow(p, n) {
            colour = colour * self.shadow_factor;
        }
        Pixel {
            colour: self.atmosphere(colour, ray, trace),
            depth: trace.t,
            steps: trace.steps,
            hit: true,
            point: p,
            normal: n,
        }
    }

    /// Everything for one sample of pixel (i, j): its camera ray (`primary_ray`), sphere
    /// tracing, and shading (`shade_pixel`).
    pub fn trace_pixel(&self, i: u32, j: u32, sample: u32, t_min: F, shade: bool) -> Pixel<F> {
        let ray = self.primary_ray(i, j, sample, t_min);
        self.shade_pixel(&ray, self.trace_primary(&ray), shade)
    }
}
