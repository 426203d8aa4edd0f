//! The start-up check of an adapter's f64: once per device ([`super::GpuContext::f64_support`]),
//! before any f64 kernel runs, shaders/f64check.wgsl computes every f64 operation the f64
//! kernels rely on (add, sub, mul, div, sqrt, the log path with its split of the exponent, the
//! powers of two, the f32 <-> f64
//! and u32 -> f64 conversions, floor, fract, abs, min, max, comparison, and the kernels' own
//! `real_*` functions of shaders/real64.wgsl) on a few known values, and the host compares each
//! with its own result. lavapipe, for one, has SHADER_F64 and returns wrong f64 `log` values
//! without an error, which is why the kernels take no f64 log from the driver.
//!
//! Where the adapter's sqrt fails, the kernels get `SQRT_NEWTON` (an f32 sqrt and two f64
//! Newton steps) and the check runs again with it: a repair, not a refusal. Any other failure,
//! or an adapter without SHADER_F64, refuses f64 on that device with the reason: `--backend
//! gpu --precision f64` exits 1 with it, `--backend auto` renders on the CPU.
//!
//! Test hook: `QJULIA_F64_CHECK_INJECT=OP` (an operation's name in [`OPS`]) makes that
//! operation's result wrong inside the check kernel (its `INJECT` override), and nowhere else,
//! so that a test can see the check fail loudly without editing the shader.

use bytemuck::{Pod, Zeroable};

use super::context::{F64Support, GpuContext};
use super::kernel::{Kernel, KernelSpec, OutputSpec, Run};
use super::shaders::F64CHECK_MODULE;
use crate::error::{Error, Result};

/// The operations the kernel checks, by their results' order (`OP_*` in shaders/f64check.wgsl).
pub const OPS: [&str; 21] = [
    "add",
    "sub",
    "mul",
    "div",
    "sqrt",
    "real_sqrt",
    "real_log",
    "split_mantissa",
    "split_exponent",
    "pow2",
    "to_f32",
    "from_u32",
    "floor",
    "fract",
    "abs",
    "min",
    "max",
    "less",
    "real_pow",
    "real_cos",
    "real_normalize",
];

/// The environment variable of the test hook.
pub const INJECT_ENV: &str = "QJULIA_F64_CHECK_INJECT";

/// Cases the kernel runs (the uniform's array length).
const CASES: usize = 8;

/// The operands (a, b) of each case: ordinary values, a deep zoom's small ones, one just above
/// 1 (where a log loses its digits), a large and a tiny one, negatives.
const OPERANDS: [(f64, f64); CASES] = [
    (1.5, 0.3),
    (3.0, 7.0),
    (1.0 + 1.0 / (1u64 << 30) as f64, 1e-12),
    (2.5e-9, 3.7e-10),
    (123456.789, -0.001),
    (-std::f64::consts::FRAC_1_SQRT_2, 2.0),
    (1e30, 3e-7),
    (3.1e-300, 7e-12),
];

/// Keep in sync with `struct CheckParams` in shaders/f64check.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct CheckParams {
    pub cases: [[f64; 4]; CASES],
    pub count: u32,
    /// WGSL's size is a multiple of 32 bytes (the alignment of `vec4<f64>`).
    pub _pad: [u32; 7],
}

/// Accuracy asked of the arithmetic (add, sub, mul, div, sqrt and what is built of them), in
/// units of f64's last place: the geometry of a deep zoom needs f64's digits, not exact rounding.
pub const ARITHMETIC_ULPS: f64 = 4.0;
/// Relative accuracy asked of real_log (a polynomial in f64): far below what any estimate needs,
/// far above f64 rounding.
pub const LOG_TOLERANCE: f64 = 1e-13;
/// Accuracy asked of what goes through f32 (the conversion, real_pow, real_cos), relative to
/// the value or absolute below 1: f32's rounding and its pow and cos's error.
pub const F32_TOLERANCE: f64 = 1e-5;

const OUTPUTS: [OutputSpec; 1] = [OutputSpec {
    name: "results",
    bytes_per_item: 8 * OPS.len() as u64,
    on_demand: false,
    planes: 1,
    planes_back: 1,
}];

/// The check's kernel: uniform [`CheckParams`], one output of every result of every case.
pub const F64CHECK_KERNEL: KernelSpec = KernelSpec {
    name: "f64check",
    module: F64CHECK_MODULE,
    entry_point: "main",
    uniform_bytes: size_of::<CheckParams>() as u64,
    outputs: &OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
    input: None,
    bake_keeps: None,
};

/// One wrong result.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub op: &'static str,
    pub a: f64,
    pub b: f64,
    pub got: f64,
    pub want: f64,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of ({:e}, {:e}) gave {:e}, expected {:e}",
            self.op, self.a, self.b, self.got, self.want
        )
    }
}

