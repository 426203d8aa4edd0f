//! The scene: plain data describing one picture, its defaults (the seed's constants) and its
//! validation. Every key is declared once, below, with its type, default, range, README comment
//! and explorer slider ([`schema`]); loading from TOML, `--set` and PNGs lives in `load` ([`SceneLoader`]).

pub mod animation;
mod choices;
mod error;
mod exr;
mod image;
mod limits;
mod load;
pub mod loaded;
mod png;
pub mod presets;
pub mod rotation;
pub mod schema;

pub use self::image::{Denoiser, ToneMap};
pub use choices::{Algebra, Colouring, NormalMethod, PathSampler, ShadingModel, Tracing, View};
pub use error::{SceneError, SceneSource, one_line};
pub use exr::{SCENE_EXR_ATTRIBUTE, scene_from_exr, scene_from_exr_bytes};
pub use limits::{SCENE_TEXT_LIMIT, SET_LIMIT};
pub use load::{SceneLoader, check_scene_length};
pub use loaded::Loaded;
pub use png::{SCENE_PNG_KEYWORD, scene_from_png, scene_from_png_bytes};

use schema::{Range, scene_schema};

scene_schema! {
    /// Everything one picture depends on. Defaults reproduce the seed's constants (docs/CONTRACT.md).
    pub struct Scene {
        fractal: Fractal "" {
            /// The algebra z and c live in: quaternions (4D), octonions (8D) or sedenions (16D).
            algebra: Algebra = Algebra::Quaternion, choice(),
                "\"quaternion\", \"octonion\" or \"sedenion\": 4, 8 or 16 numbers in c and the slice";
            /// The Julia constant, `[real, i, j, k, ...]`: as many numbers as the algebra has
            /// dimensions.
            c: Vec<f64> = vec![-0.2, 0.6, 0.2, 0.2], hyper(), slider(-1.5, 1.5),
                "the Julia constant";
            /// Iterations of z <- z^2 + c per distance estimate.
            max_iterations: u32 = 10, integer(1, 100_000), slider(1, 200, log),
                "iterations of z <- z^2 + c per distance estimate ({range})";
            /// |z|^2 above this counts as escaped (the seed's ESCAPE_THRESHOLD).
            escape_radius_squared: f64 = 10.0, float(Range::above(0.0)), slider(4.0, 1e6, log),
                "|z|^2 above this counts as escaped ({range})";
            /// A ray hits when the distance estimate drops below this.
            epsilon: f64 = 0.003, float(Range::above(0.0)), slider(1e-5, 0.1, log),
                "a ray hits when the distance estimate drops below this ({range})";
            /// The 4D ball |q|^2 <= this bounds the set.
            bounding_radius_squared: f64 = 3.0, float(Range::above(0.0)), slider(0.5, 16.0),
                "the 4D ball |q|^2 <= this bounds the set ({range})";
            /// Sphere-tracing steps per ray before giving up (a miss).
            max_steps: u32 = 1000, integer(1, 1_000_000), slider(1, 5000, log),
                "sphere-tracing steps per ray before giving up ({range})";
            /// Over-relaxation of sphere-tracing steps (omega in (0, 2]; 1 is the seed's plain
            /// step). Above 1, steps are omega d with a safe fallback when they overshoot.
            step_scale: f64 = 1.0, float(Range::open_closed(0.0, 2.0)), slider(0.5, 2.0),
                "over-relaxed steps omega d, {range}, with a safe fallback; 1 = the seed";
            /// Also hit where d < pixel_epsilon times the pixel's footprint at that distance (0:
            /// off, the seed's fixed epsilon only).
            pixel_epsilon: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 4.0),
                "also hit below this many pixel footprints, {range} (0 = off, the seed)";
            /// "seed": every ray sphere-traced from the bounding ball (docs/CONTRACT.md's
            /// definitions, exactly); "cone": each 8x8 block of rays first marches one cone, and
            /// its rays start where the cone stopped.
            tracing: Tracing = Tracing::Seed, choice(),
                "\"seed\" (the contract's definitions, exactly) or \"cone\" (one cone per 8x8 block first)";
        }

        /// The 3D slice of the algebra's space: p -> offset + p.x*x + p.y*y + p.z*z, each vector
        /// with as many numbers as the algebra has dimensions.
        slice: Slice "the 3D slice of 4D space: p -> offset + p.x*x + p.y*y + p.z*z" {
            x: Vec<f64> = vec![1.0, 0.0, 0.0, 0.0], hyper(),
                "orthonormal; within 1e-3 of it, re-orthonormalised";
            y: Vec<f64> = vec![0.0, 1.0, 0.0, 0.0], hyper(), "";
            z: Vec<f64> = vec![0.0, 0.0, 1.0, 0.0], hyper(), "";
            offset: Vec<f64> = vec![0.0; 4], hyper(), slider(-1.5, 1.5), "";
        }

        camera: Camera "" {
            eye: [f64; 3] = [0.0, 0.0, 3.0], vector(), "";
            target: [f64; 3] = [0.0, 0.0, 0.0], vector(), "!= eye";
            up: [f64; 3] = [0.0, 1.0, 0.0], vector(), "not parallel to target - eye";
            fov_y_degrees: f64 = 45.0, float(Range::open(0.0, 180.0)), slider(1.0, 170.0),
                "{range}";
            /// The thin lens's radius (depth of field): 0 is the pinhole, the seed's camera.
            /// Only samples 1.. go through the lens (image.samples > 1 blurs).
            aperture: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 0.5),
                "thin-lens radius, {range} (0 = the pinhole, the seed); every sample through the lens; blurs with image.samples > 1";
            /// The distance from the eye of the plane in focus, along the view direction; 0
            /// is |target - eye|.
            focus_distance: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 10.0),
                "the plane in focus, {range} from the eye along the view (0 = |target - eye|)";
            /// The aperture's shape: 0 a disc, 3..16 a regular polygon of that many blades
            /// inscribed in the disc (1 and 2 are refused).
            blades: u32 = 0, integer(0, 16),
                "0 = a round aperture, 3..16 a regular polygon of that many blades ({range}, not 1 or 2)";
            /// The polygon's turn about the view direction, in degrees (its first corner
            /// toward camera right at 0).
            blade_rotation: f64 = 0.0, float(Range::ANY), slider(0.0, 360.0),
                "degrees, the polygon's first corner toward the camera's right at 0";
        }

        light: Light "" {
            position: [f64; 3] = [2.0, 2.0, 3.0], vector(), slider(-6.0, 6.0),
                "the light's centre";
            /// The light's radius: 0 is the seed's point light with hard shadows; above 0 the
            /// light is a sphere and shadows have a penumbra.
            radius: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 1.0),
                "a sphere of this radius, {range}: soft shadows (0 = a point light, the seed)";
            /// Path mode: the sphere light's intensity, the irradiance it gives a surface facing
            /// it at distance 1 (white); 0 is no sphere light. Radius 0 is a point light.
            intensity: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 50.0),
                "path mode: the irradiance at distance 1, {range} (0 = no sphere light)";
        }

        /// Path mode: the radiance of rays that leave the bounding region, a gradient about
        /// `up` (docs/book/light.md gives the function).
        sky: Sky "path mode: the radiance of rays that leave the bounding region" {
            /// The colour straight up (linear).
            zenith: [f64; 3] = [0.35, 0.45, 0.6], vector(Range::at_least(0.0)),
                "linear colour straight up, {range}";
            /// The colour at the horizon (linear).
            horizon: [f64; 3] = [0.75, 0.8, 0.85], vector(Range::at_least(0.0)),
                "linear colour at the horizon, {range}";
            /// The colour straight down (linear).
            ground: [f64; 3] = [0.25, 0.24, 0.22], vector(Range::at_least(0.0)),
                "linear colour straight down, {range}";
            /// The sky's up direction, normalised when read; must not be zero.
            up: [f64; 3] = [0.0, 1.0, 0.0], vector(), "the gradient's up; not zero";
            intensity: f64 = 1.0, float(Range::at_least(0.0)), slider(0.0, 4.0),
                "the colours are multiplied by this, {range}";
        }

        /// Path mode: a distant disc light.
        sun: Sun "path mode: a distant disc light" {
            /// Toward the sun, normalised when read; the seed's light (2, 2, 3) seen from the
            /// origin.
            direction: [f64; 3] = [2.0, 2.0, 3.0], vector(), slider(-1.0, 1.0),
                "toward the sun; not zero";
            /// The disc's angular radius in degrees; the real sun's 0.53 / 2 is 0.27.
            angular_radius_degrees: f64 = 0.53, float(Range::open_closed(0.0, 90.0)),
                slider(0.05, 20.0, log),
                "the disc's angular radius in degrees, {range}";
            colour: [f64; 3] = [1.0, 1.0, 1.0], vector(Range::at_least(0.0)),
                "linear colour, {range}";
            /// The irradiance the sun gives a surface facing it (times the colour).
            intensity: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 20.0),
                "the irradiance on a surface facing it, {range} (0 = no sun)";
        }

        /// An HDR environment (docs/book/atmosphere.md): an equirectangular map about `sky.up`,
        /// path mode's sky (importance-sampled light) and phong mode's background.
        environment: Environment "an HDR equirectangular map about sky.up: path mode's sky, phong mode's background" {
            /// The map: OpenEXR (`.exr`) or Radiance (`.hdr`), exactly twice as wide as high,
            /// linear RGB, row 0 at the zenith; `qjulia:NAME` is a map built into the binary.
            /// Empty: none (path mode's gradient sky, phong mode's flat background).
            file: String = String::new(), path(),
                "an equirectangular .exr or .hdr, 2:1, resolved against the scene file's folder (\"\" = none; \"qjulia:dusk.hdr\" is built in)";
            /// The map's turn about `sky.up`, in degrees: its left edge (u = 0) faces the
            /// frame's front at 0 (docs/book/atmosphere.md).
            rotation_degrees: f64 = 0.0, float(Range::ANY), slider(0.0, 360.0),
                "degrees about sky.up";
            /// The map's radiance is multiplied by this.
            intensity: f64 = 1.0, float(Range::at_least(0.0)), slider(0.0, 8.0, log),
                "the map's radiance is multiplied by this, {range}";
            /// The CRC-32 of the map's file: recorded in the scene of every picture rendered
            /// with it, and verified when a scene that records it loads the map again (0: not
            /// recorded).
            checksum: u32 = 0, integer(0, 4_294_967_295),
                "the map file's CRC-32, recorded when it loads and verified after, {range} (0 = unchecked)";
        }

        /// A homogeneous medium filling the bounding region (docs/book/atmosphere.md): path mode
        /// scatters light in it (light shafts through the set), phong mode blends toward its
        /// colour.
        fog: Fog "a homogeneous medium filling the bounding region: light shafts in path mode" {
            /// The extinction coefficient sigma_t per unit length, grey (0: no fog).
            density: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 4.0),
                "extinction per unit length, {range} (0 = no fog)";
            /// The single-scattering albedo (path mode), the colour blended toward (phong mode).
            colour: [f64; 3] = [0.8, 0.8, 0.8], vector(Range::closed(0.0, 1.0)),
                "single-scattering albedo (path), the colour blended toward (phong), {range}";
            /// Path mode: the Henyey-Greenstein g (0 isotropic, > 0 forward scattering).
            anisotropy: f64 = 0.0, float(Range::open(-1.0, 1.0)), slider(-0.95, 0.95),
                "path mode: Henyey-Greenstein g, {range} (0 = isotropic, > 0 forward)";
        }

        /// Phong mode: a halo around the set, added to rays that miss by how close they came.
        glow: Glow "phong mode: a halo around the set on rays that miss" {
            /// Linear colour of the halo.
            colour: [f64; 3] = [1.0, 0.6, 0.3], vector(Range::closed(0.0, 1.0)),
                "linear colour, {range}";
            /// The halo's brightness where a ray grazes the set (0: off).
            strength: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 4.0),
                "colour += strength x colour x exp(-d_min / radius), {range} (0 = off)";
            /// The distance over which the halo falls to 1/e.
            radius: f64 = 0.1, float(Range::above(0.0)), slider(0.005, 1.0, log),
                "the halo falls to 1/e over this distance, {range}";
        }

        shading: Shading "" {
            /// How hits are lit: the seed's Phong, or the path tracer (docs/book/path.md).
            model: ShadingModel = ShadingModel::Phong, choice(),
                "\"phong\" (the seed's lighting) or \"path\" (the path tracer)";
            /// Cast a shadow ray from every hit toward the light.
            shadows: bool = true, boolean(), "cast a shadow ray from every hit";
            /// How the shading normal is computed: the seed's central differences, four
            /// tetrahedral samples, or the analytic gradient.
            normal: NormalMethod = NormalMethod::Central, choice(),
                "\"central\" (the seed), \"tetrahedral\" or \"analytic\" (exact gradient)";
            /// The finite-difference step of the central and tetrahedral normals (the seed's
            /// 1e-4).
            normal_delta: f64 = 1e-4, float(Range::ANY), slider(1e-6, 1e-2, log),
                "finite-difference step of the central and tetrahedral normals";
            /// The base (diffuse) colour; the seed's (1, 0.45, 0.25).
            diffuse: [f64; 3] = [1.0, 0.45, 0.25], vector(Range::closed(0.0, 1.0)),
                "base colour, {range}";
            /// How much of |N| tints the diffuse colour; the seed's 0.3.
            normal_tint: f64 = 0.3, float(Range::at_least(0.0)), slider(0.0, 1.0),
                "colour += normal_tint * |N|, {range}";
            /// Amplitude of the specular highlight; the seed's 0.45.
            specular: f64 = 0.45, float(Range::at_least(0.0)), slider(0.0, 2.0),
                "highlight amplitude, {range}";
            /// Phong exponent; the seed's 10.
            shininess: f64 = 10.0, float(Range::at_least(0.0)), slider(0.0, 200.0, log),
                "Phong exponent, {range}";
            /// A shadowed hit's colour is multiplied by this; the seed's 0.4.
            shadow_factor: f64 = 0.4, float(Range::closed(0.0, 1.0)), slider(0.0, 1.0),
                "a shadowed hit's colour is multiplied by this, {range}";
            /// Colour of rays that hit nothing; the seed's grey 0.3.
            background: [f64; 3] = [0.3, 0.3, 0.3], vector(Range::closed(0.0, 1.0)),
                "colour of rays that hit nothing, {range}";
            /// The ambient term's light: with an environment map, its irradiance at the hit's
            /// normal (divided by pi, prefiltered on the host) in place of white.
            environment_light: bool = false, boolean(),
                "the ambient term takes the environment map's irradiance (needs environment.file)";
            /// Light that reaches every hit, times the base colour and the occlusion.
            ambient: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 1.0),
                "colour += ambient * occlusion factor * base colour, {range} (0 = the seed)";
            /// Strength of the ambient occlusion from distance estimates along the normal.
            occlusion: f64 = 0.0, float(Range::closed(0.0, 1.0)), slider(0.0, 1.0),
                "ambient occlusion's strength, {range} (0 = off)";
            /// Where the base colour comes from: the diffuse colour, or the hit's orbit.
            colouring: Colouring = Colouring::Flat, choice(),
                "\"flat\" (the diffuse colour, the seed) or \"orbit_trap\" (the orbit's closest approach to the trap)";
            /// The trap: the sphere |z| = trap_radius of the algebra's space.
            trap_radius: f64 = 0.5, float(Range::at_least(0.0)), slider(0.0, 2.0),
                "the orbit trap, the sphere |z| = trap_radius, {range}";
            /// How many times the palette repeats per unit of trap distance.
            trap_scale: f64 = 1.0, float(Range::above(0.0)), slider(0.05, 20.0, log),
                "palette cycles per unit of trap distance, {range}";
            /// The palette's phase per channel: colour = 0.5 + 0.5 cos(2 pi (scale t + phase)).
            palette_phase: [f64; 3] = [0.0, 0.1, 0.2], vector(Range::closed(0.0, 1.0)),
                slider(0.0, 1.0),
                "the palette's phase per channel, {range}";
        }

        /// Path mode: the surface's BSDF, Lambert plus GGX (docs/book/materials.md); the albedo
        /// is the colouring's colour (`shading.diffuse`, or the orbit trap's palette).
        material: Material "path mode: Lambert plus GGX; the albedo is the colouring's colour" {
            /// GGX roughness, alpha = roughness^2, floored at 0.02.
            roughness: f64 = 0.3, float(Range::closed(0.0, 1.0)), slider(0.0, 1.0),
                "GGX roughness, {range} (alpha = roughness^2, at least 0.02^2)";
            metallic: f64 = 0.0, float(Range::closed(0.0, 1.0)), slider(0.0, 1.0),
                "0 a dielectric, 1 a metal of the albedo's colour, {range}";
            /// A dielectric's reflectance at normal incidence is 0.08 x this.
            specular: f64 = 0.5, float(Range::closed(0.0, 1.0)), slider(0.0, 1.0),
                "dielectric F0 = 0.08 x specular, {range}";
            /// Kulla and Conty's multiple-scattering lobe: the light a rough GGX lobe loses to
            /// single scattering, given back (docs/book/materials.md). On by default: the
            /// energy-conserving material is the right one; off is the single-scattering lobe
            /// of before, for comparison.
            multiscatter: bool = true, boolean(),
                "Kulla and Conty's multiple scattering for the GGX lobe (true: a white rough metal reflects all it receives)";
            /// The radiance the surface emits, times its albedo (the colouring's colour): one
            /// number for all three channels, or an RGB triple (0: none).
            emission: [f64; 3] = [0.0, 0.0, 0.0], vector_or_number(Range::at_least(0.0)),
                "emitted radiance x albedo: a number or [r, g, b], {range} (0 = none)";
        }

        /// Path mode: the paths (docs/book/path.md); adaptive sampling, in either model
        /// (docs/book/adaptive.md).
        path: Path "path mode: the paths; adaptive sampling in either model" {
            /// Scattering events at the surface: 1 is direct light only.
            bounces: u32 = 3, integer(1, 16), slider(1, 16),
                "scattering events at the surface ({range}; 1 = direct light only)";
            /// Each contribution after the first event is scaled down to at most this in its
            /// largest channel (0: off). Biased: it darkens caustics and bright indirect light.
            clamp: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 100.0),
                "a contribution after the first event is clamped to this, {range} (0 = off)";
            sampler: PathSampler = PathSampler::Sobol, choice(),
                "\"sobol\" (Owen-scrambled, the same bits on every backend) or \"random\"";
            /// Adaptive sampling, in either model (docs/book/adaptive.md): a pixel's samples
            /// alternate between two streams, each of which stops once the standard error of its
            /// own mean luminance, relative to that mean (at least `NOISE_LUMINANCE_FLOOR`), is
            /// at most this; the pixel shows both streams' halves, cross-fitted (0: off, every
            /// pixel takes `image.samples`).
            noise_target: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 0.5),
                "adaptive sampling, either model: a pixel stops once its mean's relative standard error is at most this, {range} (0 = off)";
            /// No pixel stops before max(min(min_samples, image.samples), 4) samples (4: two of
            /// each stream, one sample has no variance).
            min_samples: u32 = 16, integer(1, 4096), slider(1, 1024, log),
                "adaptive sampling's floor: max(min(min_samples, image.samples), 4) samples, {range}";
            /// Path regularisation (docs/book/path.md): after a vertex that scattered by the
            /// cosine lobe, every later GGX lobe is at least this rough. 0 is off: it is a
            /// bias, traded for the glints' noise.
            regularize: f64 = 0.0, float(Range::closed(0.0, 1.0)), slider(0.0, 1.0),
                "after a diffuse scattering, later GGX lobes are at least this rough, {range} (0 = off: it is a bias)";
            /// The sampler's seed: 0 the default; each other seed draws independently
            /// scrambled points (independent renders of one scene).
            seed: u32 = 0, integer(0, 4_294_967_295), slider(0, 1000),
                "the sampler's seed: each seed gives independent noise, {range}";
            /// With `animate`, frame k renders with seed `seed + k` (its PNG's scene says so),
            /// so that the noise moves between frames and no split of the frames changes it.
            animated_seed: bool = false, boolean(),
                "animate: frame k renders with path.seed + k, the noise moving between frames";
            /// Shadow and bounce rays step omega d, over-relaxed with sphere tracing's fallback
            /// (as `fractal.step_scale` steps camera rays): 1.6 traced the seed's set with 15%
            /// fewer estimates than 1 (docs/PERFORMANCE.md). 1 is plain.
            step_scale: f64 = 1.6, float(Range::open_closed(0.0, 2.0)), slider(0.5, 2.0),
                "shadow and bounce rays step omega d, with a safe fallback, {range} (1 = plain)";
        }

        image: Image "" {
            width: u32 = 512, integer(1, 65536), slider(1, 8192, log), "{range}";
            height: u32 = 512, integer(1, 65536), slider(1, 8192, log), "{range}";
            /// Rays per pixel: sample 0 through the centre, the others at the pixel's Halton
            /// (2, 3) points; the clamped colours are averaged.
            samples: u32 = 1, integer(1, 4096), slider(1, 1024, log),
                "rays per pixel, averaged ({range}; 1 = the seed)";
            /// What `render` draws: the shaded picture, or a heat map of the work per pixel.
            view: View = View::Shaded, choice(),
                "what render's PNG shows: \"shaded\", \"steps\", \"divergence\" or \"samples\" (--view)";
            /// Path mode: the linear image is multiplied by 2^exposure before the tone map.
            exposure: f64 = 0.0, float(Range::ANY), slider(-8.0, 8.0),
                "path mode: stops (x 2^exposure) before the tone map";
            /// Path mode: the curve from exposed linear radiance to [0, 1] (docs/book/display.md).
            tone_map: ToneMap = ToneMap::None, choice(),
                "path mode: \"none\" (a clamp), \"reinhard\" or \"aces\" (Narkowicz 2015)";
            /// The denoiser run on the linear image before the display transform, in either
            /// model (docs/book/denoise.md); its parameters are the `[denoise]` table.
            denoise: Denoiser = Denoiser::None, choice(),
                "\"none\" or \"atrous\" (edge-avoiding, guided by albedo, normal, depth and variance)";
            /// Path mode: the whole image's relative RMSE to render to (`--stats`'
            /// `estimated_relative_rmse`, docs/book/error.md): passes of more samples until the
            /// estimate is at most this or `samples` is spent (0: off, one pass of `samples`).
            /// Not `path.noise_target`, which is each pixel's.
            target_error: f64 = 0.0, float(Range::at_least(0.0)), slider(0.0, 0.2),
                "path mode: the image's estimated relative RMSE to stop at, {range} (0 = off; image.samples is the most)";
        }

        /// The denoiser's parameters (`image.denoise = "atrous"`, docs/book/denoise.md).
        denoise: Denoise "the denoiser's parameters (image.denoise = \"atrous\")" {
            /// Passes of the a-trous filter; pass k spaces its 5 x 5 taps 2^k pixels apart.
            iterations: u32 = 5, integer(1, 10), slider(1, 10),
                "a-trous passes, {range}: the filter reaches 2 (2^iterations - 1) pixels";
            /// How far a neighbour's luminance may differ, in standard deviations of the
            /// pixel's noise (0: luminance is not an edge).
            sigma_luminance: f64 = 2.0, float(Range::at_least(0.0)), slider(0.0, 16.0),
                "luminance edges, in standard deviations of the noise, {range} (0 = off)";
            /// The exponent of the normals' cosine (0: normals are not edges).
            sigma_normal: f64 = 16.0, float(Range::at_least(0.0)), slider(0.0, 256.0),
                "the exponent of the normals' cosine, {range} (0 = off)";
            /// How far a neighbour's depth may stray from the local plane, in multiples of the
            /// depth's change across the offset (0: depth is not an edge).
            sigma_depth: f64 = 4.0, float(Range::at_least(0.0)), slider(0.0, 16.0),
                "depth edges, in multiples of the depth's slope, {range} (0 = off)";
        }

        /// A cut: the set is intersected with the half-space normal . p <= offset (slice
        /// coordinates), showing its inside on the cut face.
        cut: Cut "the set within the half-space normal . p <= offset (slice coordinates)" {
            enabled: bool = false, boolean(), "cut the set (false = the whole set, the seed)";
            /// The plane's normal, normalised when read; must not be zero.
            normal: [f64; 3] = [0.0, 0.0, 1.0], vector(), "the plane's normal; not zero";
            offset: f64 = 0.0, float(Range::ANY), slider(-1.5, 1.5),
                "the plane's distance from the origin along the normal";
        }

        /// The 2D Julia view of `qjulia render2d` and the explorer's 2D mode: the filled Julia
        /// set of the complex c = `c[0] + c[1] i` (the first two components of `fractal.c`),
        /// imaginary axis up.
        view2d: View2d "the 2D Julia view (render2d, the explorer's 2D mode)" {
            /// The complex number at the image's centre, `[real, imaginary]`.
            center: [f64; 2] = [0.0, 0.0], vector(),
                "the complex number at the image's centre, [real, imaginary]; finite";
            /// The width of the image in the complex plane (the height follows the image's
            /// aspect).
            extent: f64 = 4.0, float(Range::above(0.0)), slider(1e-6, 64.0, log),
                "the image's width in the complex plane, finite and {range}";
            /// Iterations of z <- z^2 + c before a point counts as in the set.
            max_iterations: u32 = 256, integer(1, 100_000), slider(1, 5000, log),
                "iterations before a point counts as in the set ({range})";
        }
    }
}

