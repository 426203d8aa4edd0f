//! The CPU twin of shaders/denoise.wgsl: one pass of the edge-avoiding a-trous filter, function
//! by function (same names, same order; tests/architecture/twins.rs). [`crate::denoise`] runs the passes on
//! either side and demodulates and remodulates the image around them.

use rayon::prelude::*;

use super::bsdf;
use crate::algebra::Vec3;

/// One pass's parameters, as the shader's `DenoiseParams` (src/gpu/denoise.rs packs them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseParams {
    pub width: u32,
    pub height: u32,
    /// The taps' spacing in pixels, 2^pass.
    pub step: u32,
    pub sigma_luminance: f32,
    pub sigma_normal: f32,
    pub sigma_depth: f32,
}

/// A relative floor on the depth test's scale (of the centre's depth), as the shader's.
pub const DEPTH_EPSILON: f32 = 1e-3;
/// A floor on the luminance test's scale, where the variance is 0, as the shader's.
pub const LUMINANCE_EPSILON: f32 = 1e-10;

/// One pass over an image: its parameters, the image it reads (each pixel's illumination and
/// the variance of its luminance) and the guides (mean normal, depth or -1 on a miss).
pub struct Pass<'a> {
    pub params: DenoiseParams,
    pub source: &'a [[f32; 4]],
    pub guide: &'a [[f32; 4]],
}

fn xyz(v: [f32; 4]) -> Vec3<f32> {
    Vec3::new(v[0], v[1], v[2])
}

/// Rec. 709 luminance of a linear colour.
pub fn luminance(c: Vec3<f32>) -> f32 {
    bsdf::luminance(c)
}

/// The B3-spline's weight of tap k in -2..2: 1/16, 1/4, 3/8, 1/4, 1/16.
pub fn spline_tap(k: i32) -> f32 {
    match k.abs() {
        0 => 0.375,
        1 => 0.25,
        _ => 0.0625,
    }
}

impl Pass<'_> {
    pub fn load_image(&self, index: usize) -> [f32; 4] {
        self.source[index]
    }
}

/// Whether a guide is a hit's (its depth is not the miss marker).
pub fn guide_hit(g: [f32; 4]) -> bool {
    g[3] >= 0.0
}

impl Pass<'_> {
    /// The depth of pixel (i, j), or -1 outside the image or where it missed.
    pub fn depth_at(&self, i: i32, j: i32) -> f32 {
        let p = &self.params;
        if i < 0 || j < 0 || i >= p.width as i32 || j >= p.height as i32 {
            return -1.0;
        }
        self.guide[j as usize * p.width as usize + i as usize][3]
    }

    /// The change of depth per pixel at (i, j) along x and y: the central difference where
    /// both neighbours hit, one-sided where one does, 0 where none does (or the centre missed).
    pub fn depth_slope(&self, i: i32, j: i32) -> [f32; 2] {
        let z = self.depth_at(i, j);
        if z < 0.0 {
            return [0.0, 0.0];
        }
        [
            axis_slope(self.depth_at(i - 1, j), z, self.depth_at(i + 1, j)),
            axis_slope(self.depth_at(i, j - 1), z, self.depth_at(i, j + 1)),
        ]
    }
}

pub fn axis_slope(before: f32, z: f32, after: f32) -> f32 {
    if before >= 0.0 && after >= 0.0 {
        return 0.5 * (after - before);
    }
    if after >= 0.0 {
        return after - z;
    }
    if before >= 0.0 {
        return z - before;
    }
    0.0
}

impl Pass<'_> {
    /// The variance at (i, j) blurred by a 3 x 3 binomial kernel (1 2 1 / 4 each way) over the
    /// pixels inside the image, renormalised: SVGF's prefilter. The pass takes the smaller of
    /// it and the pixel's own: a firefly's variance, blurred, would open its neighbours to it.
    pub fn blurred_variance(&self, i: i32, j: i32) -> f32 {
        let p = &self.params;
        let (mut sum, mut weights) = (0.0f32, 0.0f32);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (x, y) = (i + dx, j + dy);
                if x < 0 || y < 0 || x >= p.width as i32 || y >= p.height as i32 {
                    continue;
                }
                let w = if dx == 0 { 1.0 } else { 0.5 } * if dy == 0 { 1.0 } else { 0.5 };
                sum += w * self.load_image(y as usize * p.width as usize + x as usize)[3];
                weights += w;
            }
        }
        sum / weights
    }
}

