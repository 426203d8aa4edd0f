//! Animation: the scene file's `[animation]` table (frame count, frames per second, keyframes)
//! and the resolved scene of each frame, a function of the scene options and the frame's index
//! alone (docs/CONTRACT.md's additions).
//!
//! Each animated value has a track: the keyframes that set it, by frame. Between two of its
//! keys the track is a cubic Hermite segment with Catmull-Rom tangents (finite differences over
//! the neighbouring keys, in frame units; zero at the track's first and last key), so it passes
//! exactly through every key and is C1 everywhere; before its first key and after its last it
//! holds that key's value. The slice's axes are interpolated so and then re-orthonormalised
//! (Gram-Schmidt in x, y, z order). When no keyframe sets `fractal.c`, c makes one closed loop
//! on [`c_path`] around the scene's c. The README's "Animation (exact)" states this exactly.

use std::f64::consts::TAU;

use super::Scene;
use super::schema::{self, Kind};

/// The `[animation]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// Frame count, 1 to 100000.
    pub frames: u32,
    /// Frames per second, finite and > 0 (for video).
    pub fps: f64,
    /// The radius of c's closed path when no keyframe sets `fractal.c` (the explorer's Play
    /// path).
    pub path_radius: f64,
    /// Keyframes, by frame number (unique, within the frame count).
    pub keys: Vec<Keyframe>,
}

/// One keyframe: its frame number and the float or float-vector scene values it sets, by
/// dotted path (e.g. `fractal.c`, `camera.eye`).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe {
    pub frame: u32,
    pub values: Vec<(String, Vec<f64>)>,
}

impl Default for Animation {
    fn default() -> Self {
        Self {
            frames: 120,
            fps: 30.0,
            path_radius: 0.08,
            keys: Vec::new(),
        }
    }
}

/// Fewest and most frames of an animation.
pub const FRAMES_MIN: u32 = 1;
pub const FRAMES_MAX: u32 = 100_000;

/// Whether the scene key at `path` can be animated: a float, a float vector or a number of the
/// algebra (schema kinds `Float`, `Vector`, `Hyper`).
pub fn animatable(path: &str) -> bool {
    matches!(
        schema::key(path).map(|k| k.kind),
        Some(Kind::Float { .. } | Kind::Vector { .. } | Kind::Hyper { .. })
    )
}

/// Writes `value` into the scene's key at `path` (an animatable key, `value` as long as the
/// field; a float is a one-number vector). Returns false, changing nothing, otherwise.
pub fn set_value(scene: &mut Scene, path: &str, value: &[f64]) -> bool {
    match schema::key(path).map(|k| k.kind) {
        Some(Kind::Float { at, .. }) if value.len() == 1 => {
            *(at.get_mut)(scene) = value[0];
            true
        }
        Some(Kind::Vector { at, .. } | Kind::Hyper { at })
            if (at.get)(scene).len() == value.len() =>
        {
            (at.get_mut)(scene).copy_from_slice(value);
            true
        }
        _ => false,
    }
}

/// The value of the animatable key at `path` in `scene` (a float as a one-number vector); None
/// for any other path.
pub fn get_value(scene: &Scene, path: &str) -> Option<Vec<f64>> {
    match schema::key(path).map(|k| k.kind) {
        Some(Kind::Float { at, .. }) => Some(vec![*(at.get)(scene)]),
        Some(Kind::Vector { at, .. } | Kind::Hyper { at }) => Some((at.get)(scene).to_vec()),
        _ => None,
    }
}

/// The point at `phase` of c's closed path of radius `radius` around `center` (the explorer's
/// Play path): every component moves, each at its own frequency, and the path is at `center`
/// exactly at phase 0 and returns there after 2 pi.
///
/// Component k of the point is `center[k] +`
/// - k = 0: `r (cos t - 1)`; k = 1: `r sin t`; k = 2: `0.6 r sin 2t`; k = 3: `0.6 r (cos 3t - 1)`;
/// - k >= 4 (octonions, sedenions): `0.3 r sin((k - 2) t)`.
pub fn c_path(center: &[f64], radius: f64, phase: f64) -> Vec<f64> {
    let r = radius;
    center
        .iter()
        .enumerate()
        .map(|(k, &c)| match k {
            0 => c + r * (phase.cos() - 1.0),
            1 => c + r * phase.sin(),
            2 => c + 0.6 * r * (2.0 * phase).sin(),
            3 => c + 0.6 * r * ((3.0 * phase).cos() - 1.0),
            _ => c + 0.3 * r * ((k as f64 - 2.0) * phase).sin(),
        })
        .collect()
}

