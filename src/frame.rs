//! The one result both tracers produce: colour, depth and steps per pixel, plus how it was made.

use serde::Serialize;

/// A rendered image, row 0 at the top, pixel (i, j) at index `j * width + i`.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Colour as RGBA8 0xFFBBGGRR per pixel, as the tracers pack it (alpha always 255).
    pub colour: Vec<u32>,
    /// The hit's ray parameter t (the distance from the eye along the unit ray); NaN on a miss.
    pub depth: Vec<f32>,
    /// Distance estimates along the primary ray.
    pub steps: Vec<u32>,
    /// Values that came out NaN or infinite on the way (colour, depth; the depth map's miss
    /// marker aside). Must be 0: the stability suite checks it.
    pub non_finite: u64,
}

impl Frame {
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Appends the rows of `band` (of the same width) below this frame's.
    pub fn append(&mut self, band: &Frame) {
        debug_assert_eq!(self.width, band.width);
        self.height += band.height;
        self.colour.extend_from_slice(&band.colour);
        self.depth.extend_from_slice(&band.depth);
        self.steps.extend_from_slice(&band.steps);
        self.non_finite += band.non_finite;
    }

    /// Colour as 8-bit RGB bytes, row by row.
    pub fn rgb8(&self) -> Vec<u8> {
        self.colour.iter().flat_map(|&c| unpack_rgb(c)).collect()
    }

    /// Whether each pixel's primary ray hit the set.
    pub fn hit_mask(&self) -> Vec<bool> {
        self.depth.iter().map(|d| !d.is_nan()).collect()
    }

    /// Divergence (the seed's Figure 9): for square tiles of `tile` pixels a side, the share of
    /// the work a SIMD group would do that is useful, sum of steps over sum of tile pixels times
    /// the tile's largest step count. 1 means every ray of a tile takes as many steps as the
    /// slowest; lower means lanes wait.
    pub fn tile_efficiency(&self, tile: u32) -> f64 {
        let mut work = crate::views::TileWork::new(self.width, tile);
        work.add_rows(&self.steps);
        work.finish().efficiency
    }

    /// Hit fraction and step figures over all pixels.
    pub fn summary(&self) -> FrameSummary {
        let n = self.pixel_count().max(1) as f64;
        FrameSummary {
            hit_fraction: self.depth.iter().filter(|d| !d.is_nan()).count() as f64 / n,
            steps_mean: self.steps.iter().map(|&s| s as f64).sum::<f64>() / n,
            steps_max: self.steps.iter().copied().max().unwrap_or(0),
        }
    }
}

/// `[r, g, b]` of a packed 0xAABBGGRR colour.
pub fn unpack_rgb(c: u32) -> [u8; 3] {
    [c as u8, (c >> 8) as u8, (c >> 16) as u8]
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrameSummary {
    pub hit_fraction: f64,
    pub steps_mean: f64,
    pub steps_max: u32,
}

/// What `--stats` writes (CONTRACT.md): how a frame was made and what it holds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RenderStats {
    /// "gpu" or "cpu".
    pub backend: String,
    /// Adapter name and wgpu backend, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) / Vulkan"; "cpu".
    pub adapter: String,
    /// "f32" or "f64".
    pub precision: String,
    pub width: u32,
    pub height: u32,
    /// From the first dispatch to the image in host memory, after an untimed warm-up.
    pub render_seconds: f64,
    /// GPU time from timestamp queries; None where unsupported (and on the CPU).
    pub gpu_seconds: Option<f64>,
    pub hit_fraction: f64,
    pub steps_mean: f64,
    pub steps_max: u32,
    /// Divergence in 8x8 tiles (README's "Views"): sum of steps over the sum of tile pixels
    /// times the tile's most steps.
    pub tile_efficiency: f64,
    /// Mean over pixels of the 8x8 tile's most steps minus the pixel's own.
    pub wasted_steps_mean: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_efficiency_counts_idle_lanes() {
        let frame = |steps: Vec<u32>| Frame {
            width: 2,
            height: 2,
            colour: vec![0; 4],
            depth: vec![0.0; 4],
            steps,
            non_finite: 0,
        };
        assert_eq!(frame(vec![5, 5, 5, 5]).tile_efficiency(2), 1.0);
        assert_eq!(frame(vec![4, 0, 0, 0]).tile_efficiency(2), 0.25);
        assert_eq!(frame(vec![4, 0, 0, 0]).tile_efficiency(1), 1.0);
    }
}
