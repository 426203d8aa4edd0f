//! The menu bar (File, Presets, View) and the windows it opens: the file dialogs, whose choice
//! opens, saves or exports (a PNG, or a mesh at the resolution set beside "Export mesh…"), "Render animation…" (drawn by `timeline`), and the help window
//! listing the shortcuts.

use super::app::{ExplorerApp, Mode};
use super::file_dialog::{FileDialog, Outcome, Purpose};
use super::input::SHORTCUTS;
use crate::scene::presets::PRESETS;

impl ExplorerApp {
    /// File (open, save, export), Presets, and View (mode, camera reset, help).
    pub(super) fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("Open scene…  (Ctrl+O)").clicked() {
                    self.open_dialog(Purpose::OpenScene);
                }
                if ui.button("Save scene…  (Ctrl+S)").clicked() {
                    self.open_dialog(Purpose::SaveScene);
                }
                if ui.button("Export PNG…  (Ctrl+E)").clicked() {
                    self.open_dialog(Purpose::ExportPng);
                }
                ui.horizontal(|ui| {
                    if ui.button("Export mesh…").clicked() {
                        self.open_dialog(Purpose::ExportMesh);
                    }
                    ui.add(
                        egui::DragValue::new(&mut self.mesh_resolution)
                            .range(crate::mesh::MIN_RESOLUTION..=crate::mesh::MAX_RESOLUTION)
                            .prefix("N = "),
                    )
                    .on_hover_text("grid points per axis of the mesh (qjulia mesh --resolution)");
                });
                if ui.button("Render animation…").clicked() {
                    self.timeline.render.open = true;
                }
            });
            ui.menu_button("Presets", |ui| {
                for preset in PRESETS {
                    if ui.button(preset.name).on_hover_text(preset.about).clicked() {
                        self.set_scene(preset.scene());
                        self.mode = if preset.two_d {
                            Mode::Julia2d
                        } else {
                            Mode::Slice3d
                        };
                        self.message = Some((format!("preset: {}", preset.name), false));
                    }
                }
            });
            ui.menu_button("View", |ui| {
                ui.radio_value(&mut self.mode, Mode::Slice3d, "3D slice");
                ui.radio_value(&mut self.mode, Mode::Julia2d, "2D Julia set  (M)");
                ui.separator();
                if ui.button("Reset camera  (R)").clicked() {
                    self.scene.camera = self.home_camera.clone();
                }
                if ui.button("Help  (F1)").clicked() {
                    self.show_help = true;
                }
            });
        });
    }

    /// Opens the file dialog for `purpose`, in the last folder used.
    pub(super) fn open_dialog(&mut self, purpose: Purpose) {
        let name = match purpose {
            Purpose::OpenScene => "",
            Purpose::SaveScene => "scene.toml",
            Purpose::ExportPng => "qjulia.png",
            Purpose::ExportMesh => "qjulia.ply",
        };
        self.dialog = Some(FileDialog::new(purpose, &self.last_dir, name));
    }

    /// The open file dialog, acting on its choice, and the help window.
    pub(super) fn dialogs(&mut self, ctx: &egui::Context) {
        if let Some(dialog) = &mut self.dialog {
            match dialog.show(ctx) {
                Outcome::Open => {}
                Outcome::Cancelled => self.dialog = None,
                Outcome::Chosen(path) => {
                    let purpose = dialog.purpose;
                    self.last_dir = dialog.dir().to_path_buf();
                    self.dialog = None;
                    match purpose {
                        Purpose::OpenScene => self.open(&path),
                        Purpose::SaveScene => self.save(&path),
                        Purpose::ExportPng => self.start_export(path),
                        Purpose::ExportMesh => self.start_mesh_export(path),
                    }
                }
            }
        }
        if self.show_help {
            egui::Window::new("Help")
                .open(&mut self.show_help)
                .show(ctx, |ui| {
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
}
