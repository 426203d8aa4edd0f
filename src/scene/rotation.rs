//! Turning a slice of the algebra's space: one rotation angle per coordinate plane (6 in 4D, 28
//! in 8D, 120 in 16D), applied in order to a base slice basis. Every rotation is orthogonal, so
//! an orthonormal basis stays orthonormal.

/// The name of axis k: 1, i, j, k for the quaternion units, then e4 ... e15.
pub fn axis_name(k: usize) -> String {
    match k {
        0 => "real".into(),
        1 => "i".into(),
        2 => "j".into(),
        3 => "k".into(),
        _ => format!("e{k}"),
    }
}

/// The coordinate planes (a, b), a < b < dim, in the order the angles are given and applied:
/// for 4D (real-i, real-j, real-k, i-j, i-k, j-k).
pub fn planes(dim: usize) -> Vec<(usize, usize)> {
    (0..dim)
        .flat_map(|a| (a + 1..dim).map(move |b| (a, b)))
        .collect()
}

/// A plane's name, e.g. "real-k" or "j-e6".
pub fn plane_name((a, b): (usize, usize)) -> String {
    format!("{}-{}", axis_name(a), axis_name(b))
}

/// Rotates `v` by `angles[p]` radians in plane `planes(v.len())[p]`, in order.
pub fn rotate(v: &[f64], angles: &[f64]) -> Vec<f64> {
    let mut v = v.to_vec();
    for (&(a, b), &theta) in planes(v.len()).iter().zip(angles) {
        if theta == 0.0 {
            continue;
        }
        let (s, c) = theta.sin_cos();
        let (va, vb) = (v[a], v[b]);
        v[a] = c * va - s * vb;
        v[b] = s * va + c * vb;
    }
    v
}

/// The slice basis (x, y, z) rotated by the angles; orthonormal when `base` is.
pub fn rotate_basis(base: &[Vec<f64>; 3], angles: &[f64]) -> [Vec<f64>; 3] {
    std::array::from_fn(|i| rotate(&base[i], angles))
}

/// How far a basis is from orthonormal: the largest |b_i . b_j - delta_ij|.
pub fn orthonormality_error(basis: &[Vec<f64>; 3]) -> f64 {
    let mut worst = 0f64;
    for i in 0..3 {
        for j in 0..3 {
            let expected = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((super::dot(&basis[i], &basis[j]) - expected).abs());
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn standard(dim: usize) -> [Vec<f64>; 3] {
        super::super::Slice::default().axes(dim)
    }

    #[test]
    fn zero_angles_keep_the_basis() {
        for dim in [4, 8, 16] {
            let angles = vec![0.0; planes(dim).len()];
            assert_eq!(rotate_basis(&standard(dim), &angles), standard(dim));
        }
    }

    #[test]
    fn plane_counts_and_names() {
        assert_eq!(planes(4).len(), 6);
        assert_eq!(planes(8).len(), 28);
        assert_eq!(planes(16).len(), 120);
        let names: Vec<String> = planes(4).into_iter().map(plane_name).collect();
        assert_eq!(names, ["real-i", "real-j", "real-k", "i-j", "i-k", "j-k"]);
        assert_eq!(plane_name((2, 6)), "j-e6");
    }

    #[test]
    fn rotated_bases_stay_orthonormal() {
        let mut seed = 0.1234f64;
        for dim in [4, 8, 16] {
            for _ in 0..100 {
                let mut angles = vec![0.0; planes(dim).len()];
                for a in &mut angles {
                    seed = (seed * 997.0 + 0.31).fract();
                    *a = (seed - 0.5) * 4.0 * std::f64::consts::PI;
                }
                let basis = rotate_basis(&standard(dim), &angles);
                assert!(orthonormality_error(&basis) < 1e-12, "{dim}: {angles:?}");
            }
        }
    }

    #[test]
    fn a_quarter_turn_in_the_real_k_plane_maps_real_to_k() {
        let mut angles = [0.0; 6];
        angles[2] = std::f64::consts::FRAC_PI_2;
        let x = rotate(&[1.0, 0.0, 0.0, 0.0], &angles);
        assert!((x[3] - 1.0).abs() < 1e-15 && x[0].abs() < 1e-15);
    }

    #[test]
    fn a_quarter_turn_into_a_higher_dimension() {
        // In 8D, plane index of (1, 7): i turns into e7.
        let p = planes(8).iter().position(|&p| p == (1, 7)).unwrap();
        let mut angles = vec![0.0; 28];
        angles[p] = std::f64::consts::FRAC_PI_2;
        let x = rotate(&[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], &angles);
        assert!((x[7] - 1.0).abs() < 1e-15 && x[1].abs() < 1e-15);
    }
}