/// The value at frame `t` of a track through `keys` (frame, value), sorted by frame, frames
/// distinct, values of one length, at least one key: the cubic Hermite spline through the keys
/// with Catmull-Rom tangents `m_i = (v_{i+1} - v_{i-1}) / (t_{i+1} - t_{i-1})` at inner keys
/// and `m = 0` at the first and last, held constant outside the keys.
pub fn track_value(keys: &[(f64, &[f64])], t: f64) -> Vec<f64> {
    let n = keys.len();
    let (first, last) = (keys[0], keys[n - 1]);
    if t <= first.0 {
        return first.1.to_vec();
    }
    if t >= last.0 {
        return last.1.to_vec();
    }
    // The segment [t_i, t_{i+1}) holding t (n >= 2 here).
    let i = keys.partition_point(|&(tk, _)| tk <= t) - 1;
    let (t0, v0) = keys[i];
    let (t1, v1) = keys[i + 1];
    if t == t0 {
        return v0.to_vec();
    }
    let tangent = |j: usize, c: usize| -> f64 {
        if j == 0 || j == n - 1 {
            0.0
        } else {
            (keys[j + 1].1[c] - keys[j - 1].1[c]) / (keys[j + 1].0 - keys[j - 1].0)
        }
    };
    let h = t1 - t0;
    let s = (t - t0) / h;
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    (0..v0.len())
        .map(|c| h00 * v0[c] + h10 * h * tangent(i, c) + h01 * v1[c] + h11 * h * tangent(i + 1, c))
        .collect()
}

impl Animation {
    /// The `[animation]` table as TOML, to follow a scene's tables in a scene file (see
    /// [`scene_file`]): `frames`, `fps`, `path_radius`, then one `[[animation.keys]]` per
    /// keyframe with its `frame` and each value by dotted path (`fractal.c = [...]`). Floats are
    /// written in their shortest exact form, so that the file reads back to the same numbers.
    pub fn to_toml(&self) -> String {
        use std::fmt::Write;
        let float = |x: f64| toml::Value::Float(x).to_string();
        let mut out = String::from("[animation]\n");
        writeln!(out, "frames = {}", self.frames).unwrap();
        writeln!(out, "fps = {}", float(self.fps)).unwrap();
        writeln!(out, "path_radius = {}", float(self.path_radius)).unwrap();
        for key in &self.keys {
            out.push_str("\n[[animation.keys]]\n");
            writeln!(out, "frame = {}", key.frame).unwrap();
            for (path, value) in &key.values {
                let text = match schema::key(path).map(|k| k.kind) {
                    Some(Kind::Float { .. }) if value.len() == 1 => float(value[0]),
                    _ => {
                        let items: Vec<String> = value.iter().map(|&x| float(x)).collect();
                        format!("[{}]", items.join(", "))
                    }
                };
                writeln!(out, "{path} = {text}").unwrap();
            }
        }
        out
    }

    /// The paths the keyframes set, each once, in the order first set.
    pub fn animated_paths(&self) -> Vec<&str> {
        let mut paths: Vec<&str> = Vec::new();
        for key in &self.keys {
            for (path, _) in &key.values {
                if !paths.contains(&path.as_str()) {
                    paths.push(path);
                }
            }
        }
        paths
    }

    /// The track of `path`: (frame, value) of every keyframe that sets it, by frame.
    fn track(&self, path: &str) -> Vec<(f64, &[f64])> {
        let mut track: Vec<(f64, &[f64])> = self
            .keys
            .iter()
            .filter_map(|k| {
                k.values
                    .iter()
                    .find(|(p, _)| p == path)
                    .map(|(_, v)| (f64::from(k.frame), v.as_slice()))
            })
            .collect();
        track.sort_by(|a, b| a.0.total_cmp(&b.0));
        track
    }

