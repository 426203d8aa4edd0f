//! One key's value read into a scene and checked against its range, and the checks over a
//! whole scene: what the loader (`mod.rs`) and the `[animation]` table's reader
//! (`animation.rs`) both use, in a module of its own so that neither imports the other.

use toml::Value;

use crate::scene::schema::{Kind, SCHEMA};
use crate::scene::{Algebra, Scene, dot, orthonormalise};

/// Reads one value of the kind into the scene, or says why it is not one (the reason of a
/// one-line error).
pub(super) fn parse(kind: &Kind, v: &Value, s: &mut Scene) -> Result<(), String> {
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
        Kind::Path { at } => {
            let text = v.as_str().ok_or("must be a string: a file's path")?;
            if text.contains('\0') {
                return Err("must not hold a NUL".into());
            }
            *(at.get_mut)(s) = text.to_string();
        }
        Kind::Vector {
            at, splat: true, ..
        } if number(v).is_some() => {
            // One number for every component.
            let x = number(v).unwrap_or_default();
            if !x.is_finite() {
                return Err("must be finite".into());
            }
            (at.get_mut)(s).fill(x);
        }
        Kind::Vector { at, .. } | Kind::Hyper { at } => {
            // A fixed vector keeps its length; a number of the algebra has its dimension (the
            // scene's vectors already do: `set_algebra` ran).
            let len = (at.get)(s).len();
            let algebra = s.fractal.algebra;
            let shape = || match kind {
                Kind::Hyper { .. } if algebra != Algebra::Quaternion => format!(
                    "must be an array of {len} numbers (fractal.algebra is \"{}\")",
                    algebra.name()
                ),
                Kind::Vector { splat: true, .. } => {
                    format!("must be a number or an array of {len} numbers")
                }
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
        Kind::Vector { at, each, .. } if (at.get)(s).iter().any(|&x| !each.contains(x)) => {
            Err(format!("must have every component {each}"))
        }
        _ => Ok(()),
    }
}

pub(super) fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// How far from orthonormal a slice basis may be and still be re-orthonormalised.
pub const SLICE_ORTHONORMAL_TOLERANCE: f64 = 1e-3;

/// How far from orthonormal a slice basis may be and be kept exactly as given: Gram-Schmidt's
/// own output is orthonormal to a few ulps, so a saved scene's slice loads back unchanged
/// (re-orthonormalising it would move it by an ulp each time).
pub const SLICE_EXACT_TOLERANCE: f64 = 1e-14;

/// The checks of the loader's `validate` on a scene, whatever its values came from: each key's
/// range, the camera, the cut's normal and the slice basis (which is re-orthonormalised). A
/// failure is (the key at fault, the reason); where several keys are involved, `blame` chooses
/// among them.
pub(super) fn check_scene(
    s: &mut Scene,
    blame: impl Fn(&[&str]) -> String,
) -> Result<(), (String, String)> {
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

    // A polygon aperture has at least three blades.
    if matches!(s.camera.blades, 1 | 2) {
        return Err(fail(
            "camera.blades",
            "must be 0 (round) or in [3, 16] (a polygon)",
        ));
    }

    // Directions, normalised when read: the cut's normal, the sky's up and the sun's direction.
    for (key, v) in [
        ("cut.normal", s.cut.normal),
        ("sky.up", s.sky.up),
        ("sun.direction", s.sun.direction),
    ] {
        if v.iter().all(|&x| x == 0.0) {
            return Err(fail(key, "must not be zero"));
        }
    }

    // The slice basis: orthonormal, or within tolerance of it and then re-orthonormalised.
    let keys = ["slice.x", "slice.y", "slice.z"];
    let basis = [&s.slice.x, &s.slice.y, &s.slice.z];
    let mut worst: f64 = 0.0;
    for i in 0..3 {
        for j in 0..=i {
            let expected = if i == j { 1.0 } else { 0.0 };
            let error = (dot(basis[i], basis[j]) - expected).abs();
            if error > SLICE_ORTHONORMAL_TOLERANCE {
                let key = blame(&keys[..=i]);
                return Err(fail(
                    &key,
                    "makes the slice basis (x, y, z) not orthonormal",
                ));
            }
            worst = worst.max(error);
        }
    }
    if worst <= SLICE_EXACT_TOLERANCE {
        return Ok(());
    }
    let [x, y, z] = orthonormalise(basis.map(|v| v.as_slice()))
        .ok_or_else(|| fail(&blame(&keys), "makes the slice basis degenerate"))?;
    (s.slice.x, s.slice.y, s.slice.z) = (x, y, z);
    Ok(())
}
