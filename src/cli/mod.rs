//! The command line (docs/CONTRACT.md): argument parsing and wiring only. This file holds the
//! arguments and how they become a scene and a planner; `commands` runs each command,
//! `report` the reports.

mod commands;
mod report;

pub use commands::{
    animate, explore, gpu_params, info, kernel, merge, mesh, render, render2d, schema, web,
};
pub use report::report;

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use qjulia::animation::Animation;
use qjulia::precision::PrecisionChoice;
use qjulia::scene::{SceneLoader, View};
use qjulia::{Backend, Planner, Scene};

#[derive(Parser, Debug)]
#[command(
    name = "qjulia",
    version,
    about = "Ray tracing quaternion Julia sets on the GPU"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene headless to PNG (and optionally depth, steps and stats).
    Render(RenderArgs),
    /// Put the partial EXRs of `render --tile` together: checks that they are one scene's
    /// tiles covering every row once, then writes what one `render` of the scene writes, byte
    /// for byte (the PNG, --hdr, --stats but for its times).
    Merge(MergeArgs),
    /// Render the frames of the scene's [animation] to DIR/frame-NNNNN.png, each a full qjulia
    /// PNG carrying its frame's scene.
    Animate(AnimateArgs),
    /// Render the 2D Julia set of c = c[0] + c[1] i (the scene's [view2d]) to a grey PNG.
    #[command(name = "render2d")]
    Render2d(Render2dArgs),
    /// Mesh the set's surface, the shell d = epsilon that the renderer's rays stop in, as a
    /// closed triangle mesh (PLY, STL or OBJ by the file's extension), sampled on a grid of N
    /// points per axis.
    Mesh(MeshArgs),
    /// The desktop explorer: every scene value live (starts from the scene options when given,
    /// else from the last scene shown, else the default).
    Explore(ExploreArgs),
    /// List the presets (--preset NAME) and the GPU adapters wgpu finds, and say which adapter
    /// `render` would use.
    Info,
    /// Accuracy and stability reports.
    Report(ReportArgs),
    /// Print the tracer's uniform for a scene as data: its layout (WGSL `struct Params`), its
    /// bytes and the constants of the scene's variant (for a host that packs them).
    GpuParams(GpuParamsArgs),
    /// Print the WGSL of the kernels a render of the scene runs on the GPU, as composed from
    /// shaders/ for it: each kernel's name, entry point, size, fingerprint, files and override
    /// constants, and what the host does to it after the text, as `//` lines above its text.
    Kernel(KernelArgs),
    /// The scene schema and the presets, as data (`--json`): every key's type, default, range,
    /// choices, comment and slider, the loader's messages, and each preset's scene.
    Schema(SchemaArgs),
    /// Serve the browser page (web/dist, built with `npm run build` in web/) on localhost.
    Web(WebArgs),
}

/// Where the scene comes from: defaults, then --scene, then shorthands, then each --set.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Start from a named scene instead of the defaults (`qjulia info` lists them); the scene
    /// file, the shorthands and --set apply over it.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// A scene file: TOML, or a PNG written by qjulia (default: the built-in default scene).
    #[arg(long, value_name = "FILE.toml")]
    pub scene: Option<PathBuf>,
    /// Override one scene key by its dotted path, VALUE in TOML syntax (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Shorthand for image.width.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub width: Option<i64>,
    /// Shorthand for image.height.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub height: Option<i64>,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The PNG to write (default qjulia.png, unless only --depth, --steps or --hdr is asked
    /// for).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    pub output: Option<PathBuf>,
    /// Write the depth map (float32 .npy, NaN where nothing is hit).
    #[arg(long, value_name = "FILE.npy")]
    pub depth: Option<PathBuf>,
    /// Write the sphere-tracing steps per pixel (uint32 .npy).
    #[arg(long, value_name = "FILE.npy")]
    pub steps: Option<PathBuf>,
    /// Write render statistics as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Shorthand for image.view: the shaded picture, or a heat map of the steps per ray or of
    /// the wasted steps in 8x8 blocks (with a legend strip below).
    #[arg(long, value_enum, value_name = "VIEW")]
    pub view: Option<ViewArg>,
    /// Write OpenEXR (float32): R, G, B the linear mean (phong mode: the unclamped colour
    /// mean), albedo.R/G/B and N.X/Y/Z of the first hits, Z the depth (NaN on a miss), and the
    /// scene in the header (`--scene FILE.exr` reads it back).
    #[arg(long, value_name = "FILE.exr")]
    pub hdr: Option<PathBuf>,
    /// Render only the K-th (0-based) of N bands of rows, [K*H/N, (K+1)*H/N), into a partial
    /// EXR (--hdr, required; no -o, --depth or --steps): `qjulia merge` puts the parts together.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub tile: Option<String>,
    #[command(flatten)]
    pub tracer: TracerArgs,
}

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The partial EXRs of `render --tile K/N`, in any order: one scene's, every row once.
    #[arg(value_name = "PART.exr", required = true)]
    pub parts: Vec<PathBuf>,
    /// The PNG to write (default qjulia.png, unless only --hdr is asked for).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    pub output: Option<PathBuf>,
    /// Write the whole image's OpenEXR, as `render --hdr` writes it.
    #[arg(long, value_name = "FILE.exr")]
    pub hdr: Option<PathBuf>,
    /// Write the whole image's statistics as JSON, as `render --stats` (render_seconds and
    /// gpu_seconds: the sums of the parts').
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Where the denoiser runs (`image.denoise`); auto: the parts' backend, whose bytes it
    /// then gives.
    #[arg(long, value_enum, default_value_t = BackendArg::Auto)]
    pub backend: BackendArg,
}

