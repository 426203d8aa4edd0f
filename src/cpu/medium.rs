//! The fog's medium (`fog.density` > 0): the twin of shaders/medium.wgsl, same names, same order
//! (tests/architecture/twins.rs). A homogeneous medium of grey extinction and coloured albedo filling the
//! bounding ball: the Henyey-Greenstein phase function and its sampling, and free-flight
//! distance sampling. The book's chapter "Atmosphere" gives every formula.

use super::bsdf::{basis_from_normal, pi, to_world};
use crate::algebra::{Real, Vec2, Vec3};

/// A direction drawn by [`sample_hg`], with the density (per solid angle) it was drawn with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample<F> {
    pub wi: Vec3<F>,
    pub pdf: F,
}

/// Below this |g| the phase function is sampled as isotropic (the inverse divides by g).
pub const HG_ISOTROPIC: f64 = 1e-3;

/// The Henyey-Greenstein phase function of asymmetry g in (-1, 1) at c, the cosine between the
/// direction the light travelled and the direction it scatters into:
/// (1 - g^2) / (4 pi (1 + g^2 - 2 g c)^(3/2)); it integrates to 1 over the sphere, and g > 0
/// scatters forward. Below [`HG_ISOTROPIC`] it is the isotropic 1 / (4 pi) that [`sample_hg`]
/// draws.
pub fn phase_hg<F: Real>(g: F, c: F) -> F {
    let four_pi = F::lit(4.0) * pi::<F>();
    if g.abs() < F::lit(HG_ISOTROPIC) {
        return F::one() / four_pi;
    }
    let denom = (F::one() + g * g - F::lit(2.0) * g * c).max(F::lit(1e-12));
    (F::one() - g * g) / (four_pi * denom * denom.sqrt())
}

/// A direction about `d` (unit, the way the light travelled) drawn with density [`phase_hg`]
/// from u in [0, 1)^2: the cosine by inverting the phase function's distribution,
/// c = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u.x))^2) / (2 g) (isotropic, 1 - 2 u.x, below
/// [`HG_ISOTROPIC`]), the azimuth 2 pi u.y. The pdf is `phase_hg`'s at that cosine, so a phase
/// sample's weight, phase / pdf, is 1.
pub fn sample_hg<F: Real>(g: F, d: Vec3<F>, u: Vec2<F>) -> PhaseSample<F> {
    let (one, two) = (F::one(), F::lit(2.0));
    let mut c = one - two * u.x;
    if g.abs() >= F::lit(HG_ISOTROPIC) {
        let s = (one - g * g) / (one - g + two * g * u.x);
        c = (one + g * g - s * s) / (two * g);
    }
    c = c.max(-one).min(one);
    let sin_theta = (one - c * c).max(F::zero()).sqrt();
    let phi = two * pi::<F>() * u.y;
    let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), c);
    PhaseSample {
        wi: to_world(basis_from_normal(d), local),
        pdf: phase_hg(g, c),
    }
}

/// What free-flight sampling found along a stretch of fog: the distance into the stretch of a
/// scattering event (`scattered`) or the stretch's length (none), and the weight the path's
/// throughput takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FogEvent<F> {
    pub distance: F,
    pub scattered: bool,
    pub weight: Vec3<F>,
}

/// Free-flight sampling over a stretch of `length` of the medium of extinction `density` (grey)
/// and single-scattering albedo `albedo`, from u in [0, 1): a tentative event at
/// s = -ln(1 - u) / (density a), a = the albedo's largest channel. Where s falls within the
/// stretch the light scatters there, weighted (albedo / a) exp(-density (1 - a) s); else it
/// passes, weighted exp(-density (1 - a) length). Each weight is the transmittance, times the
/// scattering coefficient at an event, over the density it was drawn with, so that the estimate
/// is unbiased, and no channel's weight exceeds 1. An albedo of 0 never scatters: the weight is
/// then the transmittance exp(-density length) exactly.
pub fn fog_event<F: Real>(density: F, albedo: Vec3<F>, length: F, u: F) -> FogEvent<F> {
    let a = albedo.x.max(albedo.y.max(albedo.z));
    let absorbed = density * (F::one() - a);
    if a > F::zero() {
        let s = -(F::one() - u).ln() / (density * a);
        if s < length {
            return FogEvent {
                distance: s,
                scattered: true,
                weight: albedo / a * (-absorbed * s).exp(),
            };
        }
    }
    FogEvent {
        distance: length,
        scattered: false,
        weight: Vec3::splat((-absorbed * length).exp()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The phase function integrates to 1 over the sphere (midpoint rule in the cosine), for
    /// backward, isotropic and strongly forward g.
    #[test]
    fn phase_hg_integrates_to_one() {
        for g in [-0.9f64, -0.3, 0.0, 0.0005, 0.5, 0.9] {
            let n = 200_000;
            let integral: f64 = (0..n)
                .map(|k| {
                    let c = -1.0 + 2.0 * (k as f64 + 0.5) / n as f64;
                    2.0 * std::f64::consts::PI * phase_hg(g, c) * (2.0 / n as f64)
                })
                .sum();
            assert!((integral - 1.0).abs() < 1e-4, "g {g}: {integral}");
        }
    }

    /// sample_hg's cosine inverts the phase function's distribution: its mean cosine is g (the
    /// Henyey-Greenstein mean), over a stratified u, and each sample's pdf is phase_hg's at it.
    #[test]
    fn sample_hg_has_mean_cosine_g() {
        let d = Vec3::new(0.0f64, 0.6, 0.8);
        for g in [-0.7f64, 0.0, 0.4, 0.85] {
            let n = 4096;
            let mut mean = 0.0;
            for k in 0..n {
                let u = Vec2::new((k as f64 + 0.5) / n as f64, 0.37);
                let s = sample_hg(g, d, u);
                let c = s.wi.dot(d);
                assert!((s.wi.length() - 1.0).abs() < 1e-12);
                assert!(
                    (s.pdf - phase_hg(g, c)).abs() < 1e-9 * s.pdf.max(1.0),
                    "g {g}"
                );
                mean += c / n as f64;
            }
            assert!((mean - g).abs() < 1e-3, "g {g}: mean cosine {mean}");
        }
    }

    /// The free-flight weights: an absorbing medium passes the transmittance exactly, and the
    /// expected weight over u of an event (or none) is the closed form: the chance of scattering
    /// albedo (1 - exp(-density length)) and of passing exp(-density length).
    #[test]
    fn fog_event_is_unbiased() {
        let (density, length) = (1.3f64, 0.9);
        let black = fog_event(density, Vec3::zero(), length, 0.5);
        assert!(!black.scattered);
        assert_eq!(black.weight, Vec3::splat((-density * length).exp()));
        let albedo = Vec3::new(0.9f64, 0.5, 0.2);
        let n = 200_000;
        let (mut scattered, mut passed) = (Vec3::zero(), Vec3::zero());
        for k in 0..n {
            let e = fog_event(density, albedo, length, (k as f64 + 0.5) / n as f64);
            if e.scattered {
                assert!(e.distance < length);
                scattered += e.weight / n as f64;
            } else {
                passed += e.weight / n as f64;
            }
        }
        let t = (-density * length).exp();
        for (got, want) in [
            (scattered.x, 0.9 * (1.0 - t)),
            (scattered.z, 0.2 * (1.0 - t)),
            (passed.y, t),
        ] {
            assert!((got - want).abs() < 1e-4, "{got} against {want}");
        }
    }
}
