//! The CPU twin of shaders/accumulate.wgsl (the same functions with the same names in the same
//! order, generic over the float type; tests/architecture/twins.rs). The accumulation: a sample's
//! outcome (Pixel), the sample positions in the pixel and on the lens, adaptive sampling's two
//! streams, the packed colour, the AOVs with their M2, the noise rule, the halves, and (WGSL only)
//! their loads and stores in the accumulator.

use crate::algebra::{Real, Vec3};
use crate::params::TraceParams;

/// One sample's outcome: its colour (unclamped), depth and steps, whether it hit, and where it
/// was shaded, the hit point and its shading normal (0 where it was not: a miss, or no
/// shading).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pixel<F> {
    pub colour: Vec3<F>,
    pub depth: F,
    pub steps: u32,
    pub hit: bool,
    pub point: Vec3<F>,
    pub normal: Vec3<F>,
}

/// The AOVs of a pixel's samples so far (`--hdr`, the denoiser): the mean of their unclamped
/// colours and the sum of the squared deviations of their luminances from the running mean
/// (Welford's M2: the denoiser's variance), and over the samples whose primary ray hit, how many
/// did and the means of their hits' base colours, shading normals and depths (0 while none has);
/// in path mode also the mean of their first hits' specular light
/// ([`crate::cpu::path::PathResult::specular`]; 0 in phong mode), and over the hits the mean
/// cosine of the view direction to the shading normal (the denoiser's specular reflectance).
/// In f32 in both precisions, as the shader keeps them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aovs {
    pub colour: Vec3<f32>,
    pub hits: f32,
    pub albedo: Vec3<f32>,
    pub normal: Vec3<f32>,
    pub m2: f32,
    pub depth: f32,
    pub specular: Vec3<f32>,
    pub cosine: f32,
}

/// Where sample k lies in its pixel, (x, y) in [0, 1)^2 from the pixel's top left corner:
/// (0.5, 0.5), the centre, for sample 0; else the Halton point of index k in bases 2 and 3
/// (k < 4096: its 12 binary and 8 ternary digits, so both coordinates are exact in f32).
pub fn sample_position<F: Real>(k: u32) -> (F, F) {
    if k == 0 {
        return (F::lit(0.5), F::lit(0.5));
    }
    let base2 = k.reverse_bits() >> 20;
    let mut base3 = 0u32;
    let mut rest = k;
    for _ in 0..8 {
        base3 = base3 * 3 + rest % 3;
        rest /= 3;
    }
    (
        F::lit(base2 as f64) * F::lit(1.0 / 4096.0),
        F::lit(base3 as f64) * F::lit(1.0 / 6561.0),
    )
}

/// Where sample k (>= 1) lies on the lens before the aperture's map, (u, v) in [0, 1)^2: the
/// Halton point of index k in bases 5 and 7 (the sub-pixel positions take 2 and 3), from k's
/// first 6 quinary and 5 septenary digits as integers over 15625 and 16807 (k < 4096 has no
/// more).
pub fn lens_position(k: u32) -> (f32, f32) {
    let mut base5 = 0u32;
    let mut rest = k;
    for _ in 0..6 {
        base5 = base5 * 5 + rest % 5;
        rest /= 5;
    }
    let mut base7 = 0u32;
    rest = k;
    for _ in 0..5 {
        base7 = base7 * 7 + rest % 7;
        rest /= 7;
    }
    (
        base5 as f32 * (1.0 / 15625.0_f64) as f32,
        base7 as f32 * (1.0 / 16807.0_f64) as f32,
    )
}

impl<F: Real> TraceParams<F> {
    /// Adaptive sampling's two streams (docs/book/adaptive.md): sample k of an adaptive pixel
    /// is sample k / 2 of stream k % 2, as (stream, index). Each stream's stop is decided by its
    /// own samples and applied to the other's mean ([`TraceParams::add_to_streams`]), so that no
    /// half of what the pixel shows depends on its own stop. Without adaptive sampling every
    /// sample is stream 0's: (0, k) (phong mode; path mode has both streams anyway:
    /// [`TraceParams::path_stream`]).
    pub fn sample_stream(&self, k: u32) -> (u32, u32) {
        if self.adaptive() {
            return (k & 1, k >> 1);
        }
        (0, k)
    }
}

/// Stream 1's points in phong mode are stream 0's turned by this Cranley-Patterson shift
/// (modulo 1, in the pixel and on the lens alike): R2's (0.7549, 0.5698) rounded to 11 bits,
/// exact in f32. The streams' points are then apart, each stream as well spread as the Halton
/// points.
pub const STREAM_SHIFT: (f32, f32) = (1545.0 / 2048.0, 1167.0 / 2048.0);

