//! The side panel: every scene value as a control, in collapsing groups (the 2D view, fractal,
//! slice, animation, camera, light and shading, path tracing, cut, image), one slider per call.
//! Each group is a function of what it edits; what reaches further (a new algebra, Play) it
//! returns as a [`Command`]. The shading model switch (Phong or path traced) sits at the top of
//! the 3D view's controls; in path mode the "Path tracing" group shows the path tracer's keys
//! and the Phong-only keys are greyed out. The denoiser switch (none or à-trous) sits under it,
//! in either model, and the "Denoising" group holds the `[denoise]` keys, which the view applies
//! to the mean it keeps without tracing again; adaptive sampling's noise target follows it.
//!
//! The groups of the light, the shading, path tracing and denoising are `lighting.rs`; the
//! sliders of scene keys and the colour picker they share are `widgets.rs`.

mod lighting;
mod widgets;

use super::c_loop::CLoop;
use super::command::Command;
use super::hypersphere::{from_hyperspherical, hyperspherical, magnitude_and_direction};
use super::state::{ExplorerState, Mode, SliceRotation};
use crate::denoise::Denoiser;
use crate::scene::rotation::{axis_name, plane_name, planes};
use crate::scene::{Camera, Cut, Fractal, Image, ShadingModel, Slice, View, View2d};
use lighting::{adaptive_sampling, atmosphere, denoiser_switch, denoising, path_tracing, shading};
use widgets::{key_slider, key_slider_u32};

/// The side panel: what the view shows, then the groups of controls.
pub fn controls(ui: &mut egui::Ui, s: &mut ExplorerState) -> Vec<Command> {
    let mut commands = Vec::new();
    egui::ScrollArea::vertical().show(ui, |ui| {
        ui.horizontal(|ui| {
            ui.label("Show");
            ui.selectable_value(&mut s.mode, Mode::Slice3d, "3D slice");
            ui.selectable_value(&mut s.mode, Mode::Julia2d, "2D Julia set");
        });
        match s.mode {
            Mode::Slice3d => {
                egui::ComboBox::from_label("view")
                    .selected_text(s.scene.image.view.name())
                    .show_ui(ui, |ui| {
                        for view in View::ALL {
                            ui.selectable_value(&mut s.scene.image.view, view, view.name());
                        }
                    });
                ui.horizontal(|ui| {
                    let model = &mut s.scene.shading.model;
                    ui.label("Lighting");
                    ui.selectable_value(model, ShadingModel::Phong, "Phong");
                    ui.selectable_value(model, ShadingModel::Path, "Path traced");
                });
                denoiser_switch(ui, &mut s.scene.image.denoise);
                adaptive_sampling(ui, &mut s.scene.path);
            }
            Mode::Julia2d => {
                egui::CollapsingHeader::new("2D view")
                    .default_open(true)
                    .show(ui, |ui| view2d(ui, &s.scene.fractal.c, &mut s.scene.view2d));
            }
        }
        egui::CollapsingHeader::new("Fractal")
            .default_open(true)
            .show(ui, |ui| commands.extend(fractal(ui, &mut s.scene.fractal)));
        egui::CollapsingHeader::new("Slice (4D)")
            .default_open(true)
            .show(ui, |ui| {
                let dim = s.scene.fractal.algebra.dim();
                slice(ui, &mut s.rotation, &mut s.scene.slice, dim)
            });
        egui::CollapsingHeader::new("Animation")
            .default_open(true)
            .show(ui, |ui| {
                let radius = &mut s.timeline.animation.path_radius;
                commands.extend(c_loop(ui, &mut s.c_loop, radius));
            });
        egui::CollapsingHeader::new("Camera")
            .show(ui, |ui| camera(ui, &mut s.scene.camera, &s.home_camera));
        egui::CollapsingHeader::new("Light and shading").show(ui, |ui| {
            shading(ui, &mut s.scene.light, &mut s.scene.shading)
        });
        if s.scene.shading.model == ShadingModel::Path {
            egui::CollapsingHeader::new("Path tracing")
                .default_open(true)
                .show(ui, |ui| path_tracing(ui, &mut s.scene));
        }
        egui::CollapsingHeader::new("Atmosphere")
            .show(ui, |ui| commands.extend(atmosphere(ui, &mut s.scene)));
        if s.mode == Mode::Slice3d && s.scene.image.denoise != Denoiser::None {
            egui::CollapsingHeader::new("Denoising")
                .default_open(true)
                .show(ui, |ui| denoising(ui, &mut s.scene.denoise));
        }
        egui::CollapsingHeader::new("Cut").show(ui, |ui| cut(ui, &mut s.scene.cut));
        egui::CollapsingHeader::new("Image").show(ui, |ui| {
            image(
                ui,
                &mut s.scene.image,
                &mut s.resolution_scale,
                &mut s.preview_samples,
            )
        });
    });
    commands
}

