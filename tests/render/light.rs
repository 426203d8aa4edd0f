//! The path tracer's light on the CPU twin (src/cpu/light.rs): the sky's gradient, the cone
//! sampling of the sun and the sphere light against their densities, and next-event
//! estimation, BSDF sampling and their power-heuristic blend against the closed-form
//! irradiance of a sphere light, E = pi L (r/d)^2 cos(theta).

use std::f64::consts::PI;

use qjulia::algebra::{Vec2, Vec3};
use qjulia::cpu::bsdf::sample_cosine_hemisphere;
use qjulia::cpu::light::{
    Sky, SphereLight, Sun, cone_solid_angle, intersect_sphere, power_heuristic,
    sample_sphere_light, sample_sun, sky_radiance, sphere_light_one_minus_cos, sphere_light_pdf,
    sphere_light_radiance, sun_one_minus_cos, sun_pdf, sun_radiance,
};

use crate::common;
use crate::common::SplitMix;

fn v(x: f64, y: f64, z: f64) -> Vec3<f64> {
    Vec3::new(x, y, z)
}

#[test]
fn the_sky_is_its_three_colours_at_zenith_horizon_and_nadir() {
    let sky = Sky {
        zenith: v(0.2, 0.4, 0.9),
        horizon: v(0.8, 0.85, 0.9),
        ground: v(0.3, 0.25, 0.2),
        up: v(0.0, 1.0, 0.0),
        intensity: 2.0,
    };
    assert_eq!(sky_radiance(sky, v(0.0, 1.0, 0.0)), sky.zenith * 2.0);
    assert_eq!(sky_radiance(sky, v(1.0, 0.0, 0.0)), sky.horizon * 2.0);
    assert_eq!(sky_radiance(sky, v(0.0, -1.0, 0.0)), sky.ground * 2.0);
    // Halfway up in sqrt(s): s = 1/4 is the midpoint of horizon and zenith.
    let d = v((1.0f64 - 0.0625).sqrt(), 0.25, 0.0);
    let mid = (sky.horizon + sky.zenith) * 0.5 * 2.0;
    assert!((sky_radiance(sky, d) - mid).length() < 1e-12);
    // One colour everywhere is a uniform sky.
    let white = Sky {
        zenith: v(1.0, 1.0, 1.0),
        horizon: v(1.0, 1.0, 1.0),
        ground: v(1.0, 1.0, 1.0),
        up: v(0.0, 0.0, 1.0),
        intensity: 1.0,
    };
    let mut rng = SplitMix(3);
    for _ in 0..100 {
        let u = rng.vec2();
        let c = 2.0 * u.x - 1.0;
        let s = (1.0 - c * c).sqrt();
        let d = v(s * (2.0 * PI * u.y).cos(), s * (2.0 * PI * u.y).sin(), c);
        assert_eq!(sky_radiance(white, d), v(1.0, 1.0, 1.0));
    }
}

#[test]
fn the_sun_is_uniform_over_its_disc_and_gives_its_irradiance() {
    let mut rng = SplitMix(5);
    for radius_deg in [0.001f64, 0.53, 5.0, 30.0] {
        let dir = v(0.3, 0.8, 0.52).normalize();
        let sun = Sun {
            direction: dir,
            one_minus_cos: sun_one_minus_cos(radius_deg),
            irradiance: v(3.0, 2.0, 1.0),
        };
        let omega = cone_solid_angle(sun.one_minus_cos);
        // The closed form of the cap's solid angle, 2 pi (1 - cos r).
        assert!((omega - 2.0 * PI * (1.0 - radius_deg.to_radians().cos())).abs() < 1e-15);
        assert!(sun.one_minus_cos > 0.0);
        // Samples: inside the disc, with the density sun_pdf gives, uniform in cos(theta).
        let bins = 10;
        let mut counts = vec![0usize; bins];
        let n = 100_000;
        for _ in 0..n {
            let s = sample_sun(sun, rng.vec2());
            let c = s.wi.dot(dir);
            assert!(1.0 - c <= sun.one_minus_cos + 1e-12, "outside the disc");
            assert!((s.wi.length() - 1.0).abs() < 1e-12);
            assert_eq!(s.pdf, sun_pdf(sun, s.wi));
            assert_eq!(s.radiance, sun_radiance(sun, s.wi));
            let k = ((1.0 - c) / sun.one_minus_cos * bins as f64) as usize;
            counts[k.min(bins - 1)] += 1;
        }
        let expected = n as f64 / bins as f64;
        let chi2: f64 = counts
            .iter()
            .map(|&o| (o as f64 - expected).powi(2) / expected)
            .sum();
        assert!(
            chi2 < 9.0 + 6.0 * 18f64.sqrt(),
            "{radius_deg}: chi-square {chi2}"
        );
        // Its radiance integrated over the disc, facing it, is its irradiance: L omega.
        let e = sun_radiance(sun, dir) * omega;
        assert!((e - sun.irradiance).length() < 1e-12);
        assert_eq!(sun_radiance(sun, -dir), v(0.0, 0.0, 0.0));
        assert_eq!(sun_pdf(sun, -dir), 0.0);
    }
}

