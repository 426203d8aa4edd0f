//! What outlives a run of the explorer: the scene, the timeline's animation and the view's
//! resolution kept between runs in eframe's storage (eframe also keeps the window size), and
//! scene files (with their `[animation]`) read and written.

use std::path::Path;

use super::state::ExplorerState;
use super::timeline::model::Timeline;
use crate::animation::Animation;
use crate::scene::{Scene, SceneError, SceneLoader, SceneSource};

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

/// Keeps the scene, the timeline and the resolution scale for the next run
/// ([`load_persisted`], [`load_persisted_timeline`]): what `eframe::App::save` writes.
pub fn persist(state: &mut ExplorerState, storage: &mut dyn eframe::Storage) {
    eframe::set_value(storage, STORAGE_SCENE, &state.scene.to_toml());
    let timeline = state.timeline.file_text(&state.scene);
    eframe::set_value(storage, STORAGE_TIMELINE, &timeline);
    eframe::set_value(storage, STORAGE_RESOLUTION, &state.resolution_scale);
}

/// A scene file and its `[animation]`, as `qjulia animate --scene` reads it; the loader's
/// error where it refuses it.
pub fn read_scene_file(path: &Path) -> Result<(Scene, Animation), SceneError> {
    let mut loader = SceneLoader::new();
    loader.file(path).and_then(|()| loader.build_animated())
}

/// Writes the scene `view` with the timeline's `[animation]` (as `qjulia animate --scene`
/// reads it) after checking that it reads back (a file it would refuse is not written); the
/// status line's word on it, and whether it is an error.
pub fn write_scene_file(timeline: &mut Timeline, view: &Scene, path: &Path) -> (String, bool) {
    let text = match timeline.checked_file(view) {
        Ok((text, _, _)) => text,
        Err(e) => return (format!("error: not saved: {e}"), true),
    };
    match std::fs::write(path, text) {
        Ok(()) => (format!("saved {}", path.display()), false),
        Err(e) => (format!("error: {}: {e}", path.display()), true),
    }
}

/// A storage in memory, like eframe's file storage (for the tests of what persists).
#[cfg(test)]
#[derive(Default)]
pub(super) struct Memory(pub std::collections::BTreeMap<String, String>);

#[cfg(test)]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The keys and their values' form stay those earlier runs wrote, so that they still load.
    #[test]
    fn the_stored_keys_are_those_of_earlier_runs() {
        let mut state = ExplorerState::with_scene(Scene::default());
        state.resolution_scale = 0.75;
        let mut storage = Memory::default();
        persist(&mut state, &mut storage);
        let keys: Vec<&str> = storage.0.keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            ["qjulia-resolution-scale", "qjulia-scene", "qjulia-timeline"]
        );
        assert_eq!(storage.0["qjulia-resolution-scale"], "0.75");
        let scene: String = eframe::get_value(&storage, STORAGE_SCENE).unwrap();
        assert_eq!(scene, Scene::default().to_toml());
    }
}
