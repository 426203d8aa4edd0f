//! The scene schema as data (`qjulia schema --json`), for a host that loads and checks scenes
//! itself, the browser's (web/): every table and key of [`TABLES`] and [`SCHEMA`] with its
//! type, default, range, choices, book comment and slider, the reasons the loader gives for
//! values out of range (the error messages' form), and the presets, each with its TOML over
//! the defaults and the whole scene it makes. Written from the one declaration in
//! src/scene/mod.rs; web/src/generated/schema.json is this output, checked in, and a test fails
//! when it is stale.

use serde::Serialize;
use serde_json::{Value, json};

use super::{Bound, Key, Kind, Range, SCHEMA, TABLES};
use crate::scene::Scene;
use crate::scene::presets::PRESETS;

/// The version of this format: a reader refuses another.
pub const FORMAT: u32 = 1;

/// What `qjulia schema --json` prints.
#[derive(Clone, Debug, Serialize)]
pub struct SchemaJson {
    pub format: u32,
    /// The crate's version that wrote it.
    pub qjulia: &'static str,
    pub tables: Vec<Value>,
    pub keys: Vec<Value>,
    /// How the loader words a bad value: `{key}` is the dotted path, `{source}` where it came
    /// from (a file's path, `--set KEY=VALUE`), `{value}` the value as TOML, `{reason}` one of
    /// the key's reasons.
    pub messages: Value,
    pub presets: Vec<Value>,
}

impl SchemaJson {
    /// The schema of this build.
    pub fn new() -> Self {
        Self {
            format: FORMAT,
            qjulia: env!("CARGO_PKG_VERSION"),
            tables: TABLES
                .iter()
                .map(|t| json!({ "name": t.name, "readme": t.readme }))
                .collect(),
            keys: SCHEMA.iter().map(key).collect(),
            messages: json!({
                "from_file": "{source}: {key} = {value}: {reason}",
                "from_flag": "{source}: {key} {reason}",
                "unknown_key": "{source}: unknown key {key}",
                "not_a_number": "must be a number",
                "not_finite": "must be finite",
                "not_an_integer": "must be an integer",
                "not_a_bool": "must be true or false",
            }),
            presets: PRESETS
                .iter()
                .map(|p| {
                    json!({
                        "name": p.name,
                        "slug": p.slug,
                        "about": p.about,
                        "toml": p.toml,
                        "two_d": p.two_d,
                        "scene": p.scene().to_toml(),
                    })
                })
                .collect(),
        }
    }

    /// The schema as pretty JSON, with a final newline (the checked-in file's bytes).
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).expect("the schema serialises");
        text.push('\n');
        text
    }
}

impl Default for SchemaJson {
    fn default() -> Self {
        Self::new()
    }
}

/// One end of a range: `{"open": x}`, `{"closed": x}` or null.
fn bound(b: Bound) -> Value {
    match b {
        Bound::None => Value::Null,
        Bound::Open(x) => json!({ "open": x }),
        Bound::Closed(x) => json!({ "closed": x }),
    }
}

/// A range as data, and what follows "must be" in its error (`> 0`, `in [0, 1]`); null for any
/// finite number.
fn range(r: Range) -> Value {
    if r == Range::ANY {
        return Value::Null;
    }
    json!({ "min": bound(r.min), "max": bound(r.max), "must_be": r.to_string() })
}

/// One key: its path, type, default (the default scene's value), range, comment and slider.
fn key(k: &Key) -> Value {
    let default = serde_json::to_value(k.kind.value(&Scene::default())).expect("a TOML value");
    let readme = match k.kind.range_text() {
        Some(text) => k.readme.replace("{range}", &text),
        None => k.readme.to_string(),
    };
    let mut out = json!({
        "path": k.path,
        "table": k.table(),
        "name": k.leaf(),
        "default": default,
        "readme": readme,
        "slider": k.slider.map(|s| json!({
            "min": s.min,
            "max": s.max,
            "logarithmic": s.logarithmic,
        })),
    });
    let fields = out.as_object_mut().expect("an object");
    let mut put = |name: &str, v: Value| {
        fields.insert(name.into(), v);
    };
    match k.kind {
        Kind::Float { range: r, .. } => {
            put("type", "float".into());
            put("range", range(r));
        }
        Kind::Integer { min, max, .. } => {
            put("type", "integer".into());
            put("min", min.into());
            put("max", max.into());
            put("must_be", format!("in [{min}, {max}]").into());
        }
        Kind::Bool { .. } => put("type", "bool".into()),
        Kind::Choice { names, .. } => {
            put("type", "choice".into());
            put("choices", names().into());
            let quoted: Vec<String> = names().iter().map(|n| format!("\"{n}\"")).collect();
            put("must_be", format!("one of {}", quoted.join(", ")).into());
        }
        Kind::Vector { at, each, splat } => {
            put("type", "vector".into());
            put("length", (at.get)(&Scene::default()).len().into());
            put("each", range(each));
            if splat {
                put("splat", true.into());
            }
        }
        Kind::Hyper { .. } => {
            put("type", "hyper".into());
            put("length_from", "fractal.algebra".into());
        }
        Kind::Path { .. } => {
            put("type", "path".into());
            put("must_be", "a file's path (a string; \"\" for none)".into());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_and_preset_is_in_the_schema() {
        let schema = SchemaJson::new();
        assert_eq!(schema.keys.len(), SCHEMA.len());
        assert_eq!(schema.presets.len(), PRESETS.len());
        let epsilon = schema
            .keys
            .iter()
            .find(|k| k["path"] == "fractal.epsilon")
            .expect("fractal.epsilon");
        assert_eq!(epsilon["type"], "float");
        assert_eq!(epsilon["range"]["must_be"], "> 0");
        assert_eq!(epsilon["default"], Scene::default().fractal.epsilon);
        let samples = schema
            .keys
            .iter()
            .find(|k| k["path"] == "image.samples")
            .expect("image.samples");
        assert_eq!(samples["must_be"], "in [1, 4096]");
        let model = schema
            .keys
            .iter()
            .find(|k| k["path"] == "shading.model")
            .unwrap();
        assert_eq!(model["must_be"], "one of \"phong\", \"path\"");
    }
}
