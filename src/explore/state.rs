//! What the user edits in the explorer, apart from what runs it (the GPU views, the jobs, the
//! windows: `super::app::Runtime`): the scene, the camera that "reset" returns to, the slice's
//! rotation, the c-loop, the timeline's model, what the view shows and the settings of the
//! view and the exports. What of it persists between runs is `super::persistence`'s.

use std::path::PathBuf;

use super::c_loop::CLoop;
use super::timeline::model::{AXES, Timeline};
use crate::scene::rotation::{planes, rotate_basis};
use crate::scene::{Algebra, Camera, Scene, Slice};

/// Samples the idle view accumulates unless the panel says otherwise.
pub const DEFAULT_PREVIEW_SAMPLES: u32 = 64;

/// What the view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// The quaternion Julia set's 3D slice, as `qjulia render` draws it (any `image.view`).
    #[default]
    Slice3d,
    /// The 2D Julia set of c = `c[0] + c[1] i`, as `qjulia render2d` draws it.
    Julia2d,
}

/// The slice's rotation: the basis the angles turn, and the angles, one per plane of
/// `rotation::planes(dim)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceRotation {
    base: [Vec<f64>; 3],
    pub angles: Vec<f64>,
}

impl SliceRotation {
    /// No rotation yet of `slice`'s axes, in `dim` dimensions.
    pub fn of(slice: &Slice, dim: usize) -> Self {
        Self {
            base: [slice.x.clone(), slice.y.clone(), slice.z.clone()],
            angles: vec![0.0; planes(dim).len()],
        }
    }

    /// Turns `slice`'s axes: the base turned by the angles.
    pub fn apply(&self, slice: &mut Slice) {
        let [x, y, z] = rotate_basis(&self.base, &self.angles);
        slice.x = x;
        slice.y = y;
        slice.z = z;
    }
}

/// The explorer's state as the user edits it.
pub struct ExplorerState {
    pub scene: Scene,
    /// The camera that "reset" returns to.
    pub home_camera: Camera,
    /// The slice basis the rotation angles turn, and the angles.
    pub rotation: SliceRotation,
    /// 3D view or 2D Julia set.
    pub mode: Mode,
    /// Play of c along its closed loop.
    pub c_loop: CLoop,
    /// The scene's `[animation]`: keyframes, scrubbing, playing.
    pub timeline: Timeline,
    /// Resolution of the view relative to the panel's pixels.
    pub resolution_scale: f32,
    /// Samples the idle view accumulates (independent of `image.samples`, which exports use).
    pub preview_samples: u32,
    /// Grid points per axis of "Export mesh…" (`qjulia mesh --resolution`).
    pub mesh_resolution: u32,
    /// The folder the file dialogs open in.
    pub last_dir: PathBuf,
}

impl ExplorerState {
    /// The state for a scene: its camera the home one, no rotation, the c-loop around its c, a
    /// timeline of no keys over it.
    pub fn with_scene(scene: Scene) -> Self {
        Self {
            home_camera: scene.camera.clone(),
            rotation: SliceRotation::of(&scene.slice, scene.fractal.algebra.dim()),
            c_loop: CLoop::around(scene.fractal.c.clone()),
            timeline: Timeline::new(scene.clone(), Default::default()),
            scene,
            mode: Mode::Slice3d,
            resolution_scale: 1.0,
            preview_samples: DEFAULT_PREVIEW_SAMPLES,
            mesh_resolution: crate::mesh::DEFAULT_RESOLUTION,
            last_dir: std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
        }
    }

    /// Sets `environment.file` to `file` (empty: none) and loads the map (a relative path
    /// against the current directory): what the status line says, or why the map cannot be
    /// used (the scene then unchanged).
    pub fn set_environment(&mut self, file: String) -> Result<String, String> {
        let mut scene = self.scene.clone();
        scene.environment.file = file;
        scene.environment.checksum = 0;
        scene
            .load_environment(&[], false)
            .map_err(|(key, reason)| format!("error: {key}: {reason}"))?;
        let told = match &scene.loaded.environment {
            Some(map) => format!(
                "environment map {}: {} x {}, loaded in {:.3} s",
                map.source, map.width, map.height, map.seconds
            ),
            None => "no environment map".into(),
        };
        self.scene = scene;
        Ok(told)
    }

