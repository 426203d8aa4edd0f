//! The side panel: every scene value as a control, in collapsing groups (the 2D view, fractal,
//! slice, animation, camera, light and shading, path tracing, cut, image), one slider per call.
//! Each group is a function of what it edits; what reaches further (a new algebra, Play) it
//! returns as a [`Command`]. The shading model switch (Phong or path traced) sits at the top of
//! the 3D view's controls; in path mode the "Path tracing" group shows the path tracer's keys
//! and the Phong-only keys are greyed out. The denoiser switch (none or à-trous) sits under it,
//! in either model, and the "Denoising" group holds the `[denoise]` keys, which the view applies
//! to the mean it keeps without tracing again; adaptive sampling's noise target follows it.

use super::c_loop::CLoop;
use super::command::Command;
use super::hypersphere::{from_hyperspherical, hyperspherical, magnitude_and_direction};
use super::input::slider;
use super::state::{ExplorerState, Mode, SliceRotation};
use crate::denoise::Denoiser;
use crate::display::ToneMap;
use crate::scene::rotation::{axis_name, plane_name, planes};
use crate::scene::{
    Camera, Cut, Denoise, Fractal, Image, Light, Material, Path, PathSampler, Scene, Shading,
    ShadingModel, Sky, Slice, Sun, View, View2d,
};

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

/// The light and the shading values; in path mode the Phong-only ones greyed out.
fn shading(ui: &mut egui::Ui, light: &mut Light, sh: &mut Shading) {
    for (k, name) in ["light x", "light y", "light z"].iter().enumerate() {
        ui.add(key_slider(&mut light.position[k], "light.position").text(*name));
    }
    ui.add(key_slider(&mut light.radius, "light.radius").text("light radius"));
    ui.horizontal(|ui| {
        colour_edit(ui, &mut sh.diffuse);
        ui.label("diffuse (path mode: the albedo)");
    });
    egui::ComboBox::from_label("normal")
        .selected_text(sh.normal.name())
        .show_ui(ui, |ui| {
            for method in crate::scene::NormalMethod::ALL {
                ui.selectable_value(&mut sh.normal, method, method.name());
            }
        });
    ui.add(key_slider(&mut sh.normal_delta, "shading.normal_delta").text("normal delta"));
    egui::ComboBox::from_label("colouring")
        .selected_text(sh.colouring.name())
        .show_ui(ui, |ui| {
            for colouring in crate::scene::Colouring::ALL {
                ui.selectable_value(&mut sh.colouring, colouring, colouring.name());
            }
        });
    ui.add(key_slider(&mut sh.trap_radius, "shading.trap_radius").text("trap radius"));
    ui.add(key_slider(&mut sh.trap_scale, "shading.trap_scale").text("trap scale"));
    for (k, name) in ["phase red", "phase green", "phase blue"]
        .iter()
        .enumerate()
    {
        ui.add(key_slider(&mut sh.palette_phase[k], "shading.palette_phase").text(*name));
    }
    ui.separator();
    let phong = sh.model == ShadingModel::Phong;
    if !phong {
        ui.label("Phong only (path mode ignores these):");
    }
    ui.add_enabled_ui(phong, |ui| phong_only(ui, sh));
}

/// The keys only Phong shading reads: shadows, the highlight, the background, ambient light
/// and occlusion.
fn phong_only(ui: &mut egui::Ui, sh: &mut Shading) {
    ui.checkbox(&mut sh.shadows, "shadows");
    ui.add(key_slider(&mut sh.shadow_factor, "shading.shadow_factor").text("shadow factor"));
    ui.horizontal(|ui| {
        colour_edit(ui, &mut sh.background);
        ui.label("background");
    });
    ui.add(key_slider(&mut sh.normal_tint, "shading.normal_tint").text("normal tint"));
    ui.add(key_slider(&mut sh.specular, "shading.specular").text("specular"));
    ui.add(key_slider(&mut sh.shininess, "shading.shininess").text("shininess"));
    ui.add(key_slider(&mut sh.ambient, "shading.ambient").text("ambient"));
    ui.add(key_slider(&mut sh.occlusion, "shading.occlusion").text("occlusion"));
}

