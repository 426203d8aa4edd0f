//! The GPU device: an adapter chosen as docs/CONTRACT.md asks, its device and queue with the
//! features qjulia uses, the start-up check of f64, the pipeline cache, and the record of why a
//! device stopped working ([`GpuContext`]).

use std::sync::{Arc, Mutex, OnceLock};

use super::pipeline_cache;
use crate::error::{Error, Result};

/// Records, instead of wgpu's default panic, why a device of ours stopped working: its loss
/// (the first reason kept), or an error no error scope caught.
fn watch_for_faults(device: &wgpu::Device) -> Arc<Mutex<Option<String>>> {
    let fault: Arc<Mutex<Option<String>>> = Arc::default();
    let keep = |fault: &Arc<Mutex<Option<String>>>, why: String| {
        fault.lock().expect("device fault").get_or_insert(why);
    };
    let lost = fault.clone();
    device.set_device_lost_callback(move |reason, message| {
        let why = match reason {
            wgpu::DeviceLostReason::Destroyed => "destroyed".to_string(),
            _ => format!("{reason:?}"),
        };
        let message = if message.is_empty() {
            String::new()
        } else {
            format!(": {message}")
        };
        keep(&lost, format!("the GPU device was lost ({why}){message}"));
    });
    let uncaught = fault.clone();
    device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
        keep(&uncaught, format!("the GPU failed: {e}"));
    }));
    fault
}

/// An adapter, its device and queue, and what they can do.
#[derive(Clone, Debug)]
pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// The start-up check of f64, run once per device on first use ([`Self::f64_support`]).
    pub(super) f64_check: Arc<OnceLock<std::result::Result<F64Support, String>>>,
    /// The persistent pipeline cache, where the device has one ([`pipeline_cache`]).
    pub pipeline_cache: Option<Arc<pipeline_cache::DiskPipelineCache>>,
    /// Why the device stopped working, once it has: lost, or an error no scope caught.
    fault: Arc<Mutex<Option<String>>>,
}

impl GpuContext {
    /// Picks an adapter the way docs/CONTRACT.md asks (honouring `WGPU_BACKEND` and
    /// `WGPU_ADAPTER_NAME`) and creates a device with the adapter's own limits and the optional
    /// features qjulia uses (timestamp queries, f64) where it has them.
    pub fn new() -> Result<Self> {
        let adapter = pollster::block_on(select_adapter())?;
        Self::from_adapter(adapter)
    }

    /// A device on the given adapter, with its full limits and our optional features.
    pub fn from_adapter(adapter: wgpu::Adapter) -> Result<Self> {
        let info = adapter.get_info();
        let (device, queue) =
            pollster::block_on(adapter.request_device(&device_descriptor(&adapter)))
                .map_err(|e| Error::Gpu(format!("cannot create a device on {}: {e}", info.name)))?;
        // As a device made elsewhere, but ours: its faults are recorded.
        let mut ctx = Self::from_device(adapter, device, queue);
        ctx.fault = watch_for_faults(&ctx.device);
        Ok(ctx)
    }

    /// Why the device stopped working (lost, or an error no scope caught), once it has: the
    /// kernels check it after each wait, so that a lost device ends the work with this one
    /// line rather than a panic in wgpu's default handler.
    pub fn fault(&self) -> Option<String> {
        self.fault.lock().expect("device fault").clone()
    }

    /// The test hook of a lost device (`QJULIA_FAULT_LOSE_DEVICE`): destroys the device, as a
    /// GPU reset or a driver crash would lose it.
    pub fn lose_device(&self) {
        self.device.destroy();
    }

