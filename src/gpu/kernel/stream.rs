//! Running a kernel: a run's bands as [`Step`]s, and a stream of steps two in flight (submitted,
//! waited for, decoded and handed on in order).

use std::sync::mpsc;
use std::time::{Duration, Instant};

use super::buffers::{MapResult, RunBuffers};
use super::{Band, BandOutput, Kernel, Run, RunTimes, WORKGROUP_SIZE};
use crate::error::{Error, Result};

/// Steps a stream keeps on the device at once on a GPU: one being read back, one running.
const STEPS_IN_FLIGHT: usize = 2;

/// One band of a stream ([`Kernel::run_stream`]): its pipeline's constants, the grid's width,
/// its rows, the uniform of each of its dispatches and the outputs to read back.
pub struct Step {
    pub constants: Vec<(&'static str, f64)>,
    pub width: u32,
    /// The grid's rows: the step with `row + rows == height` is its last band.
    pub height: u32,
    pub row: u32,
    pub rows: u32,
    /// The grid's rows per band (the buffers are sized for it; the last band may be shorter).
    pub band_rows: u32,
    pub uniforms: Vec<Vec<u8>>,
    pub read: Vec<bool>,
    /// The scene's input array ([`super::Run::input`]).
    pub input: super::InputData,
}

/// A step done: what `decode` made of it, when it was submitted and decoded, and its GPU time
/// (timestamp queries, where the device has them).
pub struct StepDone<T> {
    pub made: T,
    pub submitted: Instant,
    pub decoded: Instant,
    pub gpu_seconds: Option<f64>,
}

/// The test hook of a lost device: `QJULIA_FAULT_LOSE_DEVICE=N` destroys the device once the
/// process has submitted its Nth band (from 1), before that band is read back.
fn lose_device_now() -> bool {
    use std::sync::atomic::{AtomicU64, Ordering};
    static AFTER: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    static SUBMITTED: AtomicU64 = AtomicU64::new(0);
    let Some(after) = *AFTER.get_or_init(|| {
        std::env::var("QJULIA_FAULT_LOSE_DEVICE")
            .ok()
            .and_then(|v| v.parse().ok())
    }) else {
        return false;
    };
    SUBMITTED.fetch_add(1, Ordering::Relaxed) + 1 == after
}

/// A step submitted and not yet read back.
struct InFlight {
    step: Step,
    buffers: RunBuffers,
    submitted: Instant,
    index: wgpu::SubmissionIndex,
    mapped: Vec<mpsc::Receiver<MapResult>>,
}

impl Kernel {
    /// Runs the kernel over the whole grid, band by band, top to bottom. Each band's outputs
    /// are handed to `decode` (timed) and what it makes to `sink` (not timed). The first use of
    /// a pipeline is preceded by an untimed warm-up dispatch of one workgroup (lavapipe compiles
    /// a kernel at its first dispatch, not at pipeline creation). The bands are pipelined as in
    /// [`Self::run_stream`].
    pub fn run<T>(
        &self,
        run: &Run<'_>,
        decode: impl FnMut(BandOutput<'_>) -> T,
        sink: impl FnMut(T) -> Result<()>,
    ) -> Result<RunTimes> {
        self.run_rows(run, 0..run.size.1, decode, sink)
    }

    /// As [`Self::run`], over the grid's rows `rows` alone (`render --tile`): the bands are the
    /// whole grid's band size, from `rows.start` on, so that each dispatch covers the same
    /// samples as in a run of the whole grid. `rows.start` must be a multiple of the kernel's
    /// `band_row_multiple` (a cone block's row).
    pub fn run_rows<T>(
        &self,
        run: &Run<'_>,
        rows: std::ops::Range<u32>,
        mut decode: impl FnMut(BandOutput<'_>) -> T,
        mut sink: impl FnMut(T) -> Result<()>,
    ) -> Result<RunTimes> {
        assert_eq!(
            run.read.len(),
            self.spec.outputs.len(),
            "read: one flag per output"
        );
        let mut steps = self.steps_rows(run, rows);
        let mut times = RunTimes::default();
        let mut first_submitted = None;
        // The sink's time is left out, though the device may have run the next band meanwhile.
        let mut in_sink = Duration::ZERO;
        self.run_stream(
            &mut steps,
            |_, out| decode(out),
            |_, done| {
                let start = *first_submitted.get_or_insert(done.submitted);
                times.seconds = (done.decoded - start).saturating_sub(in_sink).as_secs_f64();
                times.gpu_seconds = done
                    .gpu_seconds
                    .map(|s| s + times.gpu_seconds.unwrap_or(0.0));
                let sink_start = Instant::now();
                let sunk = sink(done.made);
                in_sink += sink_start.elapsed();
                sunk
            },
        )?;
        Ok(times)
    }

    /// The bands of a run as [`Step`]s, each with its dispatches' uniforms.
    pub fn steps<'r>(&self, run: &'r Run<'_>) -> impl Iterator<Item = Step> + 'r {
        self.steps_rows(run, 0..run.size.1)
    }

    /// As [`Self::steps`], the bands of the grid's rows `rows` alone, each of the whole grid's
    /// band size (the last may be shorter), from `rows.start` on (see [`Self::run_rows`]).
    pub fn steps_rows<'r>(
        &self,
        run: &'r Run<'_>,
        rows: std::ops::Range<u32>,
    ) -> impl Iterator<Item = Step> + 'r {
        let (width, height) = run.size;
        let band_rows = self.band_rows_reading(width, height, run.read).max(1);
        let multiple = self.spec.band_row_multiple.max(1);
        assert!(
            rows.start.is_multiple_of(multiple) && rows.end <= height,
            "rows {rows:?} start on a multiple of {multiple} and lie in the grid's {height}"
        );
        let end = rows.end;
        let dispatches = run.dispatches_per_band.max(1);
        let constants = run.constants.to_vec();
        let read = run.read.to_vec();
        let input = run.input.clone();
        (rows.start..end)
            .step_by(band_rows as usize)
            .map(move |row| {
                let rows = band_rows.min(end - row);
                Step {
                    constants: constants.clone(),
                    width,
                    height,
                    row,
                    rows,
                    band_rows,
                    read: read.clone(),
                    input: input.clone(),
                    uniforms: (0..dispatches)
                        .map(|dispatch| {
                            (run.params)(Band {
                                row,
                                rows,
                                dispatch,
                            })
                        })
                        .collect(),
                }
            })
    }

