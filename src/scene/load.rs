//! Building a [`Scene`] from layers: built-in defaults, a preset, a scene file (TOML, or a PNG
//! written by qjulia), shorthand flags and `--set KEY=VALUE`, in that order of precedence. Every
//! key is checked once, after all layers, and every error names where the offending value came
//! from.

use std::collections::BTreeMap;
use std::path::Path;

use toml::Value;

use super::Scene;
use super::error::{SceneError, SceneSource};
use super::png::scene_from_png;
use super::presets::Preset;
use super::schema::{KEYS, Key, Kind, SCHEMA};
use crate::animation::{Animation, FRAMES_MAX, FRAMES_MIN, Keyframe, animatable};

/// Collects scene layers, later ones overriding earlier ones key by key, then builds and
/// validates the [`Scene`].
#[derive(Clone, Debug, Default)]
pub struct SceneLoader {
    entries: BTreeMap<String, (Value, SceneSource)>,
}

impl SceneLoader {
    pub fn new() -> Self {
        Self::default()
    }

    /// A preset by its slug (`--preset SLUG`), layered like a scene file; an unknown slug is an
    /// error listing the slugs.
    pub fn preset(&mut self, slug: &str) -> Result<(), SceneError> {
        let Some(preset) = super::presets::find(slug) else {
            return Err(SceneError::general(
                &SceneSource::Flag(format!("--preset {slug}")),
                format!(
                    "unknown preset; the presets are {}",
                    super::presets::slugs()
                ),
            ));
        };
        self.toml_str(preset.toml, SceneSource::Preset(preset.slug.to_string()))
    }

    /// Adds a scene file: TOML, or a PNG written by qjulia (its embedded scene).
    pub fn file(&mut self, path: &Path) -> Result<(), SceneError> {
        let source = SceneSource::File(path.to_path_buf());
        let is_png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let text = if is_png {
            scene_from_png(path)?
        } else {
            std::fs::read_to_string(path)
                .map_err(|e| SceneError::general(&source, format!("cannot read: {e}")))?
        };
        self.toml_str(&text, source)
    }

    /// Adds a layer given as TOML text.
    pub fn toml_str(&mut self, text: &str, source: SceneSource) -> Result<(), SceneError> {
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            SceneError::general(&source, describe_toml_error(text, &e))
        })?;
        self.insert_table("", table, &source);
        Ok(())
    }

    /// Adds one shorthand flag's value, e.g. `flag("image.width", 64, "--width 64")`.
    pub fn flag(&mut self, key: &str, value: Value, flag: impl Into<String>) {
        self.insert(key.to_string(), value, SceneSource::Flag(flag.into()));
    }

    /// Adds one `--set KEY=VALUE`: VALUE in TOML syntax, a bare word that is not TOML taken as
    /// a string.
    pub fn set(&mut self, raw: &str) -> Result<(), SceneError> {
        let source = SceneSource::Set(raw.to_string());
        let Some((key, text)) = raw.split_once('=') else {
            return Err(SceneError::general(&source, "expected KEY=VALUE"));
        };
        let key = key.trim();
        if key.is_empty() || key.split('.').any(|part| part.trim().is_empty()) {
            return Err(SceneError::general(
                &source,
                "expected KEY=VALUE with a dotted KEY",
            ));
        }
        let value = parse_set_value(text.trim());
        match value {
            Value::Table(table) => self.insert_table(key, table, &source),
            value => self.insert(key.to_string(), value, source),
        }
        Ok(())
    }

    fn insert_table(&mut self, prefix: &str, table: toml::Table, source: &SceneSource) {
        for (k, v) in table {
            let key = if prefix.is_empty() {
                k
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                Value::Table(t) if !t.is_empty() => self.insert_table(&key, t, source),
                v => self.insert(key, v, source.clone()),
            }
        }
    }

    fn insert(&mut self, key: String, value: Value, source: SceneSource) {
        self.entries.insert(key, (value, source));
    }

    /// The scene: defaults overridden by every layer, then checked as a whole.
    pub fn build(self) -> Result<Scene, SceneError> {
        self.build_animated().map(|(scene, _)| scene)
    }

    /// The scene and its `[animation]` table (the defaults where the layers give none).
    pub fn build_animated(mut self) -> Result<(Scene, Animation), SceneError> {
        let animation: BTreeMap<String, (Value, SceneSource)> = self
            .entries
            .keys()
            .filter(|k| k.as_str() == "animation" || k.starts_with("animation."))
            .cloned()
            .collect::<Vec<_>>()
            .into_iter()
            .filter_map(|k| self.entries.remove(&k).map(|v| (k, v)))
            .collect();
        let scene = self.build_scene()?;
        let animation = read_animation(animation, &scene)?;
        Ok((scene, animation))
    }

    fn build_scene(self) -> Result<Scene, SceneError> {
        let mut r = Reader {
            entries: self.entries,
            used: BTreeMap::new(),
        };
        let mut s = Scene::default();
        for key in SCHEMA {
            r.read(key, &mut s)?;
            if key.path == "fractal.algebra" {
                // The defaults follow the algebra; vectors given must have its length.
                s.set_algebra(s.fractal.algebra);
            }
        }
        r.reject_unknown()?;
        validate(&mut s, &r)?;
        Ok(s)
    }
}

