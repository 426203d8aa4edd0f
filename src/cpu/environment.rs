//! The environment map's light (issue 38, item 1; not wired yet): an equirectangular HDR image
//! about `sky.up`, looked up texel by texel (piecewise constant), and importance-sampled by a
//! 2D piecewise-constant distribution of luminance times sin(theta): the marginal over rows and
//! each row's conditional, each a CDF searched by bisection. The directions drawn and the
//! densities stated are those of the lookup, so that multiple importance sampling with the BSDF
//! is unbiased. Twin-to-be of shaders/environment.wgsl.

use crate::algebra::{Vec2, Vec3};

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

    /// The piece that `u` in [0, 1) falls in: the last k with cdf[k] <= u, by bisection.
    pub fn piece(&self, u: f32) -> usize {
        let (mut lo, mut hi) = (0usize, self.func.len());
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.cdf[mid] <= u {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// x in [0, 1) drawn with density [`Self::pdf`] from u in [0, 1), by inverting the CDF
    /// within the piece, with that density.
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let k = self.piece(u);
        let width = self.cdf[k + 1] - self.cdf[k];
        let du = if width > 0.0 {
            ((u - self.cdf[k]) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let n = self.func.len() as f32;
        let x = ((k as f32 + du) / n).min(1.0 - f32::EPSILON / 2.0);
        (x, self.pdf_piece(k))
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

/// The 2D distribution over the map's [0, 1)^2: the marginal over rows (v) and each row's
/// conditional over columns (u).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2d {
    pub rows: Vec<Distribution1d>,
    pub marginal: Distribution1d,
}

impl Distribution2d {
    /// The distribution of `func`, `width` values a row.
    pub fn new(func: &[f32], width: usize) -> Self {
        let rows: Vec<Distribution1d> = func.chunks(width).map(Distribution1d::new).collect();
        let marginal = Distribution1d::new(&rows.iter().map(|r| r.integral).collect::<Vec<_>>());
        Self { rows, marginal }
    }

    /// (u, v) drawn with density [`Self::pdf`] (over [0, 1)^2), and that density.
    pub fn sample(&self, u: Vec2<f32>) -> (Vec2<f32>, f32) {
        let (v, pdf_v) = self.marginal.sample(u.y);
        let row = self.marginal.piece(u.y);
        let (x, pdf_u) = self.rows[row].sample(u.x);
        (Vec2::new(x, v), pdf_v * pdf_u)
    }

    /// The density at (u, v) in [0, 1)^2.
    pub fn pdf(&self, uv: Vec2<f32>) -> f32 {
        let height = self.rows.len();
        let width = self.rows[0].func.len();
        let j = ((uv.y * height as f32) as usize).min(height - 1);
        let i = ((uv.x * width as f32) as usize).min(width - 1);
        self.marginal.pdf_piece(j) * self.rows[j].pdf_piece(i)
    }
}

/// An equirectangular map about an up direction: `width` = 2 `height` texels of linear RGB,
/// row 0 at the zenith, turned by `rotation` radians about up, times `intensity`.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<[f32; 3]>,
    /// Up, and two unit directions completing a right-handed frame with it: u = 0 looks along
    /// `front`, u = 1/4 along `right`.
    pub up: Vec3<f32>,
    pub front: Vec3<f32>,
    pub right: Vec3<f32>,
    pub rotation: f32,
    pub intensity: f32,
    pub distribution: Distribution2d,
}

/// Rec. 709 luminance.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl EnvironmentMap {
    /// The map of `texels` (`width` x `height`, row 0 at the zenith) about `up` (unit), turned
    /// by `rotation_degrees`, with its distribution: luminance times sin(theta) at each row's
    /// centre, theta from the zenith.
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<[f32; 3]>,
        up: Vec3<f32>,
        rotation_degrees: f64,
        intensity: f32,
    ) -> Self {
        let func: Vec<f32> = texels
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                let theta = std::f64::consts::PI * ((k / width) as f64 + 0.5) / height as f64;
                (luminance(t).max(0.0) as f64 * theta.sin()) as f32
            })
            .collect();
        // A frame about up: front is the unit vector of the world axis least along up, made
        // orthogonal to it.
        let axis = if up.y.abs() < 0.9 {
            Vec3::new(0.0, 1.0, 0.0)
        } else {
            Vec3::new(0.0, 0.0, -1.0)
        };
        let front = (axis - up * axis.dot(up)).normalize();
        let right = front.cross(up);
        Self {
            width,
            height,
            texels,
            up,
            front,
            right,
            rotation: rotation_degrees
                .to_radians()
                .rem_euclid(std::f64::consts::TAU) as f32,
            intensity,
            distribution: Distribution2d::new(&func, width),
        }
    }

    /// The map's (u, v) of the unit direction d: v = theta / pi from up, u = phi / (2 pi) about
    /// up from front toward right, less the rotation, in [0, 1).
    pub fn direction_uv(&self, d: Vec3<f32>) -> Vec2<f32> {
        let tau = std::f32::consts::TAU;
        let cos_theta = d.dot(self.up).clamp(-1.0, 1.0);
        let phi = d.dot(self.right).atan2(d.dot(self.front)) - self.rotation;
        let u = (phi / tau).rem_euclid(1.0);
        let v = cos_theta.acos() / std::f32::consts::PI;
        Vec2::new(
            u.min(1.0 - f32::EPSILON / 2.0),
            v.min(1.0 - f32::EPSILON / 2.0),
        )
    }

    /// The unit direction of the map's (u, v) ([`Self::direction_uv`]'s inverse).
    pub fn uv_direction(&self, uv: Vec2<f32>) -> Vec3<f32> {
        let theta = std::f32::consts::PI * uv.y;
        let phi = std::f32::consts::TAU * uv.x + self.rotation;
        let s = theta.sin();
        self.front * (s * phi.cos()) + self.right * (s * phi.sin()) + self.up * theta.cos()
    }

    /// The radiance along d: the texel d falls in, times the intensity.
    pub fn radiance(&self, d: Vec3<f32>) -> Vec3<f32> {
        let uv = self.direction_uv(d);
        let i = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let j = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        let t = self.texels[j * self.width + i];
        Vec3::new(t[0], t[1], t[2]) * self.intensity
    }

    /// A direction drawn toward the map's bright texels from u in [0, 1)^2, with its density per
    /// solid angle: pdf(u, v) / (2 pi^2 sin(theta)) (0 at the poles, where sin is 0).
    pub fn sample(&self, u: Vec2<f32>) -> (Vec3<f32>, f32) {
        let (uv, pdf_uv) = self.distribution.sample(u);
        let d = self.uv_direction(uv);
        (d, self.solid_angle_pdf(uv, pdf_uv))
    }

    /// The density per solid angle with which [`Self::sample`] draws the unit direction d.
    pub fn pdf(&self, d: Vec3<f32>) -> f32 {
        let uv = self.direction_uv(d);
        self.solid_angle_pdf(uv, self.distribution.pdf(uv))
    }

    fn solid_angle_pdf(&self, uv: Vec2<f32>, pdf_uv: f32) -> f32 {
        let s = (std::f32::consts::PI * uv.y).sin();
        if s <= 0.0 {
            return 0.0;
        }
        pdf_uv / (2.0 * std::f32::consts::PI * std::f32::consts::PI * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for the tests' u (PCG32, O'Neill 2014).
    struct Pcg(u64);

    impl Pcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let x = (((self.0 >> 18) ^ self.0) >> 27) as u32;
            let r = (self.0 >> 59) as u32;
            (x.rotate_right(r) >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    /// A 64 x 32 map: a dim gradient, a bright patch and a black band (the pdf must be 0
    /// there and positive wherever there is light).
    fn test_map(rotation: f64) -> EnvironmentMap {
        let (w, h) = (64, 32);
        let texels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                if (20..24).contains(&j) {
                    [0.0, 0.0, 0.0]
                } else if (40..44).contains(&i) && (6..9).contains(&j) {
                    [50.0, 40.0, 30.0]
                } else {
                    [0.1 + 0.01 * i as f32, 0.2, 0.3 + 0.02 * j as f32]
                }
            })
            .collect();
        let up = Vec3::new(0.3f32, 1.0, -0.2).normalize();
        EnvironmentMap::new(w, h, texels, up, rotation, 1.0)
    }

    /// The pdf integrates to 1 over the sphere: the sum over a fine grid of directions (in the
    /// map's own (u, v), each cell's solid angle 2 pi^2 sin(theta) du dv).
    #[test]
    fn the_pdf_integrates_to_one() {
        let map = test_map(30.0);
        let (n, m) = (1024, 512);
        let mut sum = 0.0f64;
        for j in 0..m {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / m as f32);
                let d = map.uv_direction(uv);
                let omega =
                    2.0 * std::f64::consts::PI.powi(2) * (std::f64::consts::PI * uv.y as f64).sin()
                        / (n * m) as f64;
                sum += map.pdf(d) as f64 * omega;
            }
        }
        assert!((sum - 1.0).abs() < 2e-3, "{sum}");
    }

    /// Samples fall in proportion to the pdf: a chi-square test over quarters of the map's
    /// texels (4 x 2,048 bins, so that where a sample falls within its texel counts too; those
    /// of mass, the black band gets none) with 400,000 samples, against the 0.1% critical
    /// value. Each sample's stated pdf is the pdf of its direction (but for the few whose f32
    /// direction, a rounding from a texel's edge, reads back in the neighbouring texel: at most
    /// 1 in 2,000; 56 of 400,000 here), and no sample lands where the map is black.
    #[test]
    fn samples_follow_the_pdf() {
        let map = test_map(-75.0);
        let mut rng = Pcg(0x853c_49e6_748f_ea9b);
        let n = 400_000;
        let (bw, bh) = (2 * map.width, 2 * map.height);
        let mut counts = vec![0u32; bw * bh];
        let mut read_back_elsewhere = 0;
        for _ in 0..n {
            let (d, pdf) = map.sample(Vec2::new(rng.next(), rng.next()));
            assert!(pdf > 0.0);
            if (pdf - map.pdf(d)).abs() > 1e-3 * pdf {
                read_back_elsewhere += 1;
            }
            let uv = map.direction_uv(d);
            let i = ((uv.x * bw as f32) as usize).min(bw - 1);
            let j = ((uv.y * bh as f32) as usize).min(bh - 1);
            counts[j * bw + i] += 1;
        }
        assert!(
            read_back_elsewhere <= n / 2_000,
            "{read_back_elsewhere} of {n}"
        );
        let total: f64 = map.distribution.marginal.integral as f64;
        let (mut chi2, mut bins) = (0.0f64, 0usize);
        for j in 0..bh {
            let row = &map.distribution.rows[j / 2];
            for i in 0..bw {
                let p = row.func[i / 2] as f64 / (bw * bh) as f64 / total;
                let k = counts[j * bw + i] as f64;
                if p == 0.0 {
                    assert_eq!(k, 0.0, "a sample in a black texel ({i}, {j})");
                    continue;
                }
                let expected = p * n as f64;
                chi2 += (k - expected).powi(2) / expected;
                bins += 1;
            }
        }
        // The 0.1% critical value of chi-square with df degrees of freedom (Wilson-Hilferty).
        let df = (bins - 1) as f64;
        let z = 3.0902;
        let critical = df * (1.0 - 2.0 / (9.0 * df) + z * (2.0 / (9.0 * df)).sqrt()).powi(3);
        eprintln!("chi-square {chi2:.1} over {bins} bins, critical {critical:.1}");
        assert!(
            chi2 < critical,
            "chi-square {chi2:.1} over {bins} bins, critical {critical:.1}"
        );
    }

    /// Directions and (u, v) are inverses, and the rotation turns the map about up: 360 degrees
    /// is 0, and 90 moves every direction's u by a quarter.
    #[test]
    fn rotation_turns_the_map_about_up() {
        let (a, full, quarter) = (test_map(0.0), test_map(360.0), test_map(90.0));
        let mut rng = Pcg(7);
        for _ in 0..1000 {
            let uv = Vec2::new(rng.next(), 0.02 + 0.96 * rng.next());
            let d = a.uv_direction(uv);
            let back = a.direction_uv(d);
            assert!((back.x - uv.x).abs() < 1e-4 || (back.x - uv.x).abs() > 1.0 - 1e-4);
            assert!((back.y - uv.y).abs() < 1e-4);
            let f = full.direction_uv(d);
            assert!((f.x - uv.x).abs() < 1e-4 || (f.x - uv.x).abs() > 1.0 - 1e-4);
            let q = quarter.direction_uv(d);
            let shift = (uv.x - q.x).rem_euclid(1.0);
            assert!((shift - 0.25).abs() < 1e-4, "{shift}");
            assert_eq!(a.radiance(d), a.radiance(a.uv_direction(back)));
        }
    }
}