    /// Runs a stream of bands (of one grid or of many: an animation's frames), two at a time:
    /// while the host waits for, reads back and decodes one band, the device already runs the
    /// next, so a fast GPU is not left idle between frames. Each step's outputs go to `decode`
    /// and then, with its times, to `sink`, in the order of the steps. Memory stays bounded:
    /// two sets of buffers, each of one band.
    pub fn run_stream<T>(
        &self,
        steps: &mut dyn Iterator<Item = Step>,
        mut decode: impl FnMut(&Step, BandOutput<'_>) -> T,
        mut sink: impl FnMut(Step, StepDone<T>) -> Result<()>,
    ) -> Result<()> {
        let mut free: Vec<RunBuffers> = self
            .spare
            .lock()
            .expect("spare buffers")
            .drain(..)
            .collect();
        let mut in_flight: std::collections::VecDeque<InFlight> = Default::default();
        let mut finish_oldest = |in_flight: &mut std::collections::VecDeque<InFlight>,
                                 free: &mut Vec<RunBuffers>|
         -> Result<()> {
            let flight = in_flight.pop_front().expect("a step in flight");
            let (step, done, buffers) = self.finish(flight, &mut decode)?;
            free.push(buffers);
            sink(step, done)
        };
        let depth = self.steps_in_flight();
        for step in steps {
            assert_eq!(
                step.read.len(),
                self.spec.outputs.len(),
                "one flag per output"
            );
            if in_flight.len() == depth {
                finish_oldest(&mut in_flight, &mut free)?;
            }
            let items = step.band_rows as u64 * step.width as u64;
            let input = super::input_source(&step.input);
            let buffers = match free.iter().position(|b| b.fits(items, &step.read, input)) {
                Some(k) => free.swap_remove(k),
                None => self.run_buffers(items, &step.read, &step.input),
            };
            in_flight.push_back(self.submit(step, buffers)?);
        }
        while !in_flight.is_empty() {
            finish_oldest(&mut in_flight, &mut free)?;
        }
        free.truncate(STEPS_IN_FLIGHT);
        *self.spare.lock().expect("spare buffers") = free;
        Ok(())
    }

    /// Steps in flight on this device: `STEPS_IN_FLIGHT` on a GPU; one on a CPU adapter
    /// (lavapipe, llvmpipe), whose "device" is the host's own cores: there the host's work on
    /// one band would only take cores from the next, and lavapipe's threads, which wait for
    /// each other within a dispatch, lose more than the overlap gains (measured: docs/PERFORMANCE.md).
    /// `QJULIA_STEPS_IN_FLIGHT` (1 or 2) overrides it, to measure.
    pub fn steps_in_flight(&self) -> usize {
        let default = match self.ctx.info.device_type {
            wgpu::DeviceType::Cpu => 1,
            _ => STEPS_IN_FLIGHT,
        };
        std::env::var("QJULIA_STEPS_IN_FLIGHT")
            .ok()
            .and_then(|v| v.parse::<usize>().ok())
            .map_or(default, |n| n.clamp(1, STEPS_IN_FLIGHT))
    }

    /// Submits a step's dispatches and the copies of its outputs, and asks for them to be
    /// mapped; does not wait. A pipeline's first use is warmed up first, untimed.
    fn submit(&self, step: Step, buffers: RunBuffers) -> Result<InFlight> {
        let first = step.uniforms.first().map(|u| &u[..]);
        let baked = self.baked_values(&step.constants, first)?;
        let pipeline = self.pipeline_for(&step.constants, baked.as_deref())?;
        if let Some(baked) = &baked {
            // Every dispatch of the step runs the values of its first.
            for uniform in &step.uniforms[1..] {
                if self.baked_values(&step.constants, Some(uniform))?.as_ref() != Some(baked) {
                    return Err(Error::Gpu(format!(
                        "the {} step's dispatches differ in a value baked into its pipeline",
                        self.spec.name
                    )));
                }
            }
        }
        if !self.warmed(&step.constants, baked.as_deref()) {
            let rows = step.rows.min(WORKGROUP_SIZE.1);
            let size = (step.width.min(WORKGROUP_SIZE.0), rows);
            for uniform in &step.uniforms {
                // The warm-up's uniform is the band's own: only its first rows run.
                self.dispatch(&pipeline, &buffers, uniform, size, None)?;
            }
            self.ctx
                .device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Gpu(format!("waiting for the GPU: {e}")))?;
        }
        let submitted = Instant::now();
        let dispatches = step.uniforms.len();
        for (dispatch, uniform) in step.uniforms.iter().enumerate() {
            // The band's time: from the start of its first dispatch to the end of its last.
            let (first, last) = (dispatch == 0, dispatch + 1 == dispatches);
            let timestamps = buffers
                .timestamps
                .as_ref()
                .filter(|_| first || last)
                .map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.queries,
                    beginning_of_pass_write_index: first.then_some(0),
                    end_of_pass_write_index: last.then_some(1),
                });
            self.dispatch(
                &pipeline,
                &buffers,
                uniform,
                (step.width, step.rows),
                timestamps,
            )?;
        }
        let items = step.rows as u64 * step.width as u64;
        let (index, mapped) = self.copy_out(&buffers, items);
        if lose_device_now() {
            self.ctx.lose_device();
        }
        Ok(InFlight {
            step,
            buffers,
            submitted,
            index,
            mapped,
        })
    }

    /// Waits for a step's outputs, decodes them and frees its buffers for the next step.
    fn finish<T>(
        &self,
        flight: InFlight,
        decode: &mut impl FnMut(&Step, BandOutput<'_>) -> T,
    ) -> Result<(Step, StepDone<T>, RunBuffers)> {
        let InFlight {
            step,
            buffers,
            submitted,
            index,
            mapped,
        } = flight;
        let waited = self.ctx.device.poll(wgpu::PollType::Wait {
            submission_index: Some(index),
            timeout: None,
        });
        // A lost device fails whatever was waiting on it: say why once, as the device said.
        let failed = |otherwise: String| Error::Gpu(self.ctx.fault().unwrap_or(otherwise));
        waited.map_err(|e| failed(format!("waiting for the GPU: {e}")))?;
        for result in mapped {
            result
                .recv()
                .map_err(|_| failed("the device was lost".into()))?
                .map_err(|e| failed(format!("mapping a result buffer: {e}")))?;
        }
        if let Some(why) = self.ctx.fault() {
            return Err(Error::Gpu(why));
        }
        let items = step.rows as u64 * step.width as u64;
        let made = {
            let views = self.read_mapped(&buffers, items)?;
            let slices: Vec<Option<&[u8]>> = views.iter().map(|m| m.as_deref()).collect();
            let output = BandOutput {
                row: step.row,
                rows: step.rows,
                outputs: &slices,
            };
            decode(&step, output)
        };
        let gpu_seconds = match &buffers.timestamps {
            Some(t) => Some(self.read_timestamps(t)?),
            None => None,
        };
        self.unmap(&buffers);
        let done = StepDone {
            made,
            submitted,
            decoded: Instant::now(),
            gpu_seconds,
        };
        Ok((step, done, buffers))
    }

    /// Uploads one dispatch's params and submits it.
    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        buffers: &RunBuffers,
        params: &[u8],
        size: (u32, u32),
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<()> {
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        queue.write_buffer(&buffers.uniform, 0, params);
        let mut encoder = device.create_command_encoder(&Default::default());
        self.encode(
            &mut encoder,
            pipeline,
            &buffers.bind_group,
            size,
            timestamps,
        );
        queue.submit([encoder.finish()]);
        Ok(())
    }
}
