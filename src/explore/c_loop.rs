//! The c-loop: c played along a smooth closed path through the algebra around a centre, from
//! the c it starts at, with the timeline's path radius (the loop `qjulia animate` renders when no
//! keyframe sets c). Not to be confused with [`crate::animation::Animation`], the keyframed
//! animation the timeline edits.

/// The Play loop of c: a smooth closed path through the algebra around a centre.
#[derive(Clone, Debug)]
pub struct CLoop {
    pub playing: bool,
    /// Radians of the path per second.
    pub speed: f64,
    /// The path's size.
    pub radius: f64,
    pub phase: f64,
    pub center: Vec<f64>,
}

impl CLoop {
    /// The loop around `center`, paused, at its start.
    pub fn around(center: Vec<f64>) -> Self {
        Self {
            playing: false,
            speed: 0.4,
            radius: 0.08,
            phase: 0.0,
            center,
        }
    }

    /// The point of the closed path at `phase` ([`crate::animation::c_path`], the path that
    /// `qjulia animate` moves c on): every component moves, with different frequencies, and
    /// the path returns to its start after 2 pi.
    pub fn point(&self, phase: f64) -> Vec<f64> {
        crate::animation::c_path(&self.center, self.radius, phase)
    }

    /// Play or pause; playing starts the path afresh at `c`.
    pub fn toggle(&mut self, c: &[f64]) {
        self.playing = !self.playing;
        if self.playing {
            self.center = c.to_vec();
            self.phase = 0.0;
        }
    }

    /// With the path size `radius` (the timeline's, which `qjulia animate` uses), moves `c`
    /// along the path by `dt` seconds while playing.
    pub fn advance(&mut self, dt: f64, radius: f64, c: &mut Vec<f64>) {
        self.radius = radius;
        if self.playing {
            self.phase = (self.phase + dt * self.speed) % std::f64::consts::TAU;
            *c = self.point(self.phase);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_animation_path_is_closed_and_starts_at_c() {
        let a = CLoop {
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
