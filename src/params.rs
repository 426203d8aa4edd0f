//! What the kernels need of a scene, precomputed once on the host (in f64) and then rounded to
//! the precision they run in, each uniform declared once ([`crate::uniform`]): the host
//! parameters the CPU twin reads, with the camera frame and the slice's bounding ball already
//! worked out, and their images, the uniforms the GPU reads (`Params` of shaders/params.wgsl,
//! `Julia2dParams` of shaders/julia2d.wgsl).

use std::sync::Arc;

use crate::algebra::{Vec2, Vec3, hyper_from_f64};
use crate::envmap::EnvironmentData;
use crate::scene::{Colouring, NormalMethod, Tracing};
use crate::uniform::uniform;

uniform! {
    /// The tracer's inputs in precision `F`, as the CPU twin reads them. Field names are those
    /// of `Params` in shaders/params.wgsl, in its order; [`GpuParams`] and [`GpuParams64`] are
    /// its images, made from this one table.
    #[derive(Clone, Debug, PartialEq)]
    pub struct TraceParams<F> for "Params";
    /// The tracer's uniform in f32: `struct Params` of the f32 module of shaders/trace.wgsl
    /// (the tests compare [`Self::LAYOUT`] with naga's).
    pub struct GpuParams<f32>;
    /// [`GpuParams`] in f64, for the f64 module of the same shaders/trace.wgsl.
    pub struct GpuParams64<f64>;
    fn new(scene) {
        let frame = scene.camera_frame();
        let bounds = scene.slice_bounds();
        let (f, s, sh) = (&scene.fractal, &scene.slice, &scene.shading);
        let env_frame = environment_frame(scene);
    }
    fields {
        c: Hyper = hyper_from_f64(&f.c),
        slice_x: Hyper = hyper_from_f64(&s.x),
        slice_y: Hyper = hyper_from_f64(&s.y),
        slice_z: Hyper = hyper_from_f64(&s.z),
        slice_offset: Hyper = hyper_from_f64(&s.offset),
        eye: Vec3 = Vec3::from_f64(scene.camera.eye),
        epsilon: Real = F::lit(f.epsilon),
        cam_forward: Vec3 = Vec3::from_f64(frame.forward),
        tan_half_fov_y: Real = F::lit(frame.tan_half_fov_y),
        cam_right: Vec3 = Vec3::from_f64(frame.right),
        /// width / height
        aspect: Real = F::lit(scene.image.width as f64 / scene.image.height as f64),
        cam_up: Vec3 = Vec3::from_f64(frame.up),
        escape_radius_squared: Real = F::lit(f.escape_radius_squared.min(F::ESCAPE_LIMIT)),
        light: Vec3 = Vec3::from_f64(scene.light.position),
        /// The slice's bounding ball; <= 0 when the slice misses the 4D ball.
        bounds_radius_squared: Real = F::lit(bounds.radius_squared),
        bounds_center: Vec3 = Vec3::from_f64(bounds.center),
        normal_tint: Real = F::lit(sh.normal_tint),
        diffuse: Vec3 = Vec3::from_f64(sh.diffuse),
        specular: Real = F::lit(sh.specular),
        background: Vec3 = Vec3::from_f64(sh.background),
        shininess: Real = F::lit(sh.shininess),
        palette_phase: Vec3 = Vec3::from_f64(sh.palette_phase),
        trap_scale: Real = F::lit(sh.trap_scale),
        /// Unit length.
        cut_normal: Vec3 = Vec3::from_f64(unit(scene.cut.normal)),
        cut_offset: Real = F::lit(scene.cut.offset),
        /// The fog's colour (`fog.colour`): path mode's single-scattering albedo, phong mode's
        /// colour blended toward.
        fog_colour: Vec3 = Vec3::from_f64(scene.fog.colour),
        /// The fog's extinction per unit length (`fog.density`): 0 is no fog.
        fog_density: Real = F::lit(scene.fog.density),
        /// Phong mode's halo (`[glow]`): its colour, and its strength (0: off).
        glow_colour: Vec3 = Vec3::from_f64(scene.glow.colour),
        glow_strength: Real = F::lit(scene.glow.strength),
        /// The environment map's frame (src/cpu/environment.rs): up (`sky.up`, unit) and its
        /// turn about it in radians (`environment.rotation_degrees`), front (u = 0 at turn 0,
        /// unit, orthogonal to up) and the radiance's factor (`environment.intensity`).
        env_up: Vec3 = Vec3::from_f64(env_frame.0),
        env_rotation: Real = F::lit(env_frame.2),
        env_front: Vec3 = Vec3::from_f64(env_frame.1),
        env_intensity: Real = F::lit(scene.environment.intensity),
        shadow_factor: Real = F::lit(sh.shadow_factor),
        normal_delta: Real = F::lit(sh.normal_delta),
        step_scale: Real = F::lit(f.step_scale),
        pixel_epsilon: Real = F::lit(f.pixel_epsilon),
        /// A pixel's footprint per unit distance, 2 tan(fov/2) / height.
        pixel_angle: Real = F::lit(scene.pixel_angle()),
        /// The light's radius (`light.radius`): 0 is a point light.
        light_radius: Real = F::lit(scene.light.radius),
        ambient: Real = F::lit(sh.ambient),
        occlusion: Real = F::lit(sh.occlusion),
        trap_radius: Real = F::lit(sh.trap_radius),
        /// The thin lens's radius (`camera.aperture`): 0 is the pinhole.
        aperture: Real = F::lit(scene.camera.aperture),
        /// The focus plane's distance along cam_forward: `camera.focus_distance`, or
        /// |target - eye| where that is 0.
        focus_distance: Real = F::lit(scene.focus_distance()),
        /// `camera.blade_rotation` in radians.
        blade_rotation: Real = F::lit(scene.camera.blade_rotation.to_radians()),
        /// Adaptive sampling's target (`path.noise_target`): a pixel stops once its noise
        /// (`pixel_noise`) is at most this; 0 is off.
        noise_target: Real = F::lit(scene.path.noise_target),
        /// The fog's Henyey-Greenstein g (`fog.anisotropy`), in (-1, 1).
        fog_anisotropy: Real = F::lit(scene.fog.anisotropy),
        /// The distance over which the halo falls to 1/e (`glow.radius`).
        glow_radius: Real = F::lit(scene.glow.radius),
        max_iterations: u32 = f.max_iterations,
        max_steps: u32 = f.max_steps,
        width: u32 = scene.image.width,
        height: u32 = scene.image.height,
        shadows: bool = sh.shadows,
        normal_method: NormalMethod = sh.normal,
        tracing: Tracing = f.tracing,
        /// Quaternion parts of a number of the algebra: 1 quaternion, 2 octonion, 4 sedenion.
        algebra_parts: u32 = f.algebra.parts(),
        /// Rays per pixel (`image.samples`).
        samples: u32 = scene.image.samples,
        colouring: Colouring = sh.colouring,
        /// Whether the set is cut by the half-space cut_normal . p <= cut_offset.
        cut: bool = scene.cut.enabled,
        /// The aperture's blades (`camera.blades`): 0 round, 3..16 a regular polygon.
        blades: u32 = scene.camera.blades,
        /// Adaptive sampling's floor (`path.min_samples`): no pixel stops before
        /// max(min(min_samples, samples), 4) samples.
        min_samples: u32 = scene.path.min_samples,
        /// Whether the scene's environment map is loaded and bound (`environment.file`).
        env_map: bool = scene.loaded.environment.is_some(),
        /// Phong mode's ambient light from the map's irradiance (`shading.environment_light`).
        env_light: bool = sh.environment_light,
    }
    per_dispatch(p, row_offset, row_count) {
        /// The band of rows this dispatch traces: [row_offset, row_offset + row_count).
        row_offset: u32 = row_offset,
        row_count: u32 = row_count,
        /// Pixels per row of the output arrays (>= width; a multiple of 64 where the rows are
        /// copied into a texture).
        row_stride: u32 = p.width,
        /// The output row that the band's first row lands in.
        out_row: u32 = 0,
        /// The samples this dispatch adds: [sample_start, sample_end) of `samples`.
        sample_start: u32 = 0,
        sample_end: u32 = p.samples,
    }
    host_only {
        /// The environment map as loaded and packed (`scene.loaded.environment`), which the
        /// kernels read at binding 8 and the CPU twin here; None: no map.
        environment: Option<Arc<EnvironmentData>> = scene.loaded.environment.clone(),
    }
}

