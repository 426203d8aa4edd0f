//! The explorer's camera controller: orbit about the target, zoom toward it, pan across the
//! view, and the 2D view's pan and zoom. Works on the scene's camera directly, so what the
//! explorer shows is what a saved scene renders. `up` never changes; the eye never reaches the
//! target or lines up with `up`. The pointer's moves become camera moves here too (`drag_orbit`,
//! `drag_pan`, `wheel_zoom`, `drag_2d`, `wheel_zoom_2d`), for the desktop explorer and for the
//! browser's, whose TypeScript twin (web/src/camera.ts) is held to these by
//! web/test/fixtures/camera.json.

use glam::{DQuat, DVec3};

use crate::scene::{Camera, View2d};

/// Radians of orbit per point dragged, and zoom per point scrolled (the wheel's points).
pub const ORBIT_PER_POINT: f64 = 0.01;
pub const ZOOM_PER_POINT: f64 = 0.002;

/// The narrowest 2D extent the mouse and keys zoom to: a pixel of 512 is then 2e-15, about
/// f64's spacing near the set (the view switches to f64 by itself below f32's).
pub const MIN_EXTENT: f64 = 1e-12;

/// Closest the eye may come to the target, and farthest it may go.
pub const MIN_DISTANCE: f64 = 1e-3;
pub const MAX_DISTANCE: f64 = 1e3;
/// Closest the view direction may come to `up` (or to -up), in radians.
const MIN_POLAR: f64 = 0.01;

