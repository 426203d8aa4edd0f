//! The `[image]` table's choices that later stages act on: the tone map (src/display.rs applies
//! its curve) and the denoiser (src/denoise.rs runs it). They are scene data, so they live here,
//! below those stages; their names and parsing are the scene file's.

use std::fmt;
use std::str::FromStr;

/// `image.tone_map`: the curve from exposed linear radiance to [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneMap {
    /// A clamp to [0, 1].
    #[default]
    None,
    /// Reinhard's simple operator `x / (1 + x)` (Reinhard et al. 2002, eq. 3), per channel.
    Reinhard,
    /// Narkowicz's 2015 fit of the ACES filmic curve (RRT + ODT),
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, per channel, clamped to [0, 1].
    Aces,
}

impl ToneMap {
    /// Every tone map, in the order the scene file lists them.
    pub const ALL: [ToneMap; 3] = [ToneMap::None, ToneMap::Reinhard, ToneMap::Aces];

    /// The name the scene file uses.
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::None => "none",
            ToneMap::Reinhard => "reinhard",
            ToneMap::Aces => "aces",
        }
    }
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ToneMap {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ToneMap::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = ToneMap::ALL.iter().map(|t| format!("\"{t}\"")).collect();
                format!("unknown tone map \"{s}\" (expected {})", names.join(", "))
            })
    }
}

/// `image.denoise`: which denoiser runs on the linear image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Denoiser {
    /// None: the image is the mean of its samples.
    #[default]
    None,
    /// The edge-avoiding a-trous filter, guided by the albedo, normal and depth AOVs and by
    /// each pixel's variance.
    Atrous,
}

impl Denoiser {
    /// Every denoiser, in the order the scene file lists them.
    pub const ALL: [Denoiser; 2] = [Denoiser::None, Denoiser::Atrous];

    /// The name the scene file uses.
    pub fn name(self) -> &'static str {
        match self {
            Denoiser::None => "none",
            Denoiser::Atrous => "atrous",
        }
    }
}
