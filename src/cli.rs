//! The command line (CONTRACT.md): argument parsing and wiring only.

use std::path::PathBuf;

use anyhow::Context;
use clap::{Args, Parser, Subcommand, ValueEnum};

use qjulia::animate::{self, FrameRange, Progress};
use qjulia::animation::Animation;
use qjulia::output::{OutputPaths, StreamingOutputs, write_view_outputs};
use qjulia::precision::PrecisionChoice;
use qjulia::scene::{SceneLoader, View};
use qjulia::{Backend, Picture, Planner, Precision, Scene};

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
    /// bytes and the override constants of the scene's pipeline (for a host that packs them).
    GpuParams(GpuParamsArgs),
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
    /// The PNG to write (default qjulia.png, unless only --depth or --steps is asked for).
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
    #[command(flatten)]
    pub tracer: TracerArgs,
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
    /// Skip frames whose PNG is already complete (written whole, with this frame's scene).
    #[arg(long)]
    pub resume: bool,
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
    /// The work-precision report in minutes: one scene, smaller images, one timing each.
    #[arg(long)]
    pub quick: bool,
    /// Image size in pixels a side (default: 64 for --stability, 128 with --quick or
    /// --dimensions, else 320).
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
}

impl ViewArg {
    fn view(self) -> View {
        match self {
            ViewArg::Shaded => View::Shaded,
            ViewArg::Steps => View::Steps,
            ViewArg::Divergence => View::Divergence,
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
    fn choice(self) -> PrecisionChoice {
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

pub fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let scene = args.scene.load_with_view(args.view)?;
    let mut paths = OutputPaths {
        png: args.output.clone().or_else(|| {
            (args.depth.is_none() && args.steps.is_none()).then(|| PathBuf::from("qjulia.png"))
        }),
        depth: args.depth.clone(),
        steps: args.steps.clone(),
        stats: args.stats.clone(),
        depth_f64: false,
    };
    let heat_map = scene.image.view != View::Shaded && paths.png.is_some();
    // A heat map needs depth and steps only; without a PNG, so do the .npy outputs.
    let picture = Picture::Slice {
        shade: paths.png.is_some() && !heat_map,
    };
    if heat_map {
        // A heat map is scaled to the whole image's steps: rendered whole, then written.
        let notice = &mut |n: &str| eprintln!("qjulia: {n}");
        let plan = args.tracer.planner().plan(&scene, picture.into(), notice)?;
        paths.depth_f64 = plan.decision.precision == Precision::F64;
        let (frame, stats) = plan.renderer.render_frame(&scene, picture)?;
        write_view_outputs(&paths, &frame, &stats, &scene)?;
        report_render(&stats);
        return Ok(());
    }
    // Outputs are written band by band as the render goes: any size in bounded memory.
    let rows = scene.image.height as u64;
    let pixels = scene.image.width as u64 * rows;
    let bar = if pixels >= 1 << 24 {
        let bar = indicatif::ProgressBar::new(rows);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:40}] {pos}/{len} rows, {eta} left",
            )
            .expect("a valid template")
            .progress_chars("=> "),
        );
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let notice = &mut |n: &str| bar.suspend(|| eprintln!("qjulia: {n}"));
    let plan = args.tracer.planner().plan(&scene, picture.into(), notice)?;
    paths.depth_f64 = plan.decision.precision == Precision::F64;
    let mut outputs = StreamingOutputs::create(&paths, &scene)?;
    let stats = plan.renderer.render(&scene, picture, &mut |band| {
        bar.inc(band.height as u64);
        outputs.write_band(band)
    })?;
    bar.finish_and_clear();
    outputs.finish(&stats)?;
    report_render(&stats);
    Ok(())
}

/// One line on stderr about a finished render.
fn report_render(stats: &qjulia::RenderStats) {
    eprintln!(
        "qjulia: {}x{} on {} ({}) in {:.3} s, {:.1}% hit, {:.1} steps/pixel, 8x8 tile efficiency {:.1}%",
        stats.width,
        stats.height,
        stats.adapter,
        stats.precision,
        stats.render_seconds,
        stats.summary.hit_fraction * 100.0,
        stats.summary.steps_mean,
        stats.summary.tile_efficiency * 100.0
    );
}

