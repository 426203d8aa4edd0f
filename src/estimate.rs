//! The image's error on request (`--stats`' `estimated_rmse`): estimated from each pixel's two
//! halves, the means of its two independently drawn streams ([`Frame::halves`]), without a
//! reference. The exact definitions are docs/CONTRACT.md's; the book's chapter "Adaptive
//! sampling" gives the reasoning.
//!
//! - **Raw.** A pixel shows m = (a + b) / 2 of halves a and b, which are independent and of the
//!   same expectation, so E[(a - b)^2] / 4 = Var(m), channel by channel. The image's estimated
//!   MSE is the mean of (a - b)^2 / 4 over the channels of the pixels whose halves both hold a
//!   sample.
//! - **Denoised.** The denoiser D also runs on each half alone (D_A, D_B). With b independent of
//!   D_A, E[(D_A - b)^2] = MSE(D_A) + Var(b); Var(b) = E[(a - b)^2] / 2; D's variance is
//!   E[(D_A - D_B)^2] / 4 and D_A's twice it (a filter of fixed weights); D's bias is taken to
//!   be D_A's. So MSE(D) = (E[(D_A - b)^2] + E[(D_B - a)^2]) / 2 - E[(a - b)^2] / 2
//!   - E[(D_A - D_B)^2] / 4, and at least the variance term E[(D_A - D_B)^2] / 4.

use rayon::prelude::*;
use serde::Serialize;

use crate::frame::Frame;

/// An image's estimated error.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ErrorEstimate {
    /// The root of the estimated mean squared error of the linear image, over every channel and
    /// pixel (as src/report/monte_carlo.rs measures the RMSE against a reference).
    pub rmse: f64,
    /// [`Self::rmse`] over the mean of the linear image's channels and pixels.
    pub relative: f64,
}

/// Sums of a raw estimate over bands of rows, so that a streamed render of any size can give
/// it: the squared half differences over 4 and the channels they cover, the image's channel
/// values and their count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HalvesSums {
    squared: f64,
    estimated: u64,
    sum: f64,
    values: u64,
}

impl HalvesSums {
    /// Adds the pixels of a band with its halves (path mode); a band without them adds nothing.
    pub fn add(&mut self, band: &Frame) {
        self.add_pixels(band.width, &band.halves, band.linear());
    }

    /// Adds rows of `width` pixels: their halves and the linear image they show; nothing where
    /// the two differ in length (no halves).
    pub fn add_pixels(&mut self, width: u32, halves: &[[[f32; 3]; 2]], linear: &[[f32; 3]]) {
        if halves.len() != linear.len() {
            return;
        }
        // Row by row, each row's pixels in order and the rows added in order, so that the sums
        // are the same bits however the image is cut into bands (a render's, merge's whole).
        let width = width.max(1) as usize;
        let rows: Vec<(f64, u64, f64)> = halves
            .par_chunks(width)
            .zip(linear.par_chunks(width))
            .map(|(halves, means)| {
                halves.iter().zip(means).fold((0.0, 0, 0.0), |acc, (h, m)| {
                    let total: f64 = m.iter().map(|&c| c as f64).sum();
                    match half_variance(h) {
                        Some(v) => (acc.0 + v.iter().sum::<f64>(), acc.1 + 3, acc.2 + total),
                        None => (acc.0, acc.1, acc.2 + total),
                    }
                })
            })
            .collect();
        for (squared, estimated, sum) in rows {
            self.squared += squared;
            self.estimated += estimated;
            self.sum += sum;
        }
        self.values += 3 * linear.len() as u64;
    }

    /// The raw estimate: None where no pixel's halves both hold a sample (phong mode, one
    /// sample a pixel).
    pub fn finish(&self) -> Option<ErrorEstimate> {
        (self.estimated > 0).then(|| {
            let rmse = (self.squared / self.estimated as f64).sqrt();
            let mean = self.sum / self.values.max(1) as f64;
            ErrorEstimate {
                rmse,
                relative: rmse / mean.abs().max(f64::MIN_POSITIVE),
            }
        })
    }
}

/// A half as [`Frame::halves`] holds it, from the kernels' `vec4<f32>` (its mean colour, its
/// samples): the mean colour, NaN where the half holds no sample.
pub fn half_colour(m: &[f32; 4]) -> [f32; 3] {
    match m[3] {
        0.0 => [f32::NAN; 3],
        _ => [m[0], m[1], m[2]],
    }
}

/// A pixel's estimated variance of its mean, channel by channel: (a - b)^2 / 4 of its halves;
/// None where a half holds no sample (NaN).
pub fn half_variance(h: &[[f32; 3]; 2]) -> Option<[f64; 3]> {
    let [a, b] = h;
    let v = [0, 1, 2].map(|c| {
        let d = a[c] as f64 - b[c] as f64;
        d * d / 4.0
    });
    v.iter().all(|x| x.is_finite()).then_some(v)
}

/// The raw estimate of a whole frame ([`HalvesSums`]).
pub fn raw(frame: &Frame) -> Option<ErrorEstimate> {
    let mut sums = HalvesSums::default();
    sums.add(frame);
    sums.finish()
}

