//! A file dialog drawn in egui: no GTK or desktop portal needed, so the explorer builds and runs
//! on any machine. Lists a folder (folders first, then files with the wanted extensions),
//! navigates by click, and takes a typed name.

use std::path::{Path, PathBuf};

/// What the dialog is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// Open a scene: TOML, or a PNG written by qjulia.
    OpenScene,
    /// Save the scene as TOML.
    SaveScene,
    /// Export the image as PNG.
    ExportPng,
    /// Export the set's surface as a mesh (PLY, STL or OBJ).
    ExportMesh,
    /// Choose the environment map (OpenEXR or Radiance).
    OpenEnvironment,
}

impl Purpose {
    fn title(self) -> &'static str {
        match self {
            Purpose::OpenScene => "Open scene",
            Purpose::SaveScene => "Save scene",
            Purpose::ExportPng => "Export PNG",
            Purpose::ExportMesh => "Export mesh",
            Purpose::OpenEnvironment => "Choose environment map",
        }
    }

    fn extensions(self) -> &'static [&'static str] {
        match self {
            Purpose::OpenScene => &["toml", "png"],
            Purpose::SaveScene => &["toml"],
            Purpose::ExportPng => &["png"],
            Purpose::ExportMesh => &["ply", "stl", "obj"],
            Purpose::OpenEnvironment => &["exr", "hdr"],
        }
    }

    fn action(self) -> &'static str {
        match self {
            Purpose::OpenScene | Purpose::OpenEnvironment => "Open",
            Purpose::SaveScene | Purpose::ExportPng | Purpose::ExportMesh => "Save",
        }
    }
}

/// The outcome of one frame of the dialog.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    Open,
    Cancelled,
    Chosen(PathBuf),
}

pub struct FileDialog {
    pub purpose: Purpose,
    dir: PathBuf,
    name: String,
    entries: Vec<(String, bool)>,
    error: Option<String>,
}

impl FileDialog {
    pub fn new(purpose: Purpose, dir: &Path, name: &str) -> Self {
        let mut dialog = Self {
            purpose,
            dir: dir.to_path_buf(),
            name: name.to_string(),
            entries: Vec::new(),
            error: None,
        };
        dialog.refresh();
        dialog
    }

    /// The folder shown.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn refresh(&mut self) {
        self.entries.clear();
        match std::fs::read_dir(&self.dir) {
            Ok(read) => {
                for entry in read.flatten() {
                    let name = entry.file_name().to_string_lossy().into_owned();
                    if name.starts_with('.') {
                        continue;
                    }
                    let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
                    let wanted = Path::new(&name)
                        .extension()
                        .and_then(|e| e.to_str())
                        .is_some_and(|e| {
                            self.purpose
                                .extensions()
                                .contains(&e.to_lowercase().as_str())
                        });
                    if is_dir || wanted {
                        self.entries.push((name, is_dir));
                    }
                }
                self.entries
                    .sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
                self.error = None;
            }
            Err(e) => self.error = Some(format!("{}: {e}", self.dir.display())),
        }
    }

    fn enter(&mut self, dir: PathBuf) {
        self.dir = dir;
        self.refresh();
    }

    /// The path the typed name means: relative names are in the shown folder, and the
    /// purpose's extension is added when there is none.
    pub fn chosen_path(&self) -> PathBuf {
        let mut path = self.dir.join(self.name.trim());
        if path.extension().is_none() {
            path.set_extension(self.purpose.extensions()[0]);
        }
        path
    }

    /// Draws the dialog; returns what the user did this frame.
    pub fn show(&mut self, ctx: &egui::Context) -> Outcome {
        let mut outcome = Outcome::Open;
        let mut open = true;
        egui::Window::new(self.purpose.title())
            .collapsible(false)
            .resizable(true)
            .default_size([460.0, 380.0])
            .open(&mut open)
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    if ui.button("Up").clicked()
                        && let Some(parent) = self.dir.parent()
                    {
                        self.enter(parent.to_path_buf());
                    }
                    ui.label(self.dir.display().to_string());
                });
                ui.separator();
                let mut enter = None;
                egui::ScrollArea::vertical()
                    .max_height(240.0)
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        for (name, is_dir) in &self.entries {
                            let label = if *is_dir {
                                format!("{name}/")
                            } else {
                                name.clone()
                            };
                            let selected = !*is_dir && *name == self.name;
                            let response = ui.selectable_label(selected, label);
                            if response.clicked() {
                                if *is_dir {
                                    enter = Some(self.dir.join(name));
                                } else {
                                    self.name = name.clone();
                                }
                            }
                            if response.double_clicked() && !*is_dir {
                                outcome = Outcome::Chosen(self.dir.join(name));
                            }
                        }
                    });
                if let Some(dir) = enter {
                    self.enter(dir);
                }
                if let Some(e) = &self.error {
                    ui.colored_label(ui.visuals().error_fg_color, e);
                }
                ui.separator();
                ui.horizontal(|ui| {
                    ui.label("File name:");
                    let edit = ui.text_edit_singleline(&mut self.name);
                    if edit.lost_focus()
                        && ui.input(|i| i.key_pressed(egui::Key::Enter))
                        && !self.name.trim().is_empty()
                    {
                        outcome = Outcome::Chosen(self.chosen_path());
                    }
                });
                ui.horizontal(|ui| {
                    let ok = ui.add_enabled(
                        !self.name.trim().is_empty(),
                        egui::Button::new(self.purpose.action()),
                    );
                    if ok.clicked() {
                        outcome = Outcome::Chosen(self.chosen_path());
                    }
                    if ui.button("Cancel").clicked() {
                        outcome = Outcome::Cancelled;
                    }
                });
            });
        if !open {
            outcome = Outcome::Cancelled;
        }
        outcome
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chosen_path_adds_the_extension_and_lists_only_wanted_files() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.toml"), "").unwrap();
        std::fs::write(dir.path().join("b.txt"), "").unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let d = FileDialog::new(Purpose::SaveScene, dir.path(), "mine");
        assert_eq!(d.chosen_path(), dir.path().join("mine.toml"));
        assert_eq!(
            d.entries,
            vec![("sub".to_string(), true), ("a.toml".to_string(), false)]
        );
    }
}