/// The algebra, c (by component, and as a magnitude and hyperspherical angles) and the
/// tracing values; a new algebra as a command.
fn fractal(ui: &mut egui::Ui, f: &mut Fractal) -> Option<Command> {
    let mut algebra = f.algebra;
    egui::ComboBox::from_label("algebra")
        .selected_text(algebra.name())
        .show_ui(ui, |ui| {
            for a in crate::scene::Algebra::ALL {
                ui.selectable_value(&mut algebra, a, a.name());
            }
        });
    let command = (algebra != f.algebra).then_some(Command::SetAlgebra(algebra));
    for k in 0..f.c.len() {
        let name = format!("c {}", axis_name(k));
        ui.add(key_slider(&mut f.c[k], "fractal.c").text(name));
    }
    // c as a direction on the unit sphere of the algebra and a magnitude.
    let (magnitude, direction) = magnitude_and_direction(&f.c);
    let mut angles = hyperspherical(&direction);
    let mut new_magnitude = magnitude;
    let mut turned = false;
    ui.add(
        egui::Slider::new(&mut new_magnitude, 0.0..=2.0)
            .clamping(egui::SliderClamping::Edits)
            .text("|c|"),
    );
    let last = angles.len() - 1;
    for (k, angle) in angles.iter_mut().enumerate() {
        let range = if k == last {
            -std::f64::consts::PI..=std::f64::consts::PI
        } else {
            0.0..=std::f64::consts::PI
        };
        turned |= ui
            .add(egui::Slider::new(angle, range).text(format!("c angle {}", k + 1)))
            .changed();
    }
    if turned || new_magnitude != magnitude {
        let dir = if turned {
            from_hyperspherical(&angles)
        } else {
            direction
        };
        f.c = dir.iter().map(|v| v * new_magnitude).collect();
    }
    ui.add(key_slider_u32(&mut f.max_iterations, "fractal.max_iterations").text("max iterations"));
    ui.add(key_slider(&mut f.epsilon, "fractal.epsilon").text("epsilon"));
    ui.add(
        key_slider(
            &mut f.escape_radius_squared,
            "fractal.escape_radius_squared",
        )
        .text("escape radius²"),
    );
    ui.add(
        key_slider(
            &mut f.bounding_radius_squared,
            "fractal.bounding_radius_squared",
        )
        .text("bounding radius²"),
    );
    ui.add(key_slider_u32(&mut f.max_steps, "fractal.max_steps").text("max steps"));
    ui.add(
        key_slider(&mut f.step_scale, "fractal.step_scale").text("step scale (over-relaxation)"),
    );
    ui.add(
        key_slider(&mut f.pixel_epsilon, "fractal.pixel_epsilon")
            .text("epsilon in pixels (0 = off)"),
    );
    egui::ComboBox::from_label("tracing")
        .selected_text(f.tracing.name())
        .show_ui(ui, |ui| {
            for tracing in crate::scene::Tracing::ALL {
                ui.selectable_value(&mut f.tracing, tracing, tracing.name());
            }
        });
    command
}

