//! A canvas in host memory ([`HostCanvas`]): where a live view rendering on a device of its own
//! (the explorer's view thread, [`super::view_thread`]) shows its images, so that another
//! device (the window's) can draw them. A pass's colour rows are copied on the device into a
//! buffer the host maps once the step's submissions are done ([`HostCanvas::harvest`]); an
//! image the session makes on the host (path mode's encoded radiance, a denoised mean) is kept
//! as it is.

use std::cell::Cell;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use super::Quality;
use super::canvas::Canvas;

/// Numbers the images of every canvas in the process: a new number is a new image.
static GENERATIONS: AtomicU64 = AtomicU64::new(1);

/// One quality's image: its colour (packed RGBA8, row after row), and the device buffer the
/// tiles' rows are copied into, rows `stride` pixels apart.
struct HostImage {
    size: [u32; 2],
    stride: u32,
    staging: wgpu::Buffer,
    colour: Arc<Vec<u32>>,
    generation: u64,
    /// Rows were copied into `staging` since the last harvest.
    copied: Cell<bool>,
}

/// An image as the host has it: its colour, its size, and its number ([`GENERATIONS`]).
#[derive(Clone)]
pub struct HostFrame {
    pub colour: Arc<Vec<u32>>,
    pub size: [u32; 2],
    pub generation: u64,
}

/// A live view's two images (the preview's and the full one's) in host memory.
pub struct HostCanvas {
    device: wgpu::Device,
    images: [Option<HostImage>; 2],
}

impl HostCanvas {
    pub fn new(device: wgpu::Device) -> Self {
        Self {
            device,
            images: [None, None],
        }
    }

    /// Brings the rows copied since the last call into host memory: maps each image's buffer
    /// (waiting for the device to finish what was submitted) and takes its rows. Returns
    /// whether an image changed.
    pub fn harvest(&mut self) -> bool {
        let mut changed = false;
        for image in self.images.iter_mut().flatten() {
            if !image.copied.replace(false) {
                continue;
            }
            let slice = image.staging.slice(..);
            slice.map_async(wgpu::MapMode::Read, |_| ());
            let wait = wgpu::PollType::Wait {
                submission_index: None,
                timeout: Some(std::time::Duration::from_secs(60)),
            };
            if self.device.poll(wait).is_err() {
                image.staging.unmap();
                continue;
            }
            {
                let Ok(view) = slice.get_mapped_range() else {
                    continue;
                };
                let rows: &[u32] = bytemuck::cast_slice(&view);
                let [width, height] = image.size.map(|s| s as usize);
                let colour = Arc::make_mut(&mut image.colour);
                for (j, row) in colour.chunks_exact_mut(width).take(height).enumerate() {
                    let start = j * image.stride as usize;
                    row.copy_from_slice(&rows[start..start + width]);
                }
            }
            image.staging.unmap();
            image.generation = GENERATIONS.fetch_add(1, Ordering::Relaxed);
            changed = true;
        }
        changed
    }

    /// The image of `quality`, once made.
    pub fn image(&self, quality: Quality) -> Option<HostFrame> {
        let image = self.images[quality as usize].as_ref()?;
        Some(HostFrame {
            colour: image.colour.clone(),
            size: image.size,
            generation: image.generation,
        })
    }
}

impl Canvas for HostCanvas {
    fn resize(&mut self, quality: Quality, size: [u32; 2]) {
        let stride = size[0].next_multiple_of(64);
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view rows"),
            size: stride as u64 * size[1] as u64 * 4,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.images[quality as usize] = Some(HostImage {
            size,
            stride,
            staging,
            colour: Arc::new(vec![0; size[0] as usize * size[1] as usize]),
            generation: GENERATIONS.fetch_add(1, Ordering::Relaxed),
            copied: Cell::new(false),
        });
    }

    fn copy_rows(
        &self,
        quality: Quality,
        encoder: &mut wgpu::CommandEncoder,
        (colour, stride): (&wgpu::Buffer, u32),
        (row, rows): (u32, u32),
    ) {
        let Some(image) = &self.images[quality as usize] else {
            return;
        };
        assert_eq!(stride, image.stride, "the view's rows and its canvas's");
        let offset = row as u64 * stride as u64 * 4;
        let bytes = rows as u64 * stride as u64 * 4;
        encoder.copy_buffer_to_buffer(colour, offset, &image.staging, offset, bytes);
        image.copied.set(true);
    }

    fn write(&mut self, quality: Quality, _queue: &wgpu::Queue, colour: &[u32], size: [u32; 2]) {
        // The host has it already: kept as it is.
        let Some(image) = &mut self.images[quality as usize] else {
            return;
        };
        if image.size != size {
            return;
        }
        Arc::make_mut(&mut image.colour).copy_from_slice(colour);
        image.generation = GENERATIONS.fetch_add(1, Ordering::Relaxed);
    }

    fn release(&mut self) {
        self.images = [None, None];
    }
}