fn v(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// Turns the eye about the target: `azimuth` about `up`, `elevation` toward `up` (radians).
pub fn orbit(cam: &mut Camera, azimuth: f64, elevation: f64) {
    let (eye, target, up) = (v(cam.eye), v(cam.target), v(cam.up).normalize());
    let offset = DQuat::from_axis_angle(up, azimuth) * (eye - target);
    // Angle between offset and up, kept inside (MIN_POLAR, pi - MIN_POLAR).
    let polar = offset.normalize().dot(up).clamp(-1.0, 1.0).acos();
    let new_polar = (polar - elevation).clamp(MIN_POLAR, std::f64::consts::PI - MIN_POLAR);
    let axis = up.cross(offset).normalize_or_zero();
    let offset = if axis == DVec3::ZERO {
        offset
    } else {
        DQuat::from_axis_angle(axis, new_polar - polar) * offset
    };
    cam.eye = (target + offset).to_array();
}

/// The field of view a zoom out widens back to before the eye moves away again: the default
/// camera's.
pub const WIDE_FOV_DEGREES: f64 = 45.0;
/// The narrowest field of view a zoom reaches: a pixel footprint near 1e-15 at distance 1e-3,
/// below what f64 resolves.
pub const MIN_FOV_DEGREES: f64 = 1e-10;

/// Zooms by `factor` (< 1: in, > 1: out): the eye moves toward or away from the target, and
/// once it is as close as it may come ([`MIN_DISTANCE`]) the field of view narrows instead, so
/// a zoom goes on, smoothly, to pixel footprints f64 barely resolves (1e-12 and below; the
/// view switches to f64 by itself). Zooming out widens the field of view back to
/// [`WIDE_FOV_DEGREES`] first, then moves the eye away.
pub fn zoom(cam: &mut Camera, factor: f64) {
    let (eye, target) = (v(cam.eye), v(cam.target));
    let offset = eye - target;
    let tan_half = |deg: f64| (deg.to_radians() * 0.5).tan();
    let mut factor = factor;
    let at_floor = offset.length() <= MIN_DISTANCE * (1.0 + 1e-9);
    if factor > 1.0 && at_floor && cam.fov_y_degrees < WIDE_FOV_DEGREES {
        // Out: the footprint (with tan(fov / 2)) grows by the factor, up to the wide view; the
        // rest of the factor moves the eye.
        let (now, wide) = (tan_half(cam.fov_y_degrees), tan_half(WIDE_FOV_DEGREES));
        let widened = (now * factor).min(wide);
        cam.fov_y_degrees = (2.0 * widened.atan()).to_degrees();
        factor *= now / widened;
    }
    let wanted = offset.length() * factor;
    let distance = wanted.clamp(MIN_DISTANCE, MAX_DISTANCE);
    cam.eye = (target + offset.normalize() * distance).to_array();
    if wanted < MIN_DISTANCE {
        // In, past the closest the eye comes: the rest narrows the view.
        let narrowed = tan_half(cam.fov_y_degrees) * wanted / MIN_DISTANCE;
        cam.fov_y_degrees = (2.0 * narrowed.atan()).to_degrees().max(MIN_FOV_DEGREES);
    }
}

/// How much slower the camera orbits at this field of view than at [`WIDE_FOV_DEGREES`], so
/// that a drag across a narrow (deep) view turns it by about a view, not by 1e10 views.
pub fn orbit_scale(cam: &Camera) -> f64 {
    let tan_half = |deg: f64| (deg.to_radians() * 0.5).tan();
    (tan_half(cam.fov_y_degrees) / tan_half(WIDE_FOV_DEGREES)).min(1.0)
}

/// Slides eye and target together across the view: `right` and `up` in units of the view's
/// height at the target's distance (so a drag across the whole view moves by one view height).
pub fn pan(cam: &mut Camera, right: f64, up: f64) {
    let (eye, target) = (v(cam.eye), v(cam.target));
    let forward = (target - eye).normalize();
    let r = forward.cross(v(cam.up)).normalize();
    let u = r.cross(forward);
    let height = 2.0 * (cam.fov_y_degrees.to_radians() * 0.5).tan() * (target - eye).length();
    let shift = (r * right + u * up) * height;
    cam.eye = (eye + shift).to_array();
    cam.target = (target + shift).to_array();
}

/// A drag of (dx, dy) points with the orbiting button: right turns the view left, down tilts it
/// up, slower in a narrow view ([`orbit_scale`]).
pub fn drag_orbit(cam: &mut Camera, dx: f64, dy: f64) {
    let rate = ORBIT_PER_POINT * orbit_scale(cam);
    orbit(cam, dx * rate, dy * rate);
}

/// A drag of (dx, dy) points with the panning button across a view `height` points high: the
/// scene follows the pointer.
pub fn drag_pan(cam: &mut Camera, dx: f64, dy: f64, height: f64) {
    let h = height.max(1.0);
    pan(cam, -dx / h, dy / h);
}

/// The wheel turned by `scroll` points (positive: away from the user, zooming in).
pub fn wheel_zoom(cam: &mut Camera, scroll: f64) {
    zoom(cam, (-scroll * ZOOM_PER_POINT).exp());
}

/// The 2D view's extent between [`MIN_EXTENT`] and its slider's widest.
pub fn clamp_extent(extent: f64) -> f64 {
    let widest = crate::scene::schema::slider("view2d.extent").expect("view2d.extent has a slider");
    extent.clamp(MIN_EXTENT, widest.max)
}

/// A drag of (dx, dy) points across the 2D view, `width` points wide (the extent spans it): the
/// plane follows the pointer.
pub fn drag_2d(v: &mut View2d, dx: f64, dy: f64, width: f64) {
    let per_point = v.extent / width.max(1.0);
    v.center[0] -= dx * per_point;
    v.center[1] += dy * per_point;
}

/// The wheel turned by `scroll` points over the 2D view, `width` points wide, with the pointer
/// `from_centre` points right of and below the view's centre (if over it): the point under the
/// pointer stays there.
pub fn wheel_zoom_2d(v: &mut View2d, scroll: f64, width: f64, from_centre: Option<[f64; 2]>) {
    let per_point = v.extent / width.max(1.0);
    let extent = clamp_extent(v.extent * (-scroll * ZOOM_PER_POINT).exp());
    let factor = extent / v.extent;
    if let Some([x, y]) = from_centre {
        let under = [v.center[0] + x * per_point, v.center[1] - y * per_point];
        for (centre, under) in v.center.iter_mut().zip(under) {
            *centre = under - (under - *centre) * factor;
        }
    }
    v.extent = extent;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distance(c: &Camera) -> f64 {
        (v(c.eye) - v(c.target)).length()
    }

    #[test]
    fn orbit_keeps_distance_and_never_aligns_with_up() {
        let mut cam = Camera::default();
        for step in 0..200 {
            orbit(&mut cam, 0.37, if step < 100 { 0.2 } else { -0.25 });
            assert!((distance(&cam) - 3.0).abs() < 1e-9);
            let dir = (v(cam.target) - v(cam.eye)).normalize();
            assert!(
                dir.cross(v(cam.up)).length() > 0.009,
                "view lines up with up at step {step}"
            );
        }
    }

    #[test]
    fn orbit_by_a_full_turn_returns() {
        let mut cam = Camera::default();
        orbit(&mut cam, std::f64::consts::TAU, 0.0);
        assert!((v(cam.eye) - v(Camera::default().eye)).length() < 1e-12);
        orbit(&mut cam, std::f64::consts::FRAC_PI_2, 0.0);
        // A quarter turn about +y takes the eye from +z to +x (drag right, view turns left).
        assert!(
            (v(cam.eye) - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-12,
            "{:?}",
            cam.eye
        );
    }

    #[test]
    fn zoom_is_bounded_and_keeps_direction() {
        let mut cam = Camera::default();
        zoom(&mut cam, 0.5);
        assert!((distance(&cam) - 1.5).abs() < 1e-12);
        for _ in 0..100 {
            zoom(&mut cam, 0.01);
        }
        assert!(distance(&cam) >= MIN_DISTANCE * 0.999);
        assert!(v(cam.eye).normalize().abs_diff_eq(DVec3::Z, 1e-12));
        for _ in 0..100 {
            zoom(&mut cam, 100.0);
        }
        assert!(distance(&cam) <= MAX_DISTANCE * 1.001);
    }

    #[test]
    fn zooming_in_goes_on_by_the_field_of_view_smoothly_and_back() {
        let mut cam = Camera::default();
        let footprint =
            |c: &Camera| 2.0 * distance(c) * (c.fov_y_degrees.to_radians() * 0.5).tan() / 512.0;
        let mut before = footprint(&cam);
        let mut steps = 0;
        while footprint(&cam) > 1e-12 {
            zoom(&mut cam, 0.9);
            let now = footprint(&cam);
            // Every step shrinks the footprint by the factor: no jump where the eye stops.
            assert!(
                (now / before - 0.9).abs() < 1e-6,
                "step {steps}: {before:e} to {now:e}"
            );
            before = now;
            steps += 1;
            assert!(steps < 1000, "a footprint of 1e-12 is within reach");
        }
        assert!(distance(&cam) >= MIN_DISTANCE * 0.999 && cam.fov_y_degrees < 1e-4);
        assert!(
            orbit_scale(&cam) < 1e-5,
            "orbiting slows down with the view"
        );
        // Back out: the field of view widens to the default, then the eye moves away.
        for _ in 0..steps + 20 {
            zoom(&mut cam, 1.0 / 0.9);
        }
        assert!((cam.fov_y_degrees - WIDE_FOV_DEGREES).abs() < 1e-9);
        assert!(distance(&cam) > 1.0);
        assert_eq!(orbit_scale(&cam), 1.0);
    }

    #[test]
    fn pan_moves_eye_and_target_together() {
        let mut cam = Camera::default();
        pan(&mut cam, 0.5, -0.25);
        let before = Camera::default();
        let view = |c: &Camera| v(c.target) - v(c.eye);
        assert!(view(&cam).abs_diff_eq(view(&before), 1e-12));
        let height = 2.0 * (22.5f64).to_radians().tan() * 3.0;
        assert!((cam.target[0] - 0.5 * height).abs() < 1e-12);
        assert!((cam.target[1] + 0.25 * height).abs() < 1e-12);
    }
}