impl<F: Real> TraceParams<F> {
    /// Where sample k lies in its pixel in phong mode: its stream's index's `sample_position`,
    /// shifted by [`STREAM_SHIFT`] in stream 1.
    pub fn stream_position(&self, k: u32) -> (F, F) {
        let (stream, index) = self.sample_stream(k);
        let (x, y) = sample_position::<F>(index);
        if stream == 0 {
            return (x, y);
        }
        let fract = |v: F| v - v.floor();
        (
            fract(x + F::lit(STREAM_SHIFT.0 as f64)),
            fract(y + F::lit(STREAM_SHIFT.1 as f64)),
        )
    }

    /// Where sample k lies on the lens before the aperture's map in phong mode: `lens_position`
    /// of its stream's index + 1, shifted by [`STREAM_SHIFT`] in stream 1.
    pub fn stream_lens_position(&self, k: u32) -> (f32, f32) {
        let (stream, index) = self.sample_stream(k);
        let (u, v) = lens_position(index + 1);
        if stream == 0 {
            return (u, v);
        }
        let fract = |x: f32| x - x.floor();
        (fract(u + STREAM_SHIFT.0), fract(v + STREAM_SHIFT.1))
    }
}

/// Colour clamped to [0, 1], times 255, rounded half up, packed as RGBA8 0xFFBBGGRR (opaque).
pub fn pack_colour<F: Real>(colour: Vec3<F>) -> u32 {
    let channel = |c: F| {
        let c = c.max(F::zero()).min(F::one());
        (c * F::lit(255.0) + F::lit(0.5)).floor().to_f64() as u32
    };
    channel(colour.x) | (channel(colour.y) << 8) | (channel(colour.z) << 16) | 0xff00_0000
}

/// Rec. 709 luminance of a linear colour, as [`super::bsdf::luminance`] (the shader's phong
/// module has no bsdf.wgsl).
pub fn sample_luminance(c: Vec3<f32>) -> f32 {
    super::bsdf::luminance(c)
}

/// Welford's rule: the sum of squared deviations from the mean `m2` of luminances, with one
/// more luminance `l`, given the mean's luminance before it (`before`) and after (`after`),
/// M2_k = M2_(k-1) + (l_k - L(m_(k-1))) (l_k - L(m_k)).
pub fn add_m2(m2: f32, l: f32, before: f32, after: f32) -> f32 {
    m2 + (l - before) * (l - after)
}

/// Adds sample k (0-based) to the AOVs: its colour and its specular light to the running means
/// over the samples, m_k = m_(k-1) + (c_k - m_(k-1)) / (k + 1), and its luminance l_k to M2
/// ([`add_m2`]); where it hit, its albedo, normal, depth and view cosine to the running means
/// over the hits, by the same rule with the hits counted so far.
#[allow(clippy::too_many_arguments)]
pub fn add_aovs(
    a: Aovs,
    k: u32,
    colour: Vec3<f32>,
    hit: bool,
    albedo: Vec3<f32>,
    normal: Vec3<f32>,
    depth: f32,
    (specular, cosine): (Vec3<f32>, f32),
) -> Aovs {
    let mut out = a;
    out.colour = a.colour + (colour - a.colour) / (k + 1) as f32;
    out.specular = a.specular + (specular - a.specular) / (k + 1) as f32;
    let l = sample_luminance(colour);
    out.m2 = add_m2(
        a.m2,
        l,
        sample_luminance(a.colour),
        sample_luminance(out.colour),
    );
    if hit {
        out.hits = a.hits + 1.0;
        out.albedo = a.albedo + (albedo - a.albedo) / out.hits;
        out.normal = a.normal + (normal - a.normal) / out.hits;
        out.depth = a.depth + (depth - a.depth) / out.hits;
        out.cosine = a.cosine + (cosine - a.cosine) / out.hits;
    }
    out
}

impl<F: Real> TraceParams<F> {
    /// Adds sample k's pixel to the AOVs: its colour, and where it hit, the base colour of its
    /// hit (hit_albedo), its shading normal and its depth. (AOVs are made only of shaded
    /// pictures: every hit is shaded.)
    pub fn add_pixel_aovs(&self, a: Aovs, k: u32, pixel: &Pixel<F>) -> Aovs {
        let mut albedo = Vec3::zero();
        if pixel.hit {
            albedo = self.hit_albedo(pixel.point).to_f32();
        }
        let (colour, normal) = (pixel.colour.to_f32(), pixel.normal.to_f32());
        let depth = pixel.depth.to_f64() as f32;
        add_aovs(
            a,
            k,
            colour,
            pixel.hit,
            albedo,
            normal,
            depth,
            (Vec3::zero(), 0.0),
        )
    }

