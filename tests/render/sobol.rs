//! The path tracer's sampler (src/cpu/sobol.rs and its twin shaders/sobol.wgsl): the
//! unscrambled Sobol' points against published values, the (0, 2)-net property of the first two
//! dimensions scrambled and not, the uniformity of the scrambled points, and the GPU drawing the
//! CPU's bits for both samplers.

use crate::common;

use qjulia::cpu::sobol::{
    SAMPLER_RANDOM, SAMPLER_SOBOL, SOBOL_DIMS, SOBOL_DIRECTIONS, random_sample, sample_bits, sobol,
    sobol_sample, to_unit,
};

/// The first 8 points of the unscrambled 2D Sobol' sequence as SciPy's tests publish them
/// (scipy/scipy, scipy/stats/tests/test_qmc.py, `TestSobol.unscramble_nd`, from
/// `qmc.Sobol(2, scramble=False)`). SciPy draws the points in Gray-code order (Antonov and
/// Saleev): its point n is the natural-order point n ^ (n >> 1).
const SCIPY_UNSCRAMBLED_2D: [[f64; 2]; 8] = [
    [0.0, 0.0],
    [0.5, 0.5],
    [0.75, 0.25],
    [0.25, 0.75],
    [0.375, 0.375],
    [0.875, 0.875],
    [0.625, 0.125],
    [0.125, 0.625],
];

/// Joe and Kuo's direction numbers (new-joe-kuo-6.21201, https://web.maths.unsw.edu.au/~fkuo/
/// sobol/): for their dimensions 2 to 4, the degree s of the primitive polynomial, its inner
/// coefficients a, and the initial numbers m_1..m_s.
const JOE_KUO: [(u32, u32, &[u32]); 3] = [(1, 0, &[1]), (2, 1, &[1, 3]), (3, 1, &[1, 3, 1])];

/// Point n of the unscrambled sequence, by the textbook definition: for each set bit k of n,
/// XOR in v_k = m_k / 2^k, where m_k = m_{k-s} * 2^s ^ m_{k-s} ^ sum a_j 2^j m_{k-j}
/// (Bratley and Fox), as an exact fraction (the m_k as integers with the point's denominator).
fn textbook_sobol(n: u32, (s, a, m0): (u32, u32, &[u32]), bits: u32) -> f64 {
    let s = s as usize;
    let mut m: Vec<u64> = m0.iter().map(|&x| x as u64).collect();
    for k in s..bits as usize {
        let mut x = m[k - s] ^ (m[k - s] << s);
        for j in 1..s {
            if (a >> (s - 1 - j)) & 1 == 1 {
                x ^= m[k - j] << j;
            }
        }
        m.push(x);
    }
    let mut x = 0u64;
    for (k, &mk) in m.iter().enumerate() {
        if (n >> k) & 1 == 1 {
            x ^= mk << (bits as usize - 1 - k);
        }
    }
    x as f64 / (1u64 << bits) as f64
}

fn unit64(bits: u32) -> f64 {
    bits as f64 / 4294967296.0
}

#[test]
fn unscrambled_points_match_scipy() {
    for (n, expected) in SCIPY_UNSCRAMBLED_2D.iter().enumerate() {
        let natural = (n ^ (n >> 1)) as u32;
        let got = [unit64(sobol(natural, 0)), unit64(sobol(natural, 1))];
        assert_eq!(
            &got, expected,
            "SciPy's point {n} (natural index {natural})"
        );
    }
}

#[test]
fn unscrambled_points_match_joe_kuo_numbers() {
    // Dimension 0 is the van der Corput sequence: the index's bits reversed.
    for n in 0..1024u32 {
        assert_eq!(sobol(n, 0), n.reverse_bits(), "dimension 0, point {n}");
    }
    // Dimensions 1 to 3 from Joe and Kuo's numbers, 16 points to 32 bits, and the table.
    for (d, &numbers) in JOE_KUO.iter().enumerate() {
        let dim = d as u32 + 1;
        for n in 0..16u32 {
            assert_eq!(
                unit64(sobol(n, dim)),
                textbook_sobol(n, numbers, 32),
                "dimension {dim}, point {n}"
            );
        }
        for k in 0..32u32 {
            assert_eq!(
                unit64(SOBOL_DIRECTIONS[(dim * 32 + k) as usize]),
                textbook_sobol(1 << k, numbers, 32),
                "dimension {dim}, direction number {k}"
            );
        }
    }
    assert_eq!(SOBOL_DIRECTIONS.len() as u32, SOBOL_DIMS * 32);
}

