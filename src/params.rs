//! What the tracer needs of a scene, precomputed once on the host (in f64) and then rounded to
//! the precision the tracer runs in: the twin of the WGSL `Params` uniform, with the camera
//! frame and the slice's bounding ball already worked out.

use crate::algebra::{Hyper, Real, Vec2, Vec3, hyper_from_f64};
use crate::scene::{Colouring, NormalMethod, Scene, Tracing};

/// The tracer's inputs in precision `F`. Field names are those of `Params` in
/// shaders/trace.wgsl; [`crate::gpu::GpuParams`] is its `#[repr(C)]` f32 image.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceParams<F> {
    pub c: Hyper<F>,
    pub slice_x: Hyper<F>,
    pub slice_y: Hyper<F>,
    pub slice_z: Hyper<F>,
    pub slice_offset: Hyper<F>,
    pub eye: Vec3<F>,
    pub epsilon: F,
    pub cam_forward: Vec3<F>,
    pub tan_half_fov_y: F,
    pub cam_right: Vec3<F>,
    /// width / height
    pub aspect: F,
    pub cam_up: Vec3<F>,
    pub escape_radius_squared: F,
    pub light: Vec3<F>,
    /// The slice's bounding ball; <= 0 when the slice misses the 4D ball.
    pub bounds_radius_squared: F,
    pub bounds_center: Vec3<F>,
    pub normal_tint: F,
    pub diffuse: Vec3<F>,
    pub specular: F,
    pub background: Vec3<F>,
    pub shininess: F,
    pub max_iterations: u32,
    pub max_steps: u32,
    pub width: u32,
    pub height: u32,
    pub shadows: bool,
    pub shadow_factor: F,
    pub normal_method: NormalMethod,
    pub normal_delta: F,
    pub step_scale: F,
    pub pixel_epsilon: F,
    /// A pixel's footprint per unit distance, 2 tan(fov/2) / height.
    pub pixel_angle: F,
    pub tracing: Tracing,
    /// Quaternion parts of a number of the algebra: 1 quaternion, 2 octonion, 4 sedenion.
    pub algebra_parts: u32,
    /// Rays per pixel (`image.samples`).
    pub samples: u32,
    /// The light's radius (`light.radius`): 0 is a point light.
    pub light_radius: F,
    pub ambient: F,
    pub occlusion: F,
    pub colouring: Colouring,
    pub trap_radius: F,
    pub trap_scale: F,
    pub palette_phase: Vec3<F>,
    /// Whether the set is cut by the half-space cut_normal . p <= cut_offset.
    pub cut: bool,
    /// Unit length.
    pub cut_normal: Vec3<F>,
    pub cut_offset: F,
}

impl<F: Real> TraceParams<F> {
    /// The parameters of a validated scene, rounded to `F`.
    pub fn new(scene: &Scene) -> Self {
        let frame = scene.camera_frame();
        let bounds = scene.slice_bounds();
        let (f, s, sh) = (&scene.fractal, &scene.slice, &scene.shading);
        Self {
            c: hyper_from_f64(&f.c),
            slice_x: hyper_from_f64(&s.x),
            slice_y: hyper_from_f64(&s.y),
            slice_z: hyper_from_f64(&s.z),
            slice_offset: hyper_from_f64(&s.offset),
            eye: Vec3::from_f64(scene.camera.eye),
            epsilon: F::lit(f.epsilon),
            cam_forward: Vec3::from_f64(frame.forward),
            tan_half_fov_y: F::lit(frame.tan_half_fov_y),
            cam_right: Vec3::from_f64(frame.right),
            aspect: F::lit(scene.image.width as f64 / scene.image.height as f64),
            cam_up: Vec3::from_f64(frame.up),
            escape_radius_squared: F::lit(f.escape_radius_squared.min(F::ESCAPE_LIMIT)),
            light: Vec3::from_f64(scene.light.position),
            bounds_radius_squared: F::lit(bounds.radius_squared),
            bounds_center: Vec3::from_f64(bounds.center),
            normal_tint: F::lit(sh.normal_tint),
            diffuse: Vec3::from_f64(sh.diffuse),
            specular: F::lit(sh.specular),
            background: Vec3::from_f64(sh.background),
            shininess: F::lit(sh.shininess),
            max_iterations: f.max_iterations,
            max_steps: f.max_steps,
            width: scene.image.width,
            height: scene.image.height,
            shadows: sh.shadows,
            shadow_factor: F::lit(sh.shadow_factor),
            normal_method: sh.normal,
            normal_delta: F::lit(sh.normal_delta),
            step_scale: F::lit(f.step_scale),
            pixel_epsilon: F::lit(f.pixel_epsilon),
            pixel_angle: F::lit(scene.pixel_angle()),
            tracing: f.tracing,
            algebra_parts: f.algebra.parts(),
            samples: scene.image.samples,
            light_radius: F::lit(scene.light.radius),
            ambient: F::lit(sh.ambient),
            occlusion: F::lit(sh.occlusion),
            colouring: sh.colouring,
            trap_radius: F::lit(sh.trap_radius),
            trap_scale: F::lit(sh.trap_scale),
            palette_phase: Vec3::from_f64(sh.palette_phase),
            cut: scene.cut.enabled,
            cut_normal: Vec3::from_f64(unit(scene.cut.normal)),
            cut_offset: F::lit(scene.cut.offset),
        }
    }
}

/// `v` scaled to unit length (validation has made sure it is not zero); divided by its largest
/// component first, so that neither a tiny nor a huge v under- or overflows.
fn unit(v: [f64; 3]) -> [f64; 3] {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let v = if m > 0.0 { v.map(|x| x / m) } else { v };
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n > 0.0 {
        v.map(|x| x / n)
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// What the 2D Julia kernel needs of a scene (`view2d` and the first two components of
/// `fractal.c`), precomputed in f64 and rounded to `F`. Field names are those of
/// `Julia2dParams` in shaders/julia2d.wgsl; [`crate::gpu::GpuJulia2dParams`] is its f32 image.
#[derive(Clone, Debug, PartialEq)]
pub struct Julia2dParams<F> {
    /// c = c.x + c.y i.
    pub c: Vec2<F>,
    /// The complex number at the image's centre.
    pub center: Vec2<F>,
    /// Half the image's width and height in the complex plane: extent / 2 and
    /// extent / 2 * height / width.
    pub half_extent: Vec2<F>,
    pub max_iterations: u32,
    pub width: u32,
    pub height: u32,
}

impl<F: Real> Julia2dParams<F> {
    /// The parameters of a validated scene, rounded to `F`.
    pub fn new(scene: &Scene) -> Self {
        let v = &scene.view2d;
        let (w, h) = (scene.image.width, scene.image.height);
        let half = 0.5 * v.extent;
        Self {
            c: Vec2::from_f64([scene.fractal.c[0], scene.fractal.c[1]]),
            center: Vec2::from_f64(v.center),
            half_extent: Vec2::from_f64([half, half * h as f64 / w as f64]),
            max_iterations: v.max_iterations,
            width: w,
            height: h,
        }
    }
}
