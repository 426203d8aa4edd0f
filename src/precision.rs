//! Which float type a render runs in, and why: [`Precision`] (what runs), [`PrecisionChoice`]
//! (what `--precision auto|f32|f64` asks for), the typed [`Warning`]s of what a precision cannot
//! resolve, and the [`Decision`] between them. `auto` (the default) is f32 wherever f32
//! resolves the picture (no precision warning), and f64 otherwise. Which tracer then runs it is
//! [`crate::render::Planner`]'s, which takes this decision; its reason goes to `--stats` as
//! `precision_reason`.

use std::fmt;

use crate::algebra::Real;
use crate::grid::GridSpec;
use crate::picture::{Picture, Work};
use crate::scene::Scene;

/// The float type the tracer runs in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Precision {
    #[default]
    F32,
    F64,
}

impl Precision {
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }

    /// The precision [`Self::name`] calls `name`: f64 for "f64", f32 for anything else.
    pub fn of_name(name: &str) -> Self {
        match name {
            "f64" => Precision::F64,
            _ => Precision::F32,
        }
    }

    /// The relative spacing of its values that the precision warnings hold settings to
    /// ([`Real::RELATIVE_EPSILON`]: 8 ulps).
    pub fn relative_spacing(self) -> f64 {
        match self {
            Precision::F32 => f32::RELATIVE_EPSILON,
            Precision::F64 => f64::RELATIVE_EPSILON,
        }
    }

    /// The largest escape radius squared its iterations can square without overflow.
    fn escape_limit(self) -> f64 {
        match self {
            Precision::F32 => f32::ESCAPE_LIMIT,
            Precision::F64 => f64::ESCAPE_LIMIT,
        }
    }

    /// What a warning of this precision advises.
    fn remedy(self) -> &'static str {
        match self {
            Precision::F32 => "use --precision f64 (or auto)",
            Precision::F64 => "this is beyond f64 too",
        }
    }
}

/// What the user asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrecisionChoice {
    Auto,
    F32,
    F64,
}

/// What a precision cannot resolve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WarningKind {
    /// `fractal.epsilon` below the spacing of the floats where the rays work: hits are taken
    /// at the spacing instead.
    Epsilon,
    /// A 3D pixel's footprint at the target below the spacing: neighbouring pixels trace the
    /// same points.
    Pixel,
    /// `fractal.escape_radius_squared` beyond what the iterations can square: a limit is used.
    EscapeRadius,
    /// A 2D pixel (`view2d.extent / image.width`) below the spacing at the view's reach.
    Pixel2d,
    /// A mesh's grid cell below the spacing at the grid's reach.
    GridCell,
}

/// One thing a precision cannot resolve in a scene: its kind, and the line the user reads.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    pub kind: WarningKind,
    /// What falls short, e.g. "fractal.epsilon = 1e-9 is below the spacing of f32 values at
    /// distance 3.000 (2.9e-6)": `auto`'s reason for f64.
    pub shortfall: String,
    /// The whole line: the shortfall, what is done about it, and the remedy.
    pub text: String,
}