impl Slice {
    /// The standard axes 1, i, j in `dim` dimensions.
    pub fn axes(&self, dim: usize) -> [Vec<f64>; 3] {
        std::array::from_fn(|a| (0..dim).map(|k| if k == a { 1.0 } else { 0.0 }).collect())
    }
}

/// The Euclidean inner product of two vectors (of equal length).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Gram-Schmidt in x, y, z order; None where the vectors are (nearly) dependent.
pub fn orthonormalise(basis: [&[f64]; 3]) -> Option<[Vec<f64>; 3]> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for v in basis {
        let mut w = v.to_vec();
        for u in &out {
            let d = dot(u, &w);
            for (wk, uk) in w.iter_mut().zip(u) {
                *wk -= d * uk;
            }
        }
        let length = dot(&w, &w).sqrt();
        if length.is_nan() || length <= 1e-9 {
            return None;
        }
        out.push(w.iter().map(|x| x / length).collect());
    }
    out.try_into().ok()
}

impl Scene {
    /// The full scene as TOML, every key written, so that it renders again identically.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a scene always serialises to TOML")
    }

    /// The camera's orthonormal frame (forward, right, up) as docs/CONTRACT.md defines it.
    /// Valid for any validated scene.
    pub fn camera_frame(&self) -> CameraFrame {
        let eye = glam::DVec3::from_array(self.camera.eye);
        let target = glam::DVec3::from_array(self.camera.target);
        let forward = (target - eye).normalize();
        let right = forward
            .cross(glam::DVec3::from_array(self.camera.up))
            .normalize();
        let up = right.cross(forward);
        CameraFrame {
            forward: forward.to_array(),
            right: right.to_array(),
            up: up.to_array(),
            tan_half_fov_y: (self.camera.fov_y_degrees.to_radians() * 0.5).tan(),
        }
    }

    /// The focus plane's distance from the eye along the view direction: `camera.focus_distance`,
    /// or |target - eye| where that is 0.
    pub fn focus_distance(&self) -> f64 {
        if self.camera.focus_distance > 0.0 {
            return self.camera.focus_distance;
        }
        let eye = glam::DVec3::from_array(self.camera.eye);
        let target = glam::DVec3::from_array(self.camera.target);
        (target - eye).length()
    }

    /// Whether a render adds passes until its estimated error is at most `image.target_error`
    /// (path mode, a target > 0 and `image.samples` > 1; docs/book/error.md).
    pub fn targets_error(&self) -> bool {
        self.image.target_error > 0.0
            && self.image.samples > 1
            && self.shading.model == ShadingModel::Path
    }

    /// Whether pixels are sampled adaptively (`path.noise_target` > 0 with `image.samples` >
    /// 1: a pixel stops once its noise is at most the target; docs/book/adaptive.md).
    pub fn adaptive(&self) -> bool {
        self.path.noise_target > 0.0 && self.image.samples > 1
    }

    /// A pixel's footprint per unit of distance along the ray: 2 tan(fov/2) / height.
    pub fn pixel_angle(&self) -> f64 {
        2.0 * (self.camera.fov_y_degrees.to_radians() * 0.5).tan() / self.image.height as f64
    }

    /// The 3D ball that the 4D bounding ball cuts out of the slice: centre `-B^T w` and
    /// radius^2 `bounding_radius_squared - |w - B B^T w|^2` (empty when that is <= 0).
    pub fn slice_bounds(&self) -> SliceBounds {
        let w = &self.slice.offset;
        let basis = [&self.slice.x, &self.slice.y, &self.slice.z];
        let coords = basis.map(|b| dot(b, w));
        let off_slice: f64 = (0..w.len())
            .map(|k| {
                let v = w[k] - (0..3).map(|a| basis[a][k] * coords[a]).sum::<f64>();
                v * v
            })
            .sum();
        SliceBounds {
            center: [-coords[0], -coords[1], -coords[2]],
            radius_squared: self.fractal.bounding_radius_squared - off_slice,
        }
    }

    /// Changes the algebra, keeping what fits: c, the slice axes and the offset are cut or
    /// padded with zeros to its dimension (the axes stay orthonormal: they lie in the first
    /// four dimensions unless rotated out, and cutting a rotated axis re-orthonormalises it).
    pub fn set_algebra(&mut self, algebra: Algebra) {
        let dim = algebra.dim();
        self.fractal.algebra = algebra;
        for v in [
            &mut self.fractal.c,
            &mut self.slice.x,
            &mut self.slice.y,
            &mut self.slice.z,
            &mut self.slice.offset,
        ] {
            v.resize(dim, 0.0);
        }
        let [x, y, z] = orthonormalise([&self.slice.x, &self.slice.y, &self.slice.z])
            .unwrap_or_else(|| Slice::default().axes(dim));
        (self.slice.x, self.slice.y, self.slice.z) = (x, y, z);
    }
}

/// The camera's orthonormal frame and the tangent of half the vertical field of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    pub forward: [f64; 3],
    pub right: [f64; 3],
    pub up: [f64; 3],
    pub tan_half_fov_y: f64,
}

/// The bounding ball in slice coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliceBounds {
    pub center: [f64; 3],
    /// <= 0 means the slice misses the 4D ball: everything is background.
    pub radius_squared: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_camera_frame_looks_down_minus_z() {
        let f = Scene::default().camera_frame();
        assert_eq!(f.forward, [0.0, 0.0, -1.0]);
        assert_eq!(f.right, [1.0, 0.0, 0.0]);
        assert_eq!(f.up, [0.0, 1.0, 0.0]);
    }

    #[test]
    fn slice_bounds_of_an_offset_slice() {
        let mut s = Scene::default();
        // offset (0.5, 0, 0, 0.6): 0.5 lies in the slice (along x), 0.6 off it (along k).
        s.slice.offset = vec![0.5, 0.0, 0.0, 0.6];
        let b = s.slice_bounds();
        assert_eq!(b.center, [-0.5, -0.0, -0.0]);
        assert!((b.radius_squared - (3.0 - 0.36)).abs() < 1e-12);
    }
}