#[test]
fn rays_meet_spheres_where_they_should() {
    let c = v(0.0, 0.0, 5.0);
    let t = intersect_sphere(v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), c, 1.0);
    assert!((t - 4.0).abs() < 1e-12);
    // From inside, the far side.
    let t = intersect_sphere(c, v(1.0, 0.0, 0.0), c, 1.0);
    assert!((t - 1.0).abs() < 1e-12);
    // Behind, and beside.
    assert_eq!(
        intersect_sphere(v(0.0, 0.0, 0.0), v(0.0, 0.0, -1.0), c, 1.0),
        -1.0
    );
    assert_eq!(
        intersect_sphere(v(2.0, 0.0, 0.0), v(0.0, 0.0, 1.0), c, 1.0),
        -1.0
    );
}

#[test]
fn the_power_heuristic_weights_sum_to_one() {
    let mut rng = SplitMix(7);
    for _ in 0..1000 {
        let (a, b) = (rng.next() * 10.0, rng.next() * 10.0);
        let s = power_heuristic(a, b) + power_heuristic(b, a);
        assert!((s - 1.0).abs() < 1e-12);
    }
    assert_eq!(power_heuristic(1.0, 0.0), 1.0);
    assert_eq!(power_heuristic(0.0, 0.0), 0.0);
}

/// One estimate of the irradiance at the origin (normal +z) from the sphere light, by `n`
/// samples of the given strategy: its mean and standard error.
fn irradiance(light: SphereLight<f64>, strategy: &str, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = SplitMix(seed);
    let p = v(0.0, 0.0, 0.0);
    let l = sphere_light_radiance(light).x;
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let mut x = 0.0;
        // Next-event estimation: a direction toward the light.
        if strategy != "bsdf" {
            let s = sample_sphere_light(light, p, rng.vec2());
            if s.pdf > 0.0 && s.wi.z > 0.0 {
                let cos = s.wi.z;
                let w = if strategy == "both" {
                    power_heuristic(s.pdf, cos / PI)
                } else {
                    1.0
                };
                x += w * s.radiance.x * cos / s.pdf;
            }
        }
        // BSDF sampling: a cosine-distributed direction, which may hit the light.
        if strategy != "light" {
            let wi = sample_cosine_hemisphere(rng.vec2());
            let pdf = wi.z / PI;
            if intersect_sphere(p, wi, light.center, light.radius) > 0.0 {
                let w = if strategy == "both" {
                    power_heuristic(pdf, sphere_light_pdf(light, p, wi))
                } else {
                    1.0
                };
                x += w * l * wi.z / pdf;
            }
        }
        sum += x;
        sum2 += x * x;
    }
    let mean = sum / n as f64;
    (
        mean,
        ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

#[test]
fn nee_bsdf_sampling_and_mis_agree_with_the_closed_form_irradiance() {
    // Lights wholly above the horizon of the point, near and far, small and large.
    for (center, radius) in [
        (v(0.0, 0.0, 3.0), 1.0),
        (v(1.0, 0.5, 2.0), 0.5),
        (v(0.0, 2.0, 2.5), 0.3),
        (v(0.0, 0.0, 1.5), 1.2),
    ] {
        let light = SphereLight {
            center,
            radius,
            intensity: v(2.0, 2.0, 2.0),
        };
        let d = center.length();
        let cos = center.z / d;
        assert!(cos > radius / d, "the light is wholly above the horizon");
        let l = sphere_light_radiance(light).x;
        let closed = PI * l * (radius / d).powi(2) * cos;
        // Intensity is the irradiance at distance 1: E = intensity cos / d^2.
        assert!((closed - 2.0 * cos / (d * d)).abs() < 1e-12);
        for (k, strategy) in ["light", "bsdf", "both"].into_iter().enumerate() {
            let (mean, se) = irradiance(light, strategy, 200_000, 11 + k as u64);
            assert!(
                (mean - closed).abs() < 3.0 * se + 1e-12,
                "{strategy}, light at {center:?} r {radius}: {mean} +- {se}, closed form {closed}"
            );
        }
    }
}

#[test]
fn a_point_light_gives_intensity_over_distance_squared() {
    let light = SphereLight {
        center: v(0.0, 0.0, 2.0),
        radius: 0.0,
        intensity: v(4.0, 4.0, 4.0),
    };
    let s = sample_sphere_light(light, v(0.0, 0.0, 0.0), Vec2::new(0.3, 0.7));
    assert!(s.delta);
    assert_eq!(s.wi, v(0.0, 0.0, 1.0));
    assert_eq!(s.radiance, v(1.0, 1.0, 1.0));
    assert_eq!(s.distance, 2.0);
    // No direction hits it, so BSDF sampling never finds it.
    assert_eq!(
        sphere_light_pdf(light, v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0)),
        0.0
    );
}