/// Parses a `--set` value as TOML, or takes it as a plain string when it is not TOML.
fn parse_set_value(text: &str) -> Value {
    match format!("v = {text}\n").parse::<toml::Table>() {
        Ok(mut t) if t.len() == 1 => t.remove("v").unwrap_or_else(|| Value::String(text.into())),
        _ => Value::String(text.to_string()),
    }
}

/// One line for a TOML syntax error: the message and where.
fn describe_toml_error(text: &str, e: &toml::de::Error) -> String {
    let message = e.message().lines().next().unwrap_or("invalid TOML").trim();
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            format!("invalid TOML at line {line}, column {column}: {message}")
        }
        None => format!("invalid TOML: {message}"),
    }
}

impl Preset {
    /// The preset's scene, validated.
    pub fn scene(&self) -> Scene {
        let mut loader = SceneLoader::new();
        loader
            .toml_str(self.toml, SceneSource::Preset(self.slug.to_string()))
            .and_then(|()| loader.clone().build())
            .unwrap_or_else(|e| panic!("preset {:?} is invalid: {e}", self.name))
    }
}

/// Takes typed values out of the merged layers, remembering where each came from.
struct Reader {
    entries: BTreeMap<String, (Value, SceneSource)>,
    used: BTreeMap<&'static str, (Value, SceneSource)>,
}

impl Reader {
    /// Reads `key`'s value, where a layer gives one, into the scene.
    fn read(&mut self, key: &'static Key, s: &mut Scene) -> Result<(), SceneError> {
        let Some(entry) = self.entries.remove(key.path) else {
            return Ok(());
        };
        self.used.insert(key.path, entry.clone());
        let (v, src) = entry;
        parse(&key.kind, &v, s).map_err(|reason| SceneError::value(&src, key.path, &v, &reason))
    }

    /// The source of a key's final value, for checks made after reading.
    fn source_of(&self, key: &str) -> (Value, SceneSource) {
        self.used
            .get(key)
            .cloned()
            .unwrap_or((Value::String("(default)".into()), SceneSource::Default))
    }

    /// Whatever is left was not a scene key.
    fn reject_unknown(&self) -> Result<(), SceneError> {
        let Some((key, (_, src))) = self.entries.iter().next() else {
            return Ok(());
        };
        let tables: Vec<&str> = KEYS
            .iter()
            .filter_map(|k| k.split_once('.'))
            .map(|(t, _)| t)
            .collect();
        let message = if tables.contains(&key.as_str()) {
            format!("{key} must be a table")
        } else if let Some(leaf) = KEYS.iter().find(|k| key.starts_with(&format!("{k}."))) {
            format!("{leaf} is not a table, so {key} is an unknown key")
        } else {
            format!("unknown key {key}")
        };
        Err(SceneError::key(src, key, message))
    }
}