/// Path mode's keys: the display transform (which the view applies without tracing again),
/// the material, the sphere light's intensity, the sky, the sun and the paths.
fn path_tracing(ui: &mut egui::Ui, scene: &mut Scene) {
    ui.label("Display (applied at once, no new trace):");
    display(ui, &mut scene.image);
    ui.separator();
    material(ui, &mut scene.material);
    ui.add(
        key_slider(&mut scene.light.intensity, "light.intensity")
            .text("light intensity (sphere light)"),
    );
    ui.separator();
    sky(ui, &mut scene.sky);
    ui.separator();
    sun(ui, &mut scene.sun);
    ui.separator();
    paths(ui, &mut scene.path);
}

/// `image.denoise`: the denoiser the view and the exports run, in either model.
fn denoiser_switch(ui: &mut egui::Ui, denoise: &mut Denoiser) {
    ui.horizontal(|ui| {
        ui.label("Denoiser");
        for denoiser in Denoiser::ALL {
            ui.selectable_value(denoise, denoiser, denoiser.name());
        }
    })
    .response
    .on_hover_text("the idle view shows the denoised running mean (docs/book/denoise.md)");
}

/// Adaptive sampling, in either model: `path.noise_target` (0: off) and, while it is on,
/// `path.min_samples`.
fn adaptive_sampling(ui: &mut egui::Ui, path: &mut Path) {
    ui.add(key_slider(&mut path.noise_target, "path.noise_target").text("noise target (0 = off)"))
        .on_hover_text(
            "adaptive sampling: a pixel stops once the standard error of its mean luminance, \
             relative to it, is at most this (docs/book/adaptive.md)",
        );
    if path.noise_target > 0.0 {
        ui.add(key_slider_u32(&mut path.min_samples, "path.min_samples").text("min samples"));
    }
}

/// The `[denoise]` keys: the view denoises the mean it keeps again, with no new trace.
fn denoising(ui: &mut egui::Ui, d: &mut Denoise) {
    ui.label("Applied to the kept mean at once, no new trace:");
    ui.add(key_slider_u32(&mut d.iterations, "denoise.iterations").text("denoiser passes"));
    ui.add(key_slider(&mut d.sigma_luminance, "denoise.sigma_luminance").text("sigma luminance"));
    ui.add(key_slider(&mut d.sigma_normal, "denoise.sigma_normal").text("sigma normal"));
    ui.add(key_slider(&mut d.sigma_depth, "denoise.sigma_depth").text("sigma depth"));
}

/// `image.exposure` and `image.tone_map`.
fn display(ui: &mut egui::Ui, image: &mut Image) {
    ui.add(key_slider(&mut image.exposure, "image.exposure").text("exposure (stops)"));
    egui::ComboBox::from_label("tone map")
        .selected_text(image.tone_map.name())
        .show_ui(ui, |ui| {
            for tone_map in ToneMap::ALL {
                ui.selectable_value(&mut image.tone_map, tone_map, tone_map.name());
            }
        });
}

/// `[material]`: Lambert plus GGX.
fn material(ui: &mut egui::Ui, m: &mut Material) {
    ui.add(key_slider(&mut m.roughness, "material.roughness").text("roughness"));
    ui.add(key_slider(&mut m.metallic, "material.metallic").text("metallic"));
    ui.add(key_slider(&mut m.specular, "material.specular").text("material specular (F0 / 0.08)"));
}

/// `[sky]`: its three colours, its up (as two angles) and its intensity.
fn sky(ui: &mut egui::Ui, sky: &mut Sky) {
    linear_colour(ui, &mut sky.zenith, "sky zenith");
    linear_colour(ui, &mut sky.horizon, "sky horizon");
    linear_colour(ui, &mut sky.ground, "sky ground");
    direction(ui, &mut sky.up, "sky up");
    ui.add(key_slider(&mut sky.intensity, "sky.intensity").text("sky intensity"));
}

