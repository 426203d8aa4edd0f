//! The CPU twin of shaders/camera.wgsl (the same functions with the same names in the same order,
//! generic over the float type; tests/architecture/twins.rs). The camera and the lens: the camera
//! rays of a sample, the thin lens and its aperture, the cone's start for a block of pixels, the
//! primary ray (pinhole or lens, clipped to the bounds) and its sphere tracing, alone or as a fused
//! pair.

use super::march::Trace;
use crate::algebra::{Real, Vec3};
use crate::params::TraceParams;

/// Pixels a side of the blocks that share a cone (one workgroup on the GPU).
pub const CONE_BLOCK: u32 = 8;
/// The cone stops this many epsilons short: the estimate is about half the true distance near
/// the surface, so rays must start where it is still well above epsilon.
pub const CONE_MARGIN: f64 = 4.0;

/// A sample's camera ray: its origin and direction and the stretch [t_start, t_end] of it that
/// sphere tracing covers, within the bounding ball; `hit` false where it misses the ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primary<F> {
    pub origin: Vec3<F>,
    pub dir: Vec3<F>,
    pub t_start: F,
    pub t_end: F,
    pub hit: bool,
}

/// A ray: its origin and its unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<F> {
    pub origin: Vec3<F>,
    pub dir: Vec3<F>,
}

impl<F: Real> TraceParams<F> {
    /// The ray through the point (x, y) of the image plane in pixel units, (0, 0) the top left
    /// corner.
    pub fn camera_ray_at(&self, x: F, y: F) -> Vec3<F> {
        let (one, two) = (F::one(), F::lit(2.0));
        let px = (two * x / F::lit(self.width as f64) - one) * self.tan_half_fov_y * self.aspect;
        let py = (one - two * y / F::lit(self.height as f64)) * self.tan_half_fov_y;
        (self.cam_forward + self.cam_right * px + self.cam_up * py).normalize()
    }

    /// The primary ray's direction through sample `sample` of pixel (i, j), row 0 at the top
    /// (docs/CONTRACT.md's camera); sample 0 goes through the pixel's centre.
    pub fn camera_ray(&self, i: u32, j: u32, sample: u32) -> Vec3<F> {
        let (sx, sy) = self.stream_position(sample);
        self.camera_ray_at(F::lit(i as f64) + sx, F::lit(j as f64) + sy)
    }

    /// Whether the camera's samples go through the thin lens: aperture > 0. Every sample does
    /// then, sample 0 too; the depth and the steps stay the pinhole's ray's through the pixel's
    /// centre (`pinhole_ray`), traced for them alone.
    pub fn lens_open(&self) -> bool {
        self.aperture > F::zero()
    }

    /// The thin lens's ray of sample `sample` of pixel (i, j) in phong mode: through the
    /// sample's image-plane point (`stream_position`) and the aperture's point at its lens
    /// position (`lens_point`).
    pub fn lens_ray(&self, i: u32, j: u32, sample: u32) -> Ray<F> {
        let (sx, sy) = self.stream_position(sample);
        let x = F::lit(i as f64) + sx;
        let y = F::lit(j as f64) + sy;
        self.thin_lens_ray(x, y, self.lens_point(sample))
    }

    /// The thin lens's ray through the image-plane point (x, y) (in pixels) and the point `lens`
    /// of the unit aperture: the pinhole ray through (x, y), direction f + px r + py u, meets
    /// the focus plane (at focus_distance along f) at eye + focus_distance (f + px r + py u);
    /// the ray leaves the lens at eye + aperture (lens.x r + lens.y u), toward that point.
    pub fn thin_lens_ray(&self, x: F, y: F, lens: (f32, f32)) -> Ray<F> {
        let (one, two) = (F::one(), F::lit(2.0));
        let px = (two * x / F::lit(self.width as f64) - one) * self.tan_half_fov_y * self.aspect;
        let py = (one - two * y / F::lit(self.height as f64)) * self.tan_half_fov_y;
        let (lx, ly) = (
            self.aperture * F::lit(lens.0 as f64),
            self.aperture * F::lit(lens.1 as f64),
        );
        let offset = self.cam_right * lx + self.cam_up * ly;
        let focus =
            (self.cam_forward + self.cam_right * px + self.cam_up * py) * self.focus_distance;
        Ray {
            origin: self.eye + offset,
            dir: (focus - offset).normalize(),
        }
    }

    /// Sample k's point on the unit aperture in phong mode: the aperture's point at its
    /// stream's lens position (`stream_lens_position`: the Halton point of index 0 is the
    /// lens's centre, which would make a stream's first sample a pinhole sample).
    pub fn lens_point(&self, k: u32) -> (f32, f32) {
        self.aperture_point(self.stream_lens_position(k))
    }

