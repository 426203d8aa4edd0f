//! Keys and mouse: the keyboard shortcuts (listed in the help window), and the mouse on the
//! view, moving the camera in 3D and panning and zooming the 2D view.

use egui::{Key, Modifiers};

use super::camera::{self, clamp_extent};
use super::command::Command;
use super::file_dialog::Purpose;
use super::state::Mode;
use crate::scene::{Camera, Scene, View2d};

/// The explorer's slider of a scene key, from the scene schema.
pub fn slider(path: &str) -> crate::scene::schema::Slider {
    crate::scene::schema::slider(path)
        .unwrap_or_else(|| panic!("the scene schema gives {path} no slider"))
}

/// The keyboard shortcuts, as the help window lists them.
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Left drag", "orbit the camera about its target"),
    ("Right or middle drag", "pan"),
    ("Wheel", "zoom"),
    ("Arrow keys", "orbit in steps (in 2D: pan)"),
    ("+ / -", "zoom in / out"),
    ("R", "reset the camera (in 2D: the 2D view)"),
    ("M", "switch between the 3D view and the 2D Julia set"),
    ("Space", "play / pause the animation of c"),
    ("Ctrl+O", "open a scene (TOML or a qjulia PNG)"),
    ("Ctrl+S", "save the scene as TOML"),
    ("Ctrl+E", "export a PNG"),
    ("F1", "this help"),
    (
        "Ctrl+Q",
        "quit (the scene and window size are kept for next time)",
    ),
];

/// The keyboard shortcuts, unless a text field has the keyboard: what the view shows
/// (`mode`), the camera of `scene` (back to `home` on R) or its 2D view; the rest as commands.
pub fn shortcuts(
    ctx: &egui::Context,
    mode: &mut Mode,
    scene: &mut Scene,
    home: &Camera,
) -> Vec<Command> {
    let mut commands = Vec::new();
    if ctx.egui_wants_keyboard_input() {
        return commands;
    }
    let cmd = Modifiers::COMMAND;
    let (open, save, export, quit) = ctx.input_mut(|i| {
        (
            i.consume_key(cmd, Key::O),
            i.consume_key(cmd, Key::S),
            i.consume_key(cmd, Key::E),
            i.consume_key(cmd, Key::Q),
        )
    });
    if quit {
        // eframe saves what persists (the scene, the window size) as the window closes.
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }
    if open {
        commands.push(Command::OpenDialog(Purpose::OpenScene));
    }
    if save {
        commands.push(Command::OpenDialog(Purpose::SaveScene));
    }
    if export {
        commands.push(Command::OpenDialog(Purpose::ExportPng));
    }
    ctx.input(|i| {
        if i.key_pressed(Key::M) {
            *mode = match *mode {
                Mode::Slice3d => Mode::Julia2d,
                Mode::Julia2d => Mode::Slice3d,
            };
        }
        if i.key_pressed(Key::F1) {
            commands.push(Command::ToggleHelp);
        }
        if i.key_pressed(Key::Space) {
            commands.push(Command::ToggleCLoop);
        }
        if *mode == Mode::Julia2d {
            let v = &mut scene.view2d;
            let step = 0.1 * v.extent;
            for (key, dx, dy) in [
                (Key::ArrowLeft, -step, 0.0),
                (Key::ArrowRight, step, 0.0),
                (Key::ArrowUp, 0.0, step),
                (Key::ArrowDown, 0.0, -step),
            ] {
                if i.key_pressed(key) {
                    v.center[0] += dx;
                    v.center[1] += dy;
                }
            }
            if i.key_pressed(Key::Plus) || i.key_pressed(Key::Equals) {
                v.extent = clamp_extent(v.extent * 0.8);
            }
            if i.key_pressed(Key::Minus) {
                v.extent = clamp_extent(v.extent / 0.8);
            }
            if i.key_pressed(Key::R) {
                *v = View2d::default();
            }
            return;
        }
        let cam = &mut scene.camera;
        let step = 0.1 * camera::orbit_scale(cam);
        if i.key_pressed(Key::ArrowLeft) {
            camera::orbit(cam, -step, 0.0);
        }
        if i.key_pressed(Key::ArrowRight) {
            camera::orbit(cam, step, 0.0);
        }
        if i.key_pressed(Key::ArrowUp) {
            camera::orbit(cam, 0.0, step);
        }
        if i.key_pressed(Key::ArrowDown) {
            camera::orbit(cam, 0.0, -step);
        }
        if i.key_pressed(Key::Plus) || i.key_pressed(Key::Equals) {
            camera::zoom(cam, 0.9);
        }
        if i.key_pressed(Key::Minus) {
            camera::zoom(cam, 1.0 / 0.9);
        }
        if i.key_pressed(Key::R) {
            *cam = home.clone();
        }
    });
    commands
}

/// The mouse on the 3D view (`rect`): left drag orbits, right or middle drag pans, the
/// wheel zooms.
pub fn mouse_3d(ui: &egui::Ui, rect: egui::Rect, response: &egui::Response, cam: &mut Camera) {
    if response.dragged_by(egui::PointerButton::Primary) {
        let d = response.drag_delta();
        camera::drag_orbit(cam, d.x as f64, d.y as f64);
    }
    if response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
    {
        let d = response.drag_delta();
        camera::drag_pan(cam, d.x as f64, d.y as f64, rect.height() as f64);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y) as f64;
        if scroll != 0.0 {
            camera::wheel_zoom(cam, scroll);
        }
    }
}

/// The mouse on the 2D view (`rect`): drag to pan, wheel to zoom about the pointer.
pub fn mouse_2d(ui: &egui::Ui, rect: egui::Rect, response: &egui::Response, v: &mut View2d) {
    let width = rect.width() as f64;
    if response.dragged() {
        let d = response.drag_delta();
        camera::drag_2d(v, d.x as f64, d.y as f64, width);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y) as f64;
        if scroll != 0.0 {
            let under = response.hover_pos().map(|p| {
                let d = p - rect.center();
                [d.x as f64, d.y as f64]
            });
            camera::wheel_zoom_2d(v, scroll, width, under);
        }
    }
}