pub fn animate(args: &AnimateArgs) -> anyhow::Result<()> {
    // Everything is checked before anything is written: the scene, the range, the video's
    // kind; then ffmpeg is looked for, before anything is rendered.
    let (base, animation) = args.scene.load_animated(args.view)?;
    if args.frame_count {
        println!("{}", animation.frames);
        return Ok(());
    }
    let range = match &args.frames {
        Some(text) => FrameRange::parse(text, animation.frames).map_err(qjulia::Error::from)?,
        None => FrameRange::all(animation.frames),
    };
    if let Some(video) = &args.video {
        qjulia::video::Codec::for_path(video).map_err(qjulia::Error::from)?;
        qjulia::video::find_ffmpeg()?;
    }
    // PNG frames: into --out, or the default folder unless a video alone was asked for.
    let out = match (&args.out, &args.video) {
        (Some(dir), _) => Some(dir.clone()),
        (None, Some(_)) => None,
        (None, None) => Some(PathBuf::from(animate::DEFAULT_DIR)),
    };
    let picture = Picture::Slice {
        shade: base.image.view == View::Shaded,
    };
    let bar = indicatif::ProgressBar::new(range.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:40}] {pos}/{len} frames, {per_sec}, {eta} left",
        )
        .expect("a valid template")
        .progress_chars("=> "),
    );
    // Each frame's precision by the rule of `render` (auto: by the frame's own scene), its
    // renderer made once per precision; the notices and warnings once per precision.
    // Everything the run needs is there before the first frame: the first frame's renderer.
    let mut planner = args.tracer.planner();
    let notice = &mut |n: &str| bar.suspend(|| eprintln!("qjulia: {n}"));
    planner.plan(
        &animation.scene_at(&base, range.first),
        picture.into(),
        notice,
    )?;
    let job = animate::Job {
        base: &base,
        animation: &animation,
        range,
        out: out.as_deref(),
        resume: args.resume,
        video: args.video.as_deref(),
        stop: None,
    };
    let stats = animate::run(&mut planner, notice, &job, &mut |p| match p {
        Progress::Start { to_render, skipped } => {
            if skipped > 0 {
                bar.suspend(|| {
                    eprintln!("qjulia: {skipped} frames already complete, {to_render} to render")
                });
            }
            bar.set_length(to_render as u64);
            bar.reset();
        }
        Progress::Frame { .. } => bar.inc(1),
    });
    bar.finish_and_clear();
    let stats = stats?;
    if let Some(path) = &args.stats {
        qjulia::output::write_json(path, &stats)?;
    }
    let mut wrote: Vec<String> = Vec::new();
    if let Some(dir) = &out {
        wrote.push(dir.display().to_string());
    }
    if let Some(video) = &args.video {
        wrote.push(format!(
            "{} ({} frames)",
            video.display(),
            stats.video_frames
        ));
    }
    eprintln!(
        "qjulia: frames {}..{} of {} to {}: {} rendered ({} skipped), {}x{} on {} ({}) in {:.3} s, {:.2} frames/s",
        range.first,
        range.last,
        animation.frames,
        wrote.join(" and "),
        stats.frames,
        stats.skipped,
        stats.width,
        stats.height,
        stats.adapter,
        stats.precision,
        stats.seconds,
        stats.frames_per_second
    );
    Ok(())
}

pub fn render2d(args: &Render2dArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let paths = OutputPaths {
        png: Some(args.output.clone()),
        stats: args.stats.clone(),
        ..Default::default()
    };
    let notice = &mut |n: &str| eprintln!("qjulia: {n}");
    let plan = args
        .tracer
        .planner()
        .plan(&scene, Picture::Julia2d.into(), notice)?;
    let mut outputs = StreamingOutputs::create(&paths, &scene)?;
    let stats = plan
        .renderer
        .render(&scene, Picture::Julia2d, &mut |band| {
            outputs.write_band(band)
        })?;
    outputs.finish(&stats)?;
    eprintln!(
        "qjulia: 2D Julia set of c = {} + {} i, {}x{} on {} ({}) in {:.3} s, {:.1}% in the set, {:.1} iterations/pixel",
        scene.fractal.c[0],
        scene.fractal.c[1],
        stats.width,
        stats.height,
        stats.adapter,
        stats.precision,
        stats.render_seconds,
        stats.summary.hit_fraction * 100.0,
        stats.summary.steps_mean
    );
    Ok(())
}

