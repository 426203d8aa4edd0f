//! The work-precision report's Monte Carlo page (`qjulia report --monte-carlo`): how fast path
//! mode's linear image converges. For each case (a scene, a sampler, a number of bounces) the
//! RMSE of the linear image against a converged reference of the same scene and bounces,
//! against samples per pixel and against seconds, log-log, with the fitted slope. Writes
//! `monte_carlo.csv`, `monte_carlo.png` and `monte_carlo.md` (their text and plot are
//! [`super::monte_carlo_page`]'s).
//!
//! Each scene also has a denoised curve (`image.denoise = "atrous"`, Sobol', 3 bounces), whose
//! seconds include the denoiser's, and the page measures the denoiser's bias: its error at the
//! most samples, on edge pixels and on flat ones ([`edge_mask`]), against plain averaging's.
//! And an adaptive curve (`path.noise_target` = [`ADAPTIVE_TARGET`], `image.samples` the
//! point's: the most a pixel may take), alone and denoised; its points are placed at the mean
//! samples its pixels took ([`Point::taken`]). And a regularised curve (`path.regularize` =
//! [`REGULARIZE`]), alone and denoised: a bias, which the page gives as the mean radiance of its
//! last point against the reference's ([`Curve::last_mean`]).
//!
//! The reference is rendered with the `random` sampler (the plain hash), so that the Sobol'
//! curves are measured against an independent estimate. A `random` curve's first samples are
//! the reference's own first samples: its RMSE is biased low by at most the share
//! `n / reference_samples` of the reference they make, which favours `random` in the
//! comparison, not Sobol'.

use crate::error::Result;
use crate::frame::Frame;
use crate::render::{Picture, Planner};
use crate::scene::presets::find;
use crate::scene::{PathSampler, Scene};

/// Samples per pixel of each point of a curve.
pub const SAMPLES: [u32; 9] = [1, 2, 4, 8, 16, 32, 64, 128, 256];

/// The slope is fitted over the points with at least this many samples (the first few are
/// dominated by sample 0, the pixel centre, which every sampler shares).
pub const FIT_FROM: u32 = 4;

/// The adaptive curves' `path.noise_target` (with the default `path.min_samples`, 16).
pub const ADAPTIVE_TARGET: f64 = 0.02;

/// The regularised curves' `path.regularize` (the book's chapter "Path tracing" measures its
/// glints at this value).
pub const REGULARIZE: f64 = 0.5;

/// One curve: what is varied.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub scene_name: &'static str,
    pub sampler: PathSampler,
    pub bounces: u32,
    /// Whether the denoiser runs (`image.denoise = "atrous"` at the scene's `[denoise]`).
    pub denoise: bool,
    /// Whether pixels stop at [`ADAPTIVE_TARGET`] (`path.noise_target`).
    pub adaptive: bool,
    /// Whether glossy lobes after a diffuse vertex are roughened to [`REGULARIZE`]
    /// (`path.regularize`): a bias, which the page measures against the unregularised
    /// reference.
    pub regularize: bool,
}

/// One measured point of a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// `image.samples`: every pixel's samples, or with adaptive sampling the most a pixel
    /// takes.
    pub samples: u32,
    /// The mean samples a pixel took (`samples_total` over the pixels): `samples`, or fewer
    /// with adaptive sampling.
    pub taken: f64,
    /// Root mean square error of the linear RGB (every channel of every pixel) against the
    /// reference.
    pub rmse: f64,
    /// The RMSE over all but the [`TRIM`] share of pixels with the largest errors: the
    /// error of the bulk of the image, without the rare glints (a small bright sun seen in a
    /// glossy lobe) that dominate the RMSE of a few pixels.
    pub trimmed: f64,
    /// The render's GPU seconds where the device times it, else its render seconds; with the
    /// denoiser's (its GPU seconds, else its wall seconds) added.
    pub seconds: f64,
    /// The render's own estimate of its RMSE (`--stats`' `estimated_rmse`, src/estimate.rs:
    /// from its pixels' halves, of the denoised image where the denoiser runs), which the page
    /// plots beside the measured one; None at one sample a pixel.
    pub estimated: Option<f64>,
}

