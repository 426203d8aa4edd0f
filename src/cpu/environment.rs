//! The environment map (`[environment]`, docs/book/atmosphere.md) on the CPU: the twin of
//! shaders/environment.wgsl, same names, same order (tests/architecture/twins.rs). An equirectangular HDR
//! image about `sky.up`, turned by `rotation_degrees`, looked up texel by texel (piecewise
//! constant), read from the same packed buffer the kernels bind (src/envmap.rs packs it), so
//! that both draw the same texels. Its sampling is the path tracer's light (src/cpu/light.rs).

pub use crate::envmap::{ENV_HEIGHT, ENV_IRRADIANCE, ENV_TEXELS, ENV_WIDTH};

use crate::envmap::irradiance_basis;

use crate::algebra::{Real, Vec2, Vec3};
use crate::params::TraceParams;

/// The largest f32 below 1: where u or v would round up to 1.
pub const ENV_ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;
/// Pi in f32.
pub const ENV_PI: f32 = std::f32::consts::PI;

/// The map's frame: up (`sky.up`), front (u = 0 at turn 0), right = front x up (u = 1/4), the
/// turn in radians and the radiance's factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvFrame {
    pub up: Vec3<f32>,
    pub front: Vec3<f32>,
    pub right: Vec3<f32>,
    pub rotation: f32,
    pub intensity: f32,
}

/// A direction drawn toward the map ([`sample_environment`]), the radiance along it and the
/// density per solid angle it was drawn with (0: no sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvSample<F> {
    pub wi: Vec3<F>,
    pub radiance: Vec3<F>,
    pub pdf: F,
}

impl<F: Real> TraceParams<F> {
    /// Whether the scene has a map (`environment.file`), loaded.
    pub fn environment_on(&self) -> bool {
        self.env_map && self.environment.is_some()
    }

    /// Float `k` of the packed buffer (WGSL: `environment[k]`).
    pub fn env_word(&self, k: u32) -> f32 {
        self.environment
            .as_ref()
            .map_or(0.0, |e| e.packed[k as usize])
    }

    pub fn env_frame(&self) -> EnvFrame {
        let up = self.env_up.to_f32();
        let front = self.env_front.to_f32();
        EnvFrame {
            up,
            front,
            right: front.cross(up),
            rotation: self.env_rotation.to_f64() as f32,
            intensity: self.env_intensity.to_f64() as f32,
        }
    }

    /// The map's width and height in texels.
    pub fn env_size(&self) -> (u32, u32) {
        (
            self.env_word(ENV_WIDTH) as u32,
            self.env_word(ENV_HEIGHT) as u32,
        )
    }

    /// The map's (u, v) of the unit direction d: v = theta / pi from up, u = phi / (2 pi) about
    /// up from front toward right, less the rotation, in [0, 1).
    pub fn env_direction_uv(&self, f: EnvFrame, d: Vec3<f32>) -> Vec2<f32> {
        let cos_theta = d.dot(f.up).clamp(-1.0, 1.0);
        let turns = (d.dot(f.right).atan2(d.dot(f.front)) - f.rotation) / (2.0 * ENV_PI);
        let u = turns - turns.floor();
        let v = cos_theta.acos() / ENV_PI;
        Vec2::new(u.min(ENV_ONE_BELOW), v.min(ENV_ONE_BELOW))
    }

    /// The unit direction of the map's (u, v): [`Self::env_direction_uv`]'s inverse.
    pub fn env_uv_direction(&self, f: EnvFrame, uv: Vec2<f32>) -> Vec3<f32> {
        let theta = ENV_PI * uv.y;
        let phi = 2.0 * ENV_PI * uv.x + f.rotation;
        let s = theta.sin();
        f.front * (s * phi.cos()) + f.right * (s * phi.sin()) + f.up * theta.cos()
    }

    /// The texel (u, v) falls in, as its index j * width + i.
    pub fn env_texel(&self, uv: Vec2<f32>) -> u32 {
        let (w, h) = self.env_size();
        let i = ((uv.x * w as f32) as u32).min(w - 1);
        let j = ((uv.y * h as f32) as u32).min(h - 1);
        j * w + i
    }

    /// The radiance along the unit direction d: the texel it falls in, times the intensity.
    pub fn env_radiance(&self, d: Vec3<f32>) -> Vec3<f32> {
        let f = self.env_frame();
        let k = ENV_TEXELS + 4 * self.env_texel(self.env_direction_uv(f, d));
        Vec3::new(self.env_word(k), self.env_word(k + 1), self.env_word(k + 2)) * f.intensity
    }

