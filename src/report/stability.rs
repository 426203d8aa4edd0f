//! Stiff and extreme cases: every one must finish (under a time limit), produce no NaN or Inf,
//! give the same result twice, and report its error against the f64 CPU reference. Used by the
//! tests and by `qjulia report --stability`.

use std::sync::Arc;
use std::sync::mpsc::channel;
use std::time::{Duration, Instant};

use crate::compare::{Agreement, CONTRACT_TOLERANCE};
use crate::gpu::GpuKernels;
use crate::precision::{PrecisionChoice, slice_warnings};
use crate::render::{Backend, Plan, Planner};
use crate::scene::{Scene, SceneLoader};
use crate::{Frame, Picture, Precision, Summary};

/// One stiff or extreme setting: overrides of the default scene.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: &'static str,
    /// Why it is hard.
    pub why: &'static str,
    pub sets: &'static [&'static str],
}

impl Case {
    /// The case's scene at `size` x `size` pixels (unless the case sets its own size).
    pub fn scene(&self, size: u32) -> Scene {
        let mut loader = SceneLoader::new();
        for (key, value) in [("image.width", size), ("image.height", size)] {
            loader.flag(key, toml::Value::Integer(value as i64), "size");
        }
        for s in self.sets {
            loader
                .set(s)
                .unwrap_or_else(|e| panic!("case {}: {e}", self.name));
        }
        loader
            .build()
            .unwrap_or_else(|e| panic!("case {}: {e}", self.name))
    }
}