/// The RMSE of a curve's last point split by pixel kind ([`edge_mask`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    pub edge: f64,
    pub flat: f64,
    /// The share of pixels that are edges.
    pub edge_share: f64,
}

/// A measured curve, its fitted log-log slope (RMSE against samples) and its reference's mean
/// linear radiance.
#[derive(Clone, Debug)]
pub struct Curve {
    pub case: Case,
    pub points: Vec<Point>,
    pub slope: f64,
    pub reference_mean: f64,
    /// The last point's RMSE on edge and on flat pixels.
    pub split: Split,
    /// The last point's mean linear radiance (as `reference_mean`): with the reference's, the
    /// bias of a biased way (regularisation).
    pub last_mean: f64,
}

/// The page's scenes at `size` x `size`: the two path presets, and the path-traced preset as a
/// rough metal.
pub fn scenes(size: u32) -> Vec<(&'static str, Scene)> {
    let preset = |slug: &str| find(slug).expect("a path preset").scene();
    let mut metal = preset("path-traced");
    metal.material.metallic = 1.0;
    metal.material.roughness = 0.6;
    let mut out = vec![
        ("path-traced", preset("path-traced")),
        ("path-gallery", preset("path-gallery")),
        ("rough metal", metal),
    ];
    for (_, scene) in &mut out {
        scene.image.width = size;
        scene.image.height = size;
    }
    out
}

/// The cases: every scene with both samplers at 3 bounces, and with Sobol' denoised, adaptive,
/// both, regularised, and regularised and denoised; the path-traced preset with Sobol' at 1 and
/// 5 bounces.
pub fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let case = |scene_name, sampler, bounces, (denoise, adaptive, regularize)| Case {
        scene_name,
        sampler,
        bounces,
        denoise,
        adaptive,
        regularize,
    };
    for scene_name in ["path-traced", "path-gallery", "rough metal"] {
        for sampler in PathSampler::ALL {
            out.push(case(scene_name, sampler, 3, (false, false, false)));
        }
        for kind in [
            (true, false, false),
            (false, true, false),
            (true, true, false),
            (false, false, true),
            (true, false, true),
        ] {
            out.push(case(scene_name, PathSampler::Sobol, 3, kind));
        }
    }
    for bounces in [1, 5] {
        out.push(case(
            "path-traced",
            PathSampler::Sobol,
            bounces,
            (false, false, false),
        ));
    }
    out
}

/// Which pixels are edges, for the denoiser's bias: a pixel whose primary ray hit where a
/// 4-neighbour's missed (or the other way), or whose mean normal and a neighbour's part by
/// more than [`EDGE_COSINE`], or whose depth and a neighbour's differ by more than
/// [`EDGE_DEPTH`] of its own. The rest are flat. Needs the frame's AOVs.
pub fn edge_mask(frame: &Frame) -> Vec<bool> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let unit = |v: [f32; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.0 { v.map(|c| c / l) } else { [0.0; 3] }
    };
    let parted = |a: usize, b: usize| {
        let (da, db) = (frame.depth[a], frame.depth[b]);
        if da.is_nan() || db.is_nan() {
            return da.is_nan() != db.is_nan();
        }
        let (na, nb) = (unit(frame.normal[a]), unit(frame.normal[b]));
        let cosine = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
        cosine < EDGE_COSINE || (da - db).abs() > EDGE_DEPTH * da
    };
    (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            (i > 0 && parted(k, k - 1))
                || (i + 1 < w && parted(k, k + 1))
                || (j > 0 && parted(k, k - w))
                || (j + 1 < h && parted(k, k + w))
        })
        .collect()
}

/// Neighbours' normals part (an edge) where their cosine is below this (about 25 degrees).
pub const EDGE_COSINE: f32 = 0.9;
/// Neighbours' depths part (an edge) where they differ by more than this share.
pub const EDGE_DEPTH: f32 = 0.02;

