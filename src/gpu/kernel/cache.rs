//! A kernel's pipelines cached per specialisation (their override constants as a key), the
//! cache bounded ([`MAX_PIPELINES`], the least recently used dropped), and whether each has
//! been warmed up.

use std::collections::HashMap;

/// Override constants as a hash key (the values' bits), and the uniform bytes baked in (empty
/// where none are).
pub(super) type ConstantsKey = (Vec<(&'static str, u64)>, Vec<u8>);

pub(super) fn constants_key(constants: &[(&'static str, f64)], baked: &[u8]) -> ConstantsKey {
    (
        constants.iter().map(|&(n, v)| (n, v.to_bits())).collect(),
        baked.to_vec(),
    )
}

/// The most pipelines a kernel keeps. An explorer session that visits every preset and turns
/// features on and off meets a new variant at each step, and a driver holds a pipeline's
/// compiled code (megabytes a variant, on lavapipe) until it is destroyed:
/// unbounded, the cache grew the explorer's memory for as long as it ran. Past this many, the
/// one used longest ago is dropped and built again if it comes back. 16 holds a scene's
/// preview, shaded and final variants, each with and without the denoiser's AOVs, for two
/// scenes at once.
pub const MAX_PIPELINES: usize = 16;

/// A kernel's pipelines by their constants.
#[derive(Default)]
pub(super) struct Pipelines {
    held: HashMap<ConstantsKey, Held>,
    /// Counts uses, to order them.
    clock: u64,
}

/// A pipeline held, whether it has run once, and when it was last asked for.
struct Held {
    pipeline: wgpu::ComputePipeline,
    warmed: bool,
    used: u64,
}

impl Pipelines {
    /// The pipeline of `key`, if held, marked as used now.
    pub(super) fn get(&mut self, key: &ConstantsKey) -> Option<wgpu::ComputePipeline> {
        self.clock += 1;
        let held = self.held.get_mut(key)?;
        held.used = self.clock;
        Some(held.pipeline.clone())
    }

    /// Holds a new pipeline, dropping the least recently used past [`MAX_PIPELINES`] (a
    /// pass that still runs it keeps its own reference until it is done).
    pub(super) fn insert(&mut self, key: ConstantsKey, pipeline: wgpu::ComputePipeline) {
        self.clock += 1;
        let used = self.clock;
        self.held.insert(
            key,
            Held {
                pipeline,
                warmed: false,
                used,
            },
        );
        while self.held.len() > MAX_PIPELINES {
            let oldest = self
                .held
                .iter()
                .min_by_key(|(_, h)| h.used)
                .map(|(k, _)| k.clone())
                .expect("more than none held");
            self.held.remove(&oldest);
        }
    }

    /// Whether the pipeline of `key` has run once; marks it so. One not held (dropped since it
    /// was asked for) has not.
    pub(super) fn mark_warmed(&mut self, key: &ConstantsKey) -> bool {
        self.held
            .get_mut(key)
            .is_some_and(|held| std::mem::replace(&mut held.warmed, true))
    }

    /// How many pipelines are held.
    pub(super) fn held(&self) -> usize {
        self.held.len()
    }
}
