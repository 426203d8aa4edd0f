//! Writes assets/environment/dusk.hdr, the environment map built into the binary
//! (`environment.file = "qjulia:dusk.hdr"`, the `environment` preset's): a procedural sky at
//! dusk, 1024 x 512 texels of linear RGB in Radiance's format. A low sun (about 700 times brighter
//! than the sky around it, 2.4 degrees across) over a warm horizon under a deep blue zenith,
//! its glow and a band of thin clouds lit from below, and a dark ground. Deterministic: the same
//! file every run.
//!
//! `cargo run --release --example dusk_sky [OUT]`

use std::f64::consts::PI;

/// The map's size: twice as wide as high.
const WIDTH: usize = 1024;
const HEIGHT: usize = 512;

/// A smooth value noise in [0, 1) of (x, y), periodic in x with period `period` (the map's
/// seam joins), from an integer hash.
fn noise(x: f64, y: f64, period: i64) -> f64 {
    let hash = |i: i64, j: i64| {
        let mut h = (i.rem_euclid(period) as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
            ^ (j as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f);
        h ^= h >> 29;
        h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h ^= h >> 32;
        (h >> 11) as f64 / (1u64 << 53) as f64
    };
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    let (fx, fy) = (x - x.floor(), y - y.floor());
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(fx), s(fy));
    let top = hash(i, j) * (1.0 - sx) + hash(i + 1, j) * sx;
    let bottom = hash(i, j + 1) * (1.0 - sx) + hash(i + 1, j + 1) * sx;
    top * (1.0 - sy) + bottom * sy
}

/// Five octaves of [`noise`], in [0, 1).
fn fbm(x: f64, y: f64, period: i64) -> f64 {
    let (mut sum, mut amplitude, mut scale, mut norm) = (0.0, 0.5, 1.0, 0.0);
    for _ in 0..5 {
        sum += amplitude * noise(x * scale, y * scale, period * scale as i64);
        norm += amplitude;
        amplitude *= 0.5;
        scale *= 2.0;
    }
    sum / norm
}

fn mix(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    std::array::from_fn(|c| a[c] * (1.0 - t) + b[c] * t)
}

/// The sky's radiance at map coordinates (u, v) in [0, 1)^2 (v = 0 the zenith).
fn radiance(u: f64, v: f64) -> [f64; 3] {
    let theta = PI * v;
    let phi = 2.0 * PI * u;
    let d = [
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    ];
    // The sun: 10 degrees up, a little right of the map's centre (u = 0.56).
    let (sun_elevation, sun_phi) = (10f64.to_radians(), 2.0 * PI * 0.56);
    let sun = [
        sun_elevation.cos() * sun_phi.cos(),
        sun_elevation.cos() * sun_phi.sin(),
        sun_elevation.sin(),
    ];
    let cos_sun = (d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]).clamp(-1.0, 1.0);
    let angle = cos_sun.acos();
    let elevation = PI / 2.0 - theta;
    if elevation < 0.0 {
        // The ground: dark, warmer and lighter toward the horizon.
        let t = (-elevation / 0.35).min(1.0).powf(0.5);
        return mix([0.16, 0.11, 0.08], [0.035, 0.03, 0.03], t);
    }
    let height = elevation / (PI / 2.0);
    let zenith = [0.025, 0.055, 0.22];
    let horizon = [0.95, 0.5, 0.26];
    let mut c = mix(horizon, zenith, height.powf(0.35));
    // The sun's glow: a broad halo and a tight aureole.
    let glow = 0.9 * (-angle / 0.35).exp() + 4.0 * (-angle / 0.06).exp();
    for (k, tint) in [1.0, 0.62, 0.3].iter().enumerate() {
        c[k] += glow * tint * (1.0 - 0.7 * height);
    }
    // Thin clouds above the horizon, lit warm from below and darker toward the zenith.
    let band =
        ((elevation - 0.05) / 0.08).clamp(0.0, 1.0) * ((0.6 - elevation) / 0.3).clamp(0.0, 1.0);
    let density = (fbm(u * 16.0, v * 40.0, 16) - 0.42).max(0.0) * 2.6 * band;
    let lit = mix([1.4, 0.55, 0.3], [0.25, 0.2, 0.3], height.powf(0.6));
    c = mix(c, lit, density.min(0.85));
    // The sun's disc, 1.2 degrees in radius.
    if angle < 1.2f64.to_radians() {
        c = [900.0, 700.0, 480.0];
    }
    c
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "assets/environment/dusk.hdr".into());
    // Each texel the mean of 4 x 4 points within it, so that the disc's edge is antialiased.
    let pixels: Vec<image::Rgb<f32>> = (0..HEIGHT)
        .flat_map(|j| (0..WIDTH).map(move |i| (i, j)))
        .map(|(i, j)| {
            let mut sum = [0.0f64; 3];
            for sy in 0..4 {
                for sx in 0..4 {
                    let u = (i as f64 + (sx as f64 + 0.5) / 4.0) / WIDTH as f64;
                    let v = (j as f64 + (sy as f64 + 0.5) / 4.0) / HEIGHT as f64;
                    let c = radiance(u, v);
                    for k in 0..3 {
                        sum[k] += c[k] / 16.0;
                    }
                }
            }
            image::Rgb(sum.map(|x| x as f32))
        })
        .collect();
    let file = std::fs::File::create(&out).expect("the output file");
    image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(file))
        .encode(&pixels, WIDTH, HEIGHT)
        .expect("writes the map");
    eprintln!("wrote {out} ({WIDTH} x {HEIGHT})");
}
