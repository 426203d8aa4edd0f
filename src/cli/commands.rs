//! The commands that render, animate, mesh and explore: each loads its scene, asks the one
//! decision for its renderer ([`qjulia::Planner::plan`]) and writes its outputs.

use std::path::PathBuf;

use anyhow::Context;

use qjulia::animate::{self, FrameRange, Progress};
use qjulia::error::FlagError;
use qjulia::output::{OutputPaths, StreamingOutputs, write_view_outputs};
use qjulia::scene::View;
use qjulia::tile::Tile;
use qjulia::{Frame, Picture, Precision, Readback};

use super::{
    AnimateArgs, BackendArg, ExploreArgs, GpuParamsArgs, KernelArgs, MergeArgs, MeshArgs,
    Render2dArgs, RenderArgs, SchemaArgs, WebArgs,
};

pub fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let scene = args.scene.load_with_view(args.view)?;
    if let Some(tile) = &args.tile {
        return render_tile(args, &scene, tile);
    }
    let mut paths = OutputPaths {
        png: args.output.clone().or_else(|| {
            (args.depth.is_none() && args.steps.is_none() && args.hdr.is_none())
                .then(|| PathBuf::from("qjulia.png"))
        }),
        depth: args.depth.clone(),
        steps: args.steps.clone(),
        stats: args.stats.clone(),
        hdr: args.hdr.clone(),
        depth_f64: false,
    };
    let heat_map = scene.image.view != View::Shaded && paths.png.is_some();
    // A heat map needs depth and steps only; without a PNG, so do the .npy outputs. The EXR
    // needs the shaded picture and its AOVs (depth and steps are the same either way).
    let picture = Picture::Slice {
        shade: (paths.png.is_some() && scene.image.view.needs_shading()) || paths.hdr.is_some(),
    };
    let readback = match paths.hdr {
        Some(_) => Readback::Hdr,
        None => Readback::All,
    };
    if heat_map {
        // A heat map is scaled to the whole image's steps: rendered whole, then written.
        let (width, height) = (scene.image.width, scene.image.height);
        qjulia::memory::check(
            &format!("the {width}x{height} heat map"),
            u64::from(width) * u64::from(height) * qjulia::memory::FRAME_BYTES_PER_PIXEL,
        )?;
        let notice = &mut |n: &str| eprintln!("qjulia: {n}");
        let plan = args.tracer.planner().plan(&scene, picture.into(), notice)?;
        paths.depth_f64 = plan.decision.precision == Precision::F64;
        let mut frame = Frame::empty(scene.image.width);
        let stats = plan
            .renderer
            .render_with(&scene, picture, readback, &mut |band| {
                frame.append(band);
                Ok(())
            })?;
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
    let stats = plan
        .renderer
        .render_with(&scene, picture, readback, &mut |band| {
            bar.inc(band.height as u64);
            outputs.write_band(band)
        })?;
    bar.finish_and_clear();
    outputs.finish(&stats)?;
    report_render(&stats);
    Ok(())
}

/// `render --tile K/N`: the tile's rows, with their AOVs, into the partial EXR (and --stats).
fn render_tile(args: &RenderArgs, scene: &qjulia::Scene, text: &str) -> anyhow::Result<()> {
    let flag =
        |message: &str| qjulia::Error::from(FlagError::new(format!("--tile {text}"), message));
    let tile = Tile::parse(text, scene.image.height)?;
    for (given, name) in [
        (args.output.is_some(), "-o"),
        (args.depth.is_some(), "--depth"),
        (args.steps.is_some(), "--steps"),
    ] {
        if given {
            let why = format!(
                "writes a partial EXR only: {name} is refused with it (qjulia merge writes the PNG)"
            );
            return Err(flag(&why).into());
        }
    }
    let Some(hdr) = &args.hdr else {
        return Err(flag("writes a partial EXR: give --hdr FILE.exr").into());
    };
    if scene.targets_error() {
        let why = "renders a part of the image, and image.target_error stops on the whole \
                   image's estimate: render it whole, or set image.target_error = 0";
        return Err(flag(why).into());
    }
    let rows = tile.rows(scene.image.height);
    // The tile's rows are held whole, then written as one EXR.
    qjulia::memory::check(
        &format!("tile {tile}'s {}x{} rows", scene.image.width, rows.len()),
        u64::from(scene.image.width)
            * rows.len() as u64
            * (qjulia::memory::FRAME_BYTES_PER_PIXEL + qjulia::memory::HDR_BYTES_PER_PIXEL),
    )?;
    let notice = &mut |n: &str| eprintln!("qjulia: {n}");
    let picture = Picture::SHADED;
    let plan = args.tracer.planner().plan(scene, picture.into(), notice)?;
    let mut band = Frame::empty(scene.image.width);
    let stats =
        plan.renderer
            .render_rows(scene, picture, Readback::Hdr, rows.clone(), &mut |b| {
                band.append(b);
                Ok(())
            })?;
    qjulia::tile::write_partial(hdr, args.stats.as_deref(), scene, tile, &band, &stats)?;
    eprintln!(
        "qjulia: tile {tile}, rows {}..{} of {}x{}, on {} ({}) in {:.3} s",
        rows.start,
        rows.end,
        scene.image.width,
        scene.image.height,
        stats.adapter,
        stats.precision,
        stats.render_seconds
    );
    Ok(())
}