/// The 2D mode's view of c: centre, extent and iterations.
fn view2d(ui: &mut egui::Ui, c: &[f64], v: &mut View2d) {
    ui.label(format!("c = {:.4} {:+.4} i (c real, c i)", c[0], c[1]));
    let speed = 0.002 * v.extent;
    for (value, name) in v.center.iter_mut().zip(["centre real", "centre imaginary"]) {
        ui.horizontal(|ui| {
            let drag = ui.add(egui::DragValue::new(value).speed(speed));
            drag.labelled_by(ui.label(name).id);
        });
    }
    ui.add(key_slider(&mut v.extent, "view2d.extent").text("extent (width)"));
    ui.add(key_slider_u32(&mut v.max_iterations, "view2d.max_iterations").text("2D iterations"));
    ui.label("Drag to pan, wheel to zoom about the pointer.");
    if ui.button("Reset 2D view (R)").clicked() {
        *v = View2d::default();
    }
}

/// The slice: a rotation angle per plane of the `dim`-dimensional algebra, turning the
/// slice's axes, and the offset.
fn slice(ui: &mut egui::Ui, rotation: &mut SliceRotation, slice: &mut Slice, dim: usize) {
    let mut turned = false;
    let angles = &mut rotation.angles;
    egui::ScrollArea::vertical()
        .id_salt("rotation planes")
        .max_height(260.0)
        .show(ui, |ui| {
            for (angle, plane) in angles.iter_mut().zip(planes(dim)) {
                let slider = egui::Slider::new(angle, -std::f64::consts::PI..=std::f64::consts::PI);
                turned |= ui
                    .add(slider.text(format!("turn {}", plane_name(plane))))
                    .changed();
            }
        });
    if ui.button("Reset rotation").clicked() {
        rotation.angles.iter_mut().for_each(|a| *a = 0.0);
        turned = true;
    }
    if turned {
        rotation.apply(slice);
    }
    for k in 0..slice.offset.len() {
        let name = format!("offset {}", axis_name(k));
        ui.add(key_slider(&mut slice.offset[k], "slice.offset").text(name));
    }
}

/// Play or pause the c-loop (as a command), its speed and its path's size (the
/// timeline's `radius`).
fn c_loop(ui: &mut egui::Ui, c_loop: &mut CLoop, radius: &mut f64) -> Option<Command> {
    let mut command = None;
    ui.horizontal(|ui| {
        let label = if c_loop.playing { "Pause" } else { "Play" };
        if ui.button(label).clicked() {
            command = Some(Command::ToggleCLoop);
        }
        ui.label("c moves on a closed 4D path");
    });
    ui.add(
        egui::Slider::new(&mut c_loop.speed, 0.02..=3.0)
            .logarithmic(true)
            .text("speed (rad/s)"),
    );
    ui.add(
        egui::Slider::new(radius, 0.005..=0.5)
            .logarithmic(true)
            .clamping(egui::SliderClamping::Never)
            .text("path size"),
    );
    command
}

/// The field of view; eye and target as moved by the mouse; reset to `home`.
fn camera(ui: &mut egui::Ui, cam: &mut Camera, home: &Camera) {
    ui.add(key_slider(&mut cam.fov_y_degrees, "camera.fov_y_degrees").text("field of view (°)"));
    // The thin lens: blurs in the idle view's samples (the moving view's one sample takes one
    // point of the lens).
    ui.add(key_slider(&mut cam.aperture, "camera.aperture").text("aperture (lens radius)"));
    ui.add(key_slider(&mut cam.focus_distance, "camera.focus_distance").text("focus (0 = target)"));
    let blades = |n: u32| match n {
        0 => "round".to_string(),
        n => format!("{n} blades"),
    };
    egui::ComboBox::from_label("aperture shape")
        .selected_text(blades(cam.blades))
        .show_ui(ui, |ui| {
            for n in std::iter::once(0).chain(3..=16) {
                ui.selectable_value(&mut cam.blades, n, blades(n));
            }
        });
    ui.add(key_slider(&mut cam.blade_rotation, "camera.blade_rotation").text("blade rotation (°)"));
    ui.label(format!(
        "eye    {:.3} {:.3} {:.3}",
        cam.eye[0], cam.eye[1], cam.eye[2]
    ));
    ui.label(format!(
        "target {:.3} {:.3} {:.3}",
        cam.target[0], cam.target[1], cam.target[2]
    ));
    if ui.button("Reset camera (R)").clicked() {
        *cam = home.clone();
    }
}

