//! GGX's multiple scattering (`material.multiscatter`, issue 35, item 7) on the CPU twin: the
//! albedo tables are the quadrature's and interpolate it, and a white metal with the
//! multiple-scattering lobe reflects all it receives at every roughness. (The material's other
//! tests: tests/render/bsdf.rs; the furnace through the path tracer: tests/render/path.rs.)

use qjulia::algebra::Vec3;
use qjulia::cpu::bsdf::{Material, bsdf_eval};

use crate::common::{SplitMix, dir, integrate, sampled_albedo};

/// Issue 35, item 7: with Kulla and Conty's lobe (`multiscatter`, the default) a white metal
/// reflects all it receives, at every roughness and from every direction: its directional
/// albedo, sampled, is 1 within the table's error (3e-3) and 3 standard errors from cos 0.1
/// on; so is the quadrature's, where it resolves the lobe (roughness 0.3 on), and there a
/// coloured metal's (F0 = 0.9, 0.6, 0.3) lies between its single-scattering albedo and 1.
#[test]
fn a_rough_white_metal_with_multiple_scattering_reflects_everything() {
    let metal = |roughness, f0: f64, multiscatter| Material {
        albedo: Vec3::new(1.0, 1.0, 1.0) * f0,
        roughness,
        metallic: 1.0,
        specular: 0.5,
        multiscatter,
    };
    let mut rng = SplitMix(41);
    for roughness in [0.05, 0.3, 0.6, 1.0] {
        for cos_o in [1.0, 0.7, 0.4, 0.1] {
            let wo = dir(cos_o, 0.3);
            let white = metal(roughness, 1.0, true);
            let q = integrate(800, true, |wi| bsdf_eval(white, wo, wi).x * wi.z);
            let (mean, se) = sampled_albedo(white, wo, 200_000, &mut rng);
            eprintln!(
                "white metal with multiple scattering, roughness {roughness}, cos {cos_o}: \
                 quadrature {q:.4}, sampled {mean:.4} +- {se:.4}"
            );
            assert!(
                (mean - 1.0).abs() <= 3e-3 + 3.0 * se,
                "roughness {roughness} cos {cos_o}: sampled {mean} +- {se}"
            );
            // The quadrature resolves the rough lobes only (as tests/render/bsdf.rs's
            // the_directional_albedo_is_at_most_one).
            if roughness < 0.3 {
                continue;
            }
            assert!(
                (q - 1.0).abs() <= 3e-3,
                "roughness {roughness} cos {cos_o}: {q}"
            );
            for f0 in [0.9, 0.6, 0.3] {
                let albedo = |m| integrate(400, true, |wi| bsdf_eval(m, wo, wi).x * wi.z);
                let (single, multiple) = (
                    albedo(metal(roughness, f0, false)),
                    albedo(metal(roughness, f0, true)),
                );
                assert!(
                    single <= multiple + 1e-9 && multiple <= 1.0 + 3e-3,
                    "F0 {f0}, roughness {roughness}, cos {cos_o}: single {single}, \
                     multiple {multiple}"
                );
            }
        }
    }
}

/// Issue 35, item 7: shaders/ggx_albedo.wgsl's tables are what src/cpu/ggx_albedo.rs's
/// quadrature gives: E within half a 16-bit step (7.6e-6, the file holds it as 16-bit unorms)
/// and E_avg within 1e-6 (the file's numbers are the integrals' f32s; a libm's last bit may
/// differ). `QJULIA_BLESS=1` writes them again.
#[test]
fn the_albedo_tables_are_the_integrals() {
    use qjulia::cpu::ggx_albedo::parse_tables;
    use qjulia::cpu::ggx_quadrature::{make_tables, wgsl_tables};
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/ggx_albedo.wgsl");
    let file = std::fs::read_to_string(path).expect("shaders/ggx_albedo.wgsl");
    let (e, avg) = make_tables();
    if std::env::var_os("QJULIA_BLESS").is_some() {
        let head = &file[..file.find("var<private> GGX_ALBEDO:").expect("the tables")];
        std::fs::write(path, format!("{head}{}", wgsl_tables(&e, &avg))).expect("written");
        return;
    }
    let (file_e, file_avg) = parse_tables(&file);
    assert_eq!((file_e.len(), file_avg.len()), (e.len(), avg.len()));
    let half_step = 0.5 / 65535.0 + 1e-6;
    for (name, made, held, within) in [
        ("E", &e, &file_e, half_step),
        ("E_avg", &avg, &file_avg, 1e-6),
    ] {
        for (k, (a, b)) in made.iter().zip(held.iter()).enumerate() {
            assert!(
                (a - b).abs() <= within,
                "{name}[{k}]: the quadrature gives {a}, shaders/ggx_albedo.wgsl holds {b} \
                 (QJULIA_BLESS=1 cargo test --test render multiscatter:: writes it again)"
            );
        }
    }
}

/// Between its entries the table is within 3e-3 of the quadrature from mu = 0.05 on (at the
/// midpoints of a 64 x 64 grid over (sqrt(mu), roughness); 2.7e-3 measured), and within 5e-2
/// nearer grazing, where a smooth lobe's albedo turns on mu / alpha (3.9e-2 at mu 5e-4); E_avg
/// is the mean the table's E gives, within 1e-3.
#[test]
fn the_albedo_table_interpolates_the_integral() {
    use qjulia::cpu::ggx_albedo::{ALBEDO_MU, ALBEDO_ROUGHNESS, ggx_albedo, ggx_average_albedo};
    use qjulia::cpu::ggx_quadrature::directional_albedo_integral;
    // The worst error (error, mu, roughness) from mu = 0.05 on, and below it.
    let (mut worst, mut grazing) = ((0.0f64, 0.0, 0.0), (0.0f64, 0.0, 0.0));
    for a in 0..64 {
        for b in 0..64 {
            let x = (a as f64 + 0.5) / 64.0;
            let (mu, r) = (x * x, (b as f64 + 0.5) / 64.0);
            let exact = directional_albedo_integral(mu, r, 128);
            let error = (ggx_albedo(mu, r) - exact).abs();
            let kept = if mu >= 0.05 { &mut worst } else { &mut grazing };
            if error > kept.0 {
                *kept = (error, mu, r);
            }
        }
    }
    eprintln!(
        "E table {ALBEDO_MU} x {ALBEDO_ROUGHNESS}: worst error {:.2e} at mu {:.3}, roughness \
         {:.3}; below mu 0.05, {:.2e} at mu {:.4}, roughness {:.3}",
        worst.0, worst.1, worst.2, grazing.0, grazing.1, grazing.2
    );
    assert!(worst.0 <= 3e-3, "{worst:?}");
    assert!(grazing.0 <= 5e-2, "{grazing:?}");
    for b in 0..16 {
        let r = b as f64 / 15.0;
        let n = 2000;
        let mean: f64 = (0..n)
            .map(|k| {
                let mu = (k as f64 + 0.5) / n as f64;
                2.0 * ggx_albedo(mu, r) * mu
            })
            .sum::<f64>()
            / n as f64;
        let avg: f64 = ggx_average_albedo(r);
        assert!(
            (mean - avg).abs() <= 1e-3,
            "roughness {r}: E_avg {avg}, the table's mean {mean}"
        );
    }
}
