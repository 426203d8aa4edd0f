//! GGX's directional and average albedo, the tables of multiple-scattering compensation (Kulla
//! and Conty 2017): the twin of shaders/ggx_albedo.wgsl (same names, same order;
//! tests/architecture/twins.rs), whose numbers it reads. src/cpu/ggx_quadrature.rs makes them.
//!
//! E(mu, roughness) is the light a white (F = 1) single-scattering GGX lobe reflects from the
//! direction of cosine mu, over the hemisphere; E_avg(roughness) = 2 int_0^1 E(mu) mu dmu. The
//! WGSL file holds them tabulated (`ALBEDO_MU` x `ALBEDO_ROUGHNESS`, and `ALBEDO_ROUGHNESS`),
//! as `ggx_quadrature::wgsl_tables` writes them; `QJULIA_BLESS=1 cargo test --test
//! multiscatter` writes the file again, and the test fails where the file is not what the
//! integrals give.

use std::sync::LazyLock;

use crate::algebra::Real;

/// The table's cosines: mu_i = (i / (ALBEDO_MU - 1))^2, i = 0..ALBEDO_MU, closer together
/// toward grazing, where a smooth lobe's albedo falls steeply.
pub const ALBEDO_MU: usize = 32;
/// The table's roughnesses: r_j = j / (ALBEDO_ROUGHNESS - 1), j = 0..ALBEDO_ROUGHNESS (the
/// lobe's, `bsdf::ggx_alpha`: held at the roughness floor).
pub const ALBEDO_ROUGHNESS: usize = 32;

/// The tables, read once from shaders/ggx_albedo.wgsl: E row by row (a row a roughness), then
/// E_avg.
static TABLES: LazyLock<(Vec<f32>, Vec<f32>)> =
    LazyLock::new(|| parse_tables(include_str!("../../shaders/ggx_albedo.wgsl")));

/// The value at `x` in [0, 1] of `n` samples at i / (n - 1) (`at(i)`), linearly between them:
/// its cell and the weight of the cell's upper end.
fn table_cell<F: Real>(x: F, n: usize) -> (usize, F) {
    let s = x.max(F::zero()).min(F::one()) * F::lit((n - 1) as f64);
    let i = (s.floor().to_f64() as usize).min(n - 2);
    (i, s - F::lit(i as f64))
}

/// Entry `k` of the E table (row by row, a row a roughness): the file holds two entries a
/// word, each a 16-bit unorm ([`unorm16`]), which the tables hold decoded.
pub fn albedo_entry(k: usize) -> f32 {
    TABLES.0[k]
}

/// The directional albedo E(mu, roughness) of a white single-scattering GGX lobe: the table,
/// bilinearly between its entries ([`albedo_entry`]) in sqrt(mu) and roughness (both clamped
/// to [0, 1]).
pub fn ggx_albedo<F: Real>(mu: F, roughness: F) -> F {
    let (i, a) = table_cell(mu.max(F::zero()).sqrt(), ALBEDO_MU);
    let (j, b) = table_cell(roughness, ALBEDO_ROUGHNESS);
    let at = |i: usize, j: usize| F::lit(albedo_entry(j * ALBEDO_MU + i) as f64);
    let low = at(i, j) + (at(i + 1, j) - at(i, j)) * a;
    let high = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * a;
    low + (high - low) * b
}

/// The average albedo E_avg(roughness) = 2 int_0^1 E(mu) mu dmu: the table, linearly between
/// its entries.
pub fn ggx_average_albedo<F: Real>(roughness: F) -> F {
    let e = &TABLES.1;
    let (j, b) = table_cell(roughness, ALBEDO_ROUGHNESS);
    let (low, high) = (F::lit(e[j] as f64), F::lit(e[j + 1] as f64));
    low + (high - low) * b
}

/// WGSL's `unpack2x16unorm` of one half: v / 65535.
pub fn unorm16(v: u32) -> f32 {
    (v & 0xffff) as f32 / 65535.0
}

/// The numbers of the two arrays `ggx_quadrature::wgsl_tables` writes, from a WGSL file that
/// holds them: E's entries decoded from its words ([`unorm16`], entry 2i in the low half of
/// word i), and E_avg.
pub fn parse_tables(wgsl: &str) -> (Vec<f32>, Vec<f32>) {
    let array = |name: &str| -> Vec<&str> {
        let start = wgsl
            .find(&format!("var<private> {name}:"))
            .unwrap_or_else(|| panic!("shaders/ggx_albedo.wgsl has no {name}"));
        let body = &wgsl[start..];
        let open = body.find(">(").expect("an array's values") + 2;
        let close = body[open..].find(')').expect("the array's end") + open;
        body[open..close]
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect()
    };
    let e: Vec<f32> = array("GGX_ALBEDO")
        .into_iter()
        .map(|w| {
            let hex = w.strip_prefix("0x").and_then(|w| w.strip_suffix('u'));
            u32::from_str_radix(hex.expect("a hex u32 literal"), 16).expect("a word")
        })
        .flat_map(|w| [unorm16(w), unorm16(w >> 16)])
        .collect();
    let avg: Vec<f32> = array("GGX_AVERAGE_ALBEDO")
        .into_iter()
        .map(|s| s.parse().expect("an f32 literal"))
        .collect();
    assert_eq!(e.len(), ALBEDO_MU * ALBEDO_ROUGHNESS);
    assert_eq!(avg.len(), ALBEDO_ROUGHNESS);
    (e, avg)
}
