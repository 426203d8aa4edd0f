//! The quadrature that makes GGX's albedo tables (src/cpu/ggx_albedo.rs and
//! shaders/ggx_albedo.wgsl): E(mu, roughness) over the visible normals, E_avg from it, and the
//! tables' WGSL text.

use super::bsdf::{ggx_alpha, sample_ggx_vndf, smith_g1, smith_g2};
use super::ggx_albedo::{ALBEDO_MU, ALBEDO_ROUGHNESS};
use crate::algebra::{Vec2, Vec3};

/// E(mu, roughness) by quadrature: the mean of G2 / G1 over the visible
/// normals ([`sample_ggx_vndf`]'s square), each counted where it reflects above the horizon,
/// by the midpoint rule over `4 n` x `n` points of (s, v) with u = (1 - s^2, v) (weight 2 s):
/// the disc's rim, u.x near 1, where a head-on lobe's few normals below the horizon lie, is
/// then sampled finely. The cosine mu is held at 1e-4 at least (the grazing limit).
pub fn directional_albedo_integral(mu: f64, roughness: f64, n: usize) -> f64 {
    let mu = mu.clamp(1e-4, 1.0);
    let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let alpha = ggx_alpha(roughness);
    let g1 = smith_g1(wo, alpha);
    let ns = 4 * n;
    let mut sum = 0.0;
    for a in 0..ns {
        let s = (a as f64 + 0.5) / ns as f64;
        for b in 0..n {
            let u = Vec2::new(1.0 - s * s, (b as f64 + 0.5) / n as f64);
            let h = sample_ggx_vndf(wo, alpha, u);
            let wi = h * (2.0 * wo.dot(h)) - wo;
            if wi.z > 0.0 {
                sum += 2.0 * s * smith_g2(wo, wi, alpha) / g1;
            }
        }
    }
    sum / (ns * n) as f64
}

/// E_avg(roughness) by quadrature: 2 int_0^1 E(mu) mu dmu by the
/// midpoint rule over `m` cosines, each E by [`directional_albedo_integral`] at `n`.
pub fn average_albedo_integral(roughness: f64, m: usize, n: usize) -> f64 {
    let sum: f64 = (0..m)
        .map(|k| {
            let mu = (k as f64 + 0.5) / m as f64;
            directional_albedo_integral(mu, roughness, n) * mu
        })
        .sum();
    2.0 * sum / m as f64
}

/// The tables by quadrature, as f32: E at each (mu_i, r_j), row by row
/// ([`ALBEDO_MU`], [`ALBEDO_ROUGHNESS`]), then E_avg at each r_j.
pub fn make_tables() -> (Vec<f32>, Vec<f32>) {
    use rayon::prelude::*;
    let at = |k: usize, n: usize| k as f64 / (n - 1) as f64;
    let e = (0..ALBEDO_MU * ALBEDO_ROUGHNESS)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % ALBEDO_MU, k / ALBEDO_MU);
            let mu = at(i, ALBEDO_MU).powi(2);
            directional_albedo_integral(mu, at(j, ALBEDO_ROUGHNESS), 128) as f32
        })
        .collect();
    let avg = (0..ALBEDO_ROUGHNESS)
        .into_par_iter()
        .map(|j| average_albedo_integral(at(j, ALBEDO_ROUGHNESS), 128, 64) as f32)
        .collect();
    (e, avg)
}

/// The 16-bit unorm nearest x in [0, 1] (clamped): what the file holds of an entry of E
/// (`ggx_albedo::unorm16` decodes it).
pub fn to_unorm16(x: f32) -> u32 {
    (x.clamp(0.0, 1.0) * 65535.0).round() as u32
}

/// The tables' part of shaders/ggx_albedo.wgsl: two private arrays, E's entries as 16-bit
/// unorms two a word in hex (entry 2i in the low half of word i: [`to_unorm16`]), and E_avg
/// as f32 literals, each written so that it reads back to the same bits.
pub fn wgsl_tables(e: &[f32], avg: &[f32]) -> String {
    let rows = |v: &[String], per_row: usize| {
        v.chunks(per_row)
            .map(|row| format!("    {},\n", row.join(", ")))
            .collect::<String>()
    };
    let words: Vec<String> = e
        .chunks(2)
        .map(|pair| format!("{:#010x}u", to_unorm16(pair[0]) | to_unorm16(pair[1]) << 16))
        .collect();
    let floats: Vec<String> = avg.iter().map(|x| format!("{x:?}")).collect();
    format!(
        "var<private> GGX_ALBEDO: array<u32, {}> = array<u32, {}>(\n{});\n\n\
         var<private> GGX_AVERAGE_ALBEDO: array<f32, {}> = array<f32, {}>(\n{});\n",
        words.len(),
        words.len(),
        rows(&words, 8),
        floats.len(),
        floats.len(),
        rows(&floats, 8),
    )
}
