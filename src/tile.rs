//! Tiles for farms: `render --tile K/N` renders the K-th of N bands of rows and writes a
//! partial OpenEXR; `merge` reads the parts, checks that they are one scene's and cover every
//! row once, and puts the whole frame together for the final stage `render` runs too
//! ([`crate::output::write_view_outputs`]), so that its outputs are byte-identical to one
//! render's on the same adapter.
//!
//! # The partial EXR (format version [`FORMAT_VERSION`])
//!
//! One part, scan lines, ZIP (lossless). The display window is the whole image (0, 0) to
//! (width - 1, height - 1); the data window is the tile's rows [K*H/N, (K+1)*H/N), full width,
//! so that any EXR viewer shows the tile in place. Channels (stored sorted by name):
//!
//! | channel | type | holds |
//! |---|---|---|
//! | `R`, `G`, `B` | float32 | the linear mean, bit for bit what the accumulator holds: path mode's radiance, phong mode's unclamped colour mean (as `--hdr`) |
//! | `albedo.R/G/B`, `N.X/Y/Z` | float32 | the AOVs, as `--hdr` |
//! | `Z` | float32 | the depth, NaN where the ray hits nothing, as `--hdr` |
//! | `colour8` | uint32 | the 8-bit colour the tracer made, 0xFFBBGGRR (phong mode's PNG pixels: the mean of the clamped samples, rounded on the device; path mode's is the display transform of `R`, `G`, `B`, which `merge` makes again) |
//! | `steps` | uint32 | primary-ray steps (for `--stats` and the heat-map views) |
//! | `luminance.M2` | float32 | the sum of the squared deviations of the samples' luminances from their mean (Welford's M2, the AOVs' fourth float of the albedo): the denoiser's variance |
//! | `hits` | float32 | how many of the samples the pixel's mean holds hit ([`crate::frame::Frame::hits`]): the denoiser's hit fraction |
//! | `Z.mean` | float32 | the depth of the hits, averaged over them, 0 where none hit ([`crate::frame::Frame::hit_depth`]): the denoiser's depth guide |
//! | `half.A.R/G/B`, `half.B.R/G/B` | float32 | path mode: the pixel's two halves ([`crate::frame::Frame::halves`], NaN in an empty half), so that `merge` estimates the error as one render does |
//! | `specular.R/G/B`, `view.cosine` | float32 | path mode: the first hits' specular light and mean view cosine ([`crate::frame::Frame::specular`], [`crate::frame::Frame::view_cosine`]), so that `merge` denoises as one render does |
//! | `samples` | uint32 | samples each pixel took: `image.samples`, or fewer where adaptive sampling (`path.noise_target`) stopped it; each pixel decides alone, so a tile's counts are the whole render's |
//!
//! The accumulators keep a running mean in float32 (m_k = m_(k-1) + (x_k - m_(k-1)) / (k + 1)),
//! not a sum, so the mean itself goes in float32 channels with nothing lost; a sum, where one is
//! wanted (runs combined), is mean x `samples`. No float64 is needed.
//! `merge` runs the denoiser (`image.denoise`) over the whole frame, as `render` does, from
//! these channels alone. A reader must ignore channels it does not know.
//!
//! Header attributes: `qjulia-scene` (string, the scene's TOML, as the PNG's chunk and
//! `--hdr`'s attribute; `--scene PART.exr` reads it), `qjulia-partial` (int, the format
//! version), `qjulia-tile` (string, `K/N`), `qjulia-backend`, `qjulia-adapter`,
//! `qjulia-precision`, `qjulia-precision-reason` (strings, as `--stats` names them),
//! `qjulia-render-seconds` (double), `qjulia-gpu-seconds` (double, absent where the device has
//! no timestamps), `qjulia-estimates` and `qjulia-iterations` (strings, decimal u64s: distance
//! estimates and quaternion iterations made for the tile's pixels), and in path mode `qjulia-nonfinite-samples` and `qjulia-exhausted-rays`
//! (strings, decimal u64s: `--stats`' counts of the tile; absent, from an older binary, they
//! count 0).
//!
//! The parts: `partial.rs` writes a tile's partial EXR and reads one back, checked; `merge.rs`
//! puts the parts together. A [`Tile`] is here.

mod merge;
mod partial;

pub use merge::merge;
pub use partial::{FORMAT_VERSION, check_part_bytes, write_partial};

use std::ops::Range;

use crate::error::{Error, FlagError, Result};

/// `--tile K/N`: the K-th (0-based) of N bands of rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub index: u32,
    pub count: u32,
}

impl Tile {
    /// Parses `K/N` for an image `height` rows high: 0 <= K < N <= height, else an error
    /// naming `--tile`.
    pub fn parse(text: &str, height: u32) -> Result<Self> {
        let bad = |why: String| Error::from(FlagError::new(format!("--tile {text}"), why));
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected K/N, e.g. 0/4".into()))?;
        let number = |s: &str| s.trim().parse::<u32>().ok();
        let (Some(index), Some(count)) = (number(k), number(n)) else {
            return Err(bad("K and N must be whole numbers, as in 0/4".into()));
        };
        if count == 0 || index >= count {
            return Err(bad(format!("K must be in 0..N, here 0..{count}")));
        }
        if count > height {
            return Err(bad(format!(
                "N must be at most the image's height ({height} rows)"
            )));
        }
        Ok(Self { index, count })
    }

    /// The rows of this tile of an image `height` rows high: [K*H/N, (K+1)*H/N).
    pub fn rows(&self, height: u32) -> Range<u32> {
        let at = |k: u32| (k as u64 * height as u64 / self.count as u64) as u32;
        at(self.index)..at(self.index + 1)
    }
}

impl std::fmt::Display for Tile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}