    /// Whether this render samples adaptively (the shader's `adaptive`: `noise_target` > 0 with
    /// samples > 1; the book's chapter "Adaptive sampling"). Each pixel decides alone, after
    /// each of its samples, whether it is done, so any split of the image gives the same pixels.
    pub fn adaptive(&self) -> bool {
        self.noise_target > F::zero() && self.samples > 1
    }
}

/// A pixel's noise is taken relative to its mean luminance or to this, whichever is larger (the
/// floor for dark pixels, in linear luminance: 1 is phong mode's white), so that a black
/// pixel's noise is not a division by zero.
pub const NOISE_LUMINANCE_FLOOR: f32 = 0.01;

/// A pixel's noise after n >= 2 samples whose luminances' M2 is `m2`: the standard error of
/// its mean luminance, sqrt(m2 / (n (n - 1))), relative to that mean (at least
/// [`NOISE_LUMINANCE_FLOOR`]).
pub fn pixel_noise(m2: f32, n: u32, mean_luminance: f32) -> f32 {
    let k = n as f32;
    let variance = (m2 / (k * (k - 1.0))).max(0.0);
    variance.sqrt() / mean_luminance.abs().max(NOISE_LUMINANCE_FLOOR)
}

/// A pixel's adaptive state (the kernels' `Streams`, kept on the GPU in the accumulator's four
/// planes): `a` = (A's mean colour, tau_A: 0 until A's rule fires), `b` = (B's mean colour, the
/// samples in it), `rule_a` = (A's mean luminance, its M2 ([`add_m2`]), its samples kept, the
/// samples in A's colour), `rule_b` = (B's mean luminance, its M2, its samples kept, tau_B: 0
/// until B's rule fires). Streams A and B are stream 0 and 1 of
/// [`TraceParams::sample_stream`]. A's colour takes A's draws while B's rule has not fired (A's
/// first tau_B), B's takes B's first tau_A; each stream's luminances are counted until its own
/// rule fires. The counts are exact in f32. All in f32 in both precisions, as the accumulator is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Streams {
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub rule_a: [f32; 4],
    pub rule_b: [f32; 4],
}

/// A stream's luminance statistics (`rule`: mean, M2, samples kept) with one more luminance `l`,
/// by Welford's rule ([`add_m2`], at least 0); the fourth float is kept.
pub fn add_luminance(rule: [f32; 4], l: f32) -> [f32; 4] {
    let mut out = rule;
    out[2] = rule[2] + 1.0;
    out[0] = rule[0] + (l - rule[0]) / out[2];
    out[1] = add_m2(rule[1], l, rule[0], out[0]).max(0.0);
    out
}

impl<F: Real> TraceParams<F> {
    /// Whether a stream's rule fires after its draw `draws` (from 1), its luminances' statistics
    /// being `rule` ([`add_luminance`]): at its cap of samples / 2 draws, or from half the floor
    /// max(min(min_samples, samples), 4) (rounded up) on, with at least 2 samples kept and a
    /// noise ([`pixel_noise`]) at most the target.
    pub fn stream_fires(&self, rule: [f32; 4], draws: u32) -> bool {
        if draws >= self.samples / 2 {
            return true;
        }
        let floor = self.min_samples.min(self.samples).max(4).div_ceil(2);
        if draws < floor || rule[2] < 2.0 {
            return false;
        }
        pixel_noise(rule[1], rule[2] as u32, rule[0]) <= self.noise_target.to_f64() as f32
    }

    /// A pixel's streams with its sample `k` taken (draw k / 2 + 1 of stream k % 2), of colour
    /// `colour` where it is `valid`.
    pub fn add_to_streams(&self, s: Streams, k: u32, valid: bool, colour: Vec3<f32>) -> Streams {
        let mut out = s;
        let draws = k / 2 + 1;
        let l = sample_luminance(colour);
        let c = [colour.x, colour.y, colour.z];
        let joined = |mean: [f32; 4], n: f32| [0, 1, 2].map(|k| mean[k] + (c[k] - mean[k]) / n);
        if k.is_multiple_of(2) {
            // A's draw joins A's colour while B's rule has not fired.
            if valid && s.rule_b[3] == 0.0 {
                out.rule_a[3] = s.rule_a[3] + 1.0;
                let [r, g, b] = joined(s.a, out.rule_a[3]);
                out.a = [r, g, b, s.a[3]];
            }
            if s.a[3] == 0.0 {
                if valid {
                    let [m, m2, kept, _] = add_luminance(s.rule_a, l);
                    out.rule_a = [m, m2, kept, out.rule_a[3]];
                }
                if self.stream_fires(out.rule_a, draws) {
                    out.a[3] = draws as f32;
                }
            }
        } else {
            // B's draw joins B's colour while A's rule has not fired, or up to A's stop.
            if valid && (s.a[3] == 0.0 || draws as f32 <= s.a[3]) {
                let n = s.b[3] + 1.0;
                let [r, g, b] = joined(s.b, n);
                out.b = [r, g, b, n];
            }
            if s.rule_b[3] == 0.0 {
                if valid {
                    let [m, m2, kept, _] = add_luminance(s.rule_b, l);
                    out.rule_b = [m, m2, kept, 0.0];
                }
                if self.stream_fires(out.rule_b, draws) {
                    out.rule_b[3] = draws as f32;
                }
            }
        }
        out
    }

