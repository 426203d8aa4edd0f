//! The scene's keys, declared once. `scene_schema!` turns one declaration per key (its field,
//! type, default, kind and range, README comment and explorer slider) into the scene's structs,
//! their defaults and the tables [`SCHEMA`], [`TABLES`] and [`KEYS`] that loading, `--set`,
//! validation, the scene-file block of the book (docs/book/scene-file.md) and the explorer read.
//!
//! Adding a key is one entry in the declaration in `src/scene/mod.rs`, e.g. under `[light]`:
//!
//! ```text
//! /// The light's radius: 0 is a point light.
//! radius: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 1.0),
//!     "soft shadows' light radius, {range} (0 = a point light)";
//! ```
//!
//! plus its use; the test `book_scene_block_is_the_schemas` (in `book.rs`, which writes the
//! book's scene-file block from these tables) then prints the line to add to the block.

mod book;
pub mod json;

pub use super::{KEYS, SCHEMA, TABLES};
pub use book::readme_block;

use std::fmt;
use std::ops::RangeInclusive;

use toml::Value;

use super::Scene;

/// One leaf key of the scene file.
#[derive(Clone, Copy, Debug)]
pub struct Key {
    /// The dotted path, e.g. `fractal.epsilon`.
    pub path: &'static str,
    /// Its type and range, and where its value lives in a [`Scene`].
    pub kind: Kind,
    /// Its comment in the book's scene-file block; `{range}` stands for its range.
    pub readme: &'static str,
    /// The explorer's slider for it (for a vector: for each component), where it has one.
    pub slider: Option<Slider>,
}

impl Key {
    /// The table the key belongs to, e.g. `fractal`.
    pub fn table(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(t, _)| t)
    }

    /// The key's name within its table, e.g. `epsilon`.
    pub fn leaf(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(_, l)| l)
    }
}

/// One table of the scene file, e.g. `[fractal]`.
#[derive(Clone, Copy, Debug)]
pub struct Table {
    pub name: &'static str,
    /// Its comment in the book's scene-file block ("" for none).
    pub readme: &'static str,
}

/// Where a key's value lives in a [`Scene`].
pub struct At<T: ?Sized + 'static> {
    pub get: fn(&Scene) -> &T,
    pub get_mut: fn(&mut Scene) -> &mut T,
}

impl<T: ?Sized> Clone for At<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: ?Sized> Copy for At<T> {}

impl<T: ?Sized> fmt::Debug for At<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("At")
    }
}

/// A key's type, its range, and its field.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    /// A finite number (integers accepted).
    Float { at: At<f64>, range: Range },
    /// An integer in `[min, max]`.
    Integer { at: At<u32>, min: u32, max: u32 },
    /// `true` or `false`.
    Bool { at: At<bool> },
    /// One of a fixed set of names, e.g. `shading.normal = "analytic"`.
    Choice {
        /// Every name, in order.
        names: fn() -> Vec<&'static str>,
        /// The name of the scene's value.
        get: fn(&Scene) -> &'static str,
        /// Sets the value named; false when no value has that name.
        set: fn(&mut Scene, &str) -> bool,
    },
    /// Exactly as many finite numbers as the field holds, each within `each`; with `splat`,
    /// also one number, which every component takes (`material.emission = 2`).
    Vector {
        at: At<[f64]>,
        each: Range,
        splat: bool,
    },
    /// A number of the algebra: exactly `fractal.algebra`'s dimension of finite numbers.
    Hyper { at: At<[f64]> },
    /// A file's path, as written (a string; empty: none). A relative path resolves against the
    /// folder of the scene file that gives it (then, for a PNG's or an EXR's scene, the current
    /// directory), or against the current directory where `--set` gives it; `qjulia:NAME`
    /// names a file built into the binary.
    Path { at: At<String> },
}

impl Kind {
    /// The key's value in `scene`, as TOML.
    pub fn value(&self, scene: &Scene) -> Value {
        let floats = |v: &[f64]| Value::Array(v.iter().map(|&x| Value::Float(x)).collect());
        match *self {
            Kind::Float { at, .. } => Value::Float(*(at.get)(scene)),
            Kind::Integer { at, .. } => Value::Integer(i64::from(*(at.get)(scene))),
            Kind::Bool { at } => Value::Boolean(*(at.get)(scene)),
            Kind::Choice { get, .. } => Value::String(get(scene).to_string()),
            Kind::Vector { at, .. } | Kind::Hyper { at } => floats((at.get)(scene)),
            Kind::Path { at } => Value::String((at.get)(scene).clone()),
        }
    }

