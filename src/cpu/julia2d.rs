//! The CPU twin of shaders/julia2d.wgsl (the 2D Julia view): the same functions, with the same
//! names, in the same order, generic over the float type (tests/architecture/twins.rs checks names and order,
//! and lists the functions only one side has). WGSL's global `params` is `self` here; a change to
//! one file is a change to both, and the GPU-vs-CPU tests hold them together. The kernel's `main`
//! is `julia_pixel` and `render_rows` here.

use crate::algebra::{Real, Vec2};
use crate::frame::Frame;
use crate::params::Julia2dParams;

/// |z|^2 above this counts as escaped: |z| > 16, far enough out that the smooth count is smooth
/// (above 2, the escape radius of every c with |c| <= 2, the orbit only grows).
pub const BAILOUT_SQUARED: f64 = 256.0;

/// z^2 for z = x + y i.
pub fn complex_sq<F: Real>(z: Vec2<F>) -> Vec2<F> {
    Vec2::new(z.x * z.x - z.y * z.y, F::lit(2.0) * z.x * z.y)
}

impl<F: Real> Julia2dParams<F> {
    /// The complex number at the centre of pixel (i, j), row 0 at the top: the imaginary axis
    /// points up.
    pub fn pixel_point(&self, i: u32, j: u32) -> Vec2<F> {
        let (one, two, half) = (F::one(), F::lit(2.0), F::lit(0.5));
        let x = (two * (F::lit(i as f64) + half) / F::lit(self.width as f64) - one)
            * self.half_extent.x;
        let y = (one - two * (F::lit(j as f64) + half) / F::lit(self.height as f64))
            * self.half_extent.y;
        self.center + Vec2::new(x, y)
    }
}

/// Where an orbit ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Escape<F> {
    /// The last z reached: the first with |z|^2 > BAILOUT_SQUARED when escaped.
    pub z: Vec2<F>,
    /// Iterations made.
    pub n: u32,
    pub escaped: bool,
}

impl<F: Real> Julia2dParams<F> {
    /// Iterates z <- z^2 + c from z0, testing |z|^2 > BAILOUT_SQUARED before each iteration:
    /// z_0, ..., z_max_iterations are tested, and a point none of them escapes is in the set.
    pub fn escape(&self, z0: Vec2<F>) -> Escape<F> {
        let mut z = z0;
        let mut n = 0;
        let mut escaped = false;
        loop {
            if z.dot(z) > F::lit(BAILOUT_SQUARED) {
                escaped = true;
                break;
            }
            if n >= self.max_iterations {
                break;
            }
            z = complex_sq(z) + self.c;
            n += 1;
        }
        Escape { z, n, escaped }
    }
}

/// The smooth iteration count of an escaped point, n - log2(ln|z_n| / ln 16), clamped at 0:
/// n where |z_n| is just above 16, continuous across n (z_n squares from one n to the next).
pub fn smooth_count<F: Real>(e: Escape<F>) -> F {
    let ratio = e.z.dot(e.z).ln() / F::lit(BAILOUT_SQUARED).ln();
    (F::lit(e.n as f64) - ratio.log2()).max(F::zero())
}

impl<F: Real> Julia2dParams<F> {
    /// Grey of a point: ln(1 + smooth count) / ln(1 + max_iterations), 0 (black) for a point
    /// that escapes at once, 1 (white) for one in the set.
    pub fn grey(&self, e: Escape<F>) -> F {
        if !e.escaped {
            return F::one();
        }
        let one = F::one();
        ((one + smooth_count(e)).ln() / (one + F::lit(self.max_iterations as f64)).ln()).min(one)
    }
}

/// Grey clamped to [0, 1], times 255, rounded half up, packed as RGBA8 0xFFBBGGRR (opaque).
pub fn pack_grey<F: Real>(g: F) -> u32 {
    let g = g.max(F::zero()).min(F::one());
    let v = (g * F::lit(255.0) + F::lit(0.5)).floor().to_f64() as u32;
    v | (v << 8) | (v << 16) | 0xff00_0000
}