#[test]
fn the_gpu_light_agrees_with_the_cpu_twin() {
    use qjulia::gpu::bsdf_probe::{probe_bsdf, probe_inputs, probe_lights, probe_point};
    let Some(gpu) = common::gpu("the_gpu_light_agrees_with_the_cpu_twin") else {
        return;
    };
    let material = qjulia::cpu::bsdf::Material {
        albedo: Vec3::new(0.5f32, 0.5, 0.5),
        roughness: 0.5,
        metallic: 0.0,
        specular: 0.5,
        multiscatter: true,
    };
    let count = 4096;
    let results = probe_bsdf(gpu.context().clone(), material, count).unwrap();
    let (sky, sun, light) = probe_lights();
    let close = |a: f32, b: f32, tol: f32| (a - b).abs() <= tol * a.abs().max(1.0);
    let mut rim = 0;
    for (n, r) in results.iter().enumerate() {
        let (_, _, u) = probe_inputs(n as u32);
        let p = probe_point(n as u32);
        let s = sample_sun(sun, u);
        let gpu_wi = Vec3::new(r.sun[0], r.sun[1], r.sun[2]);
        assert!((s.wi - gpu_wi).length() < 1e-5, "item {n}: sun wi");
        assert!(close(s.pdf, r.sun[3], 1e-5), "item {n}: sun pdf");
        let l = sample_sphere_light(light, p, u);
        let gpu_wi = Vec3::new(r.light[0], r.light[1], r.light[2]);
        assert!((l.wi - gpu_wi).length() < 1e-4, "item {n}: light wi");
        assert!(close(l.pdf, r.light[3], 1e-4), "item {n}: light pdf");
        assert!(
            close(l.radiance.x, r.light_value[0], 1e-5),
            "item {n}: radiance"
        );
        assert!(
            close(l.distance, r.light_value[1], 1e-4),
            "item {n}: distance"
        );
        let sky_x = sky_radiance(sky, r_sun_wi(r));
        assert!(close(sky_x.x, r.light_value[2], 1e-5), "item {n}: sky");
        // Whether the sun's direction hits the sphere light may differ at its rim.
        let pdf = sphere_light_pdf(light, p, r_sun_wi(r));
        if (pdf == 0.0) != (r.light_value[3] == 0.0) {
            rim += 1;
        } else {
            assert!(
                close(pdf, r.light_value[3], 1e-4),
                "item {n}: light pdf of sun wi"
            );
        }
    }
    assert!(rim <= 2, "{rim} directions disagree on hitting the light");
}

fn r_sun_wi(r: &qjulia::gpu::bsdf_probe::ProbeResult) -> Vec3<f32> {
    Vec3::new(r.sun[0], r.sun[1], r.sun[2])
}

