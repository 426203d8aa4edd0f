//! The CPU twin of shaders/atmosphere.wgsl (the same functions with the same names in the same
//! order, generic over the float type; tests/architecture/twins.rs). The atmosphere: fog's
//! transmittance along the primary ray and the glow of its closest approach, laid over a pixel's
//! colour.

use super::camera::Primary;
use super::march::Trace;
use crate::algebra::{Real, Vec3};
use crate::cpu::light::mix3;
use crate::params::TraceParams;

impl<F: Real> TraceParams<F> {
    /// Whether the scene has fog (`fog.density` > 0, either model).
    pub fn fog_on(&self) -> bool {
        self.fog_density > F::zero()
    }

    /// Whether phong mode's halo is on (`glow.strength` > 0).
    pub fn glow_on(&self) -> bool {
        self.glow_strength > F::zero()
    }

    /// The fog's transmittance along origin + t dir over t in [0, t_stop]: exp(-fog_density L),
    /// L the length of that stretch within the bounding ball (the fog fills the ball); 1
    /// without fog. In f32, as path mode's radiance is.
    pub fn fog_transmittance(&self, origin: Vec3<F>, dir: Vec3<F>, t_stop: F) -> f32 {
        if !self.fog_on() {
            return 1.0;
        }
        let bounds = self.intersect_bounds(origin, dir);
        if !bounds.hit {
            return 1.0;
        }
        let length = (bounds.t_exit.min(t_stop) - bounds.t_enter).max(F::zero());
        (-((self.fog_density * length).to_f64() as f32)).exp()
    }

    /// Phong mode's halo for a ray that missed: glow_strength glow_colour exp(-closest /
    /// glow_radius), closest the least distance estimate along the ray ([`Trace`]'s `closest`;
    /// a ray that missed the ball gets exp(-3e38 / r) = 0).
    pub fn glow(&self, closest: F) -> Vec3<F> {
        let fall = (-((closest.max(F::zero()) / self.glow_radius).to_f64() as f32)).exp();
        self.glow_colour * (self.glow_strength * F::lit(fall as f64))
    }

    /// Phong mode's atmosphere over a camera ray's colour (docs/book/atmosphere.md): a miss
    /// gains the halo ([`Self::glow`]); then the colour is blended toward fog_colour by the
    /// fog's transmittance T from the eye to the hit (through the whole ball on a miss),
    /// mix(fog_colour, colour, T). Without fog and glow the colour unchanged.
    pub fn atmosphere(&self, colour: Vec3<F>, ray: &Primary<F>, trace: Trace<F>) -> Vec3<F> {
        let mut c = colour;
        if !trace.hit && self.glow_on() {
            c += self.glow(trace.closest);
        }
        if self.fog_on() {
            let t_stop = if trace.hit { trace.t } else { F::lit(3.0e38) };
            let transmittance = F::lit(self.fog_transmittance(ray.origin, ray.dir, t_stop) as f64);
            c = mix3(self.fog_colour, c, transmittance);
        }
        c
    }
}