/// The RMSE of `image` against `reference` over the pixels `mask` picks.
fn rmse_where(image: &[[f32; 3]], reference: &[[f32; 3]], mask: &[bool], pick: bool) -> f64 {
    let (a, b): (Vec<[f32; 3]>, Vec<[f32; 3]>) = image
        .iter()
        .zip(reference)
        .zip(mask)
        .filter(|(_, m)| **m == pick)
        .map(|((a, b), _)| (*a, *b))
        .unzip();
    if a.is_empty() { 0.0 } else { rmse(&a, &b) }
}

/// The seconds a curve takes to reach an error of `target` by `error` (the RMSE or the trimmed
/// RMSE) and stay there: from the first point after which every point is at most `target`,
/// interpolated log-log with the point before it; None where the last point is above it. (A
/// glint met late can lift a curve above an error it had reached early.)
pub fn seconds_to(curve: &Curve, target: f64, error: fn(&Point) -> f64) -> Option<f64> {
    let points = &curve.points;
    let k = points
        .iter()
        .rposition(|p| error(p) > target)
        .map_or(0, |k| k + 1);
    let p = *points.get(k)?;
    if k == 0 {
        return Some(p.seconds);
    }
    let q = points[k - 1];
    let t = (target.ln() - error(&q).ln()) / (error(&p).ln() - error(&q).ln());
    Some((q.seconds.ln() + t * (p.seconds.ln() - q.seconds.ln())).exp())
}

/// The RMSE of two linear images over every channel of every pixel.
pub fn rmse(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    assert_eq!(a.len(), b.len(), "images of one size");
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] as f64 - q[c] as f64).powi(2)))
        .sum();
    (sum / (3 * a.len().max(1)) as f64).sqrt()
}

/// The share of pixels with the largest errors that [`rmse_trimmed`] leaves out.
pub const TRIM: f64 = 0.005;

/// The RMSE of two linear images over every channel of all but the `trim` share of pixels
/// with the largest errors.
pub fn rmse_trimmed(a: &[[f32; 3]], b: &[[f32; 3]], trim: f64) -> f64 {
    assert_eq!(a.len(), b.len(), "images of one size");
    let mut errors: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(p, q)| {
            (0..3)
                .map(|c| (p[c] as f64 - q[c] as f64).powi(2))
                .sum::<f64>()
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    let keep = ((1.0 - trim) * errors.len() as f64).ceil() as usize;
    let kept = &errors[..keep.min(errors.len())];
    (kept.iter().sum::<f64>() / (3 * kept.len().max(1)) as f64).sqrt()
}

/// The least-squares slope of log y against log x.
pub fn fit_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    sxy / sxx
}

/// The slope of a curve's RMSE against samples, over its points from [`FIT_FROM`] samples on.
pub fn curve_slope(points: &[Point]) -> f64 {
    let fit: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.samples >= FIT_FROM)
        .map(|p| (p.samples as f64, p.rmse))
        .collect();
    fit_slope(&fit)
}

/// The mean samples a pixel of `frame` took ([`Frame::samples`]; `samples` each where it has
/// none).
pub fn mean_taken(frame: &Frame, samples: u32) -> f64 {
    let pixels = frame.pixel_count().max(1);
    let total: u64 = (0..pixels)
        .map(|k| frame.samples_of(k, samples) as u64)
        .sum();
    total as f64 / pixels as f64
}

/// A path-traced render of `scene` through `planner`: the frame and its seconds.
pub fn render(planner: &mut Planner, scene: &Scene) -> Result<(Frame, f64)> {
    let (frame, stats) = render_stats(planner, scene)?;
    Ok((frame, seconds_of(&stats)))
}

/// A render's seconds as the page counts them: its GPU seconds where the device times them,
/// else its render seconds, with the denoiser's (GPU seconds, else wall seconds) added.
pub fn seconds_of(stats: &crate::stats::RenderStats) -> f64 {
    let denoise = stats
        .denoise
        .as_ref()
        .map(|d| d.gpu_seconds.unwrap_or(d.seconds));
    stats.gpu_seconds.unwrap_or(stats.render_seconds) + denoise.unwrap_or(0.0)
}

