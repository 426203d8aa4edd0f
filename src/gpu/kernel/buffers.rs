//! A band's device buffers (the uniform, the outputs, their readback copies and timestamps),
//! reused across bands, runs and frames. The kernel makes them and reads a band back through
//! them in `readback.rs`.

/// What mapping a readback buffer reports.
pub(super) type MapResult = std::result::Result<(), wgpu::BufferAsyncError>;

/// Device-side buffers of one band, reused across bands, runs and frames.
pub(super) struct RunBuffers {
    /// Items they hold.
    pub(super) items: u64,
    /// Which outputs have readback buffers.
    pub(super) read: Vec<bool>,
    pub(super) uniform: wgpu::Buffer,
    pub(super) storage: Vec<wgpu::Buffer>,
    /// Readback copies of the outputs asked for.
    pub(super) readback: Vec<Option<wgpu::Buffer>>,
    pub(super) bind_group: wgpu::BindGroup,
    /// The input array the bind group binds ([`super::input_source`]).
    pub(super) input: usize,
    pub(super) timestamps: Option<Timestamps>,
}

/// A band's two timestamp queries, their resolved values and a readback copy.
pub(super) struct Timestamps {
    pub(super) queries: wgpu::QuerySet,
    pub(super) resolve: wgpu::Buffer,
    pub(super) readback: wgpu::Buffer,
}

impl RunBuffers {
    /// Whether these buffers serve a band of `items` reading back `read` with the input array
    /// `input` (larger ones would
    /// do, but a step of another size is another grid: allocate it its own).
    pub(super) fn fits(&self, items: u64, read: &[bool], input: usize) -> bool {
        self.items == items && self.read == read && self.input == input
    }
}