    /// The map's irradiance at the unit normal n divided by pi, times the intensity: the nine
    /// coefficients' polynomial in n's coordinates in the map's own frame, at least 0.
    pub fn env_irradiance(&self, n: Vec3<f32>) -> Vec3<f32> {
        let f = self.env_frame();
        let a = n.dot(f.front);
        let b = n.dot(f.right);
        let (c, s) = (f.rotation.cos(), f.rotation.sin());
        let x = a * c + b * s;
        let y = b * c - a * s;
        let z = n.dot(f.up);
        let basis = irradiance_basis(x, y, z);
        let mut e = Vec3::new(0.0f32, 0.0, 0.0);
        for (k, b) in basis.iter().enumerate() {
            let at = ENV_IRRADIANCE + 4 * k as u32;
            e += Vec3::new(
                self.env_word(at),
                self.env_word(at + 1),
                self.env_word(at + 2),
            ) * *b;
        }
        Vec3::new(e.x.max(0.0), e.y.max(0.0), e.z.max(0.0)) * f.intensity
    }
}

// The map as a light: importance sampling by the 2D piecewise-constant distribution packed with it, the marginal
// over rows then the row's conditional over texels, each CDF searched by bisection; a
// direction's density per solid angle is its texel's density over [0, 1)^2 divided by
// 2 pi^2 sin(theta). In f32, as the kernels, whatever `F`.

/// The piece of the CDF of n pieces at words start..start + n of the map's buffer that u falls
/// in: the last k with cdf[k] <= u.
pub fn env_bisect<F: Real>(p: &TraceParams<F>, start: u32, n: u32, u: f32) -> u32 {
    let (mut lo, mut hi) = (0u32, n);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if p.env_word(start + mid) <= u {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Where u falls within piece k of the CDF at start, of n pieces: (k + du) / n, du the CDF
/// inverted within the piece (its middle for a piece of no mass), below 1.
pub fn env_piece_point<F: Real>(p: &TraceParams<F>, start: u32, k: u32, n: u32, u: f32) -> f32 {
    let c0 = p.env_word(start + k);
    let width = p.env_word(start + k + 1) - c0;
    let mut du = 0.5;
    if width > 0.0 {
        du = ((u - c0) / width).clamp(0.0, 1.0);
    }
    ((k as f32 + du) / n as f32).min(ENV_ONE_BELOW)
}

/// A direction toward the map drawn from u in [0, 1)^2 with the radiance of its texel (times
/// the intensity) and its density per solid angle (pdf 0, no sample, at a pole).
pub fn sample_environment<F: Real>(p: &TraceParams<F>, u: Vec2<F>) -> EnvSample<F> {
    let u = Vec2::new(u.x.to_f64() as f32, u.y.to_f64() as f32);
    let (w, h) = p.env_size();
    let marginal = ENV_TEXELS + 4 * w * h;
    let j = env_bisect(p, marginal, h, u.y);
    let v = env_piece_point(p, marginal, j, h, u.y);
    let row = marginal + h + 1 + j * (w + 1);
    let i = env_bisect(p, row, w, u.x);
    let x = env_piece_point(p, row, i, w, u.x);
    let k = ENV_TEXELS + 4 * (j * w + i);
    let f = p.env_frame();
    let wi = Vec3::from_f32(p.env_uv_direction(f, Vec2::new(x, v)));
    let s = (ENV_PI * v).sin();
    let pdf_uv = p.env_word(k + 3);
    if s <= 0.0 || pdf_uv <= 0.0 {
        return EnvSample {
            wi,
            radiance: Vec3::zero(),
            pdf: F::zero(),
        };
    }
    let radiance = Vec3::new(p.env_word(k), p.env_word(k + 1), p.env_word(k + 2)) * f.intensity;
    EnvSample {
        wi,
        radiance: Vec3::from_f32(radiance),
        pdf: F::lit(f64::from(pdf_uv / (2.0 * ENV_PI * ENV_PI * s))),
    }
}

/// The density per solid angle with which [`sample_environment`] draws the unit direction d.
pub fn environment_pdf<F: Real>(p: &TraceParams<F>, d: Vec3<F>) -> F {
    let uv = p.env_direction_uv(p.env_frame(), d.to_f32());
    let s = (ENV_PI * uv.y).sin();
    if s <= 0.0 {
        return F::zero();
    }
    let pdf = p.env_word(ENV_TEXELS + 4 * p.env_texel(uv) + 3) / (2.0 * ENV_PI * ENV_PI * s);
    F::lit(f64::from(pdf))
}
