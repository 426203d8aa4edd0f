//! The timeline's model, with no egui in it: the scene's `[animation]` table (frame count,
//! frames per second, c's path radius, keyframes) as the explorer edits it. Keyframes are added
//! at the current frame from the view, moved and deleted; scrubbing and Play show
//! [`Animation::scene_at`] in the view; the scene file it saves ([`Timeline::checked_file`]) is
//! what `qjulia animate --scene FILE` renders. Its strip and window are `super::panel`'s, its
//! render job `super::job`'s.
//!
//! The timeline keeps the animation's base scene (the scene file's tables). The view shows the
//! base at a frame; what the user changes in the view goes back into the base when the timeline
//! next moves, saves or renders ([`Timeline::absorb`]), except the values the keyframes set,
//! which the tracks give, and c while no keyframe sets it and the user left it where the
//! timeline put it (c's closed loop is around the base's c).

use crate::animation::{Animation, FRAMES_MAX, FRAMES_MIN, Keyframe, get_value, scene_file};
use crate::scene::schema::{self, Kind};
use crate::scene::{Scene, SceneLoader, SceneSource, Slice};

/// The values a keyframe can take from the view: what the mouse and the panel's c and slice
/// controls change.
const VIEW_PATHS: [&str; 7] = [
    "camera.eye",
    "camera.target",
    "fractal.c",
    "slice.x",
    "slice.y",
    "slice.z",
    "slice.offset",
];

/// The slice's axes, which keyframes set together.
pub const AXES: [&str; 3] = ["slice.x", "slice.y", "slice.z"];

/// The animation being edited, and the frame shown.
pub struct Timeline {
    /// The animation: keys sorted by frame, frame numbers unique and below `frames`.
    pub animation: Animation,
    /// The scene the animation animates (the scene file's tables, `animate`'s base).
    pub base: Scene,
    /// The frame the timeline is at.
    pub frame: u32,
    /// The scene the timeline last put in the view, to tell the user's changes from its own.
    shown: Option<Scene>,
    /// Playing the animation in the view at its frames per second.
    pub playing: bool,
    /// While playing: the frame position, fractional, advanced by wall time.
    position: f64,
    /// The selected keyframe, by frame number.
    pub selected: Option<u32>,
}

impl Timeline {
    /// The timeline of `animation` over `base`, at frame 0.
    pub fn new(base: Scene, animation: Animation) -> Self {
        let mut timeline = Self {
            animation,
            base,
            frame: 0,
            shown: None,
            playing: false,
            position: 0.0,
            selected: None,
        };
        timeline.animation.keys.sort_by_key(|k| k.frame);
        timeline
    }

    /// A timeline restored over a view that already shows `view` (the timeline's own frame 0
    /// or a frame of it): c on its loop stays the loop's, not a new centre.
    pub fn restored(base: Scene, animation: Animation, view: &Scene) -> Self {
        let mut timeline = Self::new(base, animation);
        timeline.shown = Some(view.clone());
        timeline
    }

    /// The last frame's number.
    pub fn last_frame(&self) -> u32 {
        self.animation.frames.max(1) - 1
    }

    /// The keyframes' frame numbers, in order.
    pub fn key_frames(&self) -> Vec<u32> {
        self.animation.keys.iter().map(|k| k.frame).collect()
    }

    /// The keyframe at `frame`, if there is one.
    pub fn key(&self, frame: u32) -> Option<&Keyframe> {
        self.animation.keys.iter().find(|k| k.frame == frame)
    }

    /// Frame `frame`'s scene, as `qjulia animate` renders it.
    pub fn scene_at(&self, frame: u32) -> Scene {
        self.animation.scene_at(&self.base, frame)
    }

    /// Takes what the user changed in `view` into the base: every value of the view, except c
    /// when no keyframe sets it and the view's c is the one the timeline put there (so c's loop
    /// keeps its centre). The values keyframes set are the tracks' whatever the base holds.
    /// After a change of algebra the keys' numbers of the algebra are cut or padded to fit.
    pub fn absorb(&mut self, view: &Scene) {
        let mut base = view.clone();
        let c_keyed = self.animation.animated_paths().contains(&"fractal.c");
        let c_untouched = self
            .shown
            .as_ref()
            .is_some_and(|s| s.fractal.c == view.fractal.c);
        if !c_keyed && c_untouched && self.base.fractal.c.len() == view.fractal.c.len() {
            base.fractal.c = self.base.fractal.c.clone();
        }
        self.base = base;
        self.fit_keys();
    }