/// Issue 35: a sun of 0.01 or 0.001 degrees (cos rounds to 1 in f32) and a sphere light of
/// radius 1e-4 (its cone's cosine rounds to 1) keep a positive solid angle in f32, so their
/// radiance and density are finite, and a light sample's radiance / density is the irradiance
/// the closed form gives, to f32's precision.
#[test]
fn tiny_lights_stay_finite_and_right_in_f32() {
    let vf = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let mut rng = SplitMix(11);
    for radius_deg in [0.01f64, 0.001, 1e-20] {
        assert_eq!(
            (radius_deg.to_radians().cos()) as f32,
            1.0,
            "the case the issue names"
        );
        let sun = Sun {
            direction: vf(0.3, 0.8, 0.52).normalize(),
            one_minus_cos: sun_one_minus_cos(radius_deg) as f32,
            irradiance: vf(3.0, 2.0, 1.0),
        };
        assert!(sun.one_minus_cos > 0.0 && sun.one_minus_cos.is_normal());
        // Directions drawn at the disc's rim can round outside it (f32 resolves a direction
        // to about 6e-8 rad, the disc of 0.001 degrees is 1.7e-5 rad wide): a few, not many.
        let mut outside = 0;
        for _ in 0..1000 {
            let u = rng.vec2();
            let s = sample_sun(sun, Vec2::new(u.x as f32, u.y as f32));
            assert!(
                s.pdf.is_finite() && s.pdf > 0.0,
                "{radius_deg}: pdf {}",
                s.pdf
            );
            let e = s.radiance / s.pdf;
            assert!((e - sun.irradiance).length() < 1e-5, "{radius_deg}: {e:?}");
            assert!((s.wi.length() - 1.0).abs() < 1e-6);
            // Its own direction lies in the disc.
            let pdf = sun_pdf(sun, s.wi);
            assert!(pdf == s.pdf || pdf == 0.0, "{radius_deg}");
            outside += usize::from(pdf == 0.0);
        }
        assert!(
            outside <= 20,
            "{radius_deg}: {outside} of 1000 outside the disc"
        );
        assert!(sun_radiance(sun, sun.direction).x.is_finite());
        assert!(power_heuristic(sun_pdf(sun, sun.direction), 0.5) > 0.999_999);
    }
    // A sphere light of radius 1e-4 seen from 3 away: cos(theta) = 1 - 5.6e-10 rounds to 1.
    let light = SphereLight {
        center: vf(0.0, 0.0, 3.0),
        radius: 1e-4,
        intensity: vf(20.0, 20.0, 20.0),
    };
    let p = vf(0.0, 0.0, 0.0);
    let h = sphere_light_one_minus_cos(light, p);
    let want = 0.5 * (1e-4f64 / 3.0).powi(2);
    assert!(
        ((h as f64) - want).abs() < 2e-6 * want,
        "{h} against {want}"
    );
    // The closed form of the irradiance at p facing the light: pi L (r/d)^2 = intensity / d^2
    // (to first order in r/d).
    let e_want = 20.0 / 9.0;
    let mut sum = 0.0f64;
    let n = 1000;
    let mut rim = 0;
    for _ in 0..n {
        let u = rng.vec2();
        let s = sample_sphere_light(light, p, Vec2::new(u.x as f32, u.y as f32));
        assert!(s.pdf > 0.0 && s.pdf.is_finite() && s.radiance.x.is_finite());
        assert!((s.distance - 3.0).abs() < 1e-3, "{}", s.distance);
        let pdf = sphere_light_pdf(light, p, s.wi);
        assert!(pdf == s.pdf || pdf == 0.0);
        let t = intersect_sphere(p, s.wi, light.center, light.radius);
        assert!(t < 0.0 || (t - 3.0).abs() < 1e-3, "{t}");
        rim += usize::from(pdf == 0.0 || t < 0.0);
        sum += (s.radiance.x * s.wi.z / s.pdf) as f64;
    }
    assert!(rim <= 20, "{rim} of {n} at the rim");
    let e = sum / n as f64;
    assert!((e - e_want).abs() < 1e-4 * e_want, "{e} against {e_want}");
}
