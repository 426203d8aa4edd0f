//! What the GPU tests need of their adapter, and what they say when it lacks it: a test whose
//! part needs a capability the adapter has not (f64 on GL llvmpipe) runs the rest and prints one
//! `skipped:` line naming the test, the part and the capability, straight to the process's
//! standard error so that `cargo test` shows it without `--nocapture`. Under CI
//! (`QJULIA_CI=1`) the backend the pass names (`WGPU_BACKEND`) decides what must be there: on
//! Vulkan (lavapipe) every capability below, so that a skip there is a failure.
//!
//! Also here: a test that needs a process of its own runs itself in a child process
//! ([`own_process`]), and on GL the GPU tests of a process take turns
//! ([`one_test_at_a_time_on_gl`]).

use std::cell::RefCell;
use std::io::Write;
use std::sync::{Mutex, MutexGuard};

use qjulia::gpu::GpuContext;

/// A capability of the adapter that some tests need.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Capability {
    /// f64 in the kernels: SHADER_F64 and the start-up check of f64 passing
    /// (`GpuContext::f64_support`).
    F64,
    /// A pipeline cache kept between processes (wgpu's PIPELINE_CACHE).
    PipelineCache,
}

impl Capability {
    /// How a `skipped:` line names it.
    pub fn name(self) -> &'static str {
        match self {
            Capability::F64 => "f64 on the GPU",
            Capability::PipelineCache => "a pipeline cache (PIPELINE_CACHE)",
        }
    }

    /// The `WGPU_BACKEND` values on which CI requires it.
    pub fn required_on(self) -> &'static [&'static str] {
        match self {
            Capability::F64 | Capability::PipelineCache => &["vulkan"],
        }
    }

    /// Whether `ctx`'s adapter has it; if not, why not.
    pub fn check(self, ctx: &GpuContext) -> Result<(), String> {
        match self {
            Capability::F64 => ctx.f64_support().map(|_| ()).map_err(|e| e.to_string()),
            Capability::PipelineCache => {
                if ctx
                    .device
                    .features()
                    .contains(wgpu::Features::PIPELINE_CACHE)
                {
                    Ok(())
                } else {
                    Err(format!(
                        "the adapter {} has no PIPELINE_CACHE",
                        ctx.adapter_label()
                    ))
                }
            }
        }
    }
}

/// Whether the tests run under CI (`QJULIA_CI` set, as `.ci/run` sets it), where nothing that
/// CI installs or that the named backend has may be skipped.
pub fn under_ci() -> bool {
    std::env::var_os("QJULIA_CI").is_some()
}

/// Whether this pass must have `capability`: under CI, where `WGPU_BACKEND` names a backend
/// that has it, or names none (a CI pass says which backend it tests).
pub fn required(capability: Capability) -> bool {
    if !under_ci() {
        return false;
    }
    match std::env::var("WGPU_BACKEND") {
        Ok(backend) => capability.required_on().iter().any(|b| {
            backend
                .to_ascii_lowercase()
                .split(',')
                .any(|x| x.trim() == *b)
        }),
        Err(_) => true,
    }
}

/// Writes `skipped: TEST: PART (WHY)` to the process's standard error, past the test harness's
/// capture, so that it shows in `cargo test`'s own output.
pub fn say_skipped(test: &str, part: &str, why: &str) {
    let _ = writeln!(std::io::stderr().lock(), "skipped: {test}: {part} ({why})");
}

/// Skips `part` of `test` for want of something CI installs or allows (a tool, root): says so
/// with a `skipped:` line, or panics under CI, where nothing skips.
pub fn skip_outside_ci(test: &str, part: &str, why: &str) {
    assert!(!under_ci(), "{test}: {part}: {why}, under CI (QJULIA_CI)");
    say_skipped(test, part, why);
}

/// Whether the adapter of `ctx` has `capability` for `part` of `test`. Where it does not, says
/// so with a `skipped:` line and returns false, except where this pass requires it
/// ([`required`]): then it panics with the reason.
pub fn has(ctx: &GpuContext, capability: Capability, test: &str, part: &str) -> bool {
    match capability.check(ctx) {
        Ok(()) => true,
        Err(why) => {
            assert!(
                !required(capability),
                "{test}: {part} needs {}, which this pass requires (QJULIA_CI=1, WGPU_BACKEND={}): \
                 {why}",
                capability.name(),
                std::env::var("WGPU_BACKEND").unwrap_or_default()
            );
            say_skipped(test, part, &format!("needs {}: {why}", capability.name()));
            false
        }
    }
}

/// The shared tracer's adapter has `capability` for `part` of `test` (see [`has`]); false too
/// where the GPU tests are skipped.
pub fn gpu_has(capability: Capability, test: &str, part: &str) -> bool {
    super::gpu(test).is_some_and(|t| has(t.context(), capability, test, part))
}

/// The variable that marks the child process [`own_process`] starts, and names its test.
const OWN_PROCESS: &str = "QJULIA_TEST_OWN_PROCESS";

/// Runs the test `name` of the module `module` (its `module_path!()`) in a process of its own,
/// with `env` added to its environment: for a test that reads a process-wide variable or
/// measures the process's resident memory. Returns true in that process, where the test's body
/// then runs, and false in the test's own thread once the child passed; panics with the child's
/// output if it failed or ran no test. The child's `skipped:` lines are passed on.
pub fn own_process(module: &str, name: &str, env: &[(&str, &str)]) -> bool {
    let module = module.split_once("::").map_or("", |(_, rest)| rest);
    let path = if module.is_empty() {
        name.to_string()
    } else {
        format!("{module}::{name}")
    };
    if std::env::var(OWN_PROCESS).is_ok_and(|v| v == path) {
        return true;
    }
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args([path.as_str(), "--exact", "--nocapture", "--test-threads=1"])
        .env(OWN_PROCESS, &path)
        .envs(env.iter().copied())
        .output()
        .expect("start the test's own process");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    for line in stderr.lines().filter(|l| l.starts_with("skipped: ")) {
        let _ = writeln!(std::io::stderr().lock(), "{line}");
    }
    assert!(
        out.status.success() && stdout.contains("test result: ok. 1 passed"),
        "{path} in its own process failed ({}):\n{stdout}\n{stderr}",
        out.status
    );
    false
}

/// The turn of the test holding the GL adapter.
static GL_TURN: Mutex<()> = Mutex::new(());

thread_local! {
    /// This test thread's turn on GL, held until the thread (the test) ends.
    static MY_GL_TURN: RefCell<Option<MutexGuard<'static, ()>>> = const { RefCell::new(None) };
}

/// On GL, makes the calling test wait for the GPU until no other test of this process holds
/// it, then hold it until the test ends. wgpu's GL backend has one context per instance behind
/// a lock that gives up after 6 s ("Could not lock adapter context. This is most-likely a
/// deadlock."), and on llvmpipe one test's long dispatch holds it past that while another
/// test's thread waits. Vulkan has no such lock, and its tests run side by side as before.
pub fn one_test_at_a_time_on_gl(ctx: &GpuContext) {
    if ctx.adapter.get_info().backend != wgpu::Backend::Gl {
        return;
    }
    MY_GL_TURN.with(|turn| {
        let mut turn = turn.borrow_mut();
        if turn.is_none() {
            // A test that panicked while it held the turn poisons the lock; the turn is free.
            *turn = Some(GL_TURN.lock().unwrap_or_else(|e| e.into_inner()));
        }
    });
}
