//! Hyperspherical coordinates, for editing c as a magnitude and a direction on the unit sphere
//! of its algebra: n - 1 angles for a unit n-vector, and back.

/// The magnitude of `v` and its direction, a unit vector (the first axis where `v` is zero).
pub fn magnitude_and_direction(v: &[f64]) -> (f64, Vec<f64>) {
    let magnitude = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let direction = if magnitude > 0.0 {
        v.iter().map(|x| x / magnitude).collect()
    } else {
        (0..v.len())
            .map(|k| if k == 0 { 1.0 } else { 0.0 })
            .collect()
    };
    (magnitude, direction)
}

/// The n - 1 hyperspherical angles of a unit n-vector: d = (cos a1, sin a1 cos a2,
/// sin a1 sin a2 cos a3, ..., sin a1 ... sin a(n-1)), the last angle in (-pi, pi].
pub fn hyperspherical(d: &[f64]) -> Vec<f64> {
    let n = d.len();
    let mut angles = Vec::with_capacity(n - 1);
    for k in 0..n - 2 {
        let rest = d[k..].iter().map(|v| v * v).sum::<f64>().sqrt();
        angles.push(if rest > 0.0 {
            (d[k] / rest).clamp(-1.0, 1.0).acos()
        } else {
            0.0
        });
    }
    angles.push(d[n - 1].atan2(d[n - 2]));
    angles
}

/// The unit vector of `angles` (the inverse of [`hyperspherical`]).
pub fn from_hyperspherical(angles: &[f64]) -> Vec<f64> {
    let mut d = Vec::with_capacity(angles.len() + 1);
    let mut sines = 1.0;
    for &a in angles {
        d.push(sines * a.cos());
        sines *= a.sin();
    }
    d.push(sines);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hyperspherical_angles_round_trip() {
        for d in [
            vec![0.5, 0.5, 0.5, 0.5],
            vec![-0.2, 0.6, 0.2, 0.2],
            vec![0.0, 0.0, -1.0, 0.0],
            vec![0.1, -0.3, 0.2, 0.0, 0.5, -0.1, 0.0, 0.7],
        ] {
            let n = d.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
            let u: Vec<f64> = d.iter().map(|v| v / n).collect();
            let back = from_hyperspherical(&hyperspherical(&u));
            for k in 0..u.len() {
                assert!((back[k] - u[k]).abs() < 1e-12, "{u:?} -> {back:?}");
            }
        }
    }
}