/// The cases, after the issue that asked for them.
pub const CASES: &[Case] = &[
    Case {
        name: "c = 0",
        why: "the unit ball, exact estimate",
        sets: &["fractal.c=[0,0,0,0]"],
    },
    Case {
        name: "parabolic c = 0.25",
        why: "orbits creep toward a parabolic fixed point",
        sets: &["fractal.c=[0.25,0,0,0]", "fractal.max_iterations=60"],
    },
    Case {
        name: "parabolic c = -0.75",
        why: "a parabolic 2-cycle",
        sets: &["fractal.c=[-0.75,0,0,0]", "fractal.max_iterations=60"],
    },
    Case {
        name: "c = 0.2501",
        why: "just outside the Mandelbrot set: slow escape",
        sets: &["fractal.c=[0.2501,0,0,0]", "fractal.max_iterations=60"],
    },
    Case {
        name: "Siegel disk",
        why: "an irrationally indifferent fixed point",
        sets: &[
            "fractal.c=[-0.390541,-0.586788,0,0]",
            "fractal.max_iterations=60",
        ],
    },
    Case {
        name: "c = -1",
        why: "z' collapses to 0 on the critical orbit",
        sets: &["fractal.c=[-1,0,0,0]", "fractal.max_iterations=40"],
    },
    Case {
        name: "c = i",
        why: "a dendrite, no interior",
        sets: &["fractal.c=[0,1,0,0]", "fractal.max_iterations=40"],
    },
    Case {
        name: "c far outside",
        why: "dust: nothing to hit",
        sets: &["fractal.c=[1.5,1.0,0.5,0.0]"],
    },
    Case {
        name: "max_iterations = 1",
        why: "the coarsest estimate",
        sets: &["fractal.max_iterations=1"],
    },
    Case {
        name: "max_iterations = 10^4",
        why: "derivatives over- and underflow inside",
        sets: &["fractal.max_iterations=10000"],
    },
    Case {
        name: "epsilon = 1e-9",
        why: "below the float spacing: steps stall",
        sets: &["fractal.epsilon=1e-9"],
    },
    Case {
        name: "epsilon = 0.5",
        why: "a very coarse surface",
        sets: &["fractal.epsilon=0.5"],
    },
    Case {
        name: "escape radius^2 = 4.0001",
        why: "barely above the escape bound",
        sets: &["fractal.escape_radius_squared=4.0001"],
    },
    Case {
        name: "escape radius^2 = 1e38",
        why: "|z|^2 overflows f32 one step later",
        sets: &["fractal.escape_radius_squared=1e38"],
    },
    Case {
        name: "eye inside the set",
        why: "the first estimate is negative",
        sets: &["camera.eye=[0.05,0.02,0.0]", "camera.target=[0,0,-1]"],
    },
    Case {
        name: "eye at the origin",
        why: "the ray starts at q = 0",
        sets: &[
            "camera.eye=[0,0,0]",
            "camera.target=[0,0,-1]",
            "camera.fov_y_degrees=90",
        ],
    },
    Case {
        name: "grazing the bounding sphere",
        why: "discriminants near 0",
        sets: &[
            "camera.target=[0.5773502691896258,0,2.183503419072274]",
            "camera.fov_y_degrees=0.5",
        ],
    },
    Case {
        name: "field of view 0.001°",
        why: "nearly parallel rays",
        sets: &["camera.fov_y_degrees=0.001"],
    },
    Case {
        name: "field of view 179.9°",
        why: "rays nearly sideways",
        sets: &["camera.fov_y_degrees=179.9"],
    },
    Case {
        name: "deep zoom",
        why: "pixels below the f32 spacing",
        sets: &[
            "camera.fov_y_degrees=0.0002",
            "fractal.epsilon=1e-7",
            "camera.target=[-0.1,0.05,0.3]",
        ],
    },
    // Deep zooms at pixel footprints of 1e-6, 1e-9 and 1e-12 at the target (64 pixels high, the
    // eye 3 from it): the deep-zoom preset's settings (30 iterations, the analytic normal,
    // epsilon one pixel footprint). f32 cannot resolve the last two (a warning says so).
    Case {
        name: "pixel 1e-6",
        why: "a deep zoom f32 still resolves",
        sets: &[
            "image.width=64",
            "image.height=64",
            "camera.fov_y_degrees=0.0012223099628993989",
            "fractal.max_iterations=30",
            "fractal.epsilon=1e-13",
            "fractal.pixel_epsilon=1",
            "shading.normal=\"analytic\"",
        ],
    },
    Case {
        name: "pixel 1e-9",
        why: "a deep zoom below f32's spacing",
        sets: &[
            "image.width=64",
            "image.height=64",
            "camera.fov_y_degrees=1.2223099629457564e-6",
            "fractal.max_iterations=30",
            "fractal.epsilon=1e-13",
            "fractal.pixel_epsilon=1",
            "shading.normal=\"analytic\"",
        ],
    },
    Case {
        name: "pixel 1e-12",
        why: "a deep zoom near f64's spacing (5e-15 here)",
        sets: &[
            "image.width=64",
            "image.height=64",
            "camera.fov_y_degrees=1.2223099629457563e-9",
            "fractal.max_iterations=30",
            "fractal.epsilon=1e-13",
            "fractal.pixel_epsilon=1",
            "shading.normal=\"analytic\"",
        ],
    },
    Case {
        name: "1x1 image",
        why: "one pixel",
        sets: &["image.width=1", "image.height=1"],
    },
    Case {
        name: "1024x4 image",
        why: "aspect 256",
        sets: &["image.width=1024", "image.height=4"],
    },
];

/// The tracer a case runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Runner {
    GpuF32,
    /// f64 on the GPU, where the adapter has it and passes the start-up check.
    GpuF64,
    CpuF32,
    CpuF64,
}

