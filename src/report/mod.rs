//! Reports on accuracy and stability: the stiff and extreme case suite (`stability`, path
//! mode's in `stability_path`) and the
//! work-precision sweep (`work_precision`), how the estimate fares as the algebra grows
//! (`dimensions`), and how path mode's images converge (`monte_carlo`).

pub mod dimensions;
pub mod error_estimate;
pub mod monte_carlo;
pub mod monte_carlo_page;
pub mod plot;
pub mod stability;
pub mod stability_path;
pub mod work_precision;

/// The machine, for a report's header: CPU model and cores, and the adapter.
pub fn machine(gpu: Option<&crate::gpu::GpuKernels>) -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "an unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let adapter = gpu.map_or("no GPU adapter".into(), |g| g.context().adapter_label());
    format!("{cpu} ({cores} cores), GPU adapter {adapter}")
}