/// The test hook's operation: `QJULIA_F64_CHECK_INJECT`, when set.
pub fn inject_from_env() -> Result<Option<&'static str>> {
    match std::env::var(INJECT_ENV) {
        Ok(name) => OPS
            .iter()
            .find(|&&op| op == name)
            .map(|&op| Some(op))
            .ok_or_else(|| {
                Error::Unsupported(format!(
                    "{INJECT_ENV}={name}: not an operation of the f64 check ({})",
                    OPS.join(", ")
                ))
            }),
        Err(_) => Ok(None),
    }
}

/// Checks the device's f64 ([`F64Support`] where it is right, repairs included), with `inject`'s
/// operation made wrong on purpose (the test hook). Err: why f64 cannot run on this device, in
/// one line.
pub fn check_f64(ctx: &GpuContext, inject: Option<&str>) -> Result<F64Support> {
    let start = std::time::Instant::now();
    let adapter = ctx.adapter_label();
    if !ctx.device.features().contains(wgpu::Features::SHADER_F64) {
        return Err(Error::Unsupported(format!(
            "the adapter {adapter} has no f64 (SHADER_F64)"
        )));
    }
    let kernel = Kernel::new(ctx.clone(), F64CHECK_KERNEL)?;
    let inject_code = match inject {
        Some(name) => {
            1 + OPS
                .iter()
                .position(|&op| op == name)
                .ok_or_else(|| Error::Unsupported(format!("no f64 check operation {name}")))?
        }
        None => 0,
    };
    let run = |sqrt_newton: bool| -> Result<Vec<Failure>> {
        let constants = [
            ("INJECT", inject_code as f64),
            ("SQRT_NEWTON", if sqrt_newton { 1.0 } else { 0.0 }),
        ];
        let results = run_kernel(&kernel, &constants)?;
        Ok(compare(&results))
    };
    let refuse = |failures: &[Failure], note: &str| {
        // The first few, on one line.
        let mut list: Vec<String> = failures.iter().take(3).map(|f| f.to_string()).collect();
        if failures.len() > 3 {
            list.push(format!("{} more", failures.len() - 3));
        }
        Error::Unsupported(format!(
            "f64 on {adapter} failed the start-up check{note}: {}",
            list.join("; ")
        ))
    };
    let failures = run(false)?;
    let mut support = F64Support {
        constants: vec![("SQRT_NEWTON", 0.0)],
        repaired: Vec::new(),
        seconds: 0.0,
    };
    if !failures.is_empty() {
        if !failures.iter().any(|f| f.op == "sqrt") {
            return Err(refuse(&failures, ""));
        }
        // The adapter's sqrt is wrong: again with the kernels' own (SQRT_NEWTON); only the
        // adapter's sqrt may still fail.
        let left: Vec<Failure> = run(true)?.into_iter().filter(|f| f.op != "sqrt").collect();
        if !left.is_empty() {
            return Err(refuse(&left, " (with sqrt replaced)"));
        }
        support.constants = vec![("SQRT_NEWTON", 1.0)];
        support.repaired.push("sqrt");
    }
    support.seconds = start.elapsed().as_secs_f64();
    Ok(support)
}

