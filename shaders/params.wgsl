// The tracer's uniform and its switches: `struct Params` (the scene, one dispatch's band and
// samples), the uniform at binding 0 every kernel over the tracer reads, the constants that name
// params' choices, and the override constants of a scene's variant (src/gpu/variant.rs). Data
// only: the host's twin of the struct is the table of `TraceParams` in src/params.rs.
#import real
#import algebra

// Keep in sync with the table of `TraceParams` in src/params.rs, which makes the host's f32 and
// f64 images of it, `GpuParams` and `GpuParams64` (tests/architecture/shaders.rs compares their layouts with
// this struct's). Ordered so that neither precision has padding inside: the numbers of the
// algebra, the vec3s each followed by a scalar filling its slot, the other scalars, the
// integers, then the integers each dispatch sets (its band, where it lands, its samples).
struct Params {
    c: Hyper,
    slice_x: Hyper,
    slice_y: Hyper,
    slice_z: Hyper,
    slice_offset: Hyper,
    eye: vec3<Real>,
    epsilon: Real,
    cam_forward: vec3<Real>,
    tan_half_fov_y: Real,
    cam_right: vec3<Real>,
    aspect: Real,
    cam_up: vec3<Real>,
    escape_radius_squared: Real,
    light: vec3<Real>,
    bounds_radius_squared: Real,
    bounds_center: vec3<Real>,
    normal_tint: Real,
    diffuse: vec3<Real>,
    specular: Real,
    background: vec3<Real>,
    shininess: Real,
    // Orbit-trap colouring: the trap |z| = trap_radius, the palette's cycles and phase.
    palette_phase: vec3<Real>,
    trap_scale: Real,
    // The cut: the set within cut_normal . p <= cut_offset (cut_normal of unit length).
    cut_normal: vec3<Real>,
    cut_offset: Real,
    // The fog (a homogeneous medium in the bounding ball): its colour and extinction (0: none).
    fog_colour: vec3<Real>,
    fog_density: Real,
    // Phong mode's halo: its colour and strength (0: off).
    glow_colour: vec3<Real>,
    glow_strength: Real,
    // The environment map's frame (shaders/environment.wgsl): up and the turn about it in
    // radians, front (u = 0 at turn 0) and the radiance's factor.
    env_up: vec3<Real>,
    env_rotation: Real,
    env_front: vec3<Real>,
    env_intensity: Real,
    shadow_factor: Real,
    normal_delta: Real,
    step_scale: Real,
    pixel_epsilon: Real,
    pixel_angle: Real,
    // The light's radius: 0 is a point light (hard shadows).
    light_radius: Real,
    ambient: Real,
    occlusion: Real,
    trap_radius: Real,
    // The thin lens (depth of field): its radius (0: the pinhole), the focus plane's distance
    // along cam_forward, and the polygon's turn in radians.
    aperture: Real,
    focus_distance: Real,
    blade_rotation: Real,
    // Adaptive sampling: a pixel stops once its noise (pixel_noise) is at most noise_target (0:
    // off), and not before min(min_samples, samples) samples nor before 2.
    noise_target: Real,
    // The fog's Henyey-Greenstein g, and the halo's 1/e distance.
    fog_anisotropy: Real,
    glow_radius: Real,
    max_iterations: u32,
    max_steps: u32,
    width: u32,
    height: u32,
    shadows: u32,
    normal_method: u32,
    tracing: u32,
    // Quaternion parts of a number of the scene's algebra: 1 quaternion, 2 octonion, 4 sedenion.
    algebra_parts: u32,
    // Rays per pixel.
    samples: u32,
    colouring: u32,
    cut: u32,
    // The aperture's blades: 0 round, 3..16 a regular polygon.
    blades: u32,
    min_samples: u32,
    // Whether the environment map is bound (1) or not (0), and whether phong mode's ambient
    // light is its irradiance (1).
    env_map: u32,
    env_light: u32,
    // This dispatch's: the band of rows, where it lands (row_stride, out_row: see the outputs
    // below), and the samples it adds, [sample_start, sample_end).
    row_offset: u32,
    row_count: u32,
    row_stride: u32,
    out_row: u32,
    sample_start: u32,
    sample_end: u32,
}

// params.normal_method: the seed's central differences, a tetrahedron of four samples, or the
// analytic gradient (the Jacobian carried through the iteration).
const NORMAL_CENTRAL: u32 = 0u;
const NORMAL_TETRAHEDRAL: u32 = 1u;
const NORMAL_ANALYTIC: u32 = 2u;

// Per-scene specialisation (src/gpu/variant.rs): a scene's features (the algebra, the slice,
// the normal's method, cone tracing, adaptive sampling, shadows, samples, the over-relaxation,
// the pixel epsilon, shading, the cut, orbit traps, occlusion, soft shadows, the lens, fog, glow
// and the environment map) are no overrides: each is a feature of shaders/kernels.json, gated
// with `#if` where it is defined, and a scene whose variant turns it off gets a text without it
// (src/gpu/shaders.rs, split_constants). The overrides below are the host's and the device's.
// The AOVs (`--hdr`): with AOVS the kernel also writes out_aovs. Off by default and in every
// Variant: only a render that reads the AOVs back sets it, so the ordinary pipeline holds none of
// their code, and out_aovs may then be a placeholder of one pixel.
override AOVS: bool = false;
// Interleaving (issue 19): with 2, the camera rays of samples k and k + 1 of a pixel are traced
// together (sphere_trace_pair: one fused sphere trace whose estimates iterate both orbits in one
// loop, each ray stopping on its own), then each sample is shaded as alone; with 1 every camera
// ray is traced alone. The same pixels bit for bit either way. Not part of a Variant: a choice
// of the device's, which the host always sets (src/gpu/variant.rs: 2 for main, 1 for path_main,
// by measurement on lavapipe, or QJULIA_INTERLEAVE).
override INTERLEAVE: u32 = 2u;
// Compaction (adaptive sampling): with COMPACT, each later dispatch packs its workgroup's live
// pixels (those not yet done) into the workgroup's first invocations (compacted_pixel), so that
// the done ones leave whole SIMD groups idle instead of a lane in each; without it, a done
// pixel's invocation returns at once (the early-out) wherever it lies. The same pixels bit for
// bit either way. A choice of the device's, as INTERLEAVE is (src/gpu/variant.rs).
override COMPACT: bool = true;

@group(0) @binding(0) var<uniform> params: Params;