    /// The point of the unit aperture at (u, v) in [0, 1)^2, in f32 (its trigonometry too, as
    /// the f64 kernels do), turned by rotation = blade_rotation: for a round aperture (blades 0)
    /// the polar map sqrt(u) (cos phi, sin phi), phi = 2 pi v + rotation (uniform over the
    /// disc); for n blades the regular n-gon inscribed in the unit circle with corners
    /// c_m = (cos a_m, sin a_m), a_m = 2 pi m / n + rotation, uniform over it: the triangle
    /// (0, c_m, c_m+1) with m = floor(n u), then with a = n u - m and b = v the point
    /// sqrt(a) ((1 - b) c_m + b c_m+1).
    pub fn aperture_point(&self, (u, v): (f32, f32)) -> (f32, f32) {
        let rotation = self.blade_rotation.to_f64() as f32;
        if self.blades == 0 {
            let phi = 6.283_185_5_f32 * v + rotation;
            let r = u.sqrt();
            return (r * phi.cos(), r * phi.sin());
        }
        let n = self.blades as f32;
        let m = (n * u).floor().min(n - 1.0);
        let a = n * u - m;
        let a0 = 6.283_185_5_f32 * (m / n) + rotation;
        let a1 = 6.283_185_5_f32 * ((m + 1.0) / n) + rotation;
        let r = a.sqrt();
        (
            r * ((1.0 - v) * a0.cos() + v * a1.cos()),
            r * ((1.0 - v) * a0.sin() + v * a1.sin()),
        )
    }

    /// Cone tracing's start for the block (bi, bj) of CONE_BLOCK x CONE_BLOCK pixels: march the
    /// ray through the block's centre, shrinking each unbounding sphere by the cone's radius at
    /// that distance (t times the tangent of the widest angle to a corner ray), so that the whole
    /// cone is known to be at least epsilon from the set up to the t returned. Every ray of the
    /// block may start there. Bounded by max_steps; 0 where the centre ray misses the ball.
    pub fn cone_start(&self, bi: u32, bj: u32) -> F {
        let x0 = F::lit((bi * CONE_BLOCK) as f64);
        let y0 = F::lit((bj * CONE_BLOCK) as f64);
        let size = F::lit(CONE_BLOCK as f64);
        let half = F::lit(0.5);
        let centre = self.camera_ray_at(x0 + half * size, y0 + half * size);
        let mut spread = F::zero();
        for k in 0..4u32 {
            let corner = self.camera_ray_at(
                x0 + size * F::lit((k & 1) as f64),
                y0 + size * F::lit((k >> 1) as f64),
            );
            let cos_angle = centre.dot(corner).max(F::lit(0.1));
            spread = spread.max(centre.cross(corner).length() / cos_angle);
        }
        let bounds = self.intersect_bounds(self.eye, centre);
        if !bounds.hit {
            return F::zero();
        }
        let mut t = bounds.t_enter;
        for _ in 0..self.max_steps {
            let free = self.estimate_distance(self.eye + centre * t) - spread * t;
            if free < F::lit(CONE_MARGIN) * self.epsilon || t > bounds.t_exit {
                return t;
            }
            t = t + free;
        }
        t
    }

    /// Sample `sample`'s pinhole ray of pixel (i, j), from the eye, against the bounds, from
    /// t_min on (the cone's start, or 0): the camera ray where the lens is closed, and with
    /// sample 0 the ray that gives the depth and the steps.
    pub fn pinhole_ray(&self, i: u32, j: u32, sample: u32, t_min: F) -> Primary<F> {
        let dir = self.camera_ray(i, j, sample);
        let bounds = self.intersect_bounds(self.eye, dir);
        Primary {
            origin: self.eye,
            dir,
            t_start: bounds.t_enter.max(t_min),
            t_end: bounds.t_exit,
            hit: bounds.hit,
        }
    }

    /// Sample `sample`'s camera ray of pixel (i, j): the pinhole's (`pinhole_ray`), or where
    /// the lens is open the thin lens's, against the bounds. A lens ray starts from the ball:
    /// the cone covers the block's rays from the eye, not rays from elsewhere on the lens.
    pub fn primary_ray(&self, i: u32, j: u32, sample: u32, t_min: F) -> Primary<F> {
        if !self.lens_open() {
            return self.pinhole_ray(i, j, sample, t_min);
        }
        let ray = self.lens_ray(i, j, sample);
        let bounds = self.intersect_bounds(ray.origin, ray.dir);
        Primary {
            origin: ray.origin,
            dir: ray.dir,
            t_start: bounds.t_enter,
            t_end: bounds.t_exit,
            hit: bounds.hit,
        }
    }

    /// A camera ray's sphere trace, with the pixel epsilon; a miss of no steps where it misses
    /// the ball.
    pub fn trace_primary(&self, ray: &Primary<F>) -> Trace<F> {
        if !ray.hit {
            return Trace::untraced();
        }
        let eps_slope = self.pixel_epsilon * self.pixel_angle;
        self.sphere_trace(ray.origin, ray.dir, ray.t_start, ray.t_end, eps_slope)
    }

    /// Two camera rays' sphere traces at once (`sphere_trace_pair`): each `trace_primary`'s
    /// bit for bit.
    pub fn trace_primary_pair(&self, a: &Primary<F>, b: &Primary<F>) -> [Trace<F>; 2] {
        let eps_slope = self.pixel_epsilon * self.pixel_angle;
        let m1 = self.march_start(a.origin, a.dir, (a.t_start, a.t_end), eps_slope, a.hit);
        let m2 = self.march_start(b.origin, b.dir, (b.t_start, b.t_end), eps_slope, b.hit);
        self.sphere_trace_pair(m1, m2)
    }
}
