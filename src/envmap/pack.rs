//! Packing an environment map for the kernels ([`pack`]): its texels with their density for
//! importance sampling (a 2D piecewise-constant distribution of luminance times sin(theta): the
//! marginal CDF over rows and each row's CDF), and the nine spherical-harmonic coefficients of
//! its irradiance, in the layout stated here ([`ENV_TEXELS`] and the rest), which both twins
//! read (shaders/environment.wgsl keeps the same constants).

use crate::algebra::Real;

/// Where the packed buffer holds the map's width (a float, exact).
pub const ENV_WIDTH: u32 = 0;
/// Where it holds the height.
pub const ENV_HEIGHT: u32 = 1;
/// Where the irradiance's nine coefficients start (RGB in a slot of four floats each).
pub const ENV_IRRADIANCE: u32 = 4;
/// Where the texels start: RGB and the density over the map's [0, 1)^2, four floats each; then
/// the marginal CDF over rows (height + 1), then each row's CDF (width + 1 each).
pub const ENV_TEXELS: u32 = 40;

/// Floats of a `width` x `height` map packed ([`pack`]).
pub fn packed_floats(width: usize, height: usize) -> usize {
    ENV_TEXELS as usize + 5 * width * height + 2 * height + 1
}

/// A piecewise-constant distribution over [0, 1) in `func.len()` equal pieces: `cdf[k]` is the
/// mass of the pieces before k (`cdf[0] = 0`, `cdf[n] = 1`), `integral` the mean of `func`. A
/// distribution of no mass (every piece 0) is uniform, so that sampling never divides by 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1d {
    pub func: Vec<f32>,
    pub cdf: Vec<f32>,
    pub integral: f32,
}

impl Distribution1d {
    /// The distribution of `func` (each value >= 0 and finite).
    pub fn new(func: &[f32]) -> Self {
        let n = func.len();
        let mut cdf = vec![0.0f64; n + 1];
        for k in 0..n {
            cdf[k + 1] = cdf[k] + f64::from(func[k]) / n as f64;
        }
        let integral = cdf[n];
        let cdf = if integral > 0.0 {
            cdf.iter().map(|c| (c / integral) as f32).collect()
        } else {
            (0..=n).map(|k| k as f32 / n as f32).collect()
        };
        Self {
            func: func.to_vec(),
            cdf,
            integral: integral as f32,
        }
    }

    /// The density of piece k: func[k] / integral (1, uniform, for a distribution of no mass).
    pub fn pdf_piece(&self, k: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[k] / self.integral
        } else {
            1.0
        }
    }
}

/// Rec. 709 luminance, as the sampling weighs texels.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The kernels' buffer of a `width` x `height` map (src/cpu/environment.rs states the layout):
/// the size; the irradiance's nine spherical-harmonic coefficients per channel, each already
/// times its band's cosine-lobe factor and divided by pi (Ramamoorthi and Hanrahan 2001: for a
/// normal n, E(n) / pi = sum k_lm y_lm(n) in the map's own frame); each texel's RGB and its
/// density over the map's [0, 1)^2; the marginal CDF over rows; each row's CDF over its texels.
/// The distribution is of luminance times sin(theta) at the row's centre (theta from the
/// zenith), so that a direction's density per solid angle follows its radiance.
pub fn pack(width: usize, height: usize, texels: &[[f32; 3]]) -> Vec<f32> {
    let sin_row = |j: usize| (std::f64::consts::PI * (j as f64 + 0.5) / height as f64).sin();
    let rows: Vec<Distribution1d> = texels
        .chunks(width)
        .enumerate()
        .map(|(j, row)| {
            let func: Vec<f32> = row
                .iter()
                .map(|&t| (f64::from(luminance(t).max(0.0)) * sin_row(j)) as f32)
                .collect();
            Distribution1d::new(&func)
        })
        .collect();
    let marginal = Distribution1d::new(&rows.iter().map(|r| r.integral).collect::<Vec<_>>());
    let mut out = vec![0.0f32; packed_floats(width, height)];
    out[ENV_WIDTH as usize] = width as f32;
    out[ENV_HEIGHT as usize] = height as f32;
    let irradiance = irradiance_coefficients(width, height, texels);
    for (k, c) in irradiance.iter().enumerate() {
        let at = ENV_IRRADIANCE as usize + 4 * k;
        out[at..at + 3].copy_from_slice(&c.map(|x| x as f32));
    }
    for (k, t) in texels.iter().enumerate() {
        let (i, j) = (k % width, k / width);
        let at = ENV_TEXELS as usize + 4 * k;
        out[at..at + 3].copy_from_slice(t);
        out[at + 3] = marginal.pdf_piece(j) * rows[j].pdf_piece(i);
    }
    let marginal_at = ENV_TEXELS as usize + 4 * width * height;
    out[marginal_at..marginal_at + height + 1].copy_from_slice(&marginal.cdf);
    for (j, row) in rows.iter().enumerate() {
        let at = marginal_at + height + 1 + j * (width + 1);
        out[at..at + width + 1].copy_from_slice(&row.cdf);
    }
    out
}