/// The environment map's frame in f64: up (`sky.up`, unit), front (the world's +z, or +y where
/// |up.z| >= 0.9, made orthogonal to up: u = 0 and the map's edges
/// lie toward front, so that its centre, u = 1/2, faces the default camera's view along -z) and
/// the turn about up in radians (`environment.rotation_degrees` modulo a full turn). Right,
/// toward u = 1/4, is front x up.
pub fn environment_frame(scene: &crate::scene::Scene) -> ([f64; 3], [f64; 3], f64) {
    let up = glam::DVec3::from_array(unit(scene.sky.up));
    let axis = if up.z.abs() < 0.9 {
        glam::DVec3::Z
    } else {
        glam::DVec3::Y
    };
    let front = (axis - up * axis.dot(up)).normalize();
    let turn = scene
        .environment
        .rotation_degrees
        .to_radians()
        .rem_euclid(std::f64::consts::TAU);
    (up.to_array(), front.to_array(), turn)
}

/// `v` scaled to unit length (validation has made sure it is not zero); divided by its largest
/// component first, so that neither a tiny nor a huge v under- or overflows.
pub(crate) fn unit(v: [f64; 3]) -> [f64; 3] {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let v = if m > 0.0 { v.map(|x| x / m) } else { v };
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n > 0.0 {
        v.map(|x| x / n)
    } else {
        [0.0, 0.0, 1.0]
    }
}

