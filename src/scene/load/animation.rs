//! The `[animation]` table of the layers: its frame count, frames per second, c's path radius
//! and keyframes, each checked against the scene built from the other keys.

use std::collections::BTreeMap;

use toml::Value;

use super::values::{check_scene, number, parse};
use crate::scene::Scene;
use crate::scene::animation::{Animation, FRAMES_MAX, FRAMES_MIN, Keyframe, animatable};
use crate::scene::error::{SceneError, SceneSource};
use crate::scene::schema::{self, Kind};

/// The `[animation]` keys other than `keys`, for errors.
const ANIMATION_KEYS: &str = "frames, fps, path_radius and keys";

/// Reads the `[animation]` table's entries (every `animation.*` of the layers) against the
/// validated base scene: the frame count, frames per second, c's path radius and the
/// keyframes, each keyframe's values checked by applying them to the base scene, and every
/// frame's scene checked.
pub(super) fn read_animation(
    entries: BTreeMap<String, (Value, SceneSource)>,
    base: &Scene,
) -> Result<Animation, SceneError> {
    let mut animation = Animation::default();
    let mut keys = None;
    for (key, (v, src)) in entries {
        let bad = |reason: &str| SceneError::value(&src, &key, &v, reason);
        match key.as_str() {
            "animation" => {
                // An empty [animation] table; anything else is not a table.
                if !v.is_table() {
                    return Err(SceneError::key(
                        &src,
                        &key,
                        "animation must be a table".into(),
                    ));
                }
            }
            "animation.frames" => {
                let Value::Integer(i) = v else {
                    return Err(bad("must be an integer"));
                };
                if i < i64::from(FRAMES_MIN) || i > i64::from(FRAMES_MAX) {
                    return Err(bad(&format!("must be in [{FRAMES_MIN}, {FRAMES_MAX}]")));
                }
                animation.frames = i as u32;
            }
            "animation.fps" | "animation.path_radius" => {
                let x = number(&v).ok_or_else(|| bad("must be a number"))?;
                if !x.is_finite() {
                    return Err(bad("must be finite"));
                }
                if key == "animation.fps" {
                    if x <= 0.0 {
                        return Err(bad("must be > 0"));
                    }
                    animation.fps = x;
                } else {
                    if x < 0.0 {
                        return Err(bad("must be >= 0"));
                    }
                    animation.path_radius = x;
                }
            }
            "animation.keys" => keys = Some((v, src)),
            _ if key.starts_with("animation.keys.") => {
                return Err(SceneError::key(
                    &src,
                    "animation.keys",
                    "animation.keys must be an array of tables ([[animation.keys]])".into(),
                ));
            }
            _ => {
                return Err(SceneError::key(
                    &src,
                    &key,
                    format!("unknown key {key}; the [animation] keys are {ANIMATION_KEYS}"),
                ));
            }
        }
    }
    if let Some((v, src)) = keys {
        animation.keys = read_keyframes(&v, &src, base, animation.frames)?;
        check_frames(&animation, base, &src)?;
    }
    Ok(animation)
}

