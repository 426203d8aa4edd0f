//! The menu bar (File, Presets, View) and the windows it opens: the file dialogs, whose choice
//! opens, saves or exports (a PNG, or a mesh at the resolution set beside "Export mesh…"), and
//! the help window listing the shortcuts ("Render animation…" is the timeline's window). What
//! they choose they return as [`Command`]s.

use std::path::PathBuf;

use super::command::Command;
use super::file_dialog::{FileDialog, Outcome, Purpose};
use super::input::SHORTCUTS;
use super::state::Mode;
use crate::scene::presets::PRESETS;

/// File (open, save, export), Presets, and View (mode, camera reset, help). Edits what the view
/// shows and the mesh export's resolution.
pub fn menu_bar(ui: &mut egui::Ui, mode: &mut Mode, mesh_resolution: &mut u32) -> Vec<Command> {
    let mut commands = Vec::new();
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            if ui.button("Open scene…  (Ctrl+O)").clicked() {
                commands.push(Command::OpenDialog(Purpose::OpenScene));
            }
            if ui.button("Save scene…  (Ctrl+S)").clicked() {
                commands.push(Command::OpenDialog(Purpose::SaveScene));
            }
            if ui.button("Export PNG…  (Ctrl+E)").clicked() {
                commands.push(Command::OpenDialog(Purpose::ExportPng));
            }
            ui.horizontal(|ui| {
                if ui.button("Export mesh…").clicked() {
                    commands.push(Command::OpenDialog(Purpose::ExportMesh));
                }
                ui.add(
                    egui::DragValue::new(mesh_resolution)
                        .range(crate::mesh::MIN_RESOLUTION..=crate::mesh::MAX_RESOLUTION)
                        .prefix("N = "),
                )
                .on_hover_text("grid points per axis of the mesh (qjulia mesh --resolution)");
            });
            if ui.button("Render animation…").clicked() {
                commands.push(Command::OpenRenderWindow);
            }
        });
        ui.menu_button("Presets", |ui| {
            for (k, preset) in PRESETS.iter().enumerate() {
                if ui.button(preset.name).on_hover_text(preset.about).clicked() {
                    commands.push(Command::Preset(k));
                }
            }
        });
        ui.menu_button("View", |ui| {
            ui.radio_value(mode, Mode::Slice3d, "3D slice");
            ui.radio_value(mode, Mode::Julia2d, "2D Julia set  (M)");
            ui.separator();
            if ui.button("Reset camera  (R)").clicked() {
                commands.push(Command::ResetCamera);
            }
            if ui.button("Help  (F1)").clicked() {
                commands.push(Command::ShowHelp);
            }
        });
    });
    commands
}

/// The file name a dialog for `purpose` proposes.
pub fn proposed_name(purpose: Purpose) -> &'static str {
    match purpose {
        Purpose::OpenScene | Purpose::OpenEnvironment => "",
        Purpose::SaveScene => "scene.toml",
        Purpose::ExportPng => "qjulia.png",
        Purpose::ExportMesh => "qjulia.ply",
    }
}

/// The open file dialog, if one is: closed when cancelled or chosen, the folder it was in then
/// the last folder, and its choice as the command of its purpose.
pub fn file_dialog(
    ctx: &egui::Context,
    dialog: &mut Option<FileDialog>,
    last_dir: &mut PathBuf,
) -> Option<Command> {
    let shown = dialog.as_mut()?;
    match shown.show(ctx) {
        Outcome::Open => None,
        Outcome::Cancelled => {
            *dialog = None;
            None
        }
        Outcome::Chosen(path) => {
            let purpose = shown.purpose;
            *last_dir = shown.dir().to_path_buf();
            *dialog = None;
            Some(match purpose {
                Purpose::OpenScene => Command::OpenScene(path),
                Purpose::SaveScene => Command::SaveScene(path),
                Purpose::ExportPng => Command::ExportPng(path),
                Purpose::ExportMesh => Command::ExportMesh(path),
                Purpose::OpenEnvironment => {
                    Command::SetEnvironment(path.to_string_lossy().into_owned())
                }
            })
        }
    }
}

/// The help window, while `open`: the shortcuts.
pub fn help_window(ctx: &egui::Context, open: &mut bool) {
    if *open {
        egui::Window::new("Help").open(open).show(ctx, |ui| {
            egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                for (keys, what) in SHORTCUTS {
                    ui.strong(*keys);
                    ui.label(*what);
                    ui.end_row();
                }
            });
        });
    }
}