    /// The state for a new scene (a preset, a file): camera home, rotation, c-loop and
    /// timeline follow it; what the view shows, the view's and the exports' settings and the
    /// last folder stay.
    pub fn for_scene(&self, scene: Scene) -> Self {
        Self {
            mode: self.mode,
            resolution_scale: self.resolution_scale,
            preview_samples: self.preview_samples,
            mesh_resolution: self.mesh_resolution,
            last_dir: self.last_dir.clone(),
            ..Self::with_scene(scene)
        }
    }

    /// Switches the algebra (c, slice and offset cut or padded), the rotation starting afresh.
    pub fn set_algebra(&mut self, algebra: Algebra) {
        self.scene.set_algebra(algebra);
        self.rotation = SliceRotation::of(&self.scene.slice, algebra.dim());
        self.c_loop.center = self.scene.fractal.c.clone();
    }

    /// Turns the slice basis by the rotation angles.
    pub fn apply_rotation(&mut self) {
        self.rotation.apply(&mut self.scene.slice);
    }

    /// Whether the view changes by itself: the c-loop or the timeline playing.
    pub fn playing(&self) -> bool {
        self.c_loop.playing || self.timeline.playing
    }

    /// Play or pause the c-loop (Space, or the Play button); playing starts the path afresh
    /// at today's c, and stops the timeline's play.
    pub fn toggle_c_loop(&mut self) {
        self.timeline.playing = false;
        self.c_loop.toggle(&self.scene.fractal.c);
    }

    /// Moves the view by `dt` seconds of wall time: c along its loop, the timeline's
    /// animation, while they play. Run once a frame.
    pub fn advance(&mut self, dt: f64) {
        // One path size: the timeline's, which `qjulia animate` uses.
        let radius = self.timeline.animation.path_radius;
        self.c_loop.advance(dt, radius, &mut self.scene.fractal.c);
        self.timeline.advance(dt, &mut self.scene);
    }

    /// Shows frame `frame` of the animation in the view (c's own Play stops).
    pub fn show_frame(&mut self, frame: u32) {
        self.c_loop.playing = false;
        self.timeline.show(frame, &mut self.scene);
        self.follow_slice();
    }

    /// Play or pause the animation in the view (c's own Play stops).
    pub fn toggle_timeline_play(&mut self) {
        self.c_loop.playing = false;
        self.timeline.toggle_play(&mut self.scene);
    }

    /// When the keys set the slice, the rotation controls turn the slice shown.
    fn follow_slice(&mut self) {
        let keyed = self.timeline.animation.animated_paths();
        if AXES.iter().any(|a| keyed.contains(a)) {
            let s = &self.scene.slice;
            self.rotation.base = [s.x.clone(), s.y.clone(), s.z.clone()];
            self.rotation.angles.iter_mut().for_each(|a| *a = 0.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn switching_the_algebra_pads_c_and_the_slice_and_rotates_in_every_plane() {
        let mut app = ExplorerState::with_scene(Scene::default());
        app.set_algebra(crate::scene::Algebra::Octonion);
        assert_eq!(
            app.scene.fractal.c,
            vec![-0.2, 0.6, 0.2, 0.2, 0.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(app.rotation.angles.len(), 28);
        // Turn i into e7: the slice's y axis leaves the quaternions.
        let p = planes(8).iter().position(|&p| p == (1, 7)).unwrap();
        app.rotation.angles[p] = std::f64::consts::FRAC_PI_2;
        app.apply_rotation();
        assert!((app.scene.slice.y[7] - 1.0).abs() < 1e-12);
        assert!(
            crate::scene::rotation::orthonormality_error(&[
                app.scene.slice.x.clone(),
                app.scene.slice.y.clone(),
                app.scene.slice.z.clone(),
            ]) < 1e-12
        );
        // Back to quaternions: cut to 4D, the basis still orthonormal.
        app.set_algebra(crate::scene::Algebra::Quaternion);
        assert_eq!(app.scene.fractal.c.len(), 4);
        assert_eq!(app.rotation.angles.len(), 6);
        assert_eq!(app.scene.slice.x.len(), 4);
    }
}