    /// Cuts or pads the keys' numbers of the algebra (c, the slice) to the base's algebra, the
    /// slice axes re-orthonormalised (the standard axes where they degenerate).
    fn fit_keys(&mut self) {
        let dim = self.base.fractal.algebra.dim();
        for key in &mut self.animation.keys {
            let mut resized = false;
            for (path, value) in &mut key.values {
                let hyper = matches!(schema::key(path).map(|k| k.kind), Some(Kind::Hyper { .. }));
                if hyper && value.len() != dim {
                    value.resize(dim, 0.0);
                    resized = true;
                }
            }
            let axes: Vec<usize> = AXES
                .iter()
                .filter_map(|a| key.values.iter().position(|(p, _)| p == a))
                .collect();
            if resized && axes.len() == 3 {
                let [x, y, z] = [0, 1, 2].map(|a| key.values[axes[a]].1.as_slice());
                let fitted = crate::scene::orthonormalise([x, y, z])
                    .unwrap_or_else(|| Slice::default().axes(dim));
                for (a, axis) in fitted.into_iter().enumerate() {
                    key.values[axes[a]].1 = axis;
                }
            }
        }
    }

    /// The paths a keyframe at the current frame takes from `view`: those other keyframes set,
    /// the camera's eye and target, c where the view's c is not the animation's at this frame,
    /// the slice's axes where the algebra has more than 4 dimensions or they are not the
    /// standard ones (or not the animation's here), and the slice offset where it is not zero
    /// (or not the animation's here). The axes go together.
    fn paths_for(&self, view: &Scene) -> Vec<String> {
        let current = self.scene_at(self.frame);
        let changed = |path: &str| get_value(view, path) != get_value(&current, path);
        let dim = view.fractal.algebra.dim();
        let standard = Slice::default().axes(dim);
        let s = &view.slice;
        let turned = dim > 4 || [&s.x, &s.y, &s.z].into_iter().ne(standard.iter());
        let mut paths: Vec<String> = self
            .animation
            .animated_paths()
            .into_iter()
            .map(String::from)
            .collect();
        for path in VIEW_PATHS {
            let wanted = match path {
                "camera.eye" | "camera.target" => true,
                "fractal.c" => changed(path),
                "slice.offset" => changed(path) || s.offset.iter().any(|&x| x != 0.0),
                _ => turned || AXES.iter().any(|a| changed(a)),
            };
            if wanted && !paths.iter().any(|p| p == path) {
                paths.push(path.to_string());
            }
        }
        if AXES.iter().any(|a| paths.iter().any(|p| p == a)) {
            for axis in AXES {
                if !paths.iter().any(|p| p == axis) {
                    paths.push(axis.to_string());
                }
            }
        }
        paths
    }

    /// Adds a keyframe at the current frame from the view (replacing one there): the values of
    /// `paths_for`. Keys that did not set a path the new key sets take the value they
    /// showed, so every key still looks as it did. A key's values are in the order of their
    /// paths, as a scene file reads back. Returns the key's frame.
    pub fn add_key(&mut self, view: &Scene) -> u32 {
        // A c moved from the loop is the key's, not a new centre of the loop.
        let centre = self.base.fractal.c.clone();
        self.absorb(view);
        if self.base.fractal.c.len() == centre.len() {
            self.base.fractal.c = centre;
        }
        let paths = self.paths_for(view);
        let before = self.animation.clone();
        for key in &mut self.animation.keys {
            let showed = before.scene_at(&self.base, key.frame);
            for path in &paths {
                if !key.values.iter().any(|(p, _)| p == path) {
                    let value = get_value(&showed, path).expect("keyed paths are animatable");
                    key.values.push((path.clone(), value));
                }
            }
            key.values.sort_by(|a, b| a.0.cmp(&b.0));
        }
        let mut values: Vec<(String, Vec<f64>)> = paths
            .iter()
            .map(|p| (p.clone(), get_value(view, p).expect("animatable")))
            .collect();
        values.sort_by(|a, b| a.0.cmp(&b.0));
        let frame = self.frame;
        self.animation.keys.retain(|k| k.frame != frame);
        self.animation.keys.push(Keyframe { frame, values });
        self.animation.keys.sort_by_key(|k| k.frame);
        self.selected = Some(frame);
        self.shown = Some(view.clone());
        frame
    }

    /// Moves the keyframe at `from` to frame `to`. Refused (false, nothing changed) when there
    /// is no key at `from`, `to` is past the last frame or another key is there.
    pub fn move_key(&mut self, from: u32, to: u32) -> bool {
        if to > self.last_frame() || (from != to && self.key(to).is_some()) {
            return false;
        }
        let Some(key) = self.animation.keys.iter_mut().find(|k| k.frame == from) else {
            return false;
        };
        key.frame = to;
        self.animation.keys.sort_by_key(|k| k.frame);
        if self.selected == Some(from) {
            self.selected = Some(to);
        }
        true
    }

    /// Deletes the keyframe at `frame`; false where there is none.
    pub fn delete_key(&mut self, frame: u32) -> bool {
        let count = self.animation.keys.len();
        self.animation.keys.retain(|k| k.frame != frame);
        if self.selected == Some(frame) {
            self.selected = None;
        }
        self.animation.keys.len() != count
    }