/// A render of `scene`'s shaded picture through `planner`, whole, with its AOVs (the edge mask
/// needs them, and a denoised render has them anyway): the frame and its stats.
pub fn render_stats(
    planner: &mut Planner,
    scene: &Scene,
) -> Result<(Frame, crate::stats::RenderStats)> {
    let plan = planner.plan(scene, Picture::SHADED.into(), &mut |_| {})?;
    let mut frame = Frame::empty(scene.image.width);
    let stats = plan.renderer.render_with(
        scene,
        Picture::SHADED,
        crate::render::Readback::Hdr,
        &mut |band| {
            frame.append(band);
            Ok(())
        },
    )?;
    Ok((frame, stats))
}

/// `scene` with this case's sampler, bounces and samples.
pub fn case_scene(scene: &Scene, sampler: PathSampler, bounces: u32, samples: u32) -> Scene {
    let mut s = scene.clone();
    s.path.sampler = sampler;
    s.path.bounces = bounces;
    s.image.samples = samples;
    s
}

/// A case's scene at `samples`: [`case_scene`], with the denoiser and adaptive sampling where
/// the case has them.
fn scene_of(base: &Scene, case: &Case, samples: u32) -> Scene {
    let mut s = case_scene(base, case.sampler, case.bounces, samples);
    if case.denoise {
        s.image.denoise = crate::denoise::Denoiser::Atrous;
    }
    if case.adaptive {
        s.path.noise_target = ADAPTIVE_TARGET;
    }
    if case.regularize {
        s.path.regularize = REGULARIZE;
    }
    s
}

