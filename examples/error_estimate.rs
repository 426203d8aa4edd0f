//! The error estimate against the measured error: `cargo run --release --example
//! error_estimate -- SIZE SAMPLES REFERENCE SEEDS [BACKEND]` renders the path-traced,
//! path-gallery and fog-shafts presets at SIZE x SIZE, SAMPLES a pixel, raw and denoised, over
//! SEEDS seeds, against REFERENCE `random` samples (qjulia::report::error_estimate); with a
//! sixth argument TARGET, renders to `image.target_error = TARGET` (at most 4,096 samples)
//! instead and prints each seed's last pass, its estimate and its measured error.

use qjulia::report::error_estimate::{check, check_target, reference};
use qjulia::{Backend, Planner, PrecisionChoice};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |k: usize, default: u32| args.get(k).map_or(Ok(default), |a| a.parse());
    let (size, samples, reference_samples, seeds) = (
        number(0, 64)?,
        number(1, 64)?,
        number(2, 4096)?,
        number(3, 4)?,
    );
    let backend = match args.get(4).map(String::as_str) {
        Some("cpu") => Backend::Cpu,
        _ => Backend::Gpu,
    };
    let mut planner = Planner::new(backend, PrecisionChoice::F32);
    let seeds: Vec<u32> = (1..=seeds).collect();
    let target: Option<f64> = args.get(5).map(|a| a.parse()).transpose()?;
    println!("| scene | denoised | estimated | measured | ratio |");
    println!("|---|---|---|---|---|");
    for slug in ["path-traced", "path-gallery", "fog-shafts"] {
        let mut scene = qjulia::scene::presets::find(slug)
            .expect("a preset")
            .scene();
        scene.image.width = size;
        scene.image.height = size;
        let truth = reference(&mut planner, &scene, reference_samples)?;
        for denoise in [false, true] {
            let mut s = scene.clone();
            s.image.samples = samples;
            s.path.sampler = qjulia::scene::PathSampler::Sobol;
            s.image.denoise = match denoise {
                true => qjulia::denoise::Denoiser::Atrous,
                false => qjulia::denoise::Denoiser::None,
            };
            if let Some(target) = target {
                s.image.samples = 4096;
                s.image.target_error = target;
                let t = check_target(&mut planner, &s, &seeds, &truth)?;
                for (seed, (n, met, estimated, measured)) in seeds.iter().zip(&t.renders) {
                    println!(
                        "{slug}, denoised {denoise}, seed {seed}: {n} samples, met {met}, \
                         estimated {estimated:.4}, measured {measured:.4}"
                    );
                }
                println!(
                    "{slug}, denoised {denoise}: target {target}, measured {:.4} ({:.3}x), \
                     {:.1} samples a pixel",
                    t.measured(),
                    t.measured() / target,
                    t.mean_samples()
                );
                continue;
            }
            let c = check(&mut planner, &s, &seeds, &truth)?;
            println!(
                "| {slug} | {denoise} | {:.5} | {:.5} | {:.3} |",
                c.estimated,
                c.measured,
                c.estimated / c.measured
            );
        }
    }
    Ok(())
}