    /// Sets the frame count, within [`FRAMES_MIN`, `FRAMES_MAX`] and never below the last
    /// keyframe (move or delete it first); the current frame stays within.
    pub fn set_frames(&mut self, frames: u32) {
        let least = self
            .animation
            .keys
            .last()
            .map_or(FRAMES_MIN, |k| k.frame + 1);
        self.animation.frames = frames.clamp(least.max(FRAMES_MIN), FRAMES_MAX);
        self.frame = self.frame.min(self.last_frame());
    }

    /// Shows frame `frame` (within the animation) in `view`, the view's changes taken into the
    /// base first.
    pub fn show(&mut self, frame: u32, view: &mut Scene) {
        self.absorb(view);
        self.frame = frame.min(self.last_frame());
        *view = self.scene_at(self.frame);
        self.shown = Some(view.clone());
    }

    /// Play or pause; playing starts at the current frame, shown at once.
    pub fn toggle_play(&mut self, view: &mut Scene) {
        self.playing = !self.playing;
        if self.playing {
            self.position = f64::from(self.frame);
            self.show(self.frame, view);
        }
    }

    /// While playing, advances by `dt` seconds at the animation's frames per second, looping at
    /// the end, and shows the frame reached.
    pub fn advance(&mut self, dt: f64, view: &mut Scene) {
        if !self.playing {
            return;
        }
        let frames = f64::from(self.animation.frames);
        self.position = (self.position + dt * self.animation.fps).rem_euclid(frames);
        let frame = (self.position.floor() as u32).min(self.last_frame());
        if frame != self.frame {
            self.show(frame, view);
        }
    }

    /// The scene file of the animation, the view's changes taken into the base: the scene's
    /// tables and `[animation]`.
    pub fn file_text(&mut self, view: &Scene) -> String {
        self.absorb(view);
        scene_file(&self.base, &self.animation)
    }

