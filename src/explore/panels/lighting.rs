//! The side panel's groups of the light and the shading (the Phong-only keys greyed out in
//! path mode), path tracing (display, material, sky, sun, paths), the denoiser switch and its
//! `[denoise]` keys, adaptive sampling, and the atmosphere (the environment map, fog and glow);
//! with the direction and colour controls they use.

use super::widgets::{colour_edit, key_slider, key_slider_u32};
use crate::denoise::Denoiser;
use crate::display::ToneMap;
use crate::explore::command::Command;
use crate::explore::file_dialog::Purpose;
use crate::scene::{
    Denoise, Image, Light, Material, Path, PathSampler, Scene, Shading, ShadingModel, Sky, Sun,
};

/// The light and the shading values; in path mode the Phong-only ones greyed out.
pub(super) fn shading(ui: &mut egui::Ui, light: &mut Light, sh: &mut Shading) {
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
pub(super) fn path_tracing(ui: &mut egui::Ui, scene: &mut Scene) {
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

/// The atmosphere (docs/book/atmosphere.md): the environment map (a file picker, the built-in
/// map, none; its turn and intensity; phong mode's ambient light from it), the fog in either
/// model, phong mode's glow (greyed out in path mode). A new map is a command: the app loads it.
pub(super) fn atmosphere(ui: &mut egui::Ui, scene: &mut Scene) -> Option<Command> {
    let command = environment(ui, scene);
    ui.separator();
    let fog = &mut scene.fog;
    ui.add(key_slider(&mut fog.density, "fog.density").text("fog density (0 = none)"))
        .on_hover_text("extinction per unit length inside the bounding ball");
    ui.horizontal(|ui| {
        colour_edit(ui, &mut fog.colour);
        ui.label("fog colour (path mode: its albedo)");
    });
    ui.add(key_slider(&mut fog.anisotropy, "fog.anisotropy").text("fog anisotropy g (path)"))
        .on_hover_text("Henyey-Greenstein g: 0 isotropic, toward 1 forward (light shafts)");
    ui.separator();
    let phong = scene.shading.model == ShadingModel::Phong;
    if !phong {
        ui.label("Glow is phong only (path mode ignores it):");
    }
    let glow = &mut scene.glow;
    ui.add_enabled_ui(phong, |ui| {
        ui.add(key_slider(&mut glow.strength, "glow.strength").text("glow strength (0 = off)"));
        ui.add(key_slider(&mut glow.radius, "glow.radius").text("glow radius"));
        ui.horizontal(|ui| {
            colour_edit(ui, &mut glow.colour);
            ui.label("glow colour");
        });
    });
    command
}

/// `[environment]`: which map (chosen in the file dialog, the built-in one, or none), its turn
/// about `sky.up` and its intensity, and `shading.environment_light` (phong mode).
fn environment(ui: &mut egui::Ui, scene: &mut Scene) -> Option<Command> {
    let mut command = None;
    let env = &mut scene.environment;
    ui.horizontal(|ui| {
        ui.label("environment map:");
        match env.file.is_empty() {
            true => ui.weak("none"),
            false => ui.monospace(&env.file),
        };
    });
    ui.horizontal(|ui| {
        if ui.button("Choose…").clicked() {
            command = Some(Command::OpenDialog(Purpose::OpenEnvironment));
        }
        if ui.button("Built-in dusk").clicked() {
            command = Some(Command::SetEnvironment("qjulia:dusk.hdr".into()));
        }
        if ui
            .add_enabled(!env.file.is_empty(), egui::Button::new("None"))
            .clicked()
        {
            command = Some(Command::SetEnvironment(String::new()));
        }
    });
    let mapped = scene.loaded.environment.is_some();
    ui.add_enabled_ui(mapped, |ui| {
        ui.add(
            key_slider(&mut env.rotation_degrees, "environment.rotation_degrees")
                .text("map rotation (°)"),
        );
        ui.add(key_slider(&mut env.intensity, "environment.intensity").text("map intensity"));
        let phong = scene.shading.model == ShadingModel::Phong;
        ui.add_enabled(
            phong,
            egui::Checkbox::new(
                &mut scene.shading.environment_light,
                "ambient light from the map (phong)",
            ),
        );
    });
    command
}

/// `image.denoise`: the denoiser the view and the exports run, in either model.
pub(super) fn denoiser_switch(ui: &mut egui::Ui, denoise: &mut Denoiser) {
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
pub(super) fn adaptive_sampling(ui: &mut egui::Ui, path: &mut Path) {
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
pub(super) fn denoising(ui: &mut egui::Ui, d: &mut Denoise) {
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
    linear_colour(ui, &mut m.emission, "emission (x albedo)");
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

/// A direction's elevation above the y = 0 plane and azimuth about +y (from +z toward +x), in
/// degrees.
pub(super) fn elevation_azimuth(v: [f64; 3]) -> (f64, f64) {
    let horizontal = v[0].hypot(v[2]);
    (
        v[1].atan2(horizontal).to_degrees(),
        v[0].atan2(v[2]).to_degrees(),
    )
}

/// The unit direction at these angles (see [`elevation_azimuth`]).
pub(super) fn from_elevation_azimuth(elevation: f64, azimuth: f64) -> [f64; 3] {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    [e.cos() * a.sin(), e.sin(), e.cos() * a.cos()]
}