/// The cut plane: on or off, its normal as two angles (so it is never zero) and its offset.
fn cut(ui: &mut egui::Ui, cut: &mut Cut) {
    ui.checkbox(&mut cut.enabled, "cut the set (n . p <= offset)");
    let (mut polar, mut azimuth) = normal_angles(cut.normal);
    let mut turned = ui
        .add(egui::Slider::new(&mut polar, 0.0..=180.0).text("normal from +z (°)"))
        .changed();
    turned |= ui
        .add(egui::Slider::new(&mut azimuth, -180.0..=180.0).text("normal about z (°)"))
        .changed();
    if turned {
        cut.normal = normal_from_angles(polar, azimuth);
    }
    ui.label(format!(
        "normal {:.3} {:.3} {:.3}",
        cut.normal[0], cut.normal[1], cut.normal[2]
    ));
    ui.add(key_slider(&mut cut.offset, "cut.offset").text("offset"));
}

/// The exported image's size and samples, and the view's resolution and samples.
fn image(
    ui: &mut egui::Ui,
    image: &mut Image,
    resolution_scale: &mut f32,
    preview_samples: &mut u32,
) {
    ui.label("Exported image (File > Export):");
    ui.add(key_slider_u32(&mut image.width, "image.width").text("width"));
    ui.add(key_slider_u32(&mut image.height, "image.height").text("height"));
    ui.add(key_slider_u32(&mut image.samples, "image.samples").text("samples per pixel (exports)"));
    ui.add(egui::Slider::new(resolution_scale, 0.25..=2.0).text("view resolution scale"));
    ui.add(
        egui::Slider::new(preview_samples, 1..=1024)
            .logarithmic(true)
            .text("preview samples (idle view)"),
    );
}

/// A cut normal (not zero) as its angle from +z and its azimuth about z from +x, in degrees.
fn normal_angles(n: [f64; 3]) -> (f64, f64) {
    let horizontal = n[0].hypot(n[1]);
    (
        horizontal.atan2(n[2]).to_degrees(),
        n[1].atan2(n[0]).to_degrees(),
    )
}

/// The unit normal at these angles (see [`normal_angles`]).
fn normal_from_angles(polar: f64, azimuth: f64) -> [f64; 3] {
    let (p, a) = (polar.to_radians(), azimuth.to_radians());
    [p.sin() * a.cos(), p.sin() * a.sin(), p.cos()]
}

#[cfg(test)]
mod tests {
    use super::lighting::{elevation_azimuth, from_elevation_azimuth};
    use super::*;

    #[test]
    fn cut_normal_angles_round_trip() {
        assert_eq!(normal_angles([0.0, 0.0, 2.0]), (0.0, 0.0));
        let n = normal_from_angles(90.0, 90.0);
        assert!(n[0].abs() < 1e-15 && (n[1] - 1.0).abs() < 1e-15 && n[2].abs() < 1e-15);
        for v in [[1.0, 2.0, 2.0], [-0.3, 0.1, -0.9], [0.0, -1.0, 0.0]] {
            let (p, a) = normal_angles(v);
            let n = normal_from_angles(p, a);
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            for k in 0..3 {
                assert!((n[k] - v[k] / len).abs() < 1e-12, "{v:?} -> {n:?}");
            }
        }
    }

    #[test]
    fn direction_angles_round_trip() {
        assert_eq!(elevation_azimuth([0.0, 1.0, 0.0]).0, 90.0);
        assert_eq!(elevation_azimuth([0.0, 0.0, 3.0]), (0.0, 0.0));
        assert_eq!(elevation_azimuth([1.0, 0.0, 0.0]), (0.0, 90.0));
        for v in [[2.0, 2.0, 3.0], [-1.0, 2.0, 1.0], [0.3, -0.8, -0.1]] {
            let (e, a) = elevation_azimuth(v);
            let n = from_elevation_azimuth(e, a);
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            for k in 0..3 {
                assert!((n[k] - v[k] / len).abs() < 1e-12, "{v:?} -> {n:?}");
            }
        }
    }
}
