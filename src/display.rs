//! The display transform of path mode: linear radiance to the 8-bit sRGB a PNG holds. One
//! function serves every output that shows a path-traced picture (the PNG, the explorer's view,
//! `merge`), so that they give the same bytes. Phong mode keeps the seed's clamp, mean and
//! round, with no curve, and does not come here.
//!
//! The chain, per channel, in f64: exposure (`x 2^exposure`), the tone map, the sRGB transfer
//! function, then rounding to 8 bits (`floor(255 v + 0.5)`). The book's chapter "Display"
//! (docs/book/display.md) gives the formulas.

use rayon::prelude::*;

pub use crate::scene::ToneMap;

/// The curve itself, here with the display transform (the enum is scene data, in the scene).
impl ToneMap {
    /// The curve at `x >= 0` (exposure applied), in [0, 1]; NaN and negative values give 0.
    pub fn apply(self, x: f64) -> f64 {
        // `max` keeps a NaN out: f64::max returns the other operand.
        let x = x.max(0.0);
        let y = match self {
            ToneMap::None => x,
            ToneMap::Reinhard => reinhard(x),
            ToneMap::Aces => aces_narkowicz(x),
        };
        y.clamp(0.0, 1.0)
    }
}

/// Reinhard's simple operator, `x / (1 + x)`.
pub fn reinhard(x: f64) -> f64 {
    x / (1.0 + x)
}

/// Narkowicz's 2015 ACES fit, `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, unclamped.
pub fn aces_narkowicz(x: f64) -> f64 {
    x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)
}

/// The sRGB transfer function (IEC 61966-2-1) of `v` in [0, 1]: `12.92 v` up to 0.0031308,
/// `1.055 v^(1/2.4) - 0.055` above.
pub fn srgb_encode(v: f64) -> f64 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// `v` in [0, 1] rounded to 8 bits: `floor(255 v + 0.5)`.
pub fn quantise(v: f64) -> u8 {
    (255.0 * v.clamp(0.0, 1.0) + 0.5).floor() as u8
}

/// The display transform: `image.exposure` (stops) and `image.tone_map`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Display {
    pub exposure: f64,
    pub tone_map: ToneMap,
}

impl Display {
    /// A scene's display transform (`image.exposure`, `image.tone_map`).
    pub fn of(scene: &crate::scene::Scene) -> Self {
        Self {
            exposure: scene.image.exposure,
            tone_map: scene.image.tone_map,
        }
    }

    /// A pixel's linear radiance as the frames' packed colour, 0xFFBBGGRR.
    pub fn pack(&self, linear: [f32; 3]) -> u32 {
        let [r, g, b] = linear.map(|c| self.encode(c) as u32);
        0xFF00_0000 | (b << 16) | (g << 8) | r
    }

    /// A path-traced frame's colour, made of its radiance: what `render` and `merge` show.
    pub fn show(&self, frame: &mut crate::frame::Frame) {
        frame.colour = self.pack_all(&frame.radiance);
    }

    /// The packed colours of linear RGB triples, in parallel.
    pub fn pack_all(&self, linear: &[[f32; 3]]) -> Vec<u32> {
        linear.par_iter().map(|&c| self.pack(c)).collect()
    }

    /// One channel of linear radiance as its 8-bit sRGB value.
    pub fn encode(&self, linear: f32) -> u8 {
        let exposed = linear as f64 * self.exposure.exp2();
        quantise(srgb_encode(self.tone_map.apply(exposed)))
    }

    /// Linear RGB triples (row by row) as 8-bit sRGB bytes, in parallel.
    pub fn rgb8(&self, linear: &[[f32; 3]]) -> Vec<u8> {
        let mut out = vec![0; linear.len() * 3];
        out.par_chunks_mut(3 * 4096)
            .zip(linear.par_chunks(4096))
            .for_each(|(out, linear)| {
                for (o, rgb) in out.chunks_exact_mut(3).zip(linear) {
                    for (o, &c) in o.iter_mut().zip(rgb) {
                        *o = self.encode(c);
                    }
                }
            });
        out
    }
}