impl Runner {
    pub fn name(self) -> &'static str {
        match self {
            Runner::GpuF32 => "gpu f32",
            Runner::GpuF64 => "gpu f64",
            Runner::CpuF32 => "cpu f32",
            Runner::CpuF64 => "cpu f64",
        }
    }

    pub fn precision(self) -> Precision {
        match self {
            Runner::CpuF64 | Runner::GpuF64 => Precision::F64,
            Runner::CpuF32 | Runner::GpuF32 => Precision::F32,
        }
    }

    /// The GPU tracers `gpu` can run: f32, and f64 where the device passes its check.
    pub fn on_gpu(gpu: &Arc<GpuKernels>) -> Vec<Runner> {
        let mut runners = vec![Runner::GpuF32];
        if gpu.has_f64() {
            runners.push(Runner::GpuF64);
        }
        runners
    }

    /// The plan of this tracer for a shaded picture of `scene` (the GPU one on `gpu`): the
    /// backend and precision as asked, through the one decision.
    pub fn plan(self, scene: &Scene, gpu: Option<&Arc<GpuKernels>>) -> crate::Result<Plan> {
        let choice = match self.precision() {
            Precision::F32 => PrecisionChoice::F32,
            Precision::F64 => PrecisionChoice::F64,
        };
        let mut planner = match self {
            Runner::GpuF32 | Runner::GpuF64 => {
                let gpu =
                    gpu.ok_or_else(|| crate::Error::NoAdapter("no GPU for this run".into()))?;
                Planner::on_device(gpu.clone(), Backend::Gpu, choice)
            }
            Runner::CpuF32 | Runner::CpuF64 => Planner::new(Backend::Cpu, choice),
        };
        planner.plan(scene, Picture::SHADED.into(), &mut |_| {})
    }

    /// Renders the scene (shaded) on this tracer: the frame and its render seconds.
    pub fn render(
        self,
        scene: &Scene,
        gpu: Option<&Arc<GpuKernels>>,
    ) -> crate::Result<(Frame, f64)> {
        let plan = self.plan(scene, gpu)?;
        let (frame, stats) = plan.renderer.render_frame(scene, Picture::SHADED)?;
        Ok((frame, stats.render_seconds))
    }
}

/// What one case did on one tracer.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub case: &'static str,
    pub runner: Runner,
    /// None when it did not finish within the limit (or failed).
    pub seconds: Option<f64>,
    pub error: Option<String>,
    pub non_finite: u64,
    /// Steps above max_steps, or depths not finite where a hit is claimed.
    pub invalid: u64,
    pub deterministic: bool,
    pub hit_fraction: f64,
    /// Against the f64 CPU render of the same scene.
    pub versus_f64: Option<Agreement>,
    pub warnings: Vec<String>,
}

impl Outcome {
    /// Finished, finite, valid and repeatable.
    pub fn passed(&self) -> bool {
        self.seconds.is_some()
            && self.error.is_none()
            && self.non_finite == 0
            && self.invalid == 0
            && self.deterministic
    }
}

/// Runs `f` on its own thread; None if it takes longer than `limit` (the thread is left behind,
/// so a hang fails the caller instead of stalling it).
pub fn with_time_limit<T: Send + 'static>(
    limit: Duration,
    f: impl FnOnce() -> T + Send + 'static,
) -> Option<T> {
    let (send, receive) = channel();
    std::thread::spawn(move || {
        send.send(f()).ok();
    });
    receive.recv_timeout(limit).ok()
}

/// Renders twice with `render`, on its own thread under `limit` ([`with_time_limit`]), timing
/// the first: (the first frame, the second, the first's seconds); None past the limit.
pub fn render_twice(
    limit: Duration,
    render: impl Fn() -> crate::Result<Frame> + Send + 'static,
) -> Option<crate::Result<(Frame, Frame, f64)>> {
    with_time_limit(limit, move || {
        let start = Instant::now();
        let first = render()?;
        let seconds = start.elapsed().as_secs_f64();
        Ok((first, render()?, seconds))
    })
}

/// The tracers a case runs on, in order: the f64 CPU first (the others' reference), the f32
/// CPU, then each of the GPU's where there is one.
pub fn runners(gpu: Option<&Arc<GpuKernels>>) -> Vec<Runner> {
    let mut runners = vec![Runner::CpuF64, Runner::CpuF32];
    if let Some(gpu) = gpu {
        runners.extend(Runner::on_gpu(gpu));
    }
    runners
}

