//! `--precision auto|f32|f64`: which float type a render runs in, and why. `auto` (the default)
//! is f32 wherever f32 resolves the picture (no precision warning), and f64 otherwise: on the
//! GPU where the adapter has it, else on the CPU, with a notice; with `--backend gpu` on an
//! adapter without f64 it stays on the GPU in f32, with f32's warnings, since the GPU was asked
//! for. The reason goes to `--stats` as `precision_reason`.

use crate::error::{Error, Result};
use crate::render::{Backend, Picture, Precision, Renderer, precision_warnings};
use crate::scene::Scene;

/// What the user asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrecisionChoice {
    Auto,
    F32,
    F64,
}

/// The precision a picture is rendered in, and why (`precision_reason`).
#[derive(Clone, Debug, PartialEq)]
pub struct Decision {
    pub precision: Precision,
    pub reason: String,
}

/// What `precision` cannot resolve in this picture of `scene`, one line each with its remedy
/// (empty: it is enough): the 3D view's warnings ([`precision_warnings`]), the 2D view's pixel
/// against the spacing ([`julia2d_warnings`]), or for a mesh what the scene alone asks (its
/// grid cell plays the pixel's part: the caller adds [`mesh_warnings`]).
pub fn warnings(scene: &Scene, picture: Picture, precision: Precision) -> Vec<String> {
    match picture {
        Picture::Slice { .. } => precision_warnings(scene, precision),
        Picture::Julia2d => julia2d_warnings(scene, precision),
        Picture::Mesh => precision_warnings(scene, precision)
            .into_iter()
            .filter(|w| !w.starts_with("a pixel spans"))
            .collect(),
    }
}

/// The mesh's precision warnings for a grid cell of `cell` (slice units) around points as far
/// as `reach` from the origin: a cell below the spacing of the floats there, where neighbouring
/// grid points sample the same point.
pub fn mesh_warnings(cell: f64, reach: f64, precision: Precision) -> Vec<String> {
    let spacing = reach.max(1.0) * precision.relative_spacing();
    if cell < spacing {
        vec![format!(
            "a grid cell spans {cell:.1e}, below the spacing of {} values ({spacing:.1e}): neighbouring grid points sample the same points",
            precision.name()
        )]
    } else {
        Vec::new()
    }
}

/// The 2D view's precision warnings: a pixel (extent / width) below the spacing of the floats
/// at the view's farthest point from 0 (|centre| + half the extent, at least 1), where
/// neighbouring pixels iterate the same point.
pub fn julia2d_warnings(scene: &Scene, precision: Precision) -> Vec<String> {
    let v = &scene.view2d;
    let half = 0.5 * v.extent;
    let reach = (v.center[0].abs().max(v.center[1].abs()) + half).max(1.0);
    let spacing = reach * precision.relative_spacing();
    let pixel = v.extent / scene.image.width as f64;
    if pixel < spacing {
        vec![format!(
            "a pixel spans {pixel:.1e} (view2d.extent / image.width), below the spacing of {} values ({spacing:.1e}): neighbouring pixels iterate the same points; {}",
            precision.name(),
            match precision {
                Precision::F32 => "use --precision f64",
                Precision::F64 => "this is beyond f64 too",
            }
        )]
    } else {
        Vec::new()
    }
}

/// The precision for `choice`: as asked, or (auto) f32 where it resolves the picture and f64
/// where it does not, the first shortfall as the reason.
pub fn decide(choice: PrecisionChoice, scene: &Scene, picture: Picture) -> Decision {
    decide_by(choice, &warnings(scene, picture, Precision::F32))
}

/// [`decide`], given what f32 cannot resolve (`f32_shortfalls`, one line each).
pub fn decide_by(choice: PrecisionChoice, f32_shortfalls: &[String]) -> Decision {
    match choice {
        PrecisionChoice::F32 => Decision {
            precision: Precision::F32,
            reason: "asked for (--precision f32)".into(),
        },
        PrecisionChoice::F64 => Decision {
            precision: Precision::F64,
            reason: "asked for (--precision f64)".into(),
        },
        PrecisionChoice::Auto => match f32_shortfalls.first() {
            None => Decision {
                precision: Precision::F32,
                reason: "auto: f32 resolves the scene".into(),
            },
            Some(shortfall) => Decision {
                precision: Precision::F64,
                // The warning up to its consequence: what is below which spacing.
                reason: format!(
                    "auto: {}",
                    shortfall.split(": ").next().unwrap_or(shortfall)
                ),
            },
        },
    }
}

/// The renderer for a decision, and the decision as it stands: with `choice` auto and
/// `--backend gpu`, an adapter without f64 keeps the render on the GPU in f32 (`notice` says
/// so, and the reason records it); everything else is [`Renderer::choose`]'s.
pub fn choose_renderer(
    backend: Backend,
    choice: PrecisionChoice,
    decision: Decision,
    picture: Picture,
    notice: &mut dyn FnMut(&str),
) -> Result<(Renderer, Decision)> {
    let wants_f64 = decision.precision == Precision::F64;
    if !(wants_f64 && backend == Backend::Gpu && choice == PrecisionChoice::Auto) {
        let renderer = Renderer::choose(backend, decision.precision, picture, notice)?;
        return Ok((renderer, decision));
    }
    match Renderer::choose(Backend::Gpu, Precision::F64, picture, notice) {
        Ok(renderer) => Ok((renderer, decision)),
        Err(Error::Unsupported(why)) => {
            notice(&format!(
                "f64 would resolve this scene, but {why}; staying on the GPU in f32 as --backend gpu asks"
            ));
            let renderer = Renderer::choose(Backend::Gpu, Precision::F32, picture, notice)?;
            let reason = format!(
                "{}; the adapter has no f64, so f32 on the GPU (--backend gpu)",
                decision.reason
            );
            Ok((
                renderer,
                Decision {
                    precision: Precision::F32,
                    reason,
                },
            ))
        }
        Err(e) => Err(e),
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
        let d = decide(PrecisionChoice::Auto, &scene(&[]), Picture::SHADED);
        assert_eq!(d.precision, Precision::F32);
        assert_eq!(d.reason, "auto: f32 resolves the scene");
        let d = decide(PrecisionChoice::Auto, &scene(&[]), Picture::Julia2d);
        assert_eq!(d.precision, Precision::F32);
    }

    #[test]
    fn auto_is_f64_below_f32s_spacing_and_says_why() {
        let deep = scene(&["fractal.epsilon=1e-9"]);
        let d = decide(PrecisionChoice::Auto, &deep, Picture::SHADED);
        assert_eq!(d.precision, Precision::F64);
        assert!(
            d.reason.starts_with("auto: fractal.epsilon = 1e-9"),
            "{}",
            d.reason
        );
        assert!(!d.reason.contains("use --precision"), "{}", d.reason);
        let deep2d = scene(&["view2d.extent=1e-9", "view2d.center=[-0.12, 0.75]"]);
        let d = decide(PrecisionChoice::Auto, &deep2d, Picture::Julia2d);
        assert_eq!(d.precision, Precision::F64);
        assert!(d.reason.contains("a pixel spans"), "{}", d.reason);
        // Asked for: as asked, whatever the scene.
        let d = decide(PrecisionChoice::F32, &deep, Picture::SHADED);
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