/// A reference's scene and bounces.
type ReferenceKey = (&'static str, u32);

/// Measures every case at `size` x `size` against references of `reference_samples` (at least
/// 4 times the most samples of a point, so that no `random` point is most of its reference),
/// telling `progress` (what, done, of) as it goes.
pub fn run(
    planner: &mut Planner,
    size: u32,
    reference_samples: u32,
    progress: &mut dyn FnMut(&str, usize, usize),
) -> Result<Vec<Curve>> {
    let most = SAMPLES[SAMPLES.len() - 1];
    assert!(
        reference_samples >= 4 * most,
        "a reference of {reference_samples} samples, at least {}",
        4 * most
    );
    let scenes = scenes(size);
    let cases = cases();
    let total = cases.len() * (SAMPLES.len() + 1);
    let mut done = 0;
    let mut references: Vec<(ReferenceKey, Vec<[f32; 3]>)> = Vec::new();
    let mut curves = Vec::new();
    for case in cases {
        let base = &scenes
            .iter()
            .find(|(name, _)| *name == case.scene_name)
            .expect("a scene of the page")
            .1;
        let key = (case.scene_name, case.bounces);
        if !references.iter().any(|(k, _)| *k == key) {
            progress(
                &format!("{} reference, {} bounces", case.scene_name, case.bounces),
                done,
                total,
            );
            let scene = case_scene(base, PathSampler::Random, case.bounces, reference_samples);
            references.push((key, render(planner, &scene)?.0.radiance));
        }
        done += 1;
        let reference = &references
            .iter()
            .find(|(k, _)| *k == key)
            .expect("made above")
            .1;
        let mut points = Vec::new();
        let mut last = None;
        for samples in SAMPLES {
            progress(
                &format!(
                    "{} {} {} bounces, {samples} samples",
                    case.scene_name,
                    case.sampler.name(),
                    case.bounces
                ),
                done,
                total,
            );
            let scene = scene_of(base, &case, samples);
            let (frame, stats) = render_stats(planner, &scene)?;
            points.push(Point {
                samples,
                taken: mean_taken(&frame, samples),
                rmse: rmse(&frame.radiance, reference),
                trimmed: rmse_trimmed(&frame.radiance, reference, TRIM),
                seconds: seconds_of(&stats),
                estimated: stats.summary.estimated_rmse,
            });
            last = Some(frame);
            done += 1;
        }
        let last = last.expect("a point");
        let mask = edge_mask(&last);
        let split = Split {
            edge: rmse_where(&last.radiance, reference, &mask, true),
            flat: rmse_where(&last.radiance, reference, &mask, false),
            edge_share: mask.iter().filter(|&&e| e).count() as f64 / mask.len().max(1) as f64,
        };
        curves.push(Curve {
            slope: curve_slope(&points),
            case,
            points,
            reference_mean: image_mean(reference),
            split,
            last_mean: image_mean(&last.radiance),
        });
    }
    Ok(curves)
}

/// An image's mean linear radiance, over its pixels and channels.
pub fn image_mean(image: &[[f32; 3]]) -> f64 {
    image
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0)
        .sum::<f64>()
        / image.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slope_of_a_power_law_is_its_exponent() {
        let points: Vec<(f64, f64)> = [4.0, 8.0, 16.0, 64.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(-0.5)))
            .collect();
        assert!((fit_slope(&points) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_trimmed_rmse_leaves_out_the_worst_pixels() {
        let mut a = vec![[0.0f32; 3]; 1000];
        let b = vec![[0.0f32; 3]; 1000];
        for (k, p) in a.iter_mut().enumerate() {
            *p = [0.1; 3];
            if k < 5 {
                *p = [100.0; 3];
            }
        }
        assert!(rmse(&a, &b) > 3.0);
        assert!((rmse_trimmed(&a, &b, 0.005) - 0.1).abs() < 1e-6);
        assert!((rmse_trimmed(&a, &b, 0.0) - rmse(&a, &b)).abs() < 1e-9);
    }

    #[test]
    fn edges_are_where_hits_normals_or_depths_part() {
        // 4 x 1: a miss, then three hits, the last turned away from the others.
        let mut f = Frame::empty(4);
        f.height = 1;
        f.depth = vec![f32::NAN, 2.0, 2.0, 2.0];
        f.normal = vec![[0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];
        assert_eq!(edge_mask(&f), [true, true, true, true]);
        f.normal[3] = [0.0, 0.1, 2.0];
        assert_eq!(edge_mask(&f), [true, true, false, false]);
        f.depth[3] = 2.1;
        assert_eq!(edge_mask(&f), [true, true, true, true]);
    }

    #[test]
    fn the_seconds_to_an_error_interpolate_log_log() {
        let point = |samples, rmse, seconds| Point {
            samples,
            taken: samples as f64,
            rmse,
            trimmed: rmse,
            seconds,
            estimated: None,
        };
        let curve = Curve {
            case: cases()[0].clone(),
            points: vec![point(1, 0.4, 1.0), point(4, 0.1, 16.0)],
            slope: -1.0,
            reference_mean: 1.0,
            split: Split {
                edge: 0.0,
                flat: 0.0,
                edge_share: 0.0,
            },
            last_mean: 1.0,
        };
        // Halfway in log error between 0.4 and 0.1 is 0.2: halfway in log seconds, 4 s.
        let rmse = |p: &Point| p.rmse;
        assert!((seconds_to(&curve, 0.2, rmse).unwrap() - 4.0).abs() < 1e-9);
        assert_eq!(seconds_to(&curve, 0.5, rmse), Some(1.0));
        assert_eq!(seconds_to(&curve, 0.05, rmse), None);
        // A curve that dips below the target and rises again reaches it only where it stays.
        let mut late = curve.clone();
        late.points.insert(1, point(2, 0.3, 4.0));
        late.points[0].rmse = 0.1;
        // From (0.3, 4 s) to (0.1, 16 s): 0.2 is ln(2/3) / ln(1/3) of the way in log error.
        let expected = 4.0 * 4f64.powf((2.0f64 / 3.0).ln() / (1.0f64 / 3.0).ln());
        assert!((seconds_to(&late, 0.2, rmse).unwrap() - expected).abs() < 1e-9);
    }

    #[test]
    fn rmse_of_a_constant_offset_is_the_offset() {
        let a = vec![[1.0f32, 2.0, 3.0]; 10];
        let b = vec![[1.5f32, 2.5, 3.5]; 10];
        assert!((rmse(&a, &b) - 0.5).abs() < 1e-12);
        assert_eq!(rmse(&a, &a), 0.0);
    }
}