uniform! {
    /// What the 2D Julia kernel needs of a scene (`view2d` and the first two components of
    /// `fractal.c`), precomputed in f64 and rounded to `F`. Field names are those of
    /// `Julia2dParams` in shaders/julia2d.wgsl, in its order; [`GpuJulia2dParams`] and
    /// [`GpuJulia2dParams64`] are its images.
    #[derive(Clone, Debug, PartialEq)]
    pub struct Julia2dParams<F> for "Julia2dParams";
    /// The 2D view's uniform in f32: `struct Julia2dParams` of shaders/julia2d.wgsl's f32
    /// module (the tests compare [`Self::LAYOUT`] with naga's).
    pub struct GpuJulia2dParams<f32>;
    /// [`GpuJulia2dParams`] in f64, for the f64 module of shaders/julia2d.wgsl.
    pub struct GpuJulia2dParams64<f64>;
    fn new(scene) {
        let v = &scene.view2d;
        let (w, h) = (scene.image.width, scene.image.height);
        let half = 0.5 * v.extent;
    }
    fields {
        /// c = c.x + c.y i.
        c: Vec2 = Vec2::from_f64([scene.fractal.c[0], scene.fractal.c[1]]),
        /// The complex number at the image's centre.
        center: Vec2 = Vec2::from_f64(v.center),
        /// Half the image's width and height in the complex plane: extent / 2 and
        /// extent / 2 * height / width.
        half_extent: Vec2 = Vec2::from_f64([half, half * h as f64 / w as f64]),
        max_iterations: u32 = v.max_iterations,
        width: u32 = w,
        height: u32 = h,
    }
    per_dispatch(p, row_offset, row_count) {
        /// The band of rows this dispatch computes: [row_offset, row_offset + row_count).
        row_offset: u32 = row_offset,
        row_count: u32 = row_count,
        /// Pixels per row of the output arrays (>= width; a multiple of 64 where the rows are
        /// copied into a texture).
        row_stride: u32 = p.width,
        /// The output row that the band's first row lands in.
        out_row: u32 = 0,
    }
}
