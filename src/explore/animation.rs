//! The animation of c: a smooth closed path through the algebra around a centre, played from
//! the c it starts at, with the timeline's path radius (the loop `qjulia animate` renders when no
//! keyframe sets c).

use super::app::ExplorerApp;

/// The animation of c: a smooth closed path through 4D around a centre.
#[derive(Clone, Debug)]
pub struct Animation {
    pub playing: bool,
    /// Radians of the path per second.
    pub speed: f64,
    /// The path's size.
    pub radius: f64,
    pub phase: f64,
    pub center: Vec<f64>,
}

impl Animation {
    /// The point of the closed path at `phase` ([`crate::animation::c_path`], the path that
    /// `qjulia animate` moves c on): every component moves, with different frequencies, and
    /// the path returns to its start after 2 pi.
    pub fn point(&self, phase: f64) -> Vec<f64> {
        crate::animation::c_path(&self.center, self.radius, phase)
    }
}

impl ExplorerApp {
    /// Play or pause (Space, or the Play button); playing starts the path afresh at today's c.
    pub(super) fn toggle_play(&mut self) {
        self.timeline.playing = false;
        self.animation.playing = !self.animation.playing;
        if self.animation.playing {
            self.animation.center = self.scene.fractal.c.clone();
            self.animation.phase = 0.0;
        }
    }

    /// Moves c along the path by `dt` seconds, while playing.
    pub(super) fn animate(&mut self, dt: f64) {
        // One path size: the timeline's, which `qjulia animate` uses.
        self.animation.radius = self.timeline.animation.path_radius;
        if self.animation.playing {
            self.animation.phase =
                (self.animation.phase + dt * self.animation.speed) % std::f64::consts::TAU;
            self.scene.fractal.c = self.animation.point(self.animation.phase);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_animation_path_is_closed_and_starts_at_c() {
        let a = Animation {
            playing: true,
            speed: 1.0,
            radius: 0.1,
            phase: 0.0,
            center: vec![-0.2, 0.6, 0.2, 0.2, 0.1, 0.0, 0.0, -0.1],
        };
        assert_eq!(a.point(0.0), a.center);
        let end = a.point(std::f64::consts::TAU);
        assert!((0..8).all(|k| (end[k] - a.center[k]).abs() < 1e-12));
    }
}
