//! The path tracer's BSDF on the CPU twin (src/cpu/bsdf.rs): densities that integrate to 1,
//! samples distributed as their density says (chi-square), reciprocity, energy, and the
//! special cases the book states (pure Lambert, the roughness floor, the mirror).

use qjulia::algebra::{Vec2, Vec3};
use qjulia::cpu::bsdf::{
    Material, ROUGHNESS_MIN, bsdf_eval, bsdf_pdf, bsdf_sample, ggx_alpha, ggx_reflection_pdf,
    sample_cosine_hemisphere, smith_g1, smith_g2, specular_probability,
};

use std::f64::consts::PI;

use crate::common;
use crate::common::{SplitMix, dir, integrate, sampled_albedo};

fn material(albedo: f64, roughness: f64, metallic: f64, specular: f64) -> Material<f64> {
    Material {
        albedo: Vec3::new(albedo, albedo * 0.8, albedo * 0.6),
        roughness,
        metallic,
        specular,
        multiscatter: true,
    }
}

/// The materials the tests run on: rough and smooth, dielectric, metal and between.
fn materials() -> Vec<(&'static str, Material<f64>)> {
    vec![
        ("lambert", material(0.8, 0.5, 0.0, 0.0)),
        ("rough plastic", material(0.8, 0.7, 0.0, 0.5)),
        ("glossy plastic", material(0.5, 0.3, 0.0, 1.0)),
        ("rough metal", material(0.9, 0.6, 1.0, 0.5)),
        ("half metal", material(0.7, 0.4, 0.5, 0.5)),
        ("black dielectric", material(0.0, 0.5, 0.0, 0.5)),
    ]
}

/// The outgoing directions the tests run on: near the normal to near grazing.
fn outgoing() -> Vec<Vec3<f64>> {
    [0.95, 0.7, 0.4, 0.15]
        .iter()
        .enumerate()
        .map(|(k, &c)| dir(c, 0.3 + k as f64))
        .collect()
}

#[test]
fn each_lobe_density_integrates_to_one_over_the_sphere() {
    // The cosine lobe over the hemisphere.
    let cosine = integrate(1000, true, |wi| wi.z / PI);
    assert!((cosine - 1.0).abs() < 1e-5, "cosine lobe: {cosine}");
    // The visible-normal GGX lobe: wi = reflect(-wo, h) maps the normals wo sees one to one
    // onto the sphere (directions below the horizon included: the sampler rejects those), so
    // its density integrates to 1 over the whole sphere.
    for roughness in [0.35, 0.5, 0.8, 1.0] {
        let alpha = ggx_alpha(roughness);
        for wo in outgoing() {
            let total = integrate(1500, false, |wi| {
                let h = (wo + wi).normalize();
                ggx_reflection_pdf(wo, h, alpha)
            });
            assert!(
                (total - 1.0).abs() < 2e-3,
                "GGX lobe, roughness {roughness}, wo.z {}: {total}",
                wo.z
            );
        }
    }
}

