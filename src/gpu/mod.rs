//! The GPU path: adapter and device choice, the compute pipeline, dispatch and readback.

mod julia2d;
mod params;
pub mod shaders;
mod tracer;
pub mod variant;

pub use julia2d::{GpuJulia2d, GpuJulia2dParams};
pub use params::GpuParams;
pub use tracer::{GpuRender, GpuTracer, OUTPUTS, WORKGROUP};
pub use variant::Variant;

use crate::error::{Error, Result};

/// An adapter, its device and queue, and what they can do.
#[derive(Clone, Debug)]
pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
}

impl GpuContext {
    /// Picks an adapter the way CONTRACT.md asks (honouring `WGPU_BACKEND` and
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
        Ok(Self {
            adapter,
            device,
            queue,
            info,
        })
    }

    /// "name / Backend", e.g. "llvmpipe (LLVM 15.0.6, 256 bits) / Vulkan".
    pub fn adapter_label(&self) -> String {
        adapter_label(&self.info)
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

/// Every adapter wgpu finds for the backends `WGPU_BACKEND` allows (all when unset).
pub async fn available_adapters() -> Vec<wgpu::Adapter> {
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
    let wanted = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::SHADER_F64;
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

/// A bind group of a uniform buffer (binding 0) and the colour, depth and steps arrays
/// (bindings 1 to 3): the layout of every kernel here.
pub(crate) fn output_bind_group(
    device: &wgpu::Device,
    (label, layout): (&str, &wgpu::BindGroupLayout),
    uniform: &wgpu::Buffer,
    outputs: [&wgpu::Buffer; OUTPUTS],
) -> wgpu::BindGroup {
    fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
        wgpu::BindGroupEntry {
            binding,
            resource: buffer.as_entire_binding(),
        }
    }
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[
            entry(0, uniform),
            entry(1, outputs[0]),
            entry(2, outputs[1]),
            entry(3, outputs[2]),
        ],
    })
}

/// The colour, depth and steps arrays of `bytes` each on the device, and their readback copies.
pub(crate) fn output_buffers(
    device: &wgpu::Device,
    bytes: u64,
) -> ([wgpu::Buffer; OUTPUTS], [wgpu::Buffer; OUTPUTS]) {
    let make = |label, usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let out = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let read = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
    (
        [make("colour", out), make("depth", out), make("steps", out)],
        [
            make("colour readback", read),
            make("depth readback", read),
            make("steps readback", read),
        ],
    )
}
