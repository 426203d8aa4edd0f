//! `qjulia report`: the work-precision report, the stability suite and the dimensions report,
//! on one device shared by every GPU case.

use anyhow::Context;

use qjulia::Scene;

use super::ReportArgs;

pub fn report(args: &ReportArgs) -> anyhow::Result<()> {
    use qjulia::report::{stability, stability_path};
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
    if args.monte_carlo {
        return monte_carlo(args, gpu);
    }
    if !args.stability {
        return work_precision(args, gpu);
    }
    let size = args.size.unwrap_or(64);
    let limit = std::time::Duration::from_secs(args.limit);
    let outcomes = stability::run_all(size, gpu.clone(), limit, |o| {
        let verdict = if o.passed() { "ok" } else { "FAILED" };
        let seconds = o.seconds.map_or("-".into(), |s| format!("{s:.3} s"));
        eprintln!(
            "qjulia: {:<28} {:<8} {seconds:>10}  {verdict}",
            o.case,
            o.runner.name()
        );
    });
    let table = stability::markdown(&outcomes);
    // Path mode's cases, at a quarter of the size (each pixel takes 16 samples).
    let path_size = (size / 2).max(8);
    let path_outcomes = stability_path::run_all_path(path_size, gpu, limit, |o| {
        let verdict = if o.passed() { "ok" } else { "FAILED" };
        let seconds = o.seconds.map_or("-".into(), |s| format!("{s:.3} s"));
        eprintln!(
            "qjulia: path {:<23} {:<8} {seconds:>10}  {verdict}",
            o.case,
            o.runner.name()
        );
    });
    let path_table = stability_path::path_markdown(path_size, &path_outcomes);
    let path = args.out.join("stability.md");
    let text = stability::page(size, args.limit, &format!("{table}{path_table}"));
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    println!("{table}{path_table}");
    if outcomes.iter().any(|o| !o.passed()) || path_outcomes.iter().any(|o| !o.passed()) {
        anyhow::bail!("some cases failed: see {}", path.display());
    }
    Ok(())
}

fn monte_carlo(
    args: &ReportArgs,
    gpu: Option<std::sync::Arc<qjulia::gpu::GpuKernels>>,
) -> anyhow::Result<()> {
    use qjulia::report::monte_carlo as mc;
    let size = args.size.unwrap_or(64);
    let machine = qjulia::report::machine(gpu.as_deref());
    let mut planner = match gpu {
        Some(kernels) => {
            qjulia::Planner::on_device(kernels, qjulia::Backend::Gpu, qjulia::PrecisionChoice::F32)
        }
        None => qjulia::Planner::new(qjulia::Backend::Cpu, qjulia::PrecisionChoice::F32),
    };
    let bar = indicatif::ProgressBar::new(1);
    let curves = mc::run(
        &mut planner,
        size,
        args.reference_samples,
        &mut |msg, k, n| {
            bar.set_length(n as u64);
            bar.set_position(k as u64);
            bar.set_message(msg.to_string());
        },
    )?;
    bar.finish_and_clear();
    let write = |name: &str, text: &str| -> anyhow::Result<()> {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
    };
    use qjulia::report::monte_carlo_page as page;
    write("monte_carlo.csv", &page::csv(&curves))?;
    let png = args.out.join("monte_carlo.png");
    page::plot(&png, &curves).map_err(|e| anyhow::anyhow!("{}: {e}", png.display()))?;
    let md = page::markdown(&curves, size, args.reference_samples, &machine);
    write("monte_carlo.md", &md)?;
    println!("{md}");
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