/// Which tracer renders, and in which precision (`render`, `render2d`, `animate`).
#[derive(Args, Debug)]
pub struct TracerArgs {
    #[arg(long, value_enum, default_value_t = BackendArg::Auto)]
    pub backend: BackendArg,
    /// auto: f32 wherever f32 resolves the scene (no precision warning), else f64.
    #[arg(long, value_enum, default_value_t = PrecisionArg::Auto)]
    pub precision: PrecisionArg,
}

#[derive(Args, Debug)]
pub struct AnimateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The frames to render, A..B: 0-based and inclusive, A <= B < the frame count (default:
    /// every frame). Split a long animation into ranges to render them anywhere.
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    /// The folder for the PNG frames, created if missing (default qjulia-frames; with --video,
    /// PNG frames are written only when --out is given).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Also write a video of the frames through ffmpeg: FILE.mp4 (H.264, yuv420p) or FILE.webm
    /// (VP9); odd sizes are padded to even. With --resume, complete frames are read from --out.
    #[arg(long, value_name = "FILE.mp4|FILE.webm")]
    pub video: Option<PathBuf>,
    /// Skip frames whose PNG is already complete (written whole, with this frame's scene; with
    /// --hdr, its EXR too).
    #[arg(long)]
    pub resume: bool,
    /// Also write each frame as OpenEXR, DIR/frame-NNNNN.exr beside its PNG (the channels of
    /// `render --hdr`); needs PNG frames (--out with --video).
    #[arg(long)]
    pub hdr: bool,
    /// Write the run's statistics as JSON: frames, seconds, frames per second, backend.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Shorthand for image.view (as for `render`).
    #[arg(long, value_enum, value_name = "VIEW")]
    pub view: Option<ViewArg>,
    /// Print the animation's frame count on stdout and exit, rendering and writing nothing (for
    /// scripts that split the frames, such as scripts/slurm/submit.sh).
    #[arg(long)]
    pub frame_count: bool,
    #[command(flatten)]
    pub tracer: TracerArgs,
}

#[derive(Args, Debug)]
pub struct Render2dArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The PNG to write.
    #[arg(
        short = 'o',
        long = "output",
        value_name = "FILE.png",
        default_value = "qjulia.png"
    )]
    pub output: PathBuf,
    /// Write render statistics as JSON (hits: points in the set; steps: iterations).
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    #[command(flatten)]
    pub tracer: TracerArgs,
}

#[derive(Args, Debug)]
pub struct WebArgs {
    /// The port (0: any free one, printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// The address to listen on; other machines reach the page only where this is not the
    /// loopback address.
    #[arg(long, default_value = "127.0.0.1")]
    pub host: std::net::IpAddr,
    /// The built page (default: web/dist of the sources this binary was built from).
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct SchemaArgs {
    /// Print JSON (the only format, so required).
    #[arg(long, required = true)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct GpuParamsArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The module and layout (the browser's host is f32-only).
    #[arg(long, value_parser = ["f32", "f64"], default_value = "f32")]
    pub precision: String,
    /// Print JSON (the only format, so required): see README.md.
    #[arg(long, required = true)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct KernelArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The kernels' precision, as `render` decides it (auto: f32 wherever f32 resolves the
    /// scene).
    #[arg(long, value_enum, default_value_t = PrecisionArg::Auto)]
    pub precision: PrecisionArg,
    /// Print JSON instead: a list of the kernels, each with its name, entry, files, bytes,
    /// fingerprint, overrides, after and text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct MeshArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Grid points per axis, from 8 to 4096, over the cube around the bounding region (or the
    /// box).
    #[arg(long, value_name = "N", default_value_t = qjulia::mesh::DEFAULT_RESOLUTION as i64, allow_negative_numbers = true)]
    pub resolution: i64,
    /// Mesh this box (slice coordinates) instead of the cube around the bounding region.
    #[arg(
        long = "box",
        value_name = "X0,Y0,Z0,X1,Y1,Z1",
        allow_hyphen_values = true
    )]
    pub region: Option<String>,
    /// Multiply the coordinates written by S (e.g. to millimetres for a printer).
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    pub scale: f64,
    /// The mesh file: .ply (binary, with normals), .stl (binary) or .obj (with normals).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "FILE.ply|FILE.stl|FILE.obj",
        default_value = "qjulia.ply"
    )]
    pub output: PathBuf,
    /// Write the run's statistics as JSON: grid points, triangles, vertices, seconds, grid
    /// points per second, backend, precision.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    #[command(flatten)]
    pub tracer: TracerArgs,
}

