//! Making a band's device buffers ([`RunBuffers`]) and reading a band back through them: the
//! copies out, the mapping, the timestamps.

use std::sync::mpsc;

use super::buffers::{MapResult, RunBuffers, Timestamps};
use super::{Kernel, buffer};
use crate::error::{Error, Result};

/// Bytes of the two timestamps a band writes.
const TIMESTAMP_BYTES: u64 = 16;

impl Kernel {
    /// A band's buffers for `items` items, with readback copies of the outputs `read` asks for,
    /// binding the input array `input`.
    pub(super) fn run_buffers(
        &self,
        items: u64,
        read: &[bool],
        input: &super::InputData,
    ) -> RunBuffers {
        let device = &self.ctx.device;
        let uniform = self.uniform_buffer(&format!("{} params", self.spec.name));
        let storage = self.output_buffers(items, self.spec.name, read);
        let read_usage = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let readback = self
            .spec
            .outputs
            .iter()
            .zip(read)
            .map(|(o, &wanted)| {
                let label = format!("{} {} readback", self.spec.name, o.name);
                wanted.then(|| buffer(device, &label, items * o.read_bytes(), read_usage))
            })
            .collect();
        let bind_group = self.bind_group(&uniform, &storage, input);
        let timestamps = self.ctx.has_timestamps().then(|| Timestamps {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("kernel time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer(
                device,
                "timestamps",
                TIMESTAMP_BYTES,
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(device, "timestamps readback", TIMESTAMP_BYTES, read_usage),
        });
        RunBuffers {
            items,
            read: read.to_vec(),
            uniform,
            storage,
            readback,
            bind_group,
            input: super::input_source(input),
            timestamps,
        }
    }

    /// Copies the band's outputs asked for (and its timestamps) to the readback buffers and asks
    /// for them to be mapped: the submission to wait for, and one report per buffer mapped.
    pub(super) fn copy_out(
        &self,
        buffers: &RunBuffers,
        items: u64,
    ) -> (wgpu::SubmissionIndex, Vec<mpsc::Receiver<MapResult>>) {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        let mut encoder = device.create_command_encoder(&Default::default());
        let mut to_map: Vec<(&wgpu::Buffer, u64)> = Vec::new();
        for ((src, dst), spec) in buffers
            .storage
            .iter()
            .zip(&buffers.readback)
            .zip(self.spec.outputs)
        {
            let bytes = items * spec.read_bytes();
            if let Some(dst) = dst
                && bytes > 0
            {
                // Plane p of the band's `items` lies at p times the buffers' items (a last band
                // may be shorter than the buffers were made for) and comes back after plane p - 1.
                let plane = items * spec.bytes_per_item;
                for p in 0..spec.planes_back {
                    let from = p * buffers.items * spec.bytes_per_item;
                    encoder.copy_buffer_to_buffer(src, from, dst, p * plane, plane);
                }
                to_map.push((dst, bytes));
            }
        }
        if let Some(t) = &buffers.timestamps {
            encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, TIMESTAMP_BYTES);
            to_map.push((&t.readback, TIMESTAMP_BYTES));
        }
        let index = queue.submit([encoder.finish()]);
        let mapped = to_map
            .into_iter()
            .map(|(buffer, bytes)| {
                let (sender, receiver) = mpsc::channel();
                buffer
                    .slice(..bytes)
                    .map_async(wgpu::MapMode::Read, move |r| drop(sender.send(r)));
                receiver
            })
            .collect();
        (index, mapped)
    }

    /// The mapped bytes of each output asked for.
    pub(super) fn read_mapped(
        &self,
        buffers: &RunBuffers,
        items: u64,
    ) -> Result<Vec<Option<wgpu::BufferView>>> {
        buffers
            .readback
            .iter()
            .zip(self.spec.outputs)
            .map(|(b, spec)| {
                let bytes = items * spec.read_bytes();
                match b {
                    Some(b) if bytes > 0 => b
                        .slice(..bytes)
                        .get_mapped_range()
                        .map(Some)
                        .map_err(|e| Error::Gpu(format!("reading back the image: {e}"))),
                    _ => Ok(None),
                }
            })
            .collect()
    }

    /// Seconds between the band's two timestamps.
    pub(super) fn read_timestamps(&self, t: &Timestamps) -> Result<f64> {
        let view = t
            .readback
            .slice(..TIMESTAMP_BYTES)
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("reading timestamps: {e}")))?;
        let stamps: &[u64] = bytemuck::cast_slice(&view);
        let ticks = stamps[1].saturating_sub(stamps[0]);
        Ok(ticks as f64 * self.ctx.queue.get_timestamp_period() as f64 * 1e-9)
    }

    pub(super) fn unmap(&self, buffers: &RunBuffers) {
        for b in buffers.readback.iter().flatten() {
            b.unmap();
        }
        if let Some(t) = &buffers.timestamps {
            t.readback.unmap();
        }
    }
}
