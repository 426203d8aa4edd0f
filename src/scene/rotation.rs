//! Turning a slice of 4D space: six rotation angles, one per coordinate plane, applied to a base
//! slice basis. Every rotation is orthogonal, so an orthonormal basis stays orthonormal.

use glam::DVec4;

/// The six planes of 4D rotation, in the order the angles are given and applied.
pub const PLANES: [(usize, usize, &str); 6] = [
    (0, 1, "real-i"),
    (0, 2, "real-j"),
    (0, 3, "real-k"),
    (1, 2, "i-j"),
    (1, 3, "i-k"),
    (2, 3, "j-k"),
];

/// Rotates `v` by `angles[p]` radians in plane `PLANES[p]`, for p = 0..6 in order.
pub fn rotate4(v: [f64; 4], angles: &[f64; 6]) -> [f64; 4] {
    let mut v = v;
    for (&(a, b, _), &theta) in PLANES.iter().zip(angles) {
        let (s, c) = theta.sin_cos();
        let (va, vb) = (v[a], v[b]);
        v[a] = c * va - s * vb;
        v[b] = s * va + c * vb;
    }
    v
}

/// The slice basis (x, y, z) rotated by the angles; orthonormal when `base` is.
pub fn rotate_basis(base: [[f64; 4]; 3], angles: &[f64; 6]) -> [[f64; 4]; 3] {
    base.map(|b| rotate4(b, angles))
}

/// How far a basis is from orthonormal: the largest |b_i . b_j - delta_ij|.
pub fn orthonormality_error(basis: &[[f64; 4]; 3]) -> f64 {
    let v = basis.map(DVec4::from_array);
    let mut worst = 0f64;
    for i in 0..3 {
        for j in 0..3 {
            let expected = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((v[i].dot(v[j]) - expected).abs());
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    const STANDARD: [[f64; 4]; 3] = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ];

    #[test]
    fn zero_angles_keep_the_basis() {
        assert_eq!(rotate_basis(STANDARD, &[0.0; 6]), STANDARD);
    }

    #[test]
    fn rotated_bases_stay_orthonormal() {
        let mut seed = 0.1234f64;
        for _ in 0..500 {
            let mut angles = [0.0; 6];
            for a in &mut angles {
                seed = (seed * 997.0 + 0.31).fract();
                *a = (seed - 0.5) * 4.0 * std::f64::consts::PI;
            }
            let basis = rotate_basis(STANDARD, &angles);
            assert!(orthonormality_error(&basis) < 1e-12, "{angles:?}");
        }
    }

    #[test]
    fn a_quarter_turn_in_the_real_k_plane_maps_real_to_k() {
        let mut angles = [0.0; 6];
        angles[2] = std::f64::consts::FRAC_PI_2;
        let x = rotate4([1.0, 0.0, 0.0, 0.0], &angles);
        assert!((x[3] - 1.0).abs() < 1e-15 && x[0].abs() < 1e-15);
    }
}