/// Reads `animation.keys`: an array of tables, each with its `frame` (an integer, unique, below
/// `frames`) and animatable scene values by dotted path, valid on the base scene.
fn read_keyframes(
    v: &Value,
    src: &SceneSource,
    base: &Scene,
    frames: u32,
) -> Result<Vec<Keyframe>, SceneError> {
    let Some(items) = v.as_array() else {
        return Err(SceneError::value(
            src,
            "animation.keys",
            v,
            "must be an array of tables ([[animation.keys]])",
        ));
    };
    let mut keys: Vec<Keyframe> = Vec::new();
    for (i, item) in items.iter().enumerate() {
        let name = format!("animation.keys[{i}]");
        let Some(table) = item.as_table() else {
            return Err(SceneError::value(
                src,
                &name,
                item,
                "must be a table: frame = N and scene values",
            ));
        };
        let mut values = Vec::new();
        flatten("", table, &mut values);
        let frame_key = format!("{name}.frame");
        let Some((_, frame)) = values.iter().find(|(p, _)| p == "frame") else {
            return Err(SceneError::key(
                src,
                &frame_key,
                format!("{frame_key} is missing"),
            ));
        };
        let Value::Integer(f) = *frame else {
            return Err(SceneError::value(
                src,
                &frame_key,
                frame,
                "must be an integer",
            ));
        };
        if f < 0 || f >= i64::from(frames) {
            let last = frames - 1;
            let reason = format!("must be in [0, {last}] (animation.frames is {frames})");
            return Err(SceneError::value(src, &frame_key, frame, &reason));
        }
        let f = f as u32;
        if let Some(j) = keys.iter().position(|k| k.frame == f) {
            let reason = format!("repeats animation.keys[{j}]'s frame");
            return Err(SceneError::value(src, &frame_key, frame, &reason));
        }

        // Each value, applied to the base scene: its type, length and finiteness.
        let mut scene = base.clone();
        let mut set: Vec<(String, Vec<f64>)> = Vec::new();
        let mut given: Vec<(&str, &Value)> = Vec::new();
        for (path, value) in values.iter().filter(|(p, _)| p != "frame") {
            let full = format!("{name}.{path}");
            let Some(key) = schema::key(path).filter(|_| animatable(path)) else {
                let why = match schema::key(path).map(|k| k.kind) {
                    Some(Kind::Integer { .. }) => "it is an integer",
                    Some(Kind::Bool { .. }) => "it is true or false",
                    Some(Kind::Choice { .. }) => "it is a choice of names",
                    _ => "it is not a scene key",
                };
                return Err(SceneError::key(
                    src,
                    &full,
                    format!(
                        "{full} cannot be animated: {why}; keyframes set floats and float \
                         vectors (fractal.c, fractal.epsilon, camera.eye, slice.x, ...)"
                    ),
                ));
            };
            parse(&key.kind, value, &mut scene)
                .map_err(|reason| SceneError::value(src, &full, value, &reason))?;
            let number = match key.kind.value(&scene) {
                Value::Float(x) => vec![x],
                Value::Array(a) => a.iter().filter_map(Value::as_float).collect(),
                _ => unreachable!("animatable keys are floats and float vectors"),
            };
            set.push((path.clone(), number));
            given.push((path, value));
        }
        // The base scene with the keyframe's values must itself be valid.
        let blame = |involved: &[&str]| -> String {
            involved
                .iter()
                .rev()
                .find(|k| given.iter().any(|(p, _)| p == *k))
                .or(involved.last())
                .map(|k| k.to_string())
                .unwrap_or_default()
        };
        check_scene(&mut scene, blame).map_err(|(key, reason)| {
            let full = format!("{name}.{key}");
            match given.iter().find(|(p, _)| *p == key) {
                Some((_, value)) => SceneError::value(src, &full, value, &reason),
                None => SceneError::key(src, &full, format!("{full} (the scene's) {reason}")),
            }
        })?;
        keys.push(Keyframe {
            frame: f,
            values: set,
        });
    }
    Ok(keys)
}

/// The leaf values of a keyframe's table by dotted path (`fractal.c = [...]` and `[fractal] c =
/// [...]` alike).
fn flatten(prefix: &str, table: &toml::Table, out: &mut Vec<(String, Value)>) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            Value::Table(t) if !t.is_empty() => flatten(&path, t, out),
            v => out.push((path, v.clone())),
        }
    }
}

/// Every frame's scene must be valid: a track may overshoot between its keys (a range), or the
/// slice or camera may degenerate on the way.
fn check_frames(animation: &Animation, base: &Scene, src: &SceneSource) -> Result<(), SceneError> {
    let last = |keys: &[&str]| keys.last().map(|k| k.to_string()).unwrap_or_default();
    for k in 0..animation.frames {
        let mut scene = animation.scene_at(base, k);
        check_scene(&mut scene, last).map_err(|(key, reason)| {
            let value = schema::key(&key)
                .map(|schema_key| schema_key.kind.value(&scene).to_string())
                .unwrap_or_default();
            SceneError::key(
                src,
                "animation.keys",
                format!(
                    "animation.keys give frame {k} {key} = {value}, which {reason} (add a \
                     keyframe there, or move the keys)"
                ),
            )
        })?;
    }
    Ok(())
}