#[test]
fn sampled_directions_follow_the_density_chi_square() {
    const N: usize = 400_000;
    const THETA: usize = 12;
    const PHI: usize = 24;
    let mut rng = SplitMix(7);
    for (name, m) in materials() {
        for wo in outgoing() {
            // Counts per (cos theta, phi) cell of the upper hemisphere, and the failures.
            let mut counts = vec![0usize; THETA * PHI];
            let mut none = 0usize;
            for _ in 0..N {
                let s = bsdf_sample(m, wo, rng.next(), rng.vec2());
                if s.pdf == 0.0 {
                    none += 1;
                    continue;
                }
                let a = ((s.wi.z * THETA as f64) as usize).min(THETA - 1);
                let phi = s.wi.y.atan2(s.wi.x).rem_euclid(2.0 * PI);
                let b = ((phi / (2.0 * PI) * PHI as f64) as usize).min(PHI - 1);
                counts[a * PHI + b] += 1;
            }
            // Expected counts: the density integrated over each cell (16 x 16 midpoints).
            let mut expected = vec![0.0; THETA * PHI];
            let sub = 16;
            for (k, e) in expected.iter_mut().enumerate() {
                let (a, b) = (k / PHI, k % PHI);
                let dc = 1.0 / (THETA * sub) as f64;
                let dphi = 2.0 * PI / (PHI * sub) as f64;
                let mut p = 0.0;
                for sa in 0..sub {
                    let c = (a * sub + sa) as f64 * dc + 0.5 * dc;
                    for sb in 0..sub {
                        let phi = (b * sub + sb) as f64 * dphi + 0.5 * dphi;
                        p += bsdf_pdf(m, wo, dir(c, phi));
                    }
                }
                *e = p * dc * dphi * N as f64;
            }
            let expected_none = N as f64 - expected.iter().sum::<f64>();
            // Pearson's statistic over the cells expecting 5 or more (the rest pooled).
            let (mut chi2, mut cells) = (0.0, 0usize);
            let (mut pool_o, mut pool_e) = (none as f64, expected_none.max(0.0));
            for (o, e) in counts.iter().zip(&expected) {
                if *e >= 5.0 {
                    chi2 += (*o as f64 - e).powi(2) / e;
                    cells += 1;
                } else {
                    pool_o += *o as f64;
                    pool_e += e;
                }
            }
            if pool_e >= 5.0 {
                chi2 += (pool_o - pool_e).powi(2) / pool_e;
                cells += 1;
            } else {
                assert!(
                    pool_o < 20.0,
                    "{name}: {pool_o} samples where {pool_e} expected"
                );
            }
            // Degrees of freedom cells - 1; the bound is the mean plus 6 standard deviations
            // (a false alarm about once in 1e8 per case).
            let df = (cells - 1) as f64;
            let bound = df + 6.0 * (2.0 * df).sqrt();
            assert!(
                chi2 < bound,
                "{name}, wo.z {:.2}: chi-square {chi2:.1} over {cells} cells (bound {bound:.1})",
                wo.z
            );
        }
    }
}

#[test]
fn the_bsdf_is_reciprocal() {
    let mut rng = SplitMix(11);
    for (name, m) in materials() {
        for _ in 0..2000 {
            let wo = sample_cosine_hemisphere(rng.vec2());
            let wi = sample_cosine_hemisphere(rng.vec2());
            let a = bsdf_eval(m, wo, wi);
            let b = bsdf_eval(m, wi, wo);
            for (x, y) in [(a.x, b.x), (a.y, b.y), (a.z, b.z)] {
                assert!(
                    (x - y).abs() <= 1e-12 * x.abs().max(1.0),
                    "{name}: f(wo, wi) {x} != f(wi, wo) {y}"
                );
            }
        }
    }
}

