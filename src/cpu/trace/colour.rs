//! The CPU twin of shaders/colour.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). Traps and colour: the orbit trap, the
//! palette, a hit's base colour, the shading features (the environment's light, shadows and
//! occlusion) and the background.

use super::estimate::count;
use super::normal::safe_normalize;
use crate::algebra::{Hyper, Real, Vec3, hyper_add, hyper_dot, hyper_sq};
use crate::params::TraceParams;
use crate::scene::Colouring;

impl<F: Real> TraceParams<F> {
    /// Whether the scene colours by the orbit trap (shading.colouring = "orbit_trap").
    pub fn trap_on(&self) -> bool {
        self.colouring == Colouring::OrbitTrap
    }

    /// The orbit trap's distance for q: t = min over n = 0..N of | |z_n| - trap_radius |,
    /// z_0 = q, z_{n+1} = z_n^2 + c, N the first n with |z_n|^2 > escape_radius_squared, or
    /// max_iterations (iterate_orbit's count and escape; no derivative is carried, so its limit
    /// does not apply).
    pub fn orbit_trap(&self, q: Hyper<F>) -> F {
        let parts = self.algebra_parts;
        let mut z = q;
        let mut trap = (hyper_dot(z, z, parts).sqrt() - self.trap_radius).abs();
        for _ in 0..self.max_iterations {
            count(&super::ITERATIONS, 1);
            z = hyper_add(hyper_sq(z, parts), self.c);
            let z_norm2 = hyper_dot(z, z, parts);
            trap = trap.min((z_norm2.sqrt() - self.trap_radius).abs());
            if z_norm2 > self.escape_radius_squared {
                break;
            }
        }
        trap
    }

    /// The palette: 0.5 + 0.5 cos(2 pi x) per channel, x = fract(trap_scale t + palette_phase)
    /// (the fraction changes nothing but keeps cos's argument small).
    pub fn palette(&self, t: F) -> Vec3<F> {
        let half = F::lit(0.5);
        let channel = |phase: F| {
            let y = self.trap_scale * t + phase;
            let x = y - y.floor();
            half + half * (F::lit(6.2831855) * x).cos()
        };
        Vec3::new(
            channel(self.palette_phase.x),
            channel(self.palette_phase.y),
            channel(self.palette_phase.z),
        )
    }

    /// The base colour of a hit at p: the diffuse colour, or the palette's colour of the orbit
    /// trap. (shade_features's B, path mode's albedo, and the albedo AOV.)
    pub fn hit_albedo(&self, p: Vec3<F>) -> Vec3<F> {
        if self.trap_on() {
            return self.palette(self.orbit_trap(self.slice_point(p)));
        }
        self.diffuse
    }

    /// Whether the hit is shaded by [`Self::shade_features`] (a light of some radius, ambient
    /// light, occlusion or orbit-trap colour) instead of the seed's phong and in_shadow.
    pub fn shading_features(&self) -> bool {
        let soft = self.shadows_on() && self.soft_shadows_on();
        soft || self.occlusion_on() || self.trap_on() || self.ambient > F::zero()
    }

    /// The shading with the picture's features, the README's formula: with base colour B
    /// (diffuse, or the palette's colour of the orbit trap), the occlusion factor A and V the light's visibility (1 lit, 0 in shadow, between
    /// in a penumbra): ambient A B + (shadow_factor + (1 - shadow_factor) V)
    /// (A (B + normal_tint |n|) max(N.L, 0) + highlight), the highlight as in phong. With
    /// ambient 0, A 1 and a point light it is phong's colour, shadowed as trace_pixel does.
    /// The viewer is at `eye`: the ray's origin (the camera's eye, or a point of the lens).
    pub fn shade_features(&self, p: Vec3<F>, n: Vec3<F>, eye: Vec3<F>) -> Vec3<F> {
        let base = self.hit_albedo(p);
        let mut a = F::one();
        if self.occlusion_on() {
            a = self.occlusion(p, n);
        }
        let mut ambient = base * (self.ambient * a);
        if self.environment_on() && self.env_light {
            ambient = ambient.mul_elem(Vec3::from_f32(self.env_irradiance(n.to_f32())));
        }
        let l = safe_normalize(self.light - p, n);
        let e = safe_normalize(eye - p, n);
        let n_dot_l = n.dot(l);
        if n_dot_l <= F::zero() {
            return ambient;
        }
        let r = n * (F::lit(2.0) * n_dot_l) - l;
        let e_dot_r = e.dot(r);
        let mut highlight = F::zero();
        if e_dot_r > F::zero() {
            highlight = self.specular * e_dot_r.powf(self.shininess);
        }
        let mut light = (base + n.abs() * self.normal_tint) * a * n_dot_l + Vec3::splat(highlight);
        // As in trace_pixel: no shadow ray for an unlit point.
        let lit = light.x > F::zero() || light.y > F::zero() || light.z > F::zero();
        if self.shadows_on() && lit {
            if self.soft_shadows_on() {
                let sf = self.shadow_factor;
                light = light * (sf + (F::one() - sf) * self.soft_shadow(p, n));
            } else if self.in_shadow(p, n) {
                light = light * self.shadow_factor;
            }
        }
        ambient + light
    }

    /// What a ray along `dir` that hits nothing shows: the environment map's radiance where
    /// the scene has one (phong mode clamps it as any colour), else the flat background.
    pub fn background(&self, dir: Vec3<F>) -> Vec3<F> {
        if self.environment_on() {
            return Vec3::from_f32(self.env_radiance(dir.to_f32()));
        }
        self.background
    }
}