    /// The range as the book's scene-file block states it (`1..100000`, `> 0`,
    /// `components in [0, 1]`); None where the key has no range beyond its type.
    pub fn range_text(&self) -> Option<String> {
        match *self {
            Kind::Integer { min, max, .. } => Some(format!("{min}..{max}")),
            Kind::Float { range, .. } if range != Range::ANY => Some(range.to_string()),
            Kind::Vector { each, .. } if each != Range::ANY => Some(format!("components {each}")),
            _ => None,
        }
    }
}

/// The values a number may take: each end open, closed or absent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    pub min: Bound,
    pub max: Bound,
}

/// One end of a [`Range`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    None,
    Open(f64),
    Closed(f64),
}

impl Range {
    /// Any (finite) number.
    pub const ANY: Range = Range {
        min: Bound::None,
        max: Bound::None,
    };

    /// `> min`.
    pub const fn above(min: f64) -> Range {
        Range {
            min: Bound::Open(min),
            max: Bound::None,
        }
    }

    /// `>= min`.
    pub const fn at_least(min: f64) -> Range {
        Range {
            min: Bound::Closed(min),
            max: Bound::None,
        }
    }

    /// `(min, max)`.
    pub const fn open(min: f64, max: f64) -> Range {
        Range {
            min: Bound::Open(min),
            max: Bound::Open(max),
        }
    }

    /// `(min, max]`.
    pub const fn open_closed(min: f64, max: f64) -> Range {
        Range {
            min: Bound::Open(min),
            max: Bound::Closed(max),
        }
    }

    /// `[min, max]`.
    pub const fn closed(min: f64, max: f64) -> Range {
        Range {
            min: Bound::Closed(min),
            max: Bound::Closed(max),
        }
    }

    pub fn contains(self, x: f64) -> bool {
        let above = match self.min {
            Bound::None => true,
            Bound::Open(m) => x > m,
            Bound::Closed(m) => x >= m,
        };
        let below = match self.max {
            Bound::None => true,
            Bound::Open(m) => x < m,
            Bound::Closed(m) => x <= m,
        };
        above && below
    }
}

/// `> 0`, `>= 0`, `in (0, 2]`, ...: what follows "must be" in an error.
impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.min, self.max) {
            (Bound::None, Bound::None) => Ok(()),
            (Bound::Open(m), Bound::None) => write!(f, "> {m}"),
            (Bound::Closed(m), Bound::None) => write!(f, ">= {m}"),
            (Bound::None, Bound::Open(m)) => write!(f, "< {m}"),
            (Bound::None, Bound::Closed(m)) => write!(f, "<= {m}"),
            (Bound::Open(lo) | Bound::Closed(lo), Bound::Open(hi) | Bound::Closed(hi)) => {
                let open = if matches!(self.min, Bound::Open(_)) {
                    '('
                } else {
                    '['
                };
                let close = if matches!(self.max, Bound::Open(_)) {
                    ')'
                } else {
                    ']'
                };
                write!(f, "in {open}{lo}, {hi}{close}")
            }
        }
    }
}

/// The explorer's slider for a numeric key (for a vector: each component).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slider {
    pub min: f64,
    pub max: f64,
    pub logarithmic: bool,
}

impl Slider {
    pub fn range(self) -> RangeInclusive<f64> {
        self.min..=self.max
    }

    /// The range of an integer key's slider.
    pub fn range_u32(self) -> RangeInclusive<u32> {
        self.min as u32..=self.max as u32
    }
}

/// The key at `path`, e.g. `key("fractal.epsilon")`.
pub fn key(path: &str) -> Option<&'static Key> {
    SCHEMA.iter().find(|k| k.path == path)
}

/// The explorer's slider for the key at `path`, where it has one.
pub fn slider(path: &str) -> Option<Slider> {
    key(path)?.slider
}