    /// The phase of c's closed path at frame `frame`: 2 pi frame / frames.
    pub fn phase(&self, frame: u32) -> f64 {
        TAU * f64::from(frame) / f64::from(self.frames.max(1))
    }

    /// The resolved scene of frame `frame` (0-based, below `frames`) of the animation of `base`:
    /// every keyed value on its track, the slice re-orthonormalised, and c on its closed path
    /// when no keyframe sets it. Frame 0 of an animation without keyframes is `base` exactly.
    pub fn scene_at(&self, base: &Scene, frame: u32) -> Scene {
        let mut scene = base.clone();
        let t = f64::from(frame);
        let paths = self.animated_paths();
        for &path in &paths {
            let value = track_value(&self.track(path), t);
            set_value(&mut scene, path, &value);
        }
        if paths
            .iter()
            .any(|p| p.starts_with("slice.") && p != &"slice.offset")
        {
            let s = &scene.slice;
            if let Some([x, y, z]) =
                crate::scene::orthonormalise([s.x.as_slice(), s.y.as_slice(), s.z.as_slice()])
            {
                (scene.slice.x, scene.slice.y, scene.slice.z) = (x, y, z);
            }
        }
        if !paths.contains(&"fractal.c") {
            scene.fractal.c = c_path(&base.fractal.c, self.path_radius, self.phase(frame));
        }
        // path.animated_seed: the frame's own seed, which depends on the frame alone.
        if scene.path.animated_seed && !paths.contains(&"path.seed") {
            scene.path.seed = base.path.seed.wrapping_add(frame);
        }
        scene
    }
}