pub fn mesh(args: &MeshArgs) -> anyhow::Result<()> {
    use qjulia::mesh::{Format, MeshOptions};
    // Everything is checked before anything is sampled or written.
    let scene = args.scene.load()?;
    let resolution = u32::try_from(args.resolution).unwrap_or(0);
    let resolution = if resolution as i64 == args.resolution {
        MeshOptions::check_resolution(resolution)
    } else {
        MeshOptions::check_resolution(0).map_err(|mut e| {
            e.flag = format!("--resolution {}", args.resolution);
            e
        })
    }
    .map_err(qjulia::Error::from)?;
    let region = args
        .region
        .as_deref()
        .map(MeshOptions::parse_box)
        .transpose()
        .map_err(qjulia::Error::from)?;
    let scale = MeshOptions::check_scale(args.scale).map_err(qjulia::Error::from)?;
    Format::for_path(&args.output).map_err(qjulia::Error::from)?;
    let options = MeshOptions { resolution, region };
    let bar = indicatif::ProgressBar::new(resolution as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:40}] {pos}/{len} grid layers, {eta} left",
        )
        .expect("a valid template")
        .progress_chars("=> "),
    );
    // The precision: as for render, the grid cell playing the pixel's part.
    let notice = &mut |n: &str| bar.suspend(|| eprintln!("qjulia: {n}"));
    let work = qjulia::mesh::work(&scene, &options);
    let plan = args.tracer.planner().plan(&scene, work, notice)?;
    let renderer = plan.renderer;
    let (mesh, stats) =
        qjulia::mesh::make_mesh(&renderer, &scene, &options, &mut |done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        })?;
    bar.finish_and_clear();
    if mesh.is_empty() {
        eprintln!(
            "qjulia: the surface is empty: no grid point lies inside it (d < epsilon within the bounding ball{}); writing an empty mesh",
            if region.is_some() { ", in the box" } else { "" }
        );
    }
    let stats_out = args.stats.as_deref().map(|p| (p, &stats));
    qjulia::mesh::write_outputs(&args.output, &mesh, scale, stats_out)?;
    eprintln!(
        "qjulia: {n}x{n}x{n} grid on {} ({}): {} vertices, {} triangles in {:.3} s (sampling {:.3} s, {:.3e} points/s); wrote {}",
        stats.adapter,
        stats.precision,
        stats.vertices,
        stats.triangles,
        stats.seconds,
        stats.sample_seconds,
        stats.grid_points_per_second,
        args.output.display(),
        n = resolution,
    );
    Ok(())
}

pub fn explore(args: &ExploreArgs) -> anyhow::Result<()> {
    let initial = if args.scene.given() || args.view.is_some() {
        Some(args.scene.load_animated(args.view)?)
    } else {
        None
    };
    qjulia::explore::run(initial)?;
    Ok(())
}

pub fn report(args: &ReportArgs) -> anyhow::Result<()> {
    use qjulia::report::stability;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    // One device for every GPU case, its kernels built once and shared.
    let gpu = match qjulia::gpu::GpuContext::new().map(qjulia::gpu::GpuKernels::new) {
        Ok(kernels) => match kernels.tracer() {
            Ok(_) => {
                eprintln!("qjulia: GPU runs on {}", kernels.context().adapter_label());
                Some(std::sync::Arc::new(kernels))
            }
            Err(e) => {
                eprintln!("qjulia: {e}; CPU cases only");
                None
            }
        },
        Err(e) => {
            eprintln!("qjulia: {e}; CPU cases only");
            None
        }
    };
    if args.dimensions {
        return dimensions(args, gpu.as_ref());
    }
    if !args.stability {
        return work_precision(args, gpu);
    }
    let size = args.size.unwrap_or(64);
    let limit = std::time::Duration::from_secs(args.limit);
    let outcomes = stability::run_all(size, gpu, limit, |o| {
        let verdict = if o.passed() { "ok" } else { "FAILED" };
        let seconds = o.seconds.map_or("-".into(), |s| format!("{s:.3} s"));
        eprintln!(
            "qjulia: {:<28} {:<8} {seconds:>10}  {verdict}",
            o.case,
            o.runner.name()
        );
    });
    let table = stability::markdown(&outcomes);
    let path = args.out.join("stability.md");
    let text = stability::page(size, args.limit, &table);
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    println!("{table}");
    if outcomes.iter().any(|o| !o.passed()) {
        anyhow::bail!("some cases failed: see {}", path.display());
    }
    Ok(())
}

fn dimensions(
    args: &ReportArgs,
    gpu: Option<&std::sync::Arc<qjulia::gpu::GpuKernels>>,
) -> anyhow::Result<()> {
    use qjulia::report::dimensions;
    let size = args.size.unwrap_or(128);
    let rows = dimensions::run(size, gpu)?;
    let table = dimensions::markdown(&rows);
    let path = args.out.join("dimensions.md");
    let text = dimensions::page(size, &qjulia::report::machine(gpu.map(|g| &**g)), &table);
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    println!("{table}");
    Ok(())
}

