//! What outlives a frame of the explorer: the scene, the timeline's animation and the view's
//! resolution kept between runs in eframe's storage (eframe also keeps the window size), and
//! scene files (with their `[animation]`) opened and saved.

use std::path::Path;

use super::app::ExplorerApp;
use crate::animation::Animation;
use crate::scene::{Scene, SceneLoader, SceneSource};

/// Storage keys for what persists between runs.
const STORAGE_SCENE: &str = "qjulia-scene";
const STORAGE_RESOLUTION: &str = "qjulia-resolution-scale";
/// The timeline's scene file: its base scene and `[animation]`.
const STORAGE_TIMELINE: &str = "qjulia-timeline";

/// What the last run left: its scene (when it still loads) and the view's resolution scale.
pub fn load_persisted(storage: Option<&dyn eframe::Storage>) -> (Option<Scene>, f32) {
    let scene = storage
        .and_then(|s| eframe::get_value::<String>(s, STORAGE_SCENE))
        .and_then(|text| {
            let mut loader = SceneLoader::new();
            loader.toml_str(&text, SceneSource::Default).ok()?;
            loader.build().ok()
        });
    let resolution = storage
        .and_then(|s| eframe::get_value::<f32>(s, STORAGE_RESOLUTION))
        .unwrap_or(1.0)
        .clamp(0.25, 2.0);
    (scene, resolution)
}

/// The timeline the last run left (its base scene and animation), when it still loads.
pub fn load_persisted_timeline(
    storage: Option<&dyn eframe::Storage>,
) -> Option<(Scene, Animation)> {
    let text = eframe::get_value::<String>(storage?, STORAGE_TIMELINE)?;
    let mut loader = SceneLoader::new();
    loader.toml_str(&text, SceneSource::Default).ok()?;
    loader.build_animated().ok()
}

impl ExplorerApp {
    /// Keeps the scene and the resolution scale for the next run ([`load_persisted`]).
    pub(super) fn persist(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STORAGE_SCENE, &self.scene.to_toml());
        let timeline = self.timeline.file_text(&self.scene);
        eframe::set_value(storage, STORAGE_TIMELINE, &timeline);
        eframe::set_value(storage, STORAGE_RESOLUTION, &self.resolution_scale);
    }

    /// Loads a scene file, its `[animation]` into the timeline; on error the previous scene
    /// stays and the error is shown.
    pub fn open(&mut self, path: &Path) {
        let mut loader = SceneLoader::new();
        match loader.file(path).and_then(|()| loader.build_animated()) {
            Ok((scene, animation)) => {
                let keys = animation.keys.len();
                self.set_scene(scene.clone());
                self.timeline = super::timeline::Timeline::new(scene, animation);
                self.message = Some((
                    format!("opened {} ({keys} keyframes)", path.display()),
                    false,
                ));
            }
            Err(e) => self.message = Some((format!("error: {e}"), true)),
        }
    }

    /// Saves the scene as TOML with the timeline's `[animation]` (as `qjulia animate --scene`
    /// reads it), after checking that it reads back; a file it would refuse is not written.
    pub fn save(&mut self, path: &Path) {
        let text = match self.timeline.checked_file(&self.scene) {
            Ok((text, _, _)) => text,
            Err(e) => {
                self.message = Some((format!("error: not saved: {e}"), true));
                return;
            }
        };
        let result = std::fs::write(path, text);
        self.message = Some(match result {
            Ok(()) => (format!("saved {}", path.display()), false),
            Err(e) => (format!("error: {}: {e}", path.display()), true),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::presets::PRESETS;

    /// A storage in memory, like eframe's file storage.
    #[derive(Default)]
    struct Memory(std::collections::HashMap<String, String>);

    impl eframe::Storage for Memory {
        fn get_string(&self, key: &str) -> Option<String> {
            self.0.get(key).cloned()
        }
        fn set_string(&mut self, key: &str, value: String) {
            self.0.insert(key.to_string(), value);
        }
        fn remove_string(&mut self, key: &str) {
            self.0.remove(key);
        }
        fn flush(&mut self) {}
    }

    #[test]
    fn the_scene_and_resolution_persist_between_runs() {
        let mut scene = PRESETS[3].scene();
        scene.camera.eye = [0.25, 1.5, 2.0];
        let mut app = ExplorerApp::with_scene(scene.clone());
        app.resolution_scale = 0.5;
        let mut storage = Memory::default();
        eframe::App::save(&mut app, &mut storage);
        let (restored, resolution) = load_persisted(Some(&storage));
        assert_eq!(restored, Some(scene));
        assert_eq!(resolution, 0.5);
        assert_eq!(load_persisted(None), (None, 1.0));
    }

    #[test]
    fn scene_files_bring_their_keyframes_and_the_timeline_persists() {
        let mut app = ExplorerApp::with_scene(Scene::default());
        app.timeline.show(40, &mut app.scene);
        app.scene.camera.eye = [0.5, 1.0, 2.5];
        app.add_key();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("anim.toml");
        app.save(&path);
        let saved = app.timeline.animation.clone();
        assert_eq!(saved.keys.len(), 1);

        let mut other = ExplorerApp::with_scene(PRESETS[3].scene());
        other.open(&path);
        assert_eq!(other.timeline.animation, saved);
        assert_eq!(other.timeline.base, app.timeline.base);

        let mut storage = Memory::default();
        eframe::App::save(&mut app, &mut storage);
        let (base, animation) = load_persisted_timeline(Some(&storage)).expect("persisted");
        assert_eq!(animation, saved);
        assert_eq!(base, app.timeline.base);
    }
}