/// `merge PARTS...`: the tiles checked and put together, then the outputs of one render.
pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let (scene, mut frame, mut stats) = qjulia::tile::merge(&args.parts)?;
    if scene.image.denoise != qjulia::denoise::Denoiser::None {
        // The denoiser sees the whole image, as in one render: on the parts' backend unless
        // asked otherwise (the same adapter gives the same bytes).
        let backend = match args.backend {
            BackendArg::Auto if stats.backend == "cpu" => qjulia::Backend::Cpu,
            BackendArg::Auto => qjulia::Backend::Gpu,
            other => other.backend(),
        };
        let plan = qjulia::Planner::new(backend, qjulia::PrecisionChoice::F32).plan(
            &scene,
            qjulia::Picture::SHADED.into(),
            &mut |_| {},
        )?;
        plan.renderer.denoise(&scene, &mut frame, &mut stats)?;
    }
    let paths = OutputPaths {
        png: args
            .output
            .clone()
            .or_else(|| args.hdr.is_none().then(|| PathBuf::from("qjulia.png"))),
        hdr: args.hdr.clone(),
        stats: args.stats.clone(),
        ..Default::default()
    };
    write_view_outputs(&paths, &frame, &stats, &scene)?;
    eprintln!(
        "qjulia: merged {} parts into {}x{} (rendered on {}, {})",
        args.parts.len(),
        stats.width,
        stats.height,
        stats.adapter,
        stats.precision
    );
    Ok(())
}

/// One line on stderr about a finished render: its figures, its estimated error where it has
/// one, and how a render to `image.target_error` stopped.
fn report_render(stats: &qjulia::RenderStats) {
    let mut error = String::new();
    if let Some(e) = stats.summary.estimated_relative_rmse {
        error = format!(", estimated error {:.2}% of the mean", 100.0 * e);
    }
    if let Some(t) = &stats.target {
        error += &format!(
            " after {} passes to {} samples (stopped by {})",
            t.target_passes.len(),
            t.samples(),
            t.stopped_by
        );
    }
    eprintln!(
        "qjulia: {}x{} on {} ({}) in {:.3} s, {:.1}% hit, {:.1} steps/pixel, 8x8 tile efficiency {:.1}%{error}",
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
    if args.hdr && out.is_none() {
        let message = "the EXR frames go beside the PNG frames: with --video, give --out DIR";
        return Err(qjulia::Error::from(qjulia::error::FlagError::new("--hdr", message)).into());
    }
    let picture = Picture::Slice {
        shade: base.image.view.needs_shading() || args.hdr,
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
        hdr: args.hdr,
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

/// `qjulia schema --json`: the scene schema and presets ([`qjulia::scene::schema::json`]).
pub fn schema(_args: &SchemaArgs) -> anyhow::Result<()> {
    print!(
        "{}",
        qjulia::scene::schema::json::SchemaJson::new().to_json()
    );
    Ok(())
}

/// `qjulia web`: serves the built page until interrupted.
pub fn web(args: &WebArgs) -> anyhow::Result<()> {
    let dir = args.dir.clone().unwrap_or_else(qjulia::web::default_dir);
    let server = qjulia::web::PageServer::bind(&dir, (args.host, args.port).into())
        .map_err(anyhow::Error::msg)?;
    println!(
        "serving {} on http://{}/ (Ctrl-C stops)",
        dir.display(),
        server.addr()
    );
    use std::io::Write;
    std::io::stdout().flush()?;
    server.run();
    Ok(())
}

/// `qjulia kernel`: the WGSL a render of the scene hands the GPU, composed for it.
pub fn kernel(args: &KernelArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let picture = qjulia::Picture::SHADED;
    let precision = qjulia::precision::decide(args.precision.choice(), &scene, &picture.into());
    let kernels = qjulia::gpu::scene_kernel::scene_kernels(&scene, picture, precision.precision);
    let out = match args.json {
        true => serde_json::to_string_pretty(&kernels)? + "\n",
        false => {
            let texts: Vec<String> = kernels.iter().map(|k| k.to_text()).collect();
            texts.join("\n")
        }
    };
    // A reader that stops early (`| head`) is no error.
    match std::io::Write::write_all(&mut std::io::stdout().lock(), out.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

pub fn gpu_params(args: &GpuParamsArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let precision = Precision::of_name(&args.precision);
    println!(
        "{}",
        qjulia::gpu::params_json::GpuParamsJson::new(&scene, precision).to_json()
    );
    Ok(())
}
