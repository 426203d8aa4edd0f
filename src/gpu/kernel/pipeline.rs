//! A kernel's pipelines, built per specialisation (override constants) into the cache
//! ([`super::cache`]) and warmed up once;
//! its uniform and output buffers and their bind group; one compute pass's encoding; the rows
//! of a band.

use super::cache::constants_key;
use super::{BAKE_VALUES, Kernel, WORKGROUP_SIZE, buffer};

use crate::error::{Error, Result};
use crate::gpu::shaders::{declaration, split_constants};

impl Kernel {
    /// The pipeline for these override constants (empty: generic), built on first use and
    /// cached.
    /// One build at a time: a second thread asking for the same pipeline waits for it rather
    /// than building it again, and [`Self::held_pipeline`] never waits behind a build.
    pub fn pipeline(&self, constants: &[(&'static str, f64)]) -> Result<wgpu::ComputePipeline> {
        self.pipeline_for(constants, None)
    }

    /// As [`Self::pipeline`], with `baked` (a dispatch's uniform bytes as
    /// [`Self::baked_values`] gives them) baked in where `constants` holds [`BAKE_VALUES`].
    pub(super) fn pipeline_for(
        &self,
        constants: &[(&'static str, f64)],
        baked: Option<&[u8]>,
    ) -> Result<wgpu::ComputePipeline> {
        if asks_to_bake(constants) && baked.is_none() {
            return Err(Error::Gpu(format!(
                "the {} pipeline cannot bake values here (a kernel that bakes, run by steps)",
                self.spec.name
            )));
        }
        let key = constants_key(constants, baked.unwrap_or_default());
        if let Some(p) = self.pipelines.lock().expect("pipeline cache").get(&key) {
            return Ok(p);
        }
        let _building = self.building.lock().expect("pipeline builds");
        if let Some(p) = self.pipelines.lock().expect("pipeline cache").get(&key) {
            return Ok(p);
        }
        let device = &self.ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        // A specialisation runs its own module, its branches cut ([`super::specialise`]),
        // with no constants left to set.
        let overrides: Vec<_> = constants
            .iter()
            .copied()
            .filter(|c| c.0 != BAKE_VALUES.0)
            .collect();
        let specialised = match self.specialised_module(&overrides, baked) {
            Ok(module) => module,
            Err(e) => {
                let _ = pollster::block_on(scope.pop());
                return Err(e);
            }
        };
        // Where naga refused the text, the generic module, its constants set by wgpu (the
        // scene features' constants are no overrides of its: they are left out).
        let (module, left) = match &specialised {
            Some(module) => (module, Vec::new()),
            None => (&self.module, split_constants(&overrides).1),
        };
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(self.spec.name),
            layout: Some(&self.pipeline_layout),
            module,
            entry_point: Some(self.spec.entry_point),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &left,
                ..Default::default()
            },
            cache: self.ctx.pipeline_cache.as_deref().map(|c| c.cache()),
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!(
                "the {} pipeline {overrides:?} was rejected: {e}",
                self.spec.name
            )));
        }
        if let Some(c) = &self.ctx.pipeline_cache {
            c.save();
        }
        let mut cache = self.pipelines.lock().expect("pipeline cache");
        cache.insert(key, pipeline.clone());
        Ok(pipeline)
    }