    /// A device made elsewhere (the explorer's window's), on its adapter.
    pub fn from_device(adapter: wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Self {
        let info = adapter.get_info();
        let pipeline_cache = pipeline_cache::DiskPipelineCache::open(&device, &info).map(Arc::new);
        // The window's device keeps its owner's handlers (eframe's).
        Self {
            adapter,
            device,
            queue,
            info,
            f64_check: Arc::default(),
            pipeline_cache,
            fault: Arc::default(),
        }
    }

    /// "name / Backend", e.g. "llvmpipe (LLVM 15.0.6, 256 bits) / Vulkan".
    pub fn adapter_label(&self) -> String {
        adapter_label(&self.info)
    }

    /// Whether the kernels bind their params as read-only storage rather than as uniforms:
    /// on lavapipe (Vulkan on a CPU adapter). Mesa 22.3's lavapipe "inlines" a uniform that an
    /// `if` or a loop tests: where that shrinks the shader by half (the tracer's params do), it
    /// compiles a new variant of the shader at every bind of the pipeline, each render, and
    /// never frees it: 30 KB of code and about 0.6 MB of the process's memory a render
    /// (examples/driver_leak.rs; docs/book/robustness.md). It inlines uniforms only, so the
    /// same bytes bound as storage are left alone. `QJULIA_UNIFORMS_AS_STORAGE` (0 or 1)
    /// overrides the choice, to measure.
    pub fn uniforms_as_storage(&self) -> bool {
        let lavapipe = self.info.device_type == wgpu::DeviceType::Cpu
            && self.info.backend == wgpu::Backend::Vulkan;
        match std::env::var("QJULIA_UNIFORMS_AS_STORAGE").as_deref() {
            Ok("1") => true,
            Ok("0") => false,
            _ => lavapipe,
        }
    }

    /// Whether GPU time can be measured with timestamp queries.
    pub fn has_timestamps(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
    }
}

/// "name / Backend" for an adapter.
pub fn adapter_label(info: &wgpu::AdapterInfo) -> String {
    format!("{} / {:?}", info.name, info.backend)
}

/// Mesa's EGL, which wgpu probes for its GL backend, prints "error: XDG_RUNTIME_DIR is invalid
/// or not set" twice when the variable is missing (a headless machine, CI, ssh, a test process),
/// which reads like a failure before a successful render. Where it is missing or not a
/// directory, point it at a private one in the temporary folder; where it is set, as on every
/// desktop, nothing changes. Done once, before the first instance is made (the binary calls it
/// first thing in `main`, before any other thread exists).
pub fn give_a_runtime_dir() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        #[cfg(unix)]
        {
            use std::os::unix::fs::DirBuilderExt;
            let valid = std::env::var_os("XDG_RUNTIME_DIR")
                .is_some_and(|d| std::path::Path::new(&d).is_dir());
            if valid {
                return;
            }
            let user = std::env::var("USER").unwrap_or_else(|_| "user".into());
            let dir = std::env::temp_dir().join(format!("qjulia-runtime-{user}"));
            let made = std::fs::DirBuilder::new()
                .recursive(true)
                .mode(0o700)
                .create(&dir);
            if made.is_ok() {
                // SAFETY: before the first wgpu instance, so before any driver thread that
                // could read the environment; std's own readers take the same lock.
                unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
            }
        }
    });
}

/// Every adapter wgpu finds for the backends `WGPU_BACKEND` allows (all when unset).
pub async fn available_adapters() -> Vec<wgpu::Adapter> {
    give_a_runtime_dir();
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all());
    instance.enumerate_adapters(backends).await
}

/// The adapter to use among those wgpu finds; see [`choose_adapter`].
pub async fn select_adapter() -> Result<wgpu::Adapter> {
    choose_adapter(available_adapters().await)
}

/// The adapter to use: the first whose name contains `WGPU_ADAPTER_NAME` (case-insensitive)
/// when that is set; else the best by kind (discrete, integrated, virtual, CPU) and then by
/// backend (Vulkan, Metal, DX12, GL), so that lavapipe wins over GL llvmpipe on a machine with
/// both.
pub fn choose_adapter(mut adapters: Vec<wgpu::Adapter>) -> Result<wgpu::Adapter> {
    if adapters.is_empty() {
        return Err(Error::NoAdapter("wgpu found none".into()));
    }
    if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
        let wanted_lower = wanted.to_lowercase();
        let names: Vec<String> = adapters
            .iter()
            .map(|a| adapter_label(&a.get_info()))
            .collect();
        return adapters
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&wanted_lower))
            .ok_or_else(|| {
                Error::NoAdapter(format!(
                    "none matches WGPU_ADAPTER_NAME={wanted:?} (found: {})",
                    names.join(", ")
                ))
            });
    }
    adapters.sort_by_key(|a| adapter_rank(&a.get_info()));
    Ok(adapters.remove(0))
}

/// The device qjulia asks for: the adapter's own limits (the defaults cap buffers at 256 MiB
/// and, on GL, leave compute out) and the optional features it uses where present.
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    let wanted = wgpu::Features::TIMESTAMP_QUERY
        | wgpu::Features::SHADER_F64
        | wgpu::Features::PIPELINE_CACHE;
    wgpu::DeviceDescriptor {
        label: Some("qjulia"),
        required_features: adapter.features() & wanted,
        required_limits: adapter.limits(),
        ..Default::default()
    }
}

/// Lower is better: device kind first, then backend.
fn adapter_rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    let backend = match info.backend {
        wgpu::Backend::Vulkan => 0,
        wgpu::Backend::Metal => 1,
        wgpu::Backend::Dx12 => 2,
        wgpu::Backend::Gl => 3,
        _ => 4,
    };
    (kind, backend)
}

/// An adapter's f64, checked: the repairs its kernels need (override constants of
/// shaders/real64.wgsl) and what the check cost.
#[derive(Clone, Debug, PartialEq)]
pub struct F64Support {
    /// Override constants every f64 pipeline is built with (`SQRT_NEWTON`).
    pub constants: Vec<(&'static str, f64)>,
    /// The operations replaced, by name ("sqrt"); empty where the adapter's own are right.
    pub repaired: Vec<&'static str>,
    /// The check's wall time: building the kernel, its runs, the comparisons.
    pub seconds: f64,
}