/// `sobol` takes dimension 0 as the index's bits reversed and dimension 1 by Pascal's triangle
/// (`pascal_xor`), without the table: on full 32-bit indices (the shuffled indices it is given)
/// every dimension is the XOR of the table's direction numbers of the index's set bits.
#[test]
fn every_dimension_is_the_tables_xor_on_full_indices() {
    let mut index = 0x9e37_79b9u32;
    for n in 0..100_000u32 {
        index = index.wrapping_mul(747_796_405).wrapping_add(2_891_336_453) ^ n;
        for dim in 0..SOBOL_DIMS {
            let table = (0..32)
                .filter(|k| (index >> k) & 1 == 1)
                .fold(0u32, |x, k| x ^ SOBOL_DIRECTIONS[(dim * 32 + k) as usize]);
            assert_eq!(
                sobol(index, dim),
                table,
                "dimension {dim}, index {index:#010x}"
            );
        }
    }
}

/// Whether the points (0.32 fixed point) are a (0, k, 2)-net: each box 2^-a x 2^-b with
/// a + b = k holds exactly one.
fn assert_net(points: &[(u32, u32)], k: u32, what: &str) {
    assert_eq!(points.len(), 1 << k);
    for a in 0..=k {
        let b = k - a;
        let mut seen = vec![false; 1 << k];
        for &(x, y) in points {
            let cx = if a == 0 { 0 } else { x >> (32 - a) };
            let cy = if b == 0 { 0 } else { y >> (32 - b) };
            let cell = ((cx << b) | cy) as usize;
            assert!(
                !seen[cell],
                "{what}: 2^{k} points, boxes 2^-{a} x 2^-{b}: cell {cell} twice"
            );
            seen[cell] = true;
        }
    }
}

#[test]
fn first_two_dimensions_are_nets_scrambled_or_not() {
    for k in 0..=10u32 {
        let n = 1u32 << k;
        let plain: Vec<_> = (0..n).map(|i| (sobol(i, 0), sobol(i, 1))).collect();
        assert_net(&plain, k, "unscrambled");
        for pixel in [0u32, 1, 77, 123_456, u32::MAX] {
            for base in [0u32, 4, 12] {
                // The image plane's pair, and the pairs starting later padding groups.
                let points: Vec<_> = (0..n)
                    .map(|i| {
                        (
                            sobol_sample(pixel, i, base),
                            sobol_sample(pixel, i, base + 1),
                        )
                    })
                    .collect();
                assert_net(
                    &points,
                    k,
                    &format!("pixel {pixel}, dimensions {base}, {}", base + 1),
                );
            }
        }
    }
}

#[test]
fn scrambled_points_are_uniform_and_differ_by_pixel() {
    let n = 4096u32;
    for pixel in [3u32, 999] {
        for dim in 0..12u32 {
            let mean = (0..n)
                .map(|i| to_unit(sobol_sample(pixel, i, dim)) as f64)
                .sum::<f64>()
                / n as f64;
            // A stratified 1D set of 4096 points: within a stratum's width of 1/2.
            assert!(
                (mean - 0.5).abs() < 1.0 / 4096.0,
                "pixel {pixel} dim {dim}: mean {mean}"
            );
        }
    }
    let first: Vec<u32> = (0..64).map(|i| sobol_sample(5, i, 0)).collect();
    let other: Vec<u32> = (0..64).map(|i| sobol_sample(6, i, 0)).collect();
    assert_ne!(first, other, "two pixels draw the same scramble");
    // Different padding groups of one pixel differ too (their own shuffles and scrambles).
    let group1: Vec<u32> = (0..64).map(|i| sobol_sample(5, i, 4)).collect();
    assert_ne!(first, group1);
    // The random sampler is uniform too, to random accuracy.
    let mean = (0..n)
        .map(|i| to_unit(random_sample(1, i, 0)) as f64)
        .sum::<f64>()
        / n as f64;
    assert!((mean - 0.5).abs() < 0.03, "random: mean {mean}");
}