fn same(a: &Frame, b: &Frame) -> bool {
    a.colour == b.colour
        && a.steps == b.steps
        && a.depth
            .iter()
            .zip(&b.depth)
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Runs one case on one tracer twice, under the time limit, and compares with `reference`.
pub fn run_case(
    case: &'static Case,
    size: u32,
    runner: Runner,
    gpu: Option<Arc<GpuKernels>>,
    reference: Option<&Frame>,
    limit: Duration,
) -> Outcome {
    let scene = case.scene(size);
    let max_steps = scene.fractal.max_steps;
    let warnings = slice_warnings(&scene, runner.precision())
        .into_iter()
        .map(|w| w.text)
        .collect();
    let mut outcome = Outcome {
        case: case.name,
        runner,
        seconds: None,
        error: None,
        non_finite: 0,
        invalid: 0,
        deterministic: false,
        hit_fraction: 0.0,
        versus_f64: None,
        warnings,
    };
    let run = render_twice(limit, move || Ok(runner.render(&scene, gpu.as_ref())?.0));
    match run {
        None => outcome.error = Some(format!("did not finish within {} s", limit.as_secs())),
        Some(Err(e)) => outcome.error = Some(e.to_string()),
        Some(Ok((first, second, seconds))) => {
            outcome.seconds = Some(seconds);
            outcome.non_finite = first.non_finite + second.non_finite;
            outcome.invalid = first.steps.iter().filter(|&&s| s > max_steps).count() as u64
                + first
                    .depth
                    .iter()
                    .filter(|d| !d.is_nan() && (!d.is_finite() || **d < 0.0))
                    .count() as u64;
            outcome.deterministic = same(&first, &second);
            outcome.hit_fraction = Summary::of(&first).hit_fraction;
            outcome.versus_f64 =
                reference.map(|r| Agreement::measure(r, &first, &CONTRACT_TOLERANCE));
        }
    }
    outcome
}

/// Every case on every runner given, the f64 CPU first as the reference for the others.
pub fn run_all(
    size: u32,
    gpu: Option<Arc<GpuKernels>>,
    limit: Duration,
    mut progress: impl FnMut(&Outcome),
) -> Vec<Outcome> {
    let mut outcomes = Vec::new();
    for case in CASES {
        let reference_scene = case.scene(size);
        let reference = with_time_limit(limit, move || {
            Runner::CpuF64.render(&reference_scene, None).ok()
        })
        .flatten()
        .map(|(frame, _)| frame);
        for runner in runners(gpu.as_ref()) {
            let against = if runner == Runner::CpuF64 {
                None
            } else {
                reference.as_ref()
            };
            let outcome = run_case(case, size, runner, gpu.clone(), against, limit);
            progress(&outcome);
            outcomes.push(outcome);
        }
    }
    outcomes
}

/// The report page (docs/stability.md) around the outcomes' table.
pub fn page(size: u32, limit_seconds: u64, table: &str) -> String {
    format!(
        "# Stability: stiff and extreme cases\n\n`qjulia report --stability --size {size}` on this machine. \
         Each case runs twice per tracer under a {limit_seconds} s limit; errors are against the f64 CPU \
         render of the same scene (masks and colour: share of pixels within CONTRACT_TOLERANCE).\n\n{table}"
    )
}

/// The outcomes as a Markdown table, with a totals line.
pub fn markdown(outcomes: &[Outcome]) -> String {
    let mut out = String::from(
        "| case | tracer | seconds | NaN/Inf | invalid | repeatable | hits | masks vs f64 | colour vs f64 | depth max err vs f64 | notes |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for o in outcomes {
        let seconds = o.seconds.map_or("—".into(), |s| format!("{s:.3}"));
        let (mask, colour, depth) =
            o.versus_f64
                .map_or(("ref".into(), "ref".into(), "ref".into()), |a| {
                    (
                        format!("{:.2}%", a.mask * 100.0),
                        format!("{:.2}%", a.colour * 100.0),
                        format!("{:.1e}", a.depth_max_error),
                    )
                });
        let mut notes: Vec<String> = o.error.iter().cloned().collect();
        notes.extend(
            o.warnings
                .iter()
                .map(|w| format!("warning: {}", w.split(':').next().unwrap_or(w))),
        );
        out += &format!(
            "| {} | {} | {seconds} | {} | {} | {} | {:.1}% | {mask} | {colour} | {depth} | {} |\n",
            o.case,
            o.runner.name(),
            o.non_finite,
            o.invalid,
            if o.deterministic { "yes" } else { "NO" },
            o.hit_fraction * 100.0,
            notes.join("; ")
        );
    }
    let failed = outcomes.iter().filter(|o| !o.passed()).count();
    let hangs = outcomes.iter().filter(|o| o.seconds.is_none()).count();
    let nan: u64 = outcomes.iter().map(|o| o.non_finite).sum();
    out += &format!(
        "\n{} runs: {} passed, {failed} failed; {hangs} did not finish; {nan} NaN/Inf values.\n",
        outcomes.len(),
        outcomes.len() - failed
    );
    out
}