    /// The pipeline for these override constants if it is built, else None: a caller that
    /// must not wait for a build (the explorer's frame) builds it elsewhere. None for constants
    /// that bake values (they need a dispatch's uniform).
    pub fn held_pipeline(
        &self,
        constants: &[(&'static str, f64)],
    ) -> Option<wgpu::ComputePipeline> {
        let key = constants_key(constants, &[]);
        self.pipelines.lock().expect("pipeline cache").get(&key)
    }

    /// The values of `uniform` a pipeline of `constants` bakes in: None where the constants do
    /// not ask for it ([`BAKE_VALUES`]); else the uniform's bytes with the members still read
    /// at run time zeroed ([`KernelSpec::bake_keeps`]), the pipeline's key.
    pub(super) fn baked_values(
        &self,
        constants: &[(&'static str, f64)],
        uniform: Option<&[u8]>,
    ) -> Result<Option<Vec<u8>>> {
        if !asks_to_bake(constants) {
            return Ok(None);
        }
        let (Some(keeps), Some(uniform)) = (self.spec.bake_keeps, uniform) else {
            return Err(Error::Gpu(format!(
                "the {} pipeline cannot bake values here (a kernel that bakes, run by steps)",
                self.spec.name
            )));
        };
        let Some(parsed) = self.parsed() else {
            return Err(Error::Gpu(format!(
                "the {} module did not parse, so its values cannot be baked",
                self.spec.name
            )));
        };
        let ranges = self.kept_ranges.get_or_init(|| {
            super::bake::kept_ranges(parsed.module(), &self.uniform_starts(), keeps)
        });
        let mut bytes = uniform.to_vec();
        for r in ranges {
            if let Some(kept) = bytes.get_mut(r.clone()) {
                kept.fill(0);
            }
        }
        Ok(Some(bytes))
    }

    /// The source parsed once (the base of every specialisation); None where naga refuses it.
    fn parsed(&self) -> Option<&super::specialise::Parsed> {
        self.parsed
            .get_or_init(|| {
                super::specialise::Parsed::new(&self.spec.module.source(), self.uniforms_as_storage)
            })
            .as_ref()
    }

    /// Runs `f` on the text composed for the scene features `scene` and parsed: the generic
    /// parse where every scene feature is on, else the last [`super::MAX_PARSED`] sets' kept;
    /// None where naga refuses the text.
    fn with_parsed<T>(
        &self,
        scene: &[&'static str],
        f: impl FnOnce(&super::specialise::Parsed) -> T,
    ) -> Option<T> {
        if scene.len() == declaration().scene_features().len() {
            return self.parsed().map(f);
        }
        let mut kept = self.parsed_scenes.lock().expect("parsed scenes");
        let parsed = match kept.iter().position(|(s, _)| s == scene) {
            Some(k) => kept.remove(k).1,
            None => {
                let text = self.spec.module.composed_with(scene).text;
                let parsed = super::specialise::Parsed::new(&text, self.uniforms_as_storage);
                std::sync::Arc::new(parsed)
            }
        };
        if kept.len() >= super::MAX_PARSED {
            kept.remove(0);
        }
        kept.push((scene.to_vec(), parsed.clone()));
        drop(kept);
        parsed.as_ref().as_ref().map(f)
    }

    /// The module of a specialisation (constants given, or values baked): the text composed
    /// for the scene features the constants leave on ([`split_constants`]), the other
    /// constants applied and the branches they decide cut; None for the generic pipeline, or
    /// where naga cannot parse the source itself (the plain module then reports why).
    fn specialised_module(
        &self,
        constants: &[(&'static str, f64)],
        baked: Option<&[u8]>,
    ) -> Result<Option<wgpu::ShaderModule>> {
        if constants.is_empty() && baked.is_none() {
            return Ok(None);
        }
        let (scene, constants) = split_constants(constants);
        let constants = &constants[..];
        let bake = baked.map(|bytes| {
            let values: Vec<_> = self
                .uniform_starts()
                .into_iter()
                .map(|(binding, start)| super::bake::Baked {
                    binding,
                    bytes: bytes.get(start..).unwrap_or_default(),
                })
                .collect();
            (values, self.spec.bake_keeps.unwrap_or_default())
        });
        let specialised = self.with_parsed(&scene, |parsed| {
            parsed.specialise(
                self.spec.entry_point,
                constants,
                bake.as_ref().map(|(v, k)| (&v[..], *k)),
            )
        });
        let Some(specialised) = specialised else {
            return Ok(None);
        };
        let module = specialised.map_err(|e| {
            Error::Gpu(format!(
                "the {} pipeline {constants:?} could not be specialised: {e}",
                self.spec.name
            ))
        })?;
        Ok(Some(super::create_module(
            &self.ctx.device,
            &self.spec,
            wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        )))
    }

    /// Whether the pipeline of these constants has run once; marks it so. One dropped from
    /// the cache since it was asked for (another thread's variants pushed it out) counts as
    /// not warmed.
    pub(super) fn warmed(&self, constants: &[(&'static str, f64)], baked: Option<&[u8]>) -> bool {
        let key = constants_key(constants, baked.unwrap_or_default());
        self.pipelines
            .lock()
            .expect("pipeline cache")
            .mark_warmed(&key)
    }

    /// How many pipelines the kernel holds (at most [`super::MAX_PIPELINES`]).
    pub fn pipelines_held(&self) -> usize {
        self.pipelines.lock().expect("pipeline cache").held()
    }

    /// A uniform buffer for this kernel's params (and its second uniform's, after them).
    pub fn uniform_buffer(&self, label: &str) -> wgpu::Buffer {
        let size = match self.spec.second_uniform {
            Some(second) => self.second_uniform_offset() + second.bytes,
            None => self.spec.uniform_bytes,
        };
        self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::COPY_DST
                | match self.uniforms_as_storage {
                    true => wgpu::BufferUsages::STORAGE,
                    false => wgpu::BufferUsages::UNIFORM,
                },
            mapped_at_creation: false,
        })
    }

    /// Storage buffers for the outputs, `items` each, usable as copy sources (for readback or
    /// a texture), each of its planes ([`super::OutputSpec::planes`]). An on-demand output
    /// ([`super::OutputSpec::on_demand`]) is allocated whole only where `read` reads it back
    /// (by index), else as one item.
    pub fn output_buffers(&self, items: u64, label: &str, read: &[bool]) -> Vec<wgpu::Buffer> {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        self.spec
            .outputs
            .iter()
            .enumerate()
            .map(|(k, o)| {
                let whole = !o.on_demand || read.get(k) == Some(&true);
                buffer(
                    &self.ctx.device,
                    &format!("{label} {}", o.name),
                    if whole { items * o.planes } else { 1 } * o.bytes_per_item,
                    usage,
                )
            })
            .collect()
    }

    /// Each uniform's binding and where its bytes start in a dispatch's uniform bytes: binding
    /// 0 at 0, the second uniform at [`Self::second_uniform_offset`].
    fn uniform_starts(&self) -> Vec<(u32, usize)> {
        let second = self.spec.second_uniform;
        std::iter::once((0, 0))
            .chain(second.map(|s| (s.binding, self.second_uniform_offset() as usize)))
            .collect()
    }

    /// Where the second uniform starts in the uniform buffer: after the first, at the device's
    /// alignment of uniform offsets.
    pub fn second_uniform_offset(&self) -> u64 {
        let limits = self.ctx.device.limits();
        let align = match self.uniforms_as_storage {
            true => limits.min_storage_buffer_offset_alignment,
            false => limits.min_uniform_buffer_offset_alignment,
        } as u64;
        self.spec.uniform_bytes.next_multiple_of(align)
    }

    /// A dispatch's uniform bytes for a kernel with a second uniform: `first`, zeros up to
    /// [`Self::second_uniform_offset`], then `second`.
    pub fn pack_uniforms(&self, first: &[u8], second: &[u8]) -> Vec<u8> {
        let mut bytes = first.to_vec();
        bytes.resize(self.second_uniform_offset() as usize, 0);
        bytes.extend_from_slice(second);
        bytes
    }

    /// Binds a uniform buffer (binding 0, and the second uniform's binding), the output arrays
    /// (bindings 1..) and the scene's input array ([`KernelSpec::input`], [`Kernel::input_buffer`]).
    pub fn bind_group(
        &self,
        uniform: &wgpu::Buffer,
        outputs: &[wgpu::Buffer],
        input: &super::InputData,
    ) -> wgpu::BindGroup {
        assert_eq!(
            outputs.len(),
            self.spec.outputs.len(),
            "one buffer per output"
        );
        let input = self.input_buffer(input);
        let part = |offset, bytes| {
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: uniform,
                offset,
                size: wgpu::BufferSize::new(bytes),
            })
        };
        let first = match self.spec.second_uniform {
            Some(_) => part(0, self.spec.uniform_bytes),
            None => uniform.as_entire_binding(),
        };
        let entries: Vec<_> = std::iter::once(wgpu::BindGroupEntry {
            binding: 0,
            resource: first,
        })
        .chain(
            outputs
                .iter()
                .enumerate()
                .map(|(k, b)| wgpu::BindGroupEntry {
                    binding: k as u32 + 1,
                    resource: b.as_entire_binding(),
                }),
        )
        .chain(self.spec.second_uniform.map(|second| wgpu::BindGroupEntry {
            binding: second.binding,
            resource: part(self.second_uniform_offset(), second.bytes),
        }))
        .chain(self.spec.input.map(|binding| wgpu::BindGroupEntry {
            binding,
            resource: input.as_entire_binding(),
        }))
        .collect();
        self.ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(self.spec.name),
                layout: &self.layout,
                entries: &entries,
            })
    }

    /// Records one compute pass over `width` x `rows` items with the bound parameters.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        (width, rows): (u32, u32),
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.spec.name),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(
            width.div_ceil(WORKGROUP_SIZE.0),
            rows.div_ceil(WORKGROUP_SIZE.1),
            1,
        );
    }

    /// Rows per band for a grid this wide: at most `band_pixels()` items (bounded memory, and
    /// bounded time per dispatch so that no driver watchdog fires on big grids), within the
    /// device's buffer and dispatch limits, a multiple of `band_row_multiple`. The on-demand
    /// outputs are left out ([`Self::band_rows_reading`] counts those read).
    pub fn band_rows(&self, width: u32, height: u32) -> u32 {
        self.band_rows_reading(width, height, &[])
    }

    /// As [`Self::band_rows`], within the limits of the on-demand outputs `read` reads back too:
    /// where a device's limits are too small for a band of them, the bands of a run that reads
    /// them are shorter (never longer) than [`Self::band_rows`].
    pub fn band_rows_reading(&self, width: u32, height: u32, read: &[bool]) -> u32 {
        let limit = self.ctx.device.limits();
        let widest = self
            .spec
            .outputs
            .iter()
            .enumerate()
            .filter(|(k, o)| !o.on_demand || read.get(*k) == Some(&true))
            .map(|(_, o)| o.bytes_per_item * o.planes)
            .max()
            .unwrap_or(1);
        let items = crate::memory::band_pixels()
            .min(limit.max_storage_buffer_binding_size / widest)
            .min(limit.max_buffer_size / widest);
        let multiple = self.spec.band_row_multiple.max(1);
        let rows = ((items / width.max(1) as u64) as u32 / multiple * multiple).max(multiple);
        let max_groups = limit.max_compute_workgroups_per_dimension;
        rows.min(height)
            .min(max_groups.saturating_mul(WORKGROUP_SIZE.1))
    }
}

/// Whether `constants` ask for the scene's values baked in ([`BAKE_VALUES`]).
fn asks_to_bake(constants: &[(&'static str, f64)]) -> bool {
    constants.iter().any(|c| c.0 == BAKE_VALUES.0)
}