impl<F: Real> Julia2dParams<F> {
    /// Everything for pixel (i, j), as the kernel's `main` writes it: the packed grey, whether
    /// the point is in the set, and the iterations made.
    pub fn julia_pixel(&self, i: u32, j: u32) -> (u32, bool, u32) {
        let e = self.escape(self.pixel_point(i, j));
        (pack_grey(self.grey(e)), !e.escaped, e.n)
    }
}

/// Renders the rows `rows` (0 at the top) of the 2D view, in parallel over rows: colour the
/// grey, depth 0 in the set and NaN outside it (as a miss), steps the iterations made.
pub fn render_rows<F: Real>(params: &Julia2dParams<F>, rows: std::ops::Range<u32>) -> Frame {
    super::fill_rows(params.width, rows, super::Keep::default(), |j| {
        move |i| {
            let (grey, inside, n) = params.julia_pixel(i, j);
            super::PixelOut {
                colour: grey,
                depth: if inside { 0.0 } else { f64::NAN },
                steps: n,
                non_finite: 0,
                estimates: n as u64,
                iterations: n as u64,
                radiance: [0.0; 3],
                halves: Default::default(),
                aovs: Default::default(),
                samples: 1,
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn params(c: [f64; 2], extent: f64, size: u32) -> Julia2dParams<f64> {
        let mut scene = Scene::default();
        scene.fractal.c = vec![c[0], c[1], 0.0, 0.0];
        scene.view2d.extent = extent;
        scene.image.width = size;
        scene.image.height = size;
        Julia2dParams::new(&scene)
    }

    #[test]
    fn c_zero_has_the_closed_form_smooth_count() {
        // For c = 0, z_n = z0^(2^n): the smooth count is log2(ln 16 / ln r) for |z0| = r > 1,
        // whatever n the escape happens at.
        let p = params([0.0, 0.0], 4.0, 8);
        for r in [1.001f64, 1.01, 1.3, 2.0, 3.9, 15.9] {
            let e = p.escape(Vec2::new(r * 0.6, r * 0.8));
            assert!(e.escaped, "{r}");
            let expected = (16f64.ln() / r.ln()).log2();
            assert!((smooth_count(e) - expected).abs() < 1e-9, "r = {r}");
        }
        // Inside the unit disk nothing escapes; beyond 16 everything does at once.
        let inside = p.escape(Vec2::new(0.5, -0.7));
        assert!(!inside.escaped && inside.n == 256 && p.grey(inside) == 1.0);
        let far = p.escape(Vec2::new(-20.0, 3.0));
        assert!(far.escaped && far.n == 0 && p.grey(far) == 0.0);
    }

    #[test]
    fn pixels_are_centred_and_the_imaginary_axis_points_up() {
        let p = params([0.0, 0.0], 4.0, 4);
        // Pixel centres of a 4x4 image over [-2, 2]^2: -1.5, -0.5, 0.5, 1.5.
        assert_eq!(p.pixel_point(0, 0), Vec2::new(-1.5, 1.5));
        assert_eq!(p.pixel_point(3, 3), Vec2::new(1.5, -1.5));
        assert_eq!(p.pixel_point(2, 1), Vec2::new(0.5, 0.5));
        // A wide image shows the extent across and as much as its aspect allows up.
        let mut scene = Scene::default();
        scene.image.width = 8;
        scene.image.height = 2;
        let wide = Julia2dParams::<f64>::new(&scene);
        assert_eq!(wide.half_extent, Vec2::new(2.0, 0.5));
    }

    #[test]
    fn grey_is_monotone_in_the_escape_time() {
        let p = params([0.0, 0.0], 4.0, 8);
        let mut last = -1.0;
        for r in [40.0, 15.0, 5.0, 2.0, 1.2, 1.02, 1.0001] {
            let g = p.grey(p.escape(Vec2::new(r, 0.0)));
            assert!(
                g > last || (g == 0.0 && last == 0.0),
                "r = {r}: {g} after {last}"
            );
            last = g;
        }
    }
}
