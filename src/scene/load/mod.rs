//! Building a [`Scene`] from layers: built-in defaults, a preset, a scene file (TOML, or a PNG
//! or EXR written by qjulia), shorthand flags and `--set KEY=VALUE`, in that order of
//! precedence. Every key is checked once, after all layers, and every error names where the
//! offending value came from.
//!
//! This module owns the layers and when the checks run; reading each key's value by its kind,
//! the ranges and the whole scene's consistency are in `values.rs`. The `[animation]` table's
//! keys and keyframes are read in `animation.rs`, against the scene built here.

mod animation;
#[cfg(test)]
mod tests;
mod values;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use toml::Value;

use super::Scene;
use super::error::{SceneError, SceneSource};
use super::exr::scene_from_exr;
use super::limits::{SCENE_TEXT_LIMIT, SET_LIMIT};
use super::png::scene_from_png;
use super::presets::Preset;
use super::schema::{KEYS, Key, SCHEMA};
use crate::envmap::{load_source, resolve};
use crate::scene::animation::Animation;
use animation::read_animation;
use values::{check_scene, parse};

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

    /// Adds a scene file: TOML, or a PNG or OpenEXR file written by qjulia (its embedded
    /// scene), by the extension.
    pub fn file(&mut self, path: &Path) -> Result<(), SceneError> {
        let source = SceneSource::File(path.to_path_buf());
        let extension = |ext: &str| {
            path.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case(ext))
        };
        let text = if extension("png") {
            scene_from_png(path)?
        } else if extension("exr") {
            scene_from_exr(path)?
        } else {
            read_scene_text(path, &source)?
        };
        check_scene_length(&text, &source)?;
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
        if raw.len() > SET_LIMIT {
            // The message quotes its start only.
            let start: String = raw.chars().take(40).collect();
            return Err(SceneError::general(
                &SceneSource::Set(format!("{start}...")),
                format!(
                    "is {} bytes, more than a --set may be ({SET_LIMIT})",
                    raw.len()
                ),
            ));
        }
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
            // An empty inline table where a value belongs is kept, to be refused.
            Value::Table(table) if !table.is_empty() || is_table_name(key) => {
                self.insert_table(key, table, &source)
            }
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
                // A table with no keys (a template whose keys are commented out) sets nothing;
                // an empty table where a value belongs is kept, to be refused.
                Value::Table(_) if is_table_name(&key) => {}
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
        load_files(&mut s, &r)?;
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

/// A scene file's text, refused before it is read where it is longer than
/// [`SCENE_TEXT_LIMIT`].
fn read_scene_text(path: &Path, source: &SceneSource) -> Result<String, SceneError> {
    use std::io::Read;
    let cannot = |e: std::io::Error| SceneError::general(source, format!("cannot read: {e}"));
    let file = std::fs::File::open(path).map_err(cannot)?;
    let mut bytes = Vec::new();
    file.take(SCENE_TEXT_LIMIT as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() > SCENE_TEXT_LIMIT {
        return Err(too_long(source));
    }
    String::from_utf8(bytes).map_err(|_| {
        cannot(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        ))
    })
}

/// Scene text longer than [`SCENE_TEXT_LIMIT`] is refused.
pub fn check_scene_length(text: &str, source: &SceneSource) -> Result<(), SceneError> {
    if text.len() > SCENE_TEXT_LIMIT {
        return Err(too_long(source));
    }
    Ok(())
}

fn too_long(source: &SceneSource) -> SceneError {
    SceneError::general(
        source,
        format!("the scene is longer than a scene may be ({SCENE_TEXT_LIMIT} bytes)"),
    )
}

/// Whether `key` names a table of the scene file (`[animation]` included).
fn is_table_name(key: &str) -> bool {
    key == "animation" || super::TABLES.iter().any(|t| t.name == key)
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

/// Loads the files the path keys name (`environment.file`): a relative path resolves against
/// the folder of the scene file that gave it (then, for a PNG's or an EXR's scene, the current
/// directory), or the current directory where a flag or `--set` gave it. The checksum the scene
/// records is verified where it comes from the same layer as the file, or a later one: a file
/// given later (a `--set` over a PNG's scene) takes its own checksum.
fn load_files(s: &mut Scene, r: &Reader) -> Result<(), SceneError> {
    let (_, file_source) = r.source_of("environment.file");
    let (_, checksum_source) = r.source_of("environment.checksum");
    let bases = match &file_source {
        SceneSource::File(path) => super::loaded::bases_of_file(path),
        _ => Vec::new(),
    };
    let verify = rank(&checksum_source) >= rank(&file_source);
    s.load_environment(&bases, verify).map_err(|(key, reason)| {
        let (v, src) = r.source_of(key);
        SceneError::value(&src, key, &v, &reason)
    })
}

impl Scene {
    /// Loads the map `environment.file` names (none where it is empty), a relative path
    /// resolved against each folder of `bases` in turn (the current directory where `bases` is
    /// empty); a checksum the scene records (`environment.checksum`, not 0) must be the
    /// file's where `verify` (else the file's is recorded). The reason, and the key at fault,
    /// where it cannot be used.
    pub fn load_environment(
        &mut self,
        bases: &[PathBuf],
        verify: bool,
    ) -> Result<(), (&'static str, String)> {
        if self.environment.file.is_empty() {
            self.loaded.environment = None;
            self.environment.checksum = 0;
            return Ok(());
        }
        let source = resolve(&self.environment.file, bases).map_err(|e| ("environment.file", e))?;
        let data = load_source(&source).map_err(|e| ("environment.file", e))?;
        let recorded = self.environment.checksum;
        if verify && recorded != 0 && recorded != data.checksum {
            return Err((
                "environment.checksum",
                format!(
                    "is {recorded}, but {source}'s CRC-32 is {}: the map is not the one the \
                     scene was rendered with",
                    data.checksum
                ),
            ));
        }
        self.environment.checksum = data.checksum;
        self.loaded.environment = Some(data);
        Ok(())
    }
}

/// How late a layer comes: defaults, presets, scene files, flags, `--set`.
fn rank(source: &SceneSource) -> u8 {
    match source {
        SceneSource::Default => 0,
        SceneSource::Preset(_) => 1,
        SceneSource::File(_) => 2,
        SceneSource::Flag(_) => 3,
        SceneSource::Set(_) => 4,
    }
}

/// Range and consistency checks over the whole scene, once all layers are in.
fn validate(s: &mut Scene, r: &Reader) -> Result<(), SceneError> {
    // The camera's and the slice's checks blame the later-given of the keys involved.
    let latest = |keys: &[&str]| -> String {
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