/// Declares the scene: its tables (the structs in [`Scene`]'s fields, in file order) and their
/// keys, one line each:
///
/// ```text
/// /// doc comment
/// field: type = default, kind(args), [slider(min, max[, log]),] "README comment";
/// ```
///
/// Kinds: `float(range)` (an f64 field), `integer(min, max)` (u32), `boolean()`, `choice()`
/// (an enum with `ALL` and `name`), `vector()` / `vector(range of each component)` (an
/// `[f64; N]`), `hyper()` (a `Vec<f64>` as long as the algebra's dimension), `path()` (a
/// `String`: a file's path as written). Generates the structs (deriving `Clone, Debug,
/// PartialEq, Serialize`), their `Default`s, and the constants `TABLES`, `SCHEMA` and `KEYS`;
/// the scene also holds what its path keys' files load to ([`super::Loaded`]: not keys, not
/// written).
macro_rules! scene_schema {
    (
        $(#[$scene_meta:meta])*
        pub struct $Scene:ident {
            $(
                $(#[$table_meta:meta])*
                $table:ident: $Table:ident $table_readme:literal {
                    $(
                        $(#[$field_meta:meta])*
                        $field:ident: $ty:ty = $default:expr, $kind:ident($($arg:expr),*),
                        $(slider($($slider:tt)*),)? $readme:literal;
                    )*
                }
            )*
        }
    ) => {
        $(#[$scene_meta])*
        #[derive(Clone, Debug, PartialEq, serde::Serialize, Default)]
        pub struct $Scene {
            $(
                $(#[$table_meta])*
                pub $table: $Table,
            )*
            /// What the path keys' files hold, loaded (the environment map): set where the
            /// scene is built ([`SceneLoader`](crate::scene::SceneLoader)), never written.
            #[serde(skip)]
            pub loaded: $crate::scene::Loaded,
        }

        $(
            $(#[$table_meta])*
            #[derive(Clone, Debug, PartialEq, serde::Serialize)]
            pub struct $Table {
                $(
                    $(#[$field_meta])*
                    pub $field: $ty,
                )*
            }

            impl Default for $Table {
                fn default() -> Self {
                    Self {
                        $($field: $default,)*
                    }
                }
            }
        )*

        /// The scene file's tables, in order.
        pub const TABLES: &[$crate::scene::schema::Table] = &[
            $($crate::scene::schema::Table {
                name: stringify!($table),
                readme: $table_readme,
            },)*
        ];

        /// Every leaf key of the scene file, in order: its type, range, field, README comment
        /// and slider.
        pub const SCHEMA: &[$crate::scene::schema::Key] = &[
            $($($crate::scene::schema::Key {
                path: concat!(stringify!($table), ".", stringify!($field)),
                kind: $crate::scene::schema::scene_key_kind!(
                    $kind($($arg),*), $ty, $table.$field
                ),
                readme: $readme,
                slider: $crate::scene::schema::scene_key_slider!($($($slider)*)?),
            },)*)*
        ];

        /// Every leaf key of the scene file as a dotted path, in order.
        pub const KEYS: &[&str] = &[
            $($(concat!(stringify!($table), ".", stringify!($field)),)*)*
        ];
    };
}

/// One key's [`Kind`], for [`scene_schema!`].
macro_rules! scene_key_kind {
    (@at $table:ident . $field:ident) => {
        $crate::scene::schema::At {
            get: |s| &s.$table.$field,
            get_mut: |s| &mut s.$table.$field,
        }
    };
    (float($range:expr), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Float {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
            range: $range,
        }
    };
    (integer($min:expr, $max:expr), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Integer {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
            min: $min,
            max: $max,
        }
    };
    (boolean(), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Bool {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
        }
    };
    (choice(), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Choice {
            names: || <$ty>::ALL.iter().map(|c| c.name()).collect(),
            get: |s| s.$table.$field.name(),
            set: |s, name| match <$ty>::ALL.into_iter().find(|c| c.name() == name) {
                Some(c) => {
                    s.$table.$field = c;
                    true
                }
                None => false,
            },
        }
    };
    (vector(), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::scene_key_kind!(
            vector($crate::scene::schema::Range::ANY), $ty, $table.$field
        )
    };
    (vector($each:expr), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Vector {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
            each: $each,
            splat: false,
        }
    };
    (vector_or_number($each:expr), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Vector {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
            each: $each,
            splat: true,
        }
    };
    (path(), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Path {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
        }
    };
    (hyper(), $ty:ty, $table:ident . $field:ident) => {
        $crate::scene::schema::Kind::Hyper {
            at: $crate::scene::schema::scene_key_kind!(@at $table.$field),
        }
    };
}

/// One key's explorer [`Slider`], for [`scene_schema!`].
macro_rules! scene_key_slider {
    () => {
        None
    };
    ($min:expr, $max:expr, log) => {
        Some($crate::scene::schema::Slider {
            min: $min as f64,
            max: $max as f64,
            logarithmic: true,
        })
    };
    ($min:expr, $max:expr) => {
        Some($crate::scene::schema::Slider {
            min: $min as f64,
            max: $max as f64,
            logarithmic: false,
        })
    };
}

pub(crate) use {scene_key_kind, scene_key_slider, scene_schema};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_and_tables_follow_the_schema() {
        let paths: Vec<&str> = SCHEMA.iter().map(|k| k.path).collect();
        assert_eq!(paths, KEYS);
        let mut tables: Vec<&str> = SCHEMA.iter().map(Key::table).collect();
        tables.dedup();
        let names: Vec<&str> = TABLES.iter().map(|t| t.name).collect();
        assert_eq!(
            tables, names,
            "each table's keys together, in TABLES' order"
        );
        assert_eq!(
            key("fractal.epsilon").map(|k| k.path),
            Some("fractal.epsilon")
        );
        assert!(key("fractal.colour").is_none());
    }

    #[test]
    fn the_algebra_is_read_before_the_vectors_that_follow_it() {
        let algebra = KEYS.iter().position(|&k| k == "fractal.algebra").unwrap();
        for (i, key) in SCHEMA.iter().enumerate() {
            if matches!(key.kind, Kind::Hyper { .. }) {
                assert!(i > algebra, "{} comes before fractal.algebra", key.path);
            }
        }
    }

    /// A README comment states the key's range (through `{range}`) and every name of a choice.
    #[test]
    fn readme_comments_state_ranges_and_choices() {
        let defaults = Scene::default();
        for key in SCHEMA {
            assert_eq!(
                key.kind.range_text().is_some(),
                key.readme.contains("{range}"),
                "{}: {{range}} in its comment where (and only where) it has a range",
                key.path
            );
            if let Kind::Choice { names, .. } = key.kind {
                for name in names() {
                    assert!(
                        key.readme.contains(&format!("\"{name}\"")),
                        "{}: {name}",
                        key.path
                    );
                }
            }
            // The default is valid.
            if let Kind::Float { at, range } = key.kind {
                assert!(range.contains(*(at.get)(&defaults)), "{}", key.path);
            }
        }
    }

    #[test]
    fn sliders_stay_within_their_keys_ranges() {
        for key in SCHEMA {
            let Some(slider) = key.slider else { continue };
            assert!(slider.min < slider.max, "{}", key.path);
            let ok = |x: f64| match key.kind {
                Kind::Float { range, .. } => range.contains(x),
                Kind::Integer { min, max, .. } => {
                    x.fract() == 0.0 && (min..=max).contains(&(x as u32))
                }
                Kind::Vector { each, .. } => each.contains(x),
                Kind::Hyper { .. } => true,
                Kind::Bool { .. } | Kind::Choice { .. } | Kind::Path { .. } => false,
            };
            assert!(ok(slider.min) && ok(slider.max), "{}: {slider:?}", key.path);
        }
        let epsilon = slider("fractal.epsilon").unwrap();
        assert_eq!((epsilon.range(), epsilon.logarithmic), (1e-5..=0.1, true));
        assert_eq!(slider("image.width").unwrap().range_u32(), 1..=8192);
        assert_eq!(slider("camera.eye"), None);
    }

    #[test]
    fn ranges_read_as_the_errors_say_them() {
        assert_eq!(Range::above(0.0).to_string(), "> 0");
        assert_eq!(Range::at_least(0.0).to_string(), ">= 0");
        assert_eq!(Range::open(0.0, 180.0).to_string(), "in (0, 180)");
        assert_eq!(Range::open_closed(0.0, 2.0).to_string(), "in (0, 2]");
        assert_eq!(Range::closed(0.0, 1.0).to_string(), "in [0, 1]");
        assert!(!Range::open_closed(0.0, 2.0).contains(0.0));
        assert!(Range::open_closed(0.0, 2.0).contains(2.0));
    }
}