#[derive(Args, Debug, Clone, Default)]
pub struct ExploreArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Shorthand for image.view (what the 3D view shows).
    #[arg(long, value_enum, value_name = "VIEW")]
    pub view: Option<ViewArg>,
}

#[derive(Args, Debug)]
pub struct ReportArgs {
    /// The folder to write into (created if missing).
    #[arg(long, value_name = "DIR", default_value = "report")]
    pub out: PathBuf,
    /// Run the stiff and extreme case suite on every tracer (writes DIR/stability.md) instead
    /// of the work-precision report.
    #[arg(long, conflicts_with = "dimensions")]
    pub stability: bool,
    /// Measure the distance estimate in quaternions, octonions and sedenions: steps, first-step
    /// efficiency, time, f32 error against f64 (writes DIR/dimensions.md).
    #[arg(long)]
    pub dimensions: bool,
    /// Path mode's convergence: RMSE of the linear image against a converged reference,
    /// against samples and seconds, Sobol' against random, the denoiser and adaptive sampling
    /// on and off, bounces 1, 3 and 5 (writes DIR/monte_carlo.md, .csv and .png).
    #[arg(long, conflicts_with_all = ["stability", "dimensions"])]
    pub monte_carlo: bool,
    /// Samples per pixel of the Monte Carlo page's references.
    #[arg(long, default_value_t = 4096, value_parser = clap::value_parser!(u32).range(1024..=65536))]
    pub reference_samples: u32,
    /// The work-precision report in minutes: one scene, smaller images, one timing each.
    #[arg(long)]
    pub quick: bool,
    /// Image size in pixels a side (default: 64 for --stability and --monte-carlo, 128 with
    /// --quick or --dimensions, else 320).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub size: Option<u32>,
    /// Seconds a case may take on one tracer before it counts as a hang.
    #[arg(long, default_value_t = 120, value_parser = clap::value_parser!(u64).range(1..=3600))]
    pub limit: u64,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum BackendArg {
    Auto,
    Gpu,
    Cpu,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum PrecisionArg {
    Auto,
    F32,
    F64,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum ViewArg {
    Shaded,
    Steps,
    Divergence,
    Samples,
}

impl ViewArg {
    fn view(self) -> View {
        match self {
            ViewArg::Shaded => View::Shaded,
            ViewArg::Steps => View::Steps,
            ViewArg::Divergence => View::Divergence,
            ViewArg::Samples => View::Samples,
        }
    }
}

impl BackendArg {
    fn backend(self) -> Backend {
        match self {
            BackendArg::Auto => Backend::Auto,
            BackendArg::Gpu => Backend::Gpu,
            BackendArg::Cpu => Backend::Cpu,
        }
    }
}

impl PrecisionArg {
    pub(crate) fn choice(self) -> PrecisionChoice {
        match self {
            PrecisionArg::Auto => PrecisionChoice::Auto,
            PrecisionArg::F32 => PrecisionChoice::F32,
            PrecisionArg::F64 => PrecisionChoice::F64,
        }
    }
}

impl TracerArgs {
    /// The planner of `--backend` and `--precision` ([`Planner::plan`] decides each work).
    fn planner(&self) -> Planner {
        Planner::new(self.backend.backend(), self.precision.choice())
    }
}

impl SceneArgs {
    /// Whether any scene option was given.
    pub fn given(&self) -> bool {
        self.preset.is_some()
            || self.scene.is_some()
            || !self.sets.is_empty()
            || self.width.is_some()
            || self.height.is_some()
    }

    /// The scene these options describe, validated once all layers are in.
    pub fn load(&self) -> Result<Scene, qjulia::Error> {
        self.load_with_view(None)
    }

    /// As [`Self::load`], with `--view` (a shorthand flag of `render` and `explore`).
    pub fn load_with_view(&self, view: Option<ViewArg>) -> Result<Scene, qjulia::Error> {
        Ok(self.loader(view)?.build()?)
    }

    /// The scene and its `[animation]` table (`animate`), with `--view`.
    pub fn load_animated(
        &self,
        view: Option<ViewArg>,
    ) -> Result<(Scene, Animation), qjulia::Error> {
        Ok(self.loader(view)?.build_animated()?)
    }

    /// Every layer of these options, in order, not yet built.
    fn loader(&self, view: Option<ViewArg>) -> Result<SceneLoader, qjulia::Error> {
        let mut loader = SceneLoader::new();
        if let Some(name) = &self.preset {
            loader.preset(name)?;
        }
        if let Some(path) = &self.scene {
            loader.file(path)?;
        }
        for (key, flag, value) in [
            ("image.width", "--width", self.width),
            ("image.height", "--height", self.height),
        ] {
            if let Some(v) = value {
                loader.flag(key, toml::Value::Integer(v), format!("{flag} {v}"));
            }
        }
        if let Some(view) = view {
            let name = view.view().name();
            loader.flag(
                "image.view",
                toml::Value::String(name.into()),
                format!("--view {name}"),
            );
        }
        for raw in &self.sets {
            loader.set(raw)?;
        }
        Ok(loader)
    }
}