    /// The scene file as `qjulia animate --scene FILE` reads it: its text, and the base and
    /// animation read back from it; the loader's one-line error where it would refuse it (a
    /// track that leaves a range between its keys, a degenerate camera on the way).
    pub fn checked_file(&mut self, view: &Scene) -> Result<(String, Scene, Animation), String> {
        let text = self.file_text(view);
        let mut loader = SceneLoader::new();
        loader
            .toml_str(&text, SceneSource::Default)
            .and_then(|()| loader.build_animated())
            .map(|(scene, animation)| (text, scene, animation))
            .map_err(|e| e.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Algebra;

    fn values(t: &Timeline, frame: u32) -> Vec<(String, Vec<f64>)> {
        t.key(frame).expect("a key").values.clone()
    }

    fn path_of(key: &[(String, Vec<f64>)], path: &str) -> Option<Vec<f64>> {
        key.iter().find(|(p, _)| p == path).map(|(_, v)| v.clone())
    }

    #[test]
    fn a_key_takes_the_camera_from_the_view_and_c_only_when_moved() {
        let mut view = Scene::default();
        let mut t = Timeline::new(view.clone(), Animation::default());
        assert_eq!(t.add_key(&view), 0);
        let key = values(&t, 0);
        let paths: Vec<&str> = key.iter().map(|(p, _)| p.as_str()).collect();
        assert_eq!(paths, ["camera.eye", "camera.target"]);
        // At frame 60 with the camera moved and c changed: c is keyed, and the key at 0 takes
        // the c it showed (the loop's start, the scene's c).
        t.show(60, &mut view);
        view.camera.eye = [1.0, 0.5, 2.0];
        view.fractal.c = vec![0.1, 0.2, 0.3, 0.4];
        t.add_key(&view);
        assert_eq!(t.key_frames(), [0, 60]);
        assert_eq!(
            path_of(&values(&t, 60), "fractal.c"),
            Some(view.fractal.c.clone())
        );
        assert_eq!(
            path_of(&values(&t, 0), "fractal.c"),
            Some(Scene::default().fractal.c)
        );
        // Each key is what the animation shows at its frame.
        assert_eq!(t.scene_at(60).camera.eye, [1.0, 0.5, 2.0]);
        assert_eq!(t.scene_at(0).camera.eye, Scene::default().camera.eye);
        assert_eq!(t.scene_at(0).fractal.c, Scene::default().fractal.c);
        assert_eq!(t.selected, Some(60));
    }

    #[test]
    fn the_slice_is_keyed_beyond_four_dimensions_or_when_turned() {
        let mut view = Scene::default();
        let mut t = Timeline::new(view.clone(), Animation::default());
        view.slice.offset = vec![0.0, 0.0, 0.0, 0.2];
        t.add_key(&view);
        let key = values(&t, 0);
        assert!(path_of(&key, "slice.offset").is_some());
        assert!(path_of(&key, "slice.x").is_none());
        // Octonions: the axes are keyed, all three, and fitted to eight dimensions.
        view.set_algebra(Algebra::Octonion);
        t.show(10, &mut view);
        t.add_key(&view);
        let key = values(&t, 10);
        for axis in AXES {
            assert_eq!(path_of(&key, axis).map(|v| v.len()), Some(8), "{axis}");
        }
        assert_eq!(
            path_of(&values(&t, 0), "slice.offset").map(|v| v.len()),
            Some(8)
        );
    }

    #[test]
    fn keys_move_within_range_to_free_frames_and_delete() {
        let mut view = Scene::default();
        let mut t = Timeline::new(
            view.clone(),
            Animation {
                frames: 50,
                ..Animation::default()
            },
        );
        for frame in [0, 10, 30] {
            t.show(frame, &mut view);
            view.camera.eye[0] = f64::from(frame) / 100.0;
            t.add_key(&view);
        }
        assert_eq!(t.key_frames(), [0, 10, 30]);
        // Onto another key, past the end, or from where no key is: refused.
        assert!(!t.move_key(10, 30));
        assert!(!t.move_key(10, 50));
        assert!(!t.move_key(11, 12));
        assert_eq!(t.key_frames(), [0, 10, 30]);
        // Past a neighbour: the keys stay sorted, the selection follows.
        t.selected = Some(10);
        assert!(t.move_key(10, 40));
        assert_eq!(t.key_frames(), [0, 30, 40]);
        assert_eq!(t.selected, Some(40));
        assert_eq!(t.scene_at(40).camera.eye[0], 0.1);
        // Adding where a key is replaces it.
        t.show(30, &mut view);
        view.camera.eye[0] = 0.9;
        t.add_key(&view);
        assert_eq!(t.key_frames(), [0, 30, 40]);
        assert_eq!(t.scene_at(30).camera.eye[0], 0.9);
        // The frame count stays above the last key.
        t.set_frames(20);
        assert_eq!(t.animation.frames, 41);
        t.set_frames(0);
        assert_eq!(t.animation.frames, 41);
        t.selected = Some(40);
        assert!(t.delete_key(40));
        assert!(!t.delete_key(40));
        assert_eq!(t.selected, None);
        t.set_frames(5);
        assert_eq!(t.animation.frames, 31);
        assert!(t.delete_key(30) && t.delete_key(0));
        t.set_frames(0);
        assert_eq!(t.animation.frames, FRAMES_MIN);
        assert_eq!(t.frame, 0);
    }

    #[test]
    fn scrubbing_and_playing_show_the_animation_frames() {
        let mut view = Scene::default();
        let mut t = Timeline::new(view.clone(), Animation::default());
        t.show(30, &mut view);
        view.camera.eye = [0.5, 0.5, 2.5];
        t.add_key(&view);
        t.show(90, &mut view);
        view.camera.eye = [-0.5, 0.2, 2.8];
        view.shading.ambient = 0.1; // not keyed: goes into the base
        t.add_key(&view);
        let base = t.base.clone();
        assert_eq!(base.shading.ambient, 0.1);
        assert_eq!(
            base.fractal.c,
            Scene::default().fractal.c,
            "c's loop centre"
        );
        for k in [0, 45, 60, 119] {
            t.show(k, &mut view);
            assert_eq!(view, t.animation.scene_at(&base, k), "frame {k}");
        }
        // Play: 30 fps, a tenth of a second is three frames, looping after the last.
        t.show(118, &mut view);
        t.toggle_play(&mut view);
        t.advance(0.1, &mut view);
        assert_eq!(t.frame, 1);
        assert_eq!(view, t.animation.scene_at(&base, 1));
        t.toggle_play(&mut view);
        t.advance(1.0, &mut view);
        assert_eq!(t.frame, 1, "paused");
    }

    #[test]
    fn the_saved_file_reads_back_as_the_animation() {
        let mut view = Scene::default();
        view.set_algebra(Algebra::Octonion);
        let mut t = Timeline::new(
            view.clone(),
            Animation {
                frames: 48,
                fps: 24.0,
                path_radius: 0.05,
                keys: vec![],
            },
        );
        for (frame, x) in [(0, 0.1), (20, -0.3), (47, 1.0 / 3.0)] {
            t.show(frame, &mut view);
            view.camera.eye[0] = x;
            view.fractal.c[5] = x / 7.0;
            t.add_key(&view);
        }
        let (text, base, animation) = t.checked_file(&view).expect("a valid file");
        assert_eq!(animation, t.animation, "{text}");
        assert_eq!(base, t.base);
        for k in 0..48 {
            assert_eq!(animation.scene_at(&base, k), t.scene_at(k), "frame {k}");
        }
    }
}