/// `[sun]`: its direction (as two angles), size, colour and intensity.
fn sun(ui: &mut egui::Ui, sun: &mut Sun) {
    direction(ui, &mut sun.direction, "sun");
    ui.add(
        key_slider(
            &mut sun.angular_radius_degrees,
            "sun.angular_radius_degrees",
        )
        .text("sun angular radius (°)"),
    );
    linear_colour(ui, &mut sun.colour, "sun colour");
    ui.add(key_slider(&mut sun.intensity, "sun.intensity").text("sun intensity"));
}

/// `[path]`: bounces, the clamp and the sampler.
fn paths(ui: &mut egui::Ui, path: &mut Path) {
    ui.add(key_slider_u32(&mut path.bounces, "path.bounces").text("bounces"));
    ui.add(key_slider(&mut path.clamp, "path.clamp").text("clamp (0 = off)"));
    egui::ComboBox::from_label("sampler")
        .selected_text(path.sampler.name())
        .show_ui(ui, |ui| {
            for sampler in PathSampler::ALL {
                ui.selectable_value(&mut path.sampler, sampler, sampler.name());
            }
        });
}

/// A direction (not zero; its length is ignored) as its elevation above the y = 0 plane and
/// its azimuth about +y from +z toward +x, in degrees; written back only when moved.
fn direction(ui: &mut egui::Ui, v: &mut [f64; 3], name: &str) {
    let (mut elevation, mut azimuth) = elevation_azimuth(*v);
    let mut turned = ui
        .add(egui::Slider::new(&mut elevation, -90.0..=90.0).text(format!("{name} elevation (°)")))
        .changed();
    turned |= ui
        .add(egui::Slider::new(&mut azimuth, -180.0..=180.0).text(format!("{name} azimuth (°)")))
        .changed();
    if turned {
        *v = from_elevation_azimuth(elevation, azimuth);
    }
}

/// A linear colour of channels >= 0 (above 1 too): a picker for colours within [0, 1], and
/// each channel by value.
fn linear_colour(ui: &mut egui::Ui, colour: &mut [f64; 3], name: &str) {
    ui.horizontal(|ui| {
        colour_edit(ui, colour);
        let drags: Vec<egui::Response> = colour
            .iter_mut()
            .map(|c| {
                ui.add(
                    egui::DragValue::new(c)
                        .speed(0.005)
                        .range(0.0..=f64::INFINITY)
                        .max_decimals(3),
                )
            })
            .collect();
        let label = ui.label(name).id;
        for drag in drags {
            drag.labelled_by(label);
        }
    });
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

/// A direction's elevation above the y = 0 plane and azimuth about +y (from +z toward +x), in
/// degrees.
fn elevation_azimuth(v: [f64; 3]) -> (f64, f64) {
    let horizontal = v[0].hypot(v[2]);
    (
        v[1].atan2(horizontal).to_degrees(),
        v[0].atan2(v[2]).to_degrees(),
    )
}

/// The unit direction at these angles (see [`elevation_azimuth`]).
fn from_elevation_azimuth(elevation: f64, azimuth: f64) -> [f64; 3] {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    [e.cos() * a.sin(), e.sin(), e.cos() * a.cos()]
}

/// A colour picker for an `[f64; 3]` in [0, 1].
fn colour_edit(ui: &mut egui::Ui, colour: &mut [f64; 3]) {
    let mut rgb = colour.map(|c| c as f32);
    if ui.color_edit_button_rgb(&mut rgb).changed() {
        *colour = rgb.map(|c| (c as f64).clamp(0.0, 1.0));
    }
}

/// The slider of a float scene key: range and scale from the scene schema.
fn key_slider<'a>(value: &'a mut f64, path: &str) -> egui::Slider<'a> {
    let s = slider(path);
    egui::Slider::new(value, s.range())
        .logarithmic(s.logarithmic)
        .clamping(egui::SliderClamping::Edits)
}

/// The slider of an integer scene key: range and scale from the scene schema.
fn key_slider_u32<'a>(value: &'a mut u32, path: &str) -> egui::Slider<'a> {
    let s = slider(path);
    egui::Slider::new(value, s.range_u32())
        .logarithmic(s.logarithmic)
        .clamping(egui::SliderClamping::Edits)
}

#[cfg(test)]
mod tests {
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