/// A vector of length 1 along v, or 0 where v is 0.
pub fn unit_or_zero(v: Vec3<f32>) -> Vec3<f32> {
    let l = v.length();
    if l > 0.0 { v / l } else { Vec3::zero() }
}

impl Pass<'_> {
    /// How alike a tap's geometry is to the centre's: 0 between a hit and a miss, 1 between two
    /// misses; between two hits the normals' cosine to the power sigma_normal, times
    /// exp(-|z_p - z_q| / (sigma_depth |slope . offset| + DEPTH_EPSILON z_p)).
    pub fn geometry_weight(
        &self,
        p: [f32; 4],
        q: [f32; 4],
        slope: [f32; 2],
        offset: [f32; 2],
    ) -> f32 {
        let hit = guide_hit(p);
        if hit != guide_hit(q) {
            return 0.0;
        }
        if !hit {
            return 1.0;
        }
        let params = &self.params;
        let mut w = 1.0;
        if params.sigma_normal > 0.0 {
            let c = unit_or_zero(xyz(p)).dot(unit_or_zero(xyz(q)));
            if c <= 0.0 {
                return 0.0;
            }
            w = c.powf(params.sigma_normal);
        }
        if params.sigma_depth > 0.0 {
            let along = (slope[0] * offset[0] + slope[1] * offset[1]).abs();
            let scale = params.sigma_depth * along + DEPTH_EPSILON * p[3];
            w *= (-(p[3] - q[3]).abs() / scale.max(1e-30)).exp();
        }
        w
    }

    /// How alike a tap's luminance is to the centre's, in standard deviations of the centre's
    /// noise: exp(-|l_p - l_q| / (sigma_luminance sd + LUMINANCE_EPSILON)).
    pub fn luminance_weight(&self, lp: f32, lq: f32, sd: f32) -> f32 {
        let s = self.params.sigma_luminance;
        if s <= 0.0 {
            return 1.0;
        }
        (-(lp - lq).abs() / (s * sd + LUMINANCE_EPSILON)).exp()
    }

    /// Pixel (i, j) after this pass: the weighted mean of its 5 x 5 taps' illumination (the
    /// centre's weight is its spline weight alone), and the taps' variances weighted by the
    /// squared weights over the squared sum.
    pub fn atrous_main(&self, i: i32, j: i32) -> [f32; 4] {
        let params = &self.params;
        let width = params.width as usize;
        let index = j as usize * width + i as usize;
        let centre = self.load_image(index);
        let g = self.guide[index];
        let slope = self.depth_slope(i, j);
        let sd = self.blurred_variance(i, j).min(centre[3]).sqrt();
        let lp = luminance(xyz(centre));
        let step = params.step as i32;
        let mut sum = Vec3::zero();
        let (mut weights, mut variance) = (0.0f32, 0.0f32);
        for dy in -2..=2 {
            for dx in -2..=2 {
                let (x, y) = (i + dx * step, j + dy * step);
                if x < 0 || y < 0 || x >= params.width as i32 || y >= params.height as i32 {
                    continue;
                }
                let q_index = y as usize * width + x as usize;
                let q = self.load_image(q_index);
                let mut w = spline_tap(dx) * spline_tap(dy);
                if dx != 0 || dy != 0 {
                    let offset = [(dx * step) as f32, (dy * step) as f32];
                    w *= self.geometry_weight(g, self.guide[q_index], slope, offset);
                    w *= self.luminance_weight(lp, luminance(xyz(q)), sd);
                }
                sum += xyz(q) * w;
                weights += w;
                variance += w * w * q[3];
            }
        }
        let mean = sum / weights;
        [mean.x, mean.y, mean.z, variance / (weights * weights)]
    }

    /// The whole pass, rows in parallel: the image after it (the shader's dispatch).
    pub fn atrous_pass(&self) -> Vec<[f32; 4]> {
        let (w, h) = (self.params.width as usize, self.params.height as usize);
        let mut out = vec![[0.0; 4]; w * h];
        out.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
            for (i, v) in row.iter_mut().enumerate() {
                *v = self.atrous_main(i as i32, j as i32);
            }
        });
        out
    }
}