/// Reads one value of the kind into the scene, or says why it is not one (the reason of a
/// one-line error).
fn parse(kind: &Kind, v: &Value, s: &mut Scene) -> Result<(), String> {
    match *kind {
        Kind::Float { at, .. } => {
            let x = number(v).ok_or("must be a number")?;
            if !x.is_finite() {
                return Err("must be finite".into());
            }
            *(at.get_mut)(s) = x;
        }
        Kind::Integer { at, min, max } => {
            let Value::Integer(i) = *v else {
                return Err("must be an integer".into());
            };
            if i < i64::from(min) || i > i64::from(max) {
                return Err(format!("must be in [{min}, {max}]"));
            }
            *(at.get_mut)(s) = i as u32;
        }
        Kind::Bool { at } => {
            *(at.get_mut)(s) = v.as_bool().ok_or("must be true or false")?;
        }
        Kind::Choice { names, set, .. } => {
            if !set(s, v.as_str().unwrap_or_default()) {
                let names: Vec<String> = names().iter().map(|n| format!("\"{n}\"")).collect();
                return Err(format!("must be one of {}", names.join(", ")));
            }
        }
        Kind::Vector { at, .. } | Kind::Hyper { at } => {
            // A fixed vector keeps its length; a number of the algebra has its dimension (the
            // scene's vectors already do: `set_algebra` ran).
            let len = (at.get)(s).len();
            let algebra = s.fractal.algebra;
            let shape = || match kind {
                Kind::Hyper { .. } if algebra != super::Algebra::Quaternion => format!(
                    "must be an array of {len} numbers (fractal.algebra is \"{}\")",
                    algebra.name()
                ),
                _ => format!("must be an array of {len} numbers"),
            };
            let items = v.as_array().ok_or_else(shape)?;
            if items.len() != len {
                return Err(format!("{}, not {}", shape(), items.len()));
            }
            for (slot, item) in (at.get_mut)(s).iter_mut().zip(items) {
                *slot = number(item).ok_or_else(shape)?;
                if !slot.is_finite() {
                    return Err("must be finite".into());
                }
            }
        }
    }
    Ok(())
}