impl Warning {
    fn new(kind: WarningKind, shortfall: String, consequence: &str) -> Self {
        let text = format!("{shortfall}: {consequence}");
        Self {
            kind,
            shortfall,
            text,
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// The precision a picture is rendered in, and why (`precision_reason`).
#[derive(Clone, Debug, PartialEq)]
pub struct Decision {
    pub precision: Precision,
    pub reason: String,
}

/// What `precision` cannot resolve in this work on `scene` (empty: it is enough): for the 3D
/// slice its [`slice_warnings`]; for the 2D view its pixel against the spacing
/// ([`julia2d_warnings`]); for a mesh the slice's warnings but the pixel's, whose part the grid
/// cell plays ([`grid_warnings`]).
pub fn warnings(scene: &Scene, work: &Work, precision: Precision) -> Vec<Warning> {
    match work {
        Work::Picture(Picture::Slice { .. }) => slice_warnings(scene, precision),
        Work::Picture(Picture::Julia2d) => julia2d_warnings(scene, precision),
        Work::Mesh(grid) => {
            let mut all: Vec<Warning> = slice_warnings(scene, precision)
                .into_iter()
                .filter(|w| w.kind != WarningKind::Pixel)
                .collect();
            if let Some(grid) = grid {
                all.extend(grid_warnings(grid, precision));
            }
            all
        }
    }
}

/// What the user should know before a 3D render in this precision: settings the floats cannot
/// resolve (and what is done about it), each with the remedy.
pub fn slice_warnings(scene: &Scene, precision: Precision) -> Vec<Warning> {
    let name = precision.name();
    let remedy = precision.remedy();
    let f = &scene.fractal;
    let eye = glam::DVec3::from_array(scene.camera.eye);
    let target = glam::DVec3::from_array(scene.camera.target);
    // The largest coordinate the rays work with, and the float spacing there.
    let reach = eye.length().max(f.bounding_radius_squared.sqrt()).max(1.0);
    let spacing = reach * precision.relative_spacing();
    let mut warnings = Vec::new();
    if f.epsilon < spacing {
        warnings.push(Warning::new(
            WarningKind::Epsilon,
            format!(
                "fractal.epsilon = {:e} is below the spacing of {name} values at distance {reach:.3} ({spacing:.1e})",
                f.epsilon
            ),
            &format!("hits are taken there instead; {remedy}"),
        ));
    }
    let footprint =
        2.0 * (target - eye).length() * (scene.camera.fov_y_degrees.to_radians() * 0.5).tan()
            / scene.image.height as f64;
    if footprint < spacing {
        warnings.push(Warning::new(
            WarningKind::Pixel,
            format!(
                "a pixel spans {footprint:.1e} at the target, below the spacing of {name} values ({spacing:.1e})"
            ),
            &format!("neighbouring pixels trace the same points; {remedy}"),
        ));
    }
    let escape_limit = precision.escape_limit();
    if f.escape_radius_squared > escape_limit {
        warnings.push(Warning::new(
            WarningKind::EscapeRadius,
            format!(
                "fractal.escape_radius_squared = {:e} would overflow {name} iterations",
                f.escape_radius_squared
            ),
            &format!("{escape_limit:e} is used; {remedy}"),
        ));
    }
    warnings
}

/// The mesh's precision warnings: a grid cell below the spacing of the floats at the grid's
/// reach, where neighbouring grid points sample the same point.
pub fn grid_warnings(grid: &GridSpec, precision: Precision) -> Vec<Warning> {
    let cell = grid.cell();
    let spacing = grid.reach().max(1.0) * precision.relative_spacing();
    if cell < spacing {
        vec![Warning::new(
            WarningKind::GridCell,
            format!(
                "a grid cell spans {cell:.1e}, below the spacing of {} values ({spacing:.1e})",
                precision.name()
            ),
            "neighbouring grid points sample the same points",
        )]
    } else {
        Vec::new()
    }
}

/// The 2D view's precision warnings: a pixel (extent / width) below the spacing of the floats
/// at the view's farthest point from 0 (|centre| + half the extent, at least 1), where
/// neighbouring pixels iterate the same point.
pub fn julia2d_warnings(scene: &Scene, precision: Precision) -> Vec<Warning> {
    let v = &scene.view2d;
    let half = 0.5 * v.extent;
    let reach = (v.center[0].abs().max(v.center[1].abs()) + half).max(1.0);
    let spacing = reach * precision.relative_spacing();
    let pixel = v.extent / scene.image.width as f64;
    if pixel < spacing {
        let remedy = match precision {
            Precision::F32 => "use --precision f64",
            Precision::F64 => "this is beyond f64 too",
        };
        vec![Warning::new(
            WarningKind::Pixel2d,
            format!(
                "a pixel spans {pixel:.1e} (view2d.extent / image.width), below the spacing of {} values ({spacing:.1e})",
                precision.name()
            ),
            &format!("neighbouring pixels iterate the same points; {remedy}"),
        )]
    } else {
        Vec::new()
    }
}

/// The precision for `choice`: as asked, or (auto) f32 where it resolves the work and f64
/// where it does not, the first shortfall as the reason.
pub fn decide(choice: PrecisionChoice, scene: &Scene, work: &Work) -> Decision {
    let decision = |precision: Precision, reason: String| Decision { precision, reason };
    match choice {
        PrecisionChoice::F32 => decision(Precision::F32, "asked for (--precision f32)".into()),
        PrecisionChoice::F64 => decision(Precision::F64, "asked for (--precision f64)".into()),
        PrecisionChoice::Auto => match warnings(scene, work, Precision::F32).first() {
            None => decision(Precision::F32, "auto: f32 resolves the scene".into()),
            Some(shortfall) => decision(Precision::F64, format!("auto: {}", shortfall.shortfall)),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(sets: &[&str]) -> Scene {
        let mut loader = crate::scene::SceneLoader::new();
        for s in sets {
            loader.set(s).unwrap();
        }
        loader.build().unwrap()
    }

    #[test]
    fn auto_is_f32_where_f32_resolves_the_picture() {
        let d = decide(PrecisionChoice::Auto, &scene(&[]), &Picture::SHADED.into());
        assert_eq!(d.precision, Precision::F32);
        assert_eq!(d.reason, "auto: f32 resolves the scene");
        let d = decide(PrecisionChoice::Auto, &scene(&[]), &Picture::Julia2d.into());
        assert_eq!(d.precision, Precision::F32);
    }

    #[test]
    fn auto_is_f64_below_f32s_spacing_and_says_why() {
        let deep = scene(&["fractal.epsilon=1e-9"]);
        let d = decide(PrecisionChoice::Auto, &deep, &Picture::SHADED.into());
        assert_eq!(d.precision, Precision::F64);
        assert!(
            d.reason.starts_with("auto: fractal.epsilon = 1e-9"),
            "{}",
            d.reason
        );
        assert!(!d.reason.contains("use --precision"), "{}", d.reason);
        let deep2d = scene(&["view2d.extent=1e-9", "view2d.center=[-0.12, 0.75]"]);
        let d = decide(PrecisionChoice::Auto, &deep2d, &Picture::Julia2d.into());
        assert_eq!(d.precision, Precision::F64);
        assert!(d.reason.contains("a pixel spans"), "{}", d.reason);
        // Asked for: as asked, whatever the scene.
        let d = decide(PrecisionChoice::F32, &deep, &Picture::SHADED.into());
        assert_eq!(d.precision, Precision::F32);
        assert_eq!(d.reason, "asked for (--precision f32)");
    }

    #[test]
    fn the_2d_pixel_is_held_to_the_spacing_at_the_views_reach() {
        // 512 pixels over 4: a pixel of 7.8e-3, far above f32's spacing (8 ulps: 9.5e-7 at
        // reach 1, 1.9e-6 at reach 2).
        assert!(julia2d_warnings(&scene(&[]), Precision::F32).is_empty());
        // Over an extent of 1e-3 a pixel is 2.0e-6, above it; over 1e-4, 2.0e-7, below.
        let at = |extent: &str| scene(&[&format!("view2d.extent={extent}")]);
        assert!(julia2d_warnings(&at("1e-3"), Precision::F32).is_empty());
        assert_eq!(julia2d_warnings(&at("1e-4"), Precision::F32).len(), 1);
        assert!(julia2d_warnings(&at("1e-4"), Precision::F64).is_empty());
    }
}
