//! Comparing two frames of the same scene: how far the GPU is from the CPU reference, or a
//! setting from the truth. Tolerances are explicit and named; a failed comparison can write
//! expected, actual and diff PNGs for a person to look at.

use std::path::{Path, PathBuf};

use crate::frame::{Frame, unpack_rgb};

/// What "the same picture" means, as fractions of pixels that must agree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Hit masks agree on at least this fraction of all pixels.
    pub mask_agreement: f64,
    /// Depth agrees within `depth_abs`...
    pub depth_abs: f64,
    /// ...on at least this fraction of the pixels both frames hit.
    pub depth_agreement: f64,
    /// Colour agrees within `colour_abs` (in 1/255 steps) on every channel...
    pub colour_abs: u8,
    /// ...on at least this fraction of all pixels.
    pub colour_agreement: f64,
}

/// docs/CONTRACT.md's tolerance between the GPU and the CPU reference in f32, and between a faster
/// tracing and the seed tracing: masks on 99.5%, depth within 1e-3 on 99% of common hits,
/// colour within 2/255 on 99% of pixels.
pub const CONTRACT_TOLERANCE: Tolerance = Tolerance {
    mask_agreement: 0.995,
    depth_abs: 1e-3,
    depth_agreement: 0.99,
    colour_abs: 2,
    colour_agreement: 0.99,
};

/// The 2D Julia view, GPU against the CPU twin in f32: in-set masks on 99.5% of pixels, grey
/// within 2/255 on 99% (orbits near the boundary are chaotic: one rounding apart, they can
/// escape an iteration apart). Depth is 0 wherever both are in the set.
pub const JULIA2D_TOLERANCE: Tolerance = Tolerance {
    mask_agreement: 0.995,
    depth_abs: 0.0,
    depth_agreement: 1.0,
    colour_abs: 2,
    colour_agreement: 0.99,
};

/// How well two frames agree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Agreement {
    pub pixels: usize,
    /// Fraction of pixels where both hit or both miss.
    pub mask: f64,
    /// Pixels both frames hit.
    pub common_hits: usize,
    /// Fraction of common hits whose depths agree within the tolerance's `depth_abs`.
    pub depth: f64,
    /// Largest depth difference over common hits.
    pub depth_max_error: f64,
    /// Fraction of pixels whose colour agrees within the tolerance's `colour_abs`.
    pub colour: f64,
    /// Largest channel difference, in 1/255 steps.
    pub colour_max_error: u8,
}

impl Agreement {
    /// Measures agreement of `actual` with `expected` under the tolerance's thresholds.
    pub fn measure(expected: &Frame, actual: &Frame, tol: &Tolerance) -> Self {
        assert_eq!(
            (expected.width, expected.height),
            (actual.width, actual.height),
            "frames of different sizes"
        );
        let pixels = expected.pixel_count();
        let (mut mask_same, mut common, mut depth_ok, mut colour_ok) = (0, 0, 0, 0);
        let (mut depth_max, mut colour_max) = (0f64, 0u8);
        // Both in f64 where both frames ran in f64: a deep zoom's depths differ below f32's
        // spacing.
        let fine = expected.depth_f64.len() == pixels && actual.depth_f64.len() == pixels;
        let depth = |f: &Frame, k: usize| {
            if fine {
                f.depth_f64[k]
            } else {
                f.depth[k] as f64
            }
        };
        for k in 0..pixels {
            let (de, da) = (depth(expected, k), depth(actual, k));
            if de.is_nan() == da.is_nan() {
                mask_same += 1;
            }
            if !de.is_nan() && !da.is_nan() {
                common += 1;
                let err = (de - da).abs();
                depth_max = depth_max.max(err);
                if err <= tol.depth_abs {
                    depth_ok += 1;
                }
            }
            let err = channel_error(expected.colour[k], actual.colour[k]);
            colour_max = colour_max.max(err);
            if err <= tol.colour_abs {
                colour_ok += 1;
            }
        }
        let frac = |n: usize, of: usize| if of == 0 { 1.0 } else { n as f64 / of as f64 };
        Self {
            pixels,
            mask: frac(mask_same, pixels),
            common_hits: common,
            depth: frac(depth_ok, common),
            depth_max_error: depth_max,
            colour: frac(colour_ok, pixels),
            colour_max_error: colour_max,
        }
    }

    /// Whether every fraction reaches the tolerance's minimum.
    pub fn within(&self, tol: &Tolerance) -> bool {
        self.mask >= tol.mask_agreement
            && self.depth >= tol.depth_agreement
            && self.colour >= tol.colour_agreement
    }
}

impl std::fmt::Display for Agreement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "masks agree on {:.3}% of {} pixels; depth on {:.3}% of {} common hits (max error {:.2e}); \
             colour on {:.3}% (max error {}/255)",
            self.mask * 100.0,
            self.pixels,
            self.depth * 100.0,
            self.common_hits,
            self.depth_max_error,
            self.colour * 100.0,
            self.colour_max_error
        )
    }
}

/// The largest per-channel difference of two packed colours.
fn channel_error(a: u32, b: u32) -> u8 {
    let (a, b) = (unpack_rgb(a), unpack_rgb(b));
    (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0)
}

/// Writes `NAME-expected.png`, `NAME-actual.png` and `NAME-diff.png` into `dir`: the diff shows
/// colour differences amplified 16 times in grey, and pixels hit by only one frame in magenta
/// (only expected) or green (only actual). Returns the paths written.
pub fn write_diff_images(
    dir: &Path,
    name: &str,
    expected: &Frame,
    actual: &Frame,
) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let diff: Vec<u8> = (0..expected.pixel_count())
        .flat_map(
            |k| match (expected.depth[k].is_nan(), actual.depth[k].is_nan()) {
                (false, true) => [255, 0, 255],
                (true, false) => [0, 255, 0],
                _ => [channel_error(expected.colour[k], actual.colour[k]).saturating_mul(16); 3],
            },
        )
        .collect();
    let (w, h) = (expected.width, expected.height);
    let images = [
        ("expected", expected.rgb8()),
        ("actual", actual.rgb8()),
        ("diff", diff),
    ];
    let mut paths = Vec::new();
    for (kind, rgb) in images {
        let path = dir.join(format!("{name}-{kind}.png"));
        image::save_buffer(&path, &rgb, w, h, image::ExtendedColorType::Rgb8)
            .map_err(std::io::Error::other)?;
        paths.push(path);
    }
    Ok(paths)
}