/// Checks the scene's value of one kind against its range (after all layers are read).
fn check_range(kind: &Kind, s: &Scene) -> Result<(), String> {
    match *kind {
        Kind::Float { at, range } if !range.contains(*(at.get)(s)) => {
            Err(format!("must be {range}"))
        }
        Kind::Vector { at, each } if (at.get)(s).iter().any(|&x| !each.contains(x)) => {
            Err(format!("must have every component {each}"))
        }
        _ => Ok(()),
    }
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// How far from orthonormal a slice basis may be and still be re-orthonormalised.
pub const SLICE_ORTHONORMAL_TOLERANCE: f64 = 1e-3;

/// Range and consistency checks over the whole scene, once all layers are in.
fn validate(s: &mut Scene, r: &Reader) -> Result<(), SceneError> {
    // The camera's and the slice's checks blame the later-given of the keys involved.
    let latest = |keys: &[&str]| -> String {
        let rank = |src: &SceneSource| match src {
            SceneSource::Default => 0,
            SceneSource::Preset(_) => 1,
            SceneSource::File(_) => 2,
            SceneSource::Flag(_) => 3,
            SceneSource::Set(_) => 4,
        };
        keys.iter()
            .max_by_key(|k| rank(&r.source_of(k).1))
            .map(|k| k.to_string())
            .unwrap_or_default()
    };
    check_scene(s, latest).map_err(|(key, reason)| {
        let (v, src) = r.source_of(&key);
        SceneError::value(&src, &key, &v, &reason)
    })
}

/// The checks of [`validate`] on a scene, whatever its values came from: each key's range,
/// the camera, the cut's normal and the slice basis (which is re-orthonormalised). A failure is
/// (the key at fault, the reason); where several keys are involved, `blame` chooses among them.
fn check_scene(s: &mut Scene, blame: impl Fn(&[&str]) -> String) -> Result<(), (String, String)> {
    let fail = |key: &str, reason: &str| (key.to_string(), reason.to_string());
    // Each key's range, in the schema's order.
    for key in SCHEMA {
        check_range(&key.kind, s).map_err(|reason| fail(key.path, &reason))?;
    }

    let eye = glam::DVec3::from_array(s.camera.eye);
    let target = glam::DVec3::from_array(s.camera.target);
    let up = glam::DVec3::from_array(s.camera.up);
    let view = target - eye;
    if view.length() == 0.0 || !view.length().is_finite() {
        let key = blame(&["camera.eye", "camera.target"]);
        return Err(fail(
            &key,
            "must differ from the other of camera.eye, camera.target",
        ));
    }
    if up.length() == 0.0 {
        return Err(fail("camera.up", "must not be zero"));
    }
    if view.normalize().cross(up.normalize()).length() < 1e-6 {
        let key = blame(&["camera.up", "camera.eye", "camera.target"]);
        return Err(fail(
            &key,
            "makes camera.up parallel to camera.target - camera.eye",
        ));
    }

    // The cut's normal gives the plane its direction (normalised when read).
    if s.cut.normal.iter().all(|&v| v == 0.0) {
        return Err(fail("cut.normal", "must not be zero"));
    }

    // The slice basis: orthonormal, or within tolerance of it and then re-orthonormalised.
    let keys = ["slice.x", "slice.y", "slice.z"];
    let basis = [&s.slice.x, &s.slice.y, &s.slice.z];
    for i in 0..3 {
        for j in 0..=i {
            let expected = if i == j { 1.0 } else { 0.0 };
            if (super::dot(basis[i], basis[j]) - expected).abs() > SLICE_ORTHONORMAL_TOLERANCE {
                let key = blame(&keys[..=i]);
                return Err(fail(
                    &key,
                    "makes the slice basis (x, y, z) not orthonormal",
                ));
            }
        }
    }
    let [x, y, z] = super::orthonormalise(basis.map(|v| v.as_slice()))
        .ok_or_else(|| fail(&blame(&keys), "makes the slice basis degenerate"))?;
    (s.slice.x, s.slice.y, s.slice.z) = (x, y, z);
    Ok(())
}

/// The `[animation]` keys other than `keys`, for errors.
const ANIMATION_KEYS: &str = "frames, fps, path_radius and keys";

/// Reads the `[animation]` table's entries (every `animation.*` of the layers) against the
/// validated base scene: the frame count, frames per second, c's path radius and the
/// keyframes, each keyframe's values checked by applying them to the base scene, and every
/// frame's scene checked.
fn read_animation(
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
            let Some(key) = super::schema::key(path).filter(|_| animatable(path)) else {
                let why = match super::schema::key(path).map(|k| k.kind) {
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
            let value = super::schema::key(&key)
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

#[cfg(test)]
mod tests {
    use super::*;

    fn build(layers: &[&str]) -> Result<Scene, SceneError> {
        let mut l = SceneLoader::new();
        for s in layers {
            l.set(s)?;
        }
        l.build()
    }

    #[test]
    fn defaults_round_trip_through_toml() {
        let s = Scene::default();
        let mut l = SceneLoader::new();
        l.toml_str(&s.to_toml(), SceneSource::File("x.toml".into()))
            .unwrap();
        assert_eq!(l.build().unwrap(), s);
    }

    #[test]
    fn set_overrides_and_bare_words() {
        let s = build(&[
            "fractal.c=[0,0,0,0]",
            "image.width=64",
            "shading.shadows=false",
        ])
        .unwrap();
        assert_eq!(s.fractal.c, [0.0; 4]);
        assert_eq!(s.image.width, 64);
        assert!(!s.shading.shadows);
        let e = build(&["image.width=wide"]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--set image.width=wide: image.width must be an integer"
        );
    }

    #[test]
    fn errors_name_source_and_key() {
        let e = build(&["fractal.epsilon=nan"]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--set fractal.epsilon=nan: fractal.epsilon must be finite"
        );
        let mut l = SceneLoader::new();
        l.toml_str(
            "[camera]\nfov_y_degrees = 190\n",
            SceneSource::File("scene.toml".into()),
        )
        .unwrap();
        assert_eq!(
            l.build().unwrap_err().to_string(),
            "scene.toml: camera.fov_y_degrees = 190: must be in (0, 180)"
        );
        let e = build(&["fractal.colour=1"]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("fractal.colour"));
        assert!(e.to_string().contains("unknown key fractal.colour"), "{e}");
        let e = build(&["fractal.c=[1,2,3]"]).unwrap_err();
        assert!(
            e.to_string()
                .contains("must be an array of 4 numbers, not 3"),
            "{e}"
        );
        let e = build(&["camera.eye=[0,0,0]"]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("camera.eye"));
        let e = build(&["camera.up=[0,0,2]"]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("camera.up"));
        let e = build(&["image.height=0"]).unwrap_err();
        assert!(e.to_string().contains("must be in [1, 65536]"), "{e}");
    }

    #[test]
    fn view2d_and_image_view_are_read_and_checked() {
        let s = build(&[
            "view2d.center=[-0.5, 0.25]",
            "view2d.extent=0.5",
            "view2d.max_iterations=1000",
            "image.view=divergence",
        ])
        .unwrap();
        assert_eq!(s.view2d.center, [-0.5, 0.25]);
        assert_eq!(s.view2d.extent, 0.5);
        assert_eq!(s.view2d.max_iterations, 1000);
        assert_eq!(s.image.view, super::super::View::Divergence);
        for (set, message) in [
            (
                "view2d.extent=0",
                "--set view2d.extent=0: view2d.extent must be > 0",
            ),
            ("view2d.extent=-2", "view2d.extent must be > 0"),
            ("view2d.extent=inf", "view2d.extent must be finite"),
            (
                "view2d.max_iterations=0",
                "view2d.max_iterations must be in [1, 100000]",
            ),
            (
                "view2d.max_iterations=100001",
                "view2d.max_iterations must be in [1, 100000]",
            ),
            (
                "view2d.center=[1]",
                "view2d.center must be an array of 2 numbers, not 1",
            ),
            ("view2d.center=[0, nan]", "view2d.center must be finite"),
            (
                "image.view=normals",
                "image.view must be one of \"shaded\", \"steps\", \"divergence\"",
            ),
        ] {
            let e = build(&[set]).unwrap_err();
            assert!(e.to_string().contains(message), "{set}: {e}");
            assert_eq!(e.key.as_deref(), set.split('=').next(), "{set}");
        }
    }

    #[test]
    fn slice_basis_is_reorthonormalised_within_tolerance_only() {
        let s = build(&["slice.x=[1.0004,0,0,0]"]).unwrap();
        assert_eq!(s.slice.x, [1.0, 0.0, 0.0, 0.0]);
        let e = build(&["slice.y=[0.1,1,0,0]"]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("slice.y"));
    }

    #[test]
    fn later_layers_win() {
        let mut l = SceneLoader::new();
        l.toml_str(
            "[image]\nwidth = 10\nheight = 20\n",
            SceneSource::File("a.toml".into()),
        )
        .unwrap();
        l.flag("image.width", Value::Integer(30), "--width 30");
        l.set("image.width=40").unwrap();
        let s = l.build().unwrap();
        assert_eq!((s.image.width, s.image.height), (40, 20));
    }
}