#[test]
fn the_directional_albedo_is_at_most_one() {
    // Albedo 1 (the worst case), each outgoing direction: the integral of f cos over the
    // hemisphere by quadrature (rough lobes) and by importance sampling (every lobe).
    let mut rng = SplitMix(13);
    for roughness in [ROUGHNESS_MIN, 0.1, 0.3, 0.6, 1.0] {
        for metallic in [0.0, 0.5, 1.0] {
            for specular in [0.0, 0.5, 1.0] {
                let m = Material {
                    albedo: Vec3::splat(1.0),
                    roughness,
                    metallic,
                    specular,
                    multiscatter: true,
                };
                for cos_o in [1.0, 0.8, 0.5, 0.2, 0.05] {
                    let wo = dir(cos_o, 0.0);
                    let (mean, se) = sampled_albedo(m, wo, 100_000, &mut rng);
                    // The multiple-scattering lobe gives back 1 - E from the table: it
                    // reflects 1 + (E - E_table) of a white metal's light, within the table's
                    // error (the_albedo_table_interpolates_the_integral) of 1.
                    assert!(
                        mean <= 1.0 + 3.0 * se + 3e-3,
                        "roughness {roughness} metallic {metallic} specular {specular} \
                         cos {cos_o}: albedo {mean} +- {se}"
                    );
                    if roughness >= 0.3 {
                        let q = integrate(600, true, |wi| bsdf_eval(m, wo, wi).x * wi.z);
                        assert!(q <= 1.0 + 3e-3, "quadrature albedo {q}");
                        assert!(
                            (q - mean).abs() < 4.0 * se + 3e-3,
                            "sampled albedo {mean} +- {se} against quadrature {q}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn no_metal_and_no_specular_is_pure_lambert() {
    let m = material(0.6, 0.3, 0.0, 0.0);
    let mut rng = SplitMix(17);
    for _ in 0..1000 {
        let wo = sample_cosine_hemisphere(rng.vec2());
        let wi = sample_cosine_hemisphere(rng.vec2());
        assert_eq!(bsdf_eval(m, wo, wi), m.albedo / PI);
        assert_eq!(specular_probability(m, wo), 0.0);
        assert_eq!(bsdf_pdf(m, wo, wi), wi.z / PI);
        // Even at grazing, where Schlick's term at F0 = 0 would reflect, nothing is specular.
        let grazing = dir(1e-3, 0.0);
        assert_eq!(specular_probability(m, grazing), 0.0);
    }
}

#[test]
fn a_sample_carries_the_bsdf_and_the_density_of_its_direction() {
    let mut rng = SplitMix(19);
    for (name, m) in materials() {
        for wo in outgoing() {
            for _ in 0..500 {
                let s = bsdf_sample(m, wo, rng.next(), rng.vec2());
                if s.pdf == 0.0 {
                    continue;
                }
                assert!(s.wi.z > 0.0, "{name}: below the surface");
                assert!((s.wi.length() - 1.0).abs() < 1e-12, "{name}: not unit");
                assert_eq!(s.f, bsdf_eval(m, wo, s.wi), "{name}");
                assert_eq!(s.pdf, bsdf_pdf(m, wo, s.wi), "{name}");
            }
        }
    }
}

#[test]
fn the_roughness_floor_keeps_sampling_finite_and_a_mirror_reflects_everything() {
    assert_eq!(ggx_alpha(0.0), ROUGHNESS_MIN * ROUGHNESS_MIN);
    assert_eq!(ggx_alpha(0.5), 0.25);
    // The mirror of the white furnace: metallic 1, albedo 1 (F0 = 1), roughness 0 (held at the
    // floor). Its weight f cos / pdf is G2 / G1(wo), which is 1 but for the shadowing of
    // grazing directions at alpha = 4e-4.
    let mirror = Material {
        albedo: Vec3::splat(1.0),
        roughness: 0.0,
        metallic: 1.0,
        specular: 0.5,
        // The single-scattering lobe's weight; the multiple-scattering lobe adds under 1e-7
        // here (E_avg = 1 - 1e-6 at the floor).
        multiscatter: false,
    };
    let mut rng = SplitMix(23);
    for cos_o in [1.0, 0.9, 0.5, 0.2, 0.1] {
        let wo = dir(cos_o, 0.7);
        for _ in 0..200 {
            let s = bsdf_sample(mirror, wo, rng.next(), rng.vec2());
            assert!(s.pdf > 0.0 && s.pdf.is_finite());
            let w = s.f * (s.wi.z / s.pdf);
            let expected = smith_g2(wo, s.wi, ggx_alpha(0.0)) / smith_g1(wo, ggx_alpha(0.0));
            assert!(
                (w.x - expected).abs() < 1e-9,
                "weight {} != {expected}",
                w.x
            );
            assert!(w.x > 1.0 - 1e-5, "a mirror at cos {cos_o} keeps {}", w.x);
            // Very near the mirror direction.
            let mirrored = Vec3::new(-wo.x, -wo.y, wo.z);
            assert!(s.wi.dot(mirrored) > 0.999, "cos {cos_o}: {:?}", s.wi);
        }
    }
}

#[test]
fn the_f32_twin_agrees_with_the_f64_one() {
    let mut rng = SplitMix(29);
    for (name, m) in materials() {
        let m32 = Material {
            albedo: Vec3::new(m.albedo.x as f32, m.albedo.y as f32, m.albedo.z as f32),
            roughness: m.roughness as f32,
            metallic: m.metallic as f32,
            specular: m.specular as f32,
            multiscatter: true,
        };
        for wo in outgoing() {
            let wo32 = Vec3::new(wo.x as f32, wo.y as f32, wo.z as f32);
            for _ in 0..200 {
                let (ul, u) = (rng.next(), rng.vec2());
                let a = bsdf_sample(m, wo, ul, u);
                let b = bsdf_sample(m32, wo32, ul as f32, Vec2::new(u.x as f32, u.y as f32));
                if a.pdf == 0.0 || b.pdf == 0.0 {
                    continue;
                }
                let rel = |x: f64, y: f32| (x - y as f64).abs() / x.abs().max(1e-3);
                assert!(rel(a.pdf, b.pdf) < 1e-3, "{name}: pdf {} {}", a.pdf, b.pdf);
                assert!(rel(a.f.x, b.f.x) < 1e-3, "{name}: f {} {}", a.f.x, b.f.x);
                assert!((a.wi.z - b.wi.z as f64).abs() < 1e-4, "{name}: wi");
            }
        }
    }
}

#[test]
fn the_gpu_bsdf_agrees_with_the_cpu_twin() {
    use qjulia::cpu::bsdf::specular_probability as p_spec;
    use qjulia::gpu::bsdf_probe::{probe_bsdf, probe_inputs};
    let Some(gpu) = common::gpu("the_gpu_bsdf_agrees_with_the_cpu_twin") else {
        return;
    };
    let count = 4096;
    let (mut compared, mut lobe_flips) = (0, 0);
    for (name, m) in materials() {
        let m = Material {
            albedo: Vec3::new(m.albedo.x as f32, m.albedo.y as f32, m.albedo.z as f32),
            roughness: m.roughness as f32,
            metallic: m.metallic as f32,
            specular: m.specular as f32,
            multiscatter: true,
        };
        let results = probe_bsdf(gpu.context().clone(), m, count).unwrap();
        assert_eq!(results.len(), count as usize);
        for (n, r) in results.iter().enumerate() {
            let (uo, lobe, u) = probe_inputs(n as u32);
            let wo = sample_cosine_hemisphere(uo);
            let cpu = bsdf_sample(m, wo, lobe, u);
            let p = p_spec(m, wo);
            assert!(
                (p - r.specular_probability).abs() < 1e-5,
                "{name} item {n}: specular probability {p} (CPU) {} (GPU)",
                r.specular_probability
            );
            // A lobe choice within rounding of the threshold may go either way.
            if (lobe - p).abs() < 1e-5 {
                lobe_flips += 1;
                continue;
            }
            assert_eq!(cpu.pdf == 0.0, r.sample.pdf == 0.0, "{name} item {n}");
            if cpu.pdf == 0.0 {
                continue;
            }
            let close = |a: f32, b: f32, tol: f32| (a - b).abs() <= tol * a.abs().max(1.0);
            let dw = (cpu.wi - r.sample.wi).length();
            assert!(
                dw < 1e-4,
                "{name} item {n}: wi {:?} {:?}",
                cpu.wi,
                r.sample.wi
            );
            // The density of a sharp lobe moves fast with the direction: compare it at the
            // GPU's own direction too.
            let pdf_there = bsdf_pdf(m, wo, r.sample.wi);
            assert!(
                close(cpu.pdf, r.sample.pdf, 1e-3) || close(pdf_there, r.sample.pdf, 1e-3),
                "{name} item {n}: pdf {} (CPU) {} (GPU)",
                cpu.pdf,
                r.sample.pdf
            );
            let f_there = bsdf_eval(m, wo, r.sample.wi);
            for (c, g, t) in [
                (cpu.f.x, r.sample.f.x, f_there.x),
                (cpu.f.y, r.sample.f.y, f_there.y),
                (cpu.f.z, r.sample.f.z, f_there.z),
            ] {
                assert!(
                    close(c, g, 1e-3) || close(t, g, 1e-3),
                    "{name} item {n}: f {c} (CPU) {g} (GPU)"
                );
            }
            compared += 1;
        }
    }
    eprintln!("compared {compared} samples; {lobe_flips} lobe choices at the threshold skipped");
    assert!(compared > 20_000);
}

#[test]
fn the_shading_frame_is_orthonormal_with_the_normal_as_z() {
    use qjulia::cpu::bsdf::{basis_from_normal, to_local, to_world};
    let mut rng = SplitMix(31);
    let mut normals: Vec<Vec3<f64>> = (0..2000)
        .map(|_| {
            let u = rng.vec2();
            dir(2.0 * u.x - 1.0, 2.0 * PI * u.y)
        })
        .collect();
    normals.extend([
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
    ]);
    for n in normals {
        let f = basis_from_normal(n);
        for (a, b, want) in [
            (f.t, f.t, 1.0),
            (f.b, f.b, 1.0),
            (f.t, f.b, 0.0),
            (f.t, f.n, 0.0),
            (f.b, f.n, 0.0),
        ] {
            assert!((a.dot(b) - want).abs() < 1e-12, "{n:?}");
        }
        let v = Vec3::new(0.3, -0.5, 0.8);
        assert!((to_world(f, to_local(f, v)) - v).length() < 1e-12);
        assert!((to_local(f, n) - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-12);
    }
}

/// What single scattering loses: a white metal (F0 = 1) reflects `G2 / G1` of the light, so a
/// rough one is darker than a real one, whose light bounces between microfacets until it
/// leaves. The loss, measured by quadrature, is bounded here and stated in the book.
#[test]
fn a_rough_white_metal_loses_only_what_single_scattering_loses() {
    let metal = |roughness| Material {
        albedo: Vec3::splat(1.0),
        roughness,
        metallic: 1.0,
        specular: 0.5,
        multiscatter: false,
    };
    let albedo = |roughness, cos_o: f64| {
        let wo = dir(cos_o, 0.0);
        integrate(800, true, |wi| bsdf_eval(metal(roughness), wo, wi).x * wi.z)
    };
    for (roughness, cos_o, low, high) in [
        (0.3, 1.0, 0.98, 1.0),
        (0.6, 1.0, 0.80, 0.85),
        (0.6, 0.5, 0.76, 0.80),
        (1.0, 1.0, 0.29, 0.33),
        (1.0, 0.5, 0.43, 0.47),
        (1.0, 0.2, 0.62, 0.66),
    ] {
        let a = albedo(roughness, cos_o);
        eprintln!("white metal, roughness {roughness}, cos {cos_o}: albedo {a:.4}");
        assert!(
            (low..=high).contains(&a),
            "roughness {roughness} cos {cos_o}: albedo {a} outside [{low}, {high}]"
        );
    }
    // Why roughness 1 loses so much at normal incidence, in closed form: alpha = 1 makes D
    // uniform (1 / pi), so the normals seen from wo = n are cosine distributed and wi makes
    // twice their angle with n; the half with theta_h > 45 degrees reflects below the horizon
    // (P(theta_h > 45) = cos^2 45 = 1/2), and what is left is shadowed by G2 / G1 < 1.
    let mut rng = SplitMix(37);
    let n = 200_000;
    let below = (0..n)
        .filter(|_| bsdf_sample(metal(1.0), dir(1.0, 0.0), 0.0, rng.vec2()).pdf == 0.0)
        .count() as f64
        / n as f64;
    assert!((below - 0.5).abs() < 0.005, "below the horizon: {below}");
    assert!(albedo(1.0, 1.0) < 0.5);
}