    /// Whether a pixel whose streams are `s` is done once it has taken `taken` samples: both
    /// rules have fired and B has its first tau_A draws (A has its first tau_B whenever B's rule
    /// has fired), or it has taken every sample.
    pub fn sampling_done(&self, s: &Streams, taken: u32) -> bool {
        if taken >= self.samples {
            return true;
        }
        s.a[3] > 0.0 && s.rule_b[3] > 0.0 && (taken / 2) as f32 >= s.a[3]
    }
}

/// A pixel's two halves (the kernels' `Halves`; path mode, and an adaptive pixel once it is
/// done): each stream's mean colour and the samples in it, `a` = (A's mean colour, n_A), `b` =
/// (B's mean colour, n_B). The streams are drawn independently, so the halves' disagreement
/// estimates the error of what the pixel shows: E[(a - b)^2] / 4 = Var((a + b) / 2).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Halves {
    pub a: [f32; 4],
    pub b: [f32; 4],
}

/// A pixel's halves with its valid sample `k` (of stream k % 2) of colour `colour` joined to its
/// stream's running mean, m_n = m_(n-1) + (c - m_(n-1)) / n.
pub fn add_to_halves(h: Halves, k: u32, colour: Vec3<f32>) -> Halves {
    let c = [colour.x, colour.y, colour.z];
    let joined = |m: [f32; 4]| {
        let n = m[3] + 1.0;
        [
            m[0] + (c[0] - m[0]) / n,
            m[1] + (c[1] - m[1]) / n,
            m[2] + (c[2] - m[2]) / n,
            n,
        ]
    };
    let mut out = h;
    if k.is_multiple_of(2) {
        out.a = joined(h.a);
    } else {
        out.b = joined(h.b);
    }
    out
}

/// What a pixel whose halves are `h` shows: half A's mean colour plus half B's, or the one
/// half's where the other has no sample in it (black where neither has).
pub fn halves_mean(h: &Halves) -> Vec3<f32> {
    let [a, b] = [h.a, h.b].map(|m| Vec3::new(m[0], m[1], m[2]));
    if h.a[3] == 0.0 {
        return b;
    }
    if h.b[3] == 0.0 {
        return a;
    }
    (a + b) * 0.5
}

/// An adaptive pixel's halves: A's mean of its first tau_B draws, B's of its first tau_A.
pub fn streams_halves(s: &Streams) -> Halves {
    Halves {
        a: [s.a[0], s.a[1], s.a[2], s.rule_a[3]],
        b: s.b,
    }
}

/// What a pixel whose streams are `s` shows: its halves' mean ([`halves_mean`]).
pub fn streams_mean(s: &Streams) -> Vec3<f32> {
    halves_mean(&streams_halves(s))
}

/// A done pixel's AOVs with their hits and M2 taken to the `taken` samples it took, which the
/// host divides by ([`crate::denoise::mean_variance`], [`crate::denoise::hit_fraction`]):
/// hits / taken is then the fraction of the n = n_A + n_B samples in its colours that hit, and
/// M2 / (taken (taken - 1)) the variance of what it shows, M2 / (n - 1) (1 / n_A + 1 / n_B) / 4
/// (1 / n with one stream empty).
pub fn finish_aovs(a: Aovs, s: &Streams, taken: u32) -> Aovs {
    let mut out = a;
    let n = s.rule_a[3] + s.b[3];
    let t = taken as f32;
    if n == 0.0 {
        return out;
    }
    out.hits = a.hits * t / n;
    let mut spread = 1.0 / n;
    if s.rule_a[3] > 0.0 && s.b[3] > 0.0 {
        spread = 0.25 * (1.0 / s.rule_a[3] + 1.0 / s.b[3]);
    }
    out.m2 = 0.0;
    if n >= 2.0 && t >= 2.0 {
        out.m2 = a.m2 / (n - 1.0) * spread * (t * (t - 1.0));
    }
    out
}