#[test]
fn the_float_conversion_is_exact() {
    assert_eq!(to_unit(0), 0.0);
    assert_eq!(to_unit(u32::MAX), 1.0 - 2f32.powi(-24));
    assert!(to_unit(u32::MAX) < 1.0);
    assert_eq!(to_unit(0x8000_0000), 0.5);
    assert_eq!(to_unit(0x0000_01ff), 2f32.powi(-24));
}

/// The GPU's bits for `sampler` against the CPU twin's, over a grid of pixels, samples, dims.
fn gpu_matches_cpu(sampler: u32, test: &str) {
    let Some(tracer) = common::gpu(test) else {
        return;
    };
    let (pixels, samples, dims) = (0..37u32, 70u32, 21u32);
    let pixels = (pixels.start + 1_000_000)..(pixels.end + 1_000_000);
    let gpu = qjulia::gpu::sobol_probe(tracer.context(), sampler, pixels.clone(), samples, dims)
        .expect("the probe kernel runs");
    let mut at = 0;
    for pixel in pixels {
        for sample in 0..samples {
            for dim in 0..dims {
                let cpu = sample_bits(sampler, pixel, sample, dim);
                assert_eq!(
                    gpu[at], cpu,
                    "{test}: pixel {pixel} sample {sample} dim {dim}: GPU {:#010x}, CPU {cpu:#010x}",
                    gpu[at]
                );
                at += 1;
            }
        }
    }
    assert_eq!(at, gpu.len());
}

#[test]
fn gpu_draws_the_cpus_sobol_bits() {
    gpu_matches_cpu(SAMPLER_SOBOL, "sobol sampler GPU == CPU");
}

#[test]
fn gpu_draws_the_cpus_random_bits() {
    gpu_matches_cpu(SAMPLER_RANDOM, "random sampler GPU == CPU");
}

/// Issue 35, item 8: the layout of a bounce's dimensions. Every 2D point (the sun's, the sphere
/// light's, the BSDF's direction) is the first two dimensions of a padding group of its own, the
/// best-stratified pair (`first_two_dimensions_are_nets_scrambled_or_not`); the lobe's choice
/// is in its direction's group; every bounce starts a group; no two uses share a dimension.
#[test]
fn each_light_and_the_bsdf_take_a_groups_best_pair() {
    use qjulia::cpu::sobol::{
        DIM_BOUNCE_BASE, DIM_BSDF, DIM_BSDF_CHOICE, DIM_ROULETTE, DIM_SPHERE_LIGHT, DIM_SUN,
        DIMS_PER_BOUNCE,
    };
    assert_eq!(DIM_BOUNCE_BASE % SOBOL_DIMS, 0);
    assert_eq!(DIMS_PER_BOUNCE % SOBOL_DIMS, 0);
    let points = [DIM_SUN, DIM_SPHERE_LIGHT, DIM_BSDF];
    for first in points {
        assert_eq!(first % SOBOL_DIMS, 0, "a 2D point at offset {first}");
    }
    let groups: Vec<u32> = points.iter().map(|d| d / SOBOL_DIMS).collect();
    assert!(groups[0] != groups[1] && groups[1] != groups[2] && groups[0] != groups[2]);
    assert_eq!(DIM_BSDF_CHOICE / SOBOL_DIMS, DIM_BSDF / SOBOL_DIMS);
    let mut used = vec![
        DIM_SUN,
        DIM_SUN + 1,
        DIM_SPHERE_LIGHT,
        DIM_SPHERE_LIGHT + 1,
        DIM_BSDF,
        DIM_BSDF + 1,
        DIM_BSDF_CHOICE,
        DIM_ROULETTE,
    ];
    assert!(used.iter().all(|&d| d < DIMS_PER_BOUNCE));
    used.sort();
    used.dedup();
    assert_eq!(used.len(), 8, "two uses share a dimension");
}