/// A frame's two half frames, for the denoiser's estimate: each the frame with its linear image
/// replaced by one half (by the pixel's mean where that half holds no sample) and its luminance
/// M2 doubled, so that the denoiser takes each half's mean to vary twice as much as the pixel's
/// (half its samples); the other AOVs stay the whole pixel's. None where the frame has no halves.
pub fn half_frames(frame: &Frame) -> Option<[Frame; 2]> {
    let pixels = frame.pixel_count();
    if frame.halves.len() != pixels || frame.radiance.len() != pixels {
        return None;
    }
    let noisy = match frame.noisy.len() == pixels {
        true => &frame.noisy,
        false => &frame.radiance,
    };
    Some([0, 1].map(|h| {
        let mut half = frame.clone();
        half.noisy = Vec::new();
        half.luminance_m2 = frame.luminance_m2.par_iter().map(|m| 2.0 * m).collect();
        half.radiance = (0..pixels)
            .into_par_iter()
            .map(|k| {
                let v = frame.halves[k][h];
                match v.iter().all(|c| c.is_finite()) {
                    true => v,
                    false => noisy[k],
                }
            })
            .collect();
        // The half's specular light: the pixel's, in the half's proportion to its colour
        // (the halves keep no specular light of their own).
        if frame.specular.len() == pixels {
            half.specular = (0..pixels)
                .into_par_iter()
                .map(|k| {
                    std::array::from_fn(|c| match frame.radiance[k][c] > 0.0 {
                        true => frame.specular[k][c] * half.radiance[k][c] / frame.radiance[k][c],
                        false => 0.0,
                    })
                })
                .collect();
        }
        half
    }))
}

/// The estimate of a denoised image from its halves `[a, b]` (each pixel's, as
/// [`Frame::halves`]) and the halves denoised alone `[da, db]` (the module's formula). None
/// where no pixel's halves both hold a sample.
pub fn denoised(
    halves: &[[[f32; 3]; 2]],
    denoised_halves: [&[[f32; 3]]; 2],
    image: &[[f32; 3]],
) -> Option<ErrorEstimate> {
    let [da, db] = denoised_halves;
    // Each pixel's terms in parallel, then added in order: the same bits on every run.
    let terms: Vec<(f64, f64, f64, u64, f64)> = (0..halves.len())
        .into_par_iter()
        .map(|k| {
            let total: f64 = image[k].iter().map(|&c| c as f64).sum();
            if half_variance(&halves[k]).is_none() {
                return (0.0, 0.0, 0.0, 0u64, total);
            }
            let [a, b] = halves[k];
            let (mut cross, mut spread, mut filtered) = (0.0, 0.0, 0.0);
            for c in 0..3 {
                let (a, b, da, db) = (a[c] as f64, b[c] as f64, da[k][c] as f64, db[k][c] as f64);
                cross += ((da - b).powi(2) + (db - a).powi(2)) / 2.0;
                spread += (a - b).powi(2);
                filtered += (da - db).powi(2);
            }
            (cross, spread, filtered, 3, total)
        })
        .collect();
    let (cross, spread, filtered, estimated, sum) =
        terms.iter().fold((0.0, 0.0, 0.0, 0, 0.0), |x, y| {
            (x.0 + y.0, x.1 + y.1, x.2 + y.2, x.3 + y.3, x.4 + y.4)
        });
    (estimated > 0).then(|| {
        let n = estimated as f64;
        let variance = filtered / n / 4.0;
        let mse = (cross / n - spread / n / 2.0 - variance).max(variance);
        let rmse = mse.sqrt();
        let mean = sum / (3 * image.len().max(1)) as f64;
        ErrorEstimate {
            rmse,
            relative: rmse / mean.abs().max(f64::MIN_POSITIVE),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixels_variance_is_its_halves_squared_difference_over_four() {
        let v = half_variance(&[[1.0, 0.5, 0.0], [0.0, 0.5, 2.0]]).unwrap();
        assert_eq!(v, [0.25, 0.0, 1.0]);
        assert_eq!(half_variance(&[[f32::NAN; 3], [1.0; 3]]), None);
    }

    #[test]
    fn the_raw_estimate_of_independent_halves_is_their_spread() {
        // Two halves of a constant image, each off by +-0.1 in every channel: (0.2)^2 / 4 =
        // 0.01, an RMSE of 0.1 on a mean of 0.5; a pixel with an empty half is left out of the
        // estimate but not of the mean.
        let mut frame = Frame::empty(3);
        frame.height = 1;
        frame.radiance = vec![[0.5; 3]; 3];
        frame.halves = vec![
            [[0.6; 3], [0.4; 3]],
            [[0.4; 3], [0.6; 3]],
            [[f32::NAN; 3], [0.5; 3]],
        ];
        let e = raw(&frame).unwrap();
        assert!((e.rmse - 0.1).abs() < 1e-6, "{e:?}");
        assert!((e.relative - 0.2).abs() < 1e-6, "{e:?}");
        frame.halves.clear();
        assert_eq!(raw(&frame), None);
    }

    #[test]
    fn the_denoised_estimate_is_at_least_its_variance_term() {
        // Halves that a filter made equal: no variance left, and the cross terms measure the
        // bias: D_A = D_B = 0.5 against halves 0.6 and 0.4, E[(D_A - b)^2] = 0.01, E[(a - b)^2]
        // / 2 = 0.02: the formula gives 0.01 - 0.02 < 0, floored at the variance term 0.
        let halves = vec![[[0.6f32; 3], [0.4; 3]]; 4];
        let flat = vec![[0.5f32; 3]; 4];
        let e = denoised(&halves, [&flat, &flat], &flat).unwrap();
        assert_eq!(e.rmse, 0.0);
        // A filter that moved both halves to 0.7 (a bias of 0.2 over the truth 0.5): E[(D_A -
        // b)^2] = (0.09 + 0.01) / 2 = 0.05, minus 0.02, minus no variance: 0.03.
        let off = vec![[0.7f32; 3]; 4];
        let e = denoised(&halves, [&off, &off], &off).unwrap();
        assert!((e.rmse - 0.03f64.sqrt()).abs() < 1e-6, "{e:?}");
    }
}