/// The irradiance's coefficients (nine, RGB each) as [`pack`] stores them: the projection of
/// the map onto the real spherical harmonics of bands 0 to 2, each texel weighed by its exact
/// solid angle, times A_l / pi (1, 2/3 and 1/4) and times the basis function's constant, so that
/// E(n) / pi = k0 + k1 y + k2 z + k3 x + k4 x y + k5 y z + k6 (3 z^2 - 1) + k7 x z + k8 (x^2 -
/// y^2), with x toward u = 0, y toward u = 1/4 and z up.
pub fn irradiance_coefficients(width: usize, height: usize, texels: &[[f32; 3]]) -> [[f64; 3]; 9] {
    use std::f64::consts::PI;
    // Each band's constant, squared into the evaluation: c_lm^2 times A_l / pi.
    let c0 = 0.282_094_791_773_878_1_f64;
    let c1 = 0.488_602_511_902_919_9_f64;
    let c2 = 1.092_548_430_592_079_2_f64;
    let c20 = 0.315_391_565_252_52_f64;
    let c22 = 0.546_274_215_296_039_6_f64;
    let scale = [
        c0 * c0,
        c1 * c1 * 2.0 / 3.0,
        c1 * c1 * 2.0 / 3.0,
        c1 * c1 * 2.0 / 3.0,
        c2 * c2 / 4.0,
        c2 * c2 / 4.0,
        c20 * c20 / 4.0,
        c2 * c2 / 4.0,
        c22 * c22 / 4.0,
    ];
    let mut sums = [[0.0f64; 3]; 9];
    for j in 0..height {
        let (t0, t1) = (
            PI * j as f64 / height as f64,
            PI * (j + 1) as f64 / height as f64,
        );
        let omega = 2.0 * PI / width as f64 * (t0.cos() - t1.cos());
        let theta = 0.5 * (t0 + t1);
        for i in 0..width {
            let phi = 2.0 * PI * (i as f64 + 0.5) / width as f64;
            let (x, y, z) = (
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let basis = irradiance_basis(x, y, z);
            let t = texels[j * width + i];
            for (k, b) in basis.iter().enumerate() {
                for c in 0..3 {
                    sums[k][c] += f64::from(t[c]) * b * omega;
                }
            }
        }
    }
    std::array::from_fn(|k| sums[k].map(|s| s * scale[k]))
}

/// The polynomials of the real spherical harmonics of bands 0 to 2 at (x, y, z), without their
/// constants, in the order the coefficients are packed: what the projection
/// ([`irradiance_coefficients`]) sums and the CPU twin's `env_irradiance` weighs (as
/// shaders/environment.wgsl does, written out), so that both take the same order.
pub fn irradiance_basis<F: Real>(x: F, y: F, z: F) -> [F; 9] {
    [
        F::one(),
        y,
        z,
        x,
        x * y,
        y * z,
        F::lit(3.0) * z * z - F::one(),
        x * z,
        x * x - y * y,
    ]
}