fn work_precision(
    args: &ReportArgs,
    gpu: Option<std::sync::Arc<qjulia::gpu::GpuKernels>>,
) -> anyhow::Result<()> {
    use qjulia::report::stability::Runner;
    use qjulia::report::work_precision as wp;
    use qjulia::scene::presets::PRESETS;
    let size = args.size.unwrap_or(if args.quick { 128 } else { 320 });
    let sized = |mut scene: Scene| {
        scene.image.width = size;
        scene.image.height = size;
        scene
    };
    let mut scenes = vec![("seed's look", sized(Scene::default()))];
    if !args.quick {
        scenes.push(("basilica revolved", sized(PRESETS[2].scene())));
    }
    let repeats = if args.quick { 1 } else { 5 };
    let bar = indicatif::ProgressBar::new(1);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    let (rows, truth_seconds) = wp::run(&scenes, gpu.clone(), repeats, |msg, k, n| {
        bar.set_length(n as u64);
        bar.set_position(k as u64);
        bar.set_message(msg.to_string());
    })?;
    let command = format!(
        "qjulia report --out {}{} --size {size}",
        args.out.display(),
        if args.quick { " --quick" } else { "" }
    );
    let csv_path = args.out.join("work_precision.csv");
    std::fs::write(&csv_path, wp::csv(&rows))
        .with_context(|| format!("writing {}", csv_path.display()))?;
    let png_path = args.out.join("work_precision.png");
    wp::plot(&png_path, &rows).map_err(|e| anyhow::anyhow!("{}: {e}", png_path.display()))?;
    // f32 against f64 as the zoom deepens, on every tracer there is.
    let mut zoom_runners = vec![Runner::CpuF32];
    if let Some(gpu) = &gpu {
        zoom_runners.splice(0..0, Runner::on_gpu(gpu));
    }
    let zoom = wp::zoom_sweep(size, &zoom_runners, gpu.clone(), repeats, |msg, k, n| {
        bar.set_length(n as u64);
        bar.set_position(k as u64);
        bar.set_message(msg.to_string());
    })?;
    bar.finish_and_clear();
    let mut md = wp::markdown(
        &rows,
        &truth_seconds,
        &qjulia::report::machine(gpu.as_deref()),
        &command,
    );
    md.push('\n');
    md.push_str(&wp::zoom_markdown(&zoom, size));
    let md_path = args.out.join("report.md");
    std::fs::write(&md_path, &md).with_context(|| format!("writing {}", md_path.display()))?;
    println!("{md}");
    eprintln!(
        "qjulia: wrote {}, {} and {}",
        csv_path.display(),
        png_path.display(),
        md_path.display()
    );
    Ok(())
}

pub fn info() -> anyhow::Result<()> {
    println!("presets (--preset NAME):");
    let width = qjulia::scene::presets::PRESETS
        .iter()
        .map(|p| p.slug.len())
        .max()
        .unwrap_or(0);
    for p in qjulia::scene::presets::PRESETS {
        println!("  {:width$}  {}", p.slug, p.about);
    }
    let adapters = pollster::block_on(qjulia::gpu::available_adapters());
    if adapters.is_empty() {
        println!(
            "no GPU adapters found; {}",
            qjulia::error::INSTALL_ADAPTER_HINT
        );
    }
    for a in &adapters {
        let info = a.get_info();
        let f64 = a.features().contains(wgpu::Features::SHADER_F64);
        let ts = a.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        println!(
            "adapter: {} ({:?}, driver {} {}; f64: {f64}, timestamps: {ts})",
            qjulia::gpu::adapter_label(&info),
            info.device_type,
            info.driver,
            info.driver_info
        );
    }
    let chosen =
        pollster::block_on(qjulia::gpu::select_adapter()).context("choosing an adapter")?;
    println!(
        "render uses: {}",
        qjulia::gpu::adapter_label(&chosen.get_info())
    );
    Ok(())
}

pub fn gpu_params(args: &GpuParamsArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let precision = match args.precision.as_str() {
        "f64" => Precision::F64,
        _ => Precision::F32,
    };
    println!(
        "{}",
        qjulia::uniform::json::GpuParamsJson::new(&scene, precision).to_json()
    );
    Ok(())
}