/// Runs the check kernel with these constants: every case's results, OPS to a case.
fn run_kernel(kernel: &Kernel, constants: &[(&'static str, f64)]) -> Result<Vec<f64>> {
    let mut params = CheckParams {
        count: CASES as u32,
        ..Default::default()
    };
    for (case, &(a, b)) in params.cases.iter_mut().zip(&OPERANDS) {
        *case = [a, b, 0.0, 0.0];
    }
    let uniform = |_| bytemuck::bytes_of(&params).to_vec();
    let run = Run {
        constants,
        size: (CASES as u32, 1),
        read: &[true],
        dispatches_per_band: 1,
        params: &uniform,
        input: None,
    };
    let mut results = Vec::new();
    kernel.run(
        &run,
        |band| {
            let bytes = band.outputs[0].expect("the results are read back");
            bytemuck::pod_collect_to_vec::<u8, f64>(bytes)
        },
        |made| {
            results.extend(made);
            Ok(())
        },
    )?;
    Ok(results)
}

/// Every result that differs from the host's by more than its tolerance.
pub fn compare(results: &[f64]) -> Vec<Failure> {
    let mut failures = Vec::new();
    for (k, &(a, b)) in OPERANDS.iter().enumerate() {
        for (op, &name) in OPS.iter().enumerate() {
            let got = results[k * OPS.len() + op];
            let (want, ok) = expected(name, k, a, b, got);
            if !ok {
                failures.push(Failure {
                    op: name,
                    a,
                    b,
                    got,
                    want,
                });
            }
        }
    }
    failures
}

/// The host's result of operation `name` on case k = (a, b), and whether `got` is within its
/// tolerance of it.
fn expected(name: &str, k: usize, a: f64, b: f64, got: f64) -> (f64, bool) {
    let ulps = |want: f64| {
        let ulp = (want.abs() * f64::EPSILON).max(f64::MIN_POSITIVE);
        (got - want).abs() <= ARITHMETIC_ULPS * ulp
    };
    let exact = |want: f64| got == want;
    let relative = |want: f64, tol: f64| (got - want).abs() <= tol * want.abs().max(1.0);
    let fract = |x: f64| x - x.floor();
    let (mantissa, exponent) = split_exponent(a.abs());
    match name {
        "add" => (a + b, ulps(a + b)),
        "sub" => (a - b, ulps(a - b)),
        "mul" => (a * b, ulps(a * b)),
        "div" => (a / b, ulps(a / b)),
        "sqrt" | "real_sqrt" => (a.abs().sqrt(), ulps(a.abs().sqrt())),
        "real_log" => {
            let want = a.abs().ln();
            (want, (got - want).abs() <= LOG_TOLERANCE * want.abs())
        }
        "split_mantissa" => (mantissa, exact(mantissa)),
        "split_exponent" => (exponent, exact(exponent)),
        "pow2" => {
            let want = a * 2f64.powi(k as i32 * 150 - 600);
            (want, exact(want))
        }
        "to_f32" => {
            let want = a as f32 as f64;
            (want, relative(want, F32_TOLERANCE))
        }
        "from_u32" => {
            let want = (k as u32 * 1000003 + 7) as f64;
            (want, exact(want))
        }
        "floor" => (a.floor(), exact(a.floor())),
        "fract" => (fract(a), ulps(fract(a))),
        "abs" => (a.abs(), exact(a.abs())),
        "min" => (a.min(b), exact(a.min(b))),
        "max" => (a.max(b), exact(a.max(b))),
        "less" => {
            let want = if a < b { 1.0 } else { 0.0 };
            (want, exact(want))
        }
        "real_pow" => {
            let want = (fract(a.abs()) as f32).powf(10.0) as f64;
            (want, relative(want, F32_TOLERANCE))
        }
        "real_cos" => {
            let want = (fract(a) as f32).cos() as f64;
            (want, relative(want, F32_TOLERANCE))
        }
        "real_normalize" => {
            let want = a / (a * a + b * b + 1.0).sqrt();
            (want, ulps(want))
        }
        _ => unreachable!("an operation of OPS"),
    }
}

/// x = m 2^e with m in [sqrt(1/2), sqrt(2)), as (m, e), for a normal x > 0: the host's twin of
/// real64.wgsl's split_exponent.
fn split_exponent(x: f64) -> (f64, f64) {
    let mut e = x.log2().round();
    let mut m = x / 2f64.powi(e as i32);
    // log2's rounding can put m just outside the range.
    if m >= std::f64::consts::SQRT_2 {
        m *= 0.5;
        e += 1.0;
    } else if m < std::f64::consts::FRAC_1_SQRT_2 {
        m *= 2.0;
        e -= 1.0;
    }
    (m, e)
}

impl GpuContext {
    /// Whether f64 kernels run right on this device, and with which repairs: the start-up check
    /// ([`check_f64`]) on the first call, its outcome after. Err (exit 1) where the adapter has
    /// no SHADER_F64 or an operation fails beyond repair, saying which.
    pub fn f64_support(&self) -> Result<&F64Support> {
        self.f64_check
            .get_or_init(|| {
                inject_from_env()
                    .and_then(|inject| check_f64(self, inject))
                    .map_err(|e| e.to_string())
            })
            .as_ref()
            .map_err(|e| Error::Unsupported(e.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The host's split agrees with its definition on the check's operands.
    #[test]
    fn split_exponent_splits_every_operand() {
        for &(a, _) in &OPERANDS {
            let (m, e) = split_exponent(a.abs());
            let range = std::f64::consts::FRAC_1_SQRT_2..std::f64::consts::SQRT_2;
            assert!(range.contains(&m), "{a}: {m}");
            assert_eq!(m * 2f64.powi(e as i32), a.abs(), "{a}");
        }
    }

    /// Exact results pass and a result one part in a billion off fails, for every operation
    /// but those done in f32.
    #[test]
    fn compare_accepts_the_host_and_rejects_a_wrong_value() {
        let mut results = vec![0.0; CASES * OPS.len()];
        for (k, &(a, b)) in OPERANDS.iter().enumerate() {
            for (op, &name) in OPS.iter().enumerate() {
                results[k * OPS.len() + op] = expected(name, k, a, b, 0.0).0;
            }
        }
        assert_eq!(compare(&results), vec![]);
        let div = OPS.iter().position(|&o| o == "div").unwrap();
        results[3 * OPS.len() + div] *= 1.0 + 1e-9;
        let failures = compare(&results);
        assert_eq!(failures.len(), 1, "{failures:?}");
        assert_eq!(failures[0].op, "div");
    }
}