/// A scene file holding `base` and its animation: the scene's tables, then `[animation]`, so
/// that `qjulia animate --scene FILE` renders exactly this animation.
pub fn scene_file(base: &Scene, animation: &Animation) -> String {
    format!("{}\n{}", base.to_toml(), animation.to_toml())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Algebra, dot};

    fn key(frame: u32, values: &[(&str, &[f64])]) -> Keyframe {
        Keyframe {
            frame,
            values: values
                .iter()
                .map(|(p, v)| (p.to_string(), v.to_vec()))
                .collect(),
        }
    }

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn tracks_pass_through_every_key_exactly() {
        let a = Animation {
            frames: 100,
            keys: vec![
                key(
                    0,
                    &[
                        ("camera.eye", &[0.0, 0.0, 3.0]),
                        ("fractal.epsilon", &[0.003]),
                    ],
                ),
                key(
                    17,
                    &[
                        ("camera.eye", &[1.0, 0.5, 2.7]),
                        ("fractal.c", &[0.1, 0.2, 0.3, 0.4]),
                    ],
                ),
                key(
                    40,
                    &[
                        ("camera.eye", &[-0.3, 1.1, 2.0]),
                        ("fractal.epsilon", &[0.01]),
                    ],
                ),
                key(
                    99,
                    &[
                        ("camera.eye", &[0.2, -0.7, 3.3]),
                        ("fractal.c", &[-0.3, 0.5, 0.1, 0.0]),
                    ],
                ),
            ],
            ..Animation::default()
        };
        let base = Scene::default();
        for k in &a.keys {
            let s = a.scene_at(&base, k.frame);
            for (path, v) in &k.values {
                let got = schema::key(path).unwrap().kind.value(&s);
                let got: Vec<f64> = match got {
                    toml::Value::Float(x) => vec![x],
                    toml::Value::Array(a) => a.iter().map(|x| x.as_float().unwrap()).collect(),
                    _ => unreachable!(),
                };
                assert!(
                    close(&got, v, 1e-12),
                    "frame {}: {path} {got:?} != {v:?}",
                    k.frame
                );
            }
        }
        // Between keys the track moves, and is held outside them: epsilon after frame 40.
        assert_eq!(a.scene_at(&base, 70).fractal.epsilon, 0.01);
        assert_ne!(
            a.scene_at(&base, 20).camera.eye,
            a.scene_at(&base, 21).camera.eye
        );
        // c is keyed, so it holds its first key before frame 17.
        assert_eq!(a.scene_at(&base, 3).fractal.c, vec![0.1, 0.2, 0.3, 0.4]);
    }

    #[test]
    fn the_track_is_the_hermite_spline_of_the_definition() {
        // Keys (0, 0), (10, 1), (30, 5): m_0 = 0, m_1 = (5 - 0) / 30, m_2 = 0.
        let (a, b, c) = ([0.0], [1.0], [5.0]);
        let keys = [(0.0, &a[..]), (10.0, &b[..]), (30.0, &c[..])];
        // t = 5: s = 0.5, h = 10: h00 = h01 = 0.5, h10 = 0.125, h11 = -0.125.
        let expected = 0.5 * 0.0 + 0.125 * 10.0 * 0.0 + 0.5 * 1.0 - 0.125 * 10.0 * (5.0 / 30.0);
        assert!((track_value(&keys, 5.0)[0] - expected).abs() < 1e-15);
        // t = 20: s = 0.5, h = 20, m_1 = 1/6, m_2 = 0.
        let expected = 0.5 * 1.0 + 0.125 * 20.0 * (5.0 / 30.0) + 0.5 * 5.0;
        assert!((track_value(&keys, 20.0)[0] - expected).abs() < 1e-15);
        // C1 at the inner key: one-sided slopes agree.
        let d = 1e-6;
        let left = (track_value(&keys, 10.0)[0] - track_value(&keys, 10.0 - d)[0]) / d;
        let right = (track_value(&keys, 10.0 + d)[0] - track_value(&keys, 10.0)[0]) / d;
        assert!((left - 5.0 / 30.0).abs() < 1e-5 && (right - 5.0 / 30.0).abs() < 1e-5);
        // Held outside, and flat at the ends.
        assert_eq!(track_value(&keys, -3.0), vec![0.0]);
        assert_eq!(track_value(&keys, 31.0), vec![5.0]);
    }

    #[test]
    fn a_value_set_by_one_key_only_is_constant() {
        let a = Animation {
            frames: 50,
            keys: vec![
                key(
                    20,
                    &[
                        ("light.position", &[1.0, -1.0, 4.0]),
                        ("fractal.c", &[0.0, 0.5, 0.0, 0.0]),
                    ],
                ),
                key(30, &[("camera.fov_y_degrees", &[30.0])]),
            ],
            ..Animation::default()
        };
        let base = Scene::default();
        for k in 0..50 {
            let s = a.scene_at(&base, k);
            assert_eq!(s.light.position, [1.0, -1.0, 4.0], "frame {k}");
            assert_eq!(s.fractal.c, vec![0.0, 0.5, 0.0, 0.0], "frame {k}");
            assert_eq!(s.camera.fov_y_degrees, 30.0, "frame {k}");
            assert_eq!(s.camera.eye, base.camera.eye, "frame {k}");
        }
    }

    /// A unit rotation of the standard slice in the (axis a, axis b) plane by `angle`.
    fn rotated_slice(dim: usize, a: usize, b: usize, angle: f64) -> [Vec<f64>; 3] {
        let mut axes = crate::scene::Slice::default().axes(dim);
        for v in &mut axes {
            let (x, y) = (v[a], v[b]);
            v[a] = x * angle.cos() - y * angle.sin();
            v[b] = x * angle.sin() + y * angle.cos();
        }
        axes
    }

    #[test]
    fn the_slice_halfway_between_two_keys_differs_from_both_and_is_orthonormal() {
        for algebra in Algebra::ALL {
            let dim = algebra.dim();
            let mut base = Scene::default();
            base.set_algebra(algebra);
            let s0 = rotated_slice(dim, 0, 3, 0.3);
            let s1 = rotated_slice(dim, 1, dim - 1, 0.8);
            let slice_key = |frame, s: &[Vec<f64>; 3]| {
                key(
                    frame,
                    &[("slice.x", &s[0]), ("slice.y", &s[1]), ("slice.z", &s[2])],
                )
            };
            let a = Animation {
                frames: 21,
                keys: vec![slice_key(0, &s0), slice_key(20, &s1)],
                ..Animation::default()
            };
            let axes = |s: &Scene| [s.slice.x.clone(), s.slice.y.clone(), s.slice.z.clone()];
            let at = |k| axes(&a.scene_at(&base, k));
            for (k, expected) in [(0, &s0), (20, &s1)] {
                for (got, want) in at(k).iter().zip(expected) {
                    assert!(close(got, want, 1e-12), "{dim}D frame {k}");
                }
            }
            let half = at(10);
            for (got, key) in [(&half, &s0), (&half, &s1)] {
                let distance: f64 = got
                    .iter()
                    .zip(key)
                    .map(|(g, w)| g.iter().zip(w).map(|(p, q)| (p - q).abs()).sum::<f64>())
                    .sum();
                assert!(distance > 0.05, "{dim}D: halfway is a key ({distance})");
            }
            for i in 0..3 {
                for j in 0..3 {
                    let expected = if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (dot(&half[i], &half[j]) - expected).abs() < 1e-12,
                        "{dim}D: axes {i}, {j}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_default_animation_loops_c_from_the_scene_and_back() {
        let a = Animation::default();
        for algebra in Algebra::ALL {
            let mut base = Scene::default();
            base.set_algebra(algebra);
            base.fractal.c[algebra.dim() - 1] = 0.1;
            assert_eq!(a.scene_at(&base, 0), base, "frame 0 is the scene, exactly");
            let frames: Vec<Scene> = (0..a.frames).map(|k| a.scene_at(&base, k)).collect();
            for k in 1..frames.len() {
                assert_ne!(frames[k].fractal.c, frames[k - 1].fractal.c, "frame {k}");
                // Only c moves.
                let mut same = frames[k].clone();
                same.fractal.c = base.fractal.c.clone();
                assert_eq!(same, base);
            }
            // The frame after the last (phase 2 pi) is the start again.
            let end = c_path(&base.fractal.c, a.path_radius, a.phase(a.frames));
            assert!(close(&end, &base.fractal.c, 1e-12), "{end:?}");
            // Frame k is at phase 2 pi k / frames on the path, with the path's radius.
            let k = 30;
            let t = TAU * 30.0 / 120.0;
            assert_eq!(frames[k].fractal.c[1], base.fractal.c[1] + 0.08 * t.sin());
        }
    }

    #[test]
    fn only_numeric_schema_keys_are_animatable() {
        for path in [
            "fractal.c",
            "fractal.epsilon",
            "camera.eye",
            "slice.x",
            "light.position",
        ] {
            assert!(animatable(path), "{path}");
        }
        for path in [
            "fractal.algebra",
            "fractal.max_iterations",
            "shading.shadows",
            "image.width",
            "fractal.colour",
            "animation.frames",
        ] {
            assert!(!animatable(path), "{path}");
        }
    }

    #[test]
    fn a_saved_animation_reads_back_exactly() {
        use crate::scene::{SceneLoader, SceneSource};
        let mut base = Scene::default();
        base.set_algebra(Algebra::Octonion);
        base.camera.fov_y_degrees = 0.1 + 0.2;
        let s1 = rotated_slice(8, 2, 6, 0.7);
        let a = Animation {
            frames: 77,
            fps: 23.976,
            path_radius: 1.0 / 3.0,
            keys: vec![
                key(
                    0,
                    &[
                        ("camera.eye", &[1e-17, -0.0, 3.0000000000000004]),
                        ("fractal.c", &[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 1.0 / 3.0]),
                        ("fractal.epsilon", &[3e-3]),
                    ],
                ),
                key(
                    76,
                    &[
                        ("camera.eye", &[2.0 / 3.0, 0.5, 1e20]),
                        ("slice.x", &s1[0]),
                        ("slice.y", &s1[1]),
                        ("slice.z", &s1[2]),
                    ],
                ),
                key(40, &[("light.position", &[-1.5, 2.0, 7.0 / 9.0])]),
            ],
        };
        let text = scene_file(&base, &a);
        let mut loader = SceneLoader::new();
        loader.toml_str(&text, SceneSource::Default).unwrap();
        let (read_base, read) = loader
            .build_animated()
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(read_base, base);
        assert_eq!(read, a, "{text}");
        // Bitwise, -0.0 included.
        assert!(read.keys[0].values[0].1[1].is_sign_negative());
        assert!(text.contains("[[animation.keys]]\nframe = 76\n"), "{text}");
    }
}
