//! Specialisation before the driver: a scene's override constants applied to the kernel's naga
//! module, and the branches they decide cut out, so that the driver compiles only the code the
//! scene runs.
//!
//! wgpu applies override constants itself, but hands the driver every branch: `if SHADOWS
//! { ... }` with SHADOWS false is still in the SPIR-V, and the driver translates, inlines and
//! optimises it before it finds it dead. On lavapipe that translation is nearly all of a
//! process's start-up (its pipeline cache keeps nothing), and a real GPU's compiler pays for it
//! too. Here the constants are resolved with naga's own `process_overrides`, every `if` whose
//! condition they decide becomes the block it takes, and what no entry point can reach any more
//! (functions only a cut branch called) is compacted away. The result has no overrides left to
//! set; wgpu validates it again as it would any module.

use std::borrow::Cow;
use std::collections::HashMap;

use super::walk::visit;

use naga::{
    Block, Constant, Expression, Handle, Literal, LocalVariable, Module, Statement, UnaryOperator,
    valid,
};

/// The WGSL source parsed and validated once, the base every specialisation starts from.
pub(super) struct Parsed {
    module: Module,
    info: valid::ModuleInfo,
}

impl Parsed {
    /// Parses and validates `source`, its uniforms made read-only storage where
    /// `uniforms_as_storage` ([`uniforms_as_storage`]); `None` where naga refuses it (wgpu then
    /// reports why through the plain path).
    pub(super) fn new(source: &str, uniforms_as_storage: bool) -> Option<Self> {
        let mut module = naga::front::wgsl::parse_str(source).ok()?;
        if uniforms_as_storage {
            self::uniforms_as_storage(&mut module);
        }
        let info = valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all())
            .validate(&module)
            .ok()?;
        Some(Self { module, info })
    }

    /// The module as parsed, no constants applied (the generic pipeline's).
    pub(super) fn module(&self) -> &Module {
        &self.module
    }

    /// The module with these constants applied and the branches they decide removed, for the
    /// compute entry point `entry`.
    pub(super) fn specialise(
        &self,
        entry: &str,
        constants: &[(&'static str, f64)],
        bake: Option<(&[super::bake::Baked<'_>], &[&str])>,
    ) -> Result<Module, String> {
        let values: naga::back::PipelineConstants =
            constants.iter().map(|&(n, v)| (n.to_string(), v)).collect();
        let (module, _) = naga::back::pipeline_constants::process_overrides(
            &self.module,
            &self.info,
            Some((naga::ShaderStage::Compute, entry)),
            &values,
        )
        .map_err(|e| e.to_string())?;
        let mut module = Cow::into_owned(module);
        if let Some((values, keeps)) = bake {
            super::bake::bake(&mut module, values, keeps)?;
        }
        prune_module(&mut module);
        naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
        Ok(module)
    }
}

/// Every uniform of the module made a read-only storage buffer, its layout unchanged (the
/// member offsets are explicit, and a uniform's layout rules are the stricter): what the host
/// binds on a device whose driver mistreats uniforms ([`crate::gpu::GpuContext::uniforms_as_storage`]).
pub(super) fn uniforms_as_storage(module: &mut Module) {
    for (_, global) in module.global_variables.iter_mut() {
        if global.space == naga::AddressSpace::Uniform {
            global.space = naga::AddressSpace::Storage {
                access: naga::StorageAccess::LOAD,
            };
        }
    }
}

/// Cuts every branch the module's constants decide, in its functions and entry points, and
/// the branches that a call of a function of no arguments decides where that function returns
/// one decided value (a feature's switch, such as `fog_on()`, composed for a scene without it:
/// `return false;`, or a switch that baked values decide): those are found after a round of
/// cuts, and the next round cuts what they decide.
fn prune_module(module: &mut Module) {
    let mut calls = HashMap::new();
    for _ in 0..4 {
        prune_functions(module, &calls);
        let found = decided_functions(module, &calls);
        if found == calls {
            break;
        }
        calls = found;
    }
}

/// The functions of no arguments whose body is one `return` of a value the constants decide
/// (`calls`: those found so far, whose calls decide values too).
fn decided_functions(
    module: &Module,
    calls: &HashMap<Handle<naga::Function>, bool>,
) -> HashMap<Handle<naga::Function>, bool> {
    let mut found = HashMap::new();
    for (h, f) in module.functions.iter() {
        if !f.arguments.is_empty() {
            continue;
        }
        let Some(value) = single_return(&f.body) else {
            continue;
        };
        let known = Known {
            constants: &module.constants,
            global_expressions: &module.global_expressions,
            expressions: &f.expressions,
            locals: HashMap::new(),
            calls,
        };
        if let Some(b) = known.value(value) {
            found.insert(h, b);
        }
    }
    found
}

/// The value a block returns where it is a lone `return` of a value (the `Emit`s that name
/// expressions and plain blocks aside).
fn single_return(block: &Block) -> Option<Handle<Expression>> {
    let mut statements = block.iter().filter(|s| !matches!(s, Statement::Emit(_)));
    let only = statements.next()?;
    if statements.next().is_some() {
        return None;
    }
    match only {
        Statement::Return { value } => *value,
        Statement::Block(inner) => single_return(inner),
        _ => None,
    }
}

/// One round of [`prune_module`]'s cuts, the calls of `calls` decided.
fn prune_functions(module: &mut Module, calls: &HashMap<Handle<naga::Function>, bool>) {
    let Module {
        functions,
        entry_points,
        constants,
        global_expressions,
        ..
    } = module;
    let results: HashMap<Handle<naga::Function>, Handle<naga::Type>> = functions
        .iter()
        .filter_map(|(h, f)| Some((h, f.result.as_ref()?.ty)))
        .collect();
    let bodies = functions
        .iter_mut()
        .map(|(_, f)| f)
        .chain(entry_points.iter_mut().map(|e| &mut e.function));
    for function in bodies {
        let mut known = Known {
            constants,
            global_expressions,
            expressions: &function.expressions,
            locals: HashMap::new(),
            calls,
        };
        let mut body = std::mem::take(&mut function.body);
        // WGSL's `a && b` and `a || b` reach naga's IR as a temporary set in an `if` on `a`
        // and read by the `if` around them: once the first cut decides that `if`, the
        // temporary is known, and the next round cuts what it decides.
        for _ in 0..8 {
            body = known.prune(body);
            let locals = known.decided_temporaries(&body, &function.local_variables);
            if locals.len() == known.locals.len() {
                break;
            }
            known.locals = locals;
        }
        function.body = body;
        forget_cut_calls(function, &results);
    }
}

/// The results of calls a cut removed, made zeros of their type: only cut code reads them, and a
/// result left naming a function no call reaches any more would outlive the function's
/// compaction.
fn forget_cut_calls(
    function: &mut naga::Function,
    results: &HashMap<Handle<naga::Function>, Handle<naga::Type>>,
) {
    let mut live = Vec::new();
    visit(&function.body, &mut |s| {
        if let Statement::Call {
            result: Some(r), ..
        } = *s
        {
            live.push(r);
        }
    });
    for (h, e) in function.expressions.iter_mut() {
        if let Expression::CallResult(f) = *e
            && !live.contains(&h)
        {
            *e = Expression::ZeroValue(results[&f]);
        }
    }
}

/// What is known in one function before the driver runs: the module's constants (the
/// overrides, now resolved), and the temporaries they decide.
struct Known<'a> {
    constants: &'a naga::Arena<Constant>,
    global_expressions: &'a naga::Arena<Expression>,
    expressions: &'a naga::Arena<Expression>,
    locals: HashMap<Handle<LocalVariable>, bool>,
    /// The functions whose every call returns a decided value ([`decided_functions`]).
    calls: &'a HashMap<Handle<naga::Function>, bool>,
}

impl Known<'_> {
    /// The value of a boolean expression, where the constants decide it.
    fn value(&self, expr: Handle<Expression>) -> Option<bool> {
        use naga::BinaryOperator::{LogicalAnd, LogicalOr};
        match self.expressions[expr] {
            Expression::Literal(_) | Expression::Constant(_) => match self.scalar(expr)? {
                Literal::Bool(b) => Some(b),
                _ => None,
            },
            Expression::Load { pointer } => match self.expressions[pointer] {
                Expression::LocalVariable(local) => self.locals.get(&local).copied(),
                _ => None,
            },
            Expression::CallResult(function) => self.calls.get(&function).copied(),
            Expression::Unary {
                op: UnaryOperator::LogicalNot,
                expr,
            } => self.value(expr).map(|b| !b),
            // A comparison of two known scalars (a baked value's against a literal:
            // `params.samples > 1u`).
            Expression::Binary { op, left, right } if comparison(op) => {
                compare(op, self.scalar(left)?, self.scalar(right)?)
            }
            // Expressions have no side effects in naga's IR (calls are statements), so a
            // decided side decides the whole.
            Expression::Binary {
                op: op @ (LogicalAnd | LogicalOr),
                left,
                right,
            } => {
                let decisive = op == LogicalOr;
                match (self.value(left), self.value(right)) {
                    (Some(l), _) if l == decisive => Some(decisive),
                    (_, Some(r)) if r == decisive => Some(decisive),
                    (Some(_), Some(_)) => Some(!decisive),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The value of a scalar expression that is a literal or a constant's.
    fn scalar(&self, expr: Handle<Expression>) -> Option<Literal> {
        match self.expressions[expr] {
            Expression::Literal(l) => Some(l),
            Expression::Constant(c) => match self.global_expressions[self.constants[c].init] {
                Expression::Literal(l) => Some(l),
                _ => None,
            },
            _ => None,
        }
    }

    /// The block with each decided `if` replaced by the block it takes.
    fn prune(&self, block: Block) -> Block {
        let mut out = Block::with_capacity(block.len());
        for (statement, span) in block.span_into_iter() {
            let statement = match statement {
                Statement::If {
                    condition,
                    accept,
                    reject,
                } => match self.value(condition) {
                    // `break` and `continue` inside still leave the loop around the `if`: a
                    // plain block does not catch them.
                    Some(true) => Statement::Block(self.prune(accept)),
                    Some(false) if reject.is_empty() => continue,
                    Some(false) => Statement::Block(self.prune(reject)),
                    None => Statement::If {
                        condition,
                        accept: self.prune(accept),
                        reject: self.prune(reject),
                    },
                },
                Statement::Block(inner) => Statement::Block(self.prune(inner)),
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => Statement::Loop {
                    body: self.prune(body),
                    continuing: self.prune(continuing),
                    break_if,
                },
                Statement::Switch { selector, cases } => Statement::Switch {
                    selector,
                    cases: cases
                        .into_iter()
                        .map(|case| naga::SwitchCase {
                            body: self.prune(case.body),
                            ..case
                        })
                        .collect(),
                },
                other => other,
            };
            let ends = diverges(&statement);
            out.push(statement, span);
            // What follows a `return` (a decided `if !shade_on() { return ...; }`
            // leaves one) is never reached.
            if ends {
                break;
            }
        }
        out
    }

    /// The temporaries whose every store stores one decided value. Only naga's own qualify:
    /// unnamed, with no initialiser, their pointer only stored to and loaded from, and (as
    /// the front end writes them) stored on every path before they are read. A variable of
    /// the source is never taken: it may be read before a store, as its zero.
    fn decided_temporaries(
        &self,
        body: &Block,
        locals: &naga::Arena<LocalVariable>,
    ) -> HashMap<Handle<LocalVariable>, bool> {
        let mut stored: HashMap<Handle<LocalVariable>, Option<bool>> = HashMap::new();
        let temporary = |pointer: Handle<Expression>| match self.expressions[pointer] {
            Expression::LocalVariable(l)
                if locals[l].name.is_none() && locals[l].init.is_none() =>
            {
                Some(l)
            }
            _ => None,
        };
        let mut escaped = Vec::new();
        visit(body, &mut |statement| match *statement {
            Statement::Store { pointer, value } => {
                if let Some(local) = temporary(pointer) {
                    let value = self.value(value);
                    let entry = stored.entry(local).or_insert(value);
                    if *entry != value {
                        *entry = None;
                    }
                }
            }
            Statement::Call { ref arguments, .. } => {
                escaped.extend(arguments.iter().filter_map(|&a| temporary(a)));
            }
            _ => {}
        });
        stored
            .into_iter()
            .filter(|(local, _)| !escaped.contains(local))
            .filter_map(|(local, value)| Some((local, value?)))
            .collect()
    }
}

/// Whether `op` compares (==, !=, <, <=, >, >=).
fn comparison(op: naga::BinaryOperator) -> bool {
    use naga::BinaryOperator::*;
    matches!(
        op,
        Equal | NotEqual | Less | LessEqual | Greater | GreaterEqual
    )
}

/// `a op b` for two scalars of one type (u32, i32, f32, f64, bool); None for any other pair.
fn compare(op: naga::BinaryOperator, a: Literal, b: Literal) -> Option<bool> {
    use naga::BinaryOperator::*;
    use std::cmp::Ordering;
    let order = match (a, b) {
        (Literal::U32(a), Literal::U32(b)) => a.partial_cmp(&b),
        (Literal::I32(a), Literal::I32(b)) => a.partial_cmp(&b),
        (Literal::F32(a), Literal::F32(b)) => a.partial_cmp(&b),
        (Literal::F64(a), Literal::F64(b)) => a.partial_cmp(&b),
        (Literal::Bool(a), Literal::Bool(b)) => a.partial_cmp(&b),
        _ => None,
    }?;
    Some(match op {
        Equal => order == Ordering::Equal,
        NotEqual => order != Ordering::Equal,
        Less => order == Ordering::Less,
        LessEqual => order != Ordering::Greater,
        Greater => order == Ordering::Greater,
        GreaterEqual => order != Ordering::Less,
        _ => return None,
    })
}

/// Whether control never passes a statement to the next: it returns, breaks or continues, or
/// is a block ending so.
fn diverges(statement: &Statement) -> bool {
    match statement {
        Statement::Return { .. } | Statement::Break | Statement::Continue | Statement::Kill => true,
        Statement::Block(b) => b.last().is_some_and(diverges),
        _ => false,
    }
}

/// The statements the driver meets once it has inlined every call (as drivers do): those of
/// the entry points, each call counted as the statements of the function it calls.
#[cfg(test)]
fn inlined_statements(module: &Module) -> usize {
    fn size(
        module: &Module,
        body: &Block,
        memo: &mut HashMap<Handle<naga::Function>, usize>,
    ) -> usize {
        let mut calls = Vec::new();
        let mut n = 0;
        visit(body, &mut |s| {
            n += usize::from(!matches!(s, Statement::Block(_)));
            if let Statement::Call { function, .. } = *s {
                calls.push(function);
            }
        });
        for f in calls {
            let inner = match memo.get(&f) {
                Some(&k) => k,
                None => {
                    let k = size(module, &module.functions[f].body, memo);
                    memo.insert(f, k);
                    k
                }
            };
            n += inner;
        }
        n
    }
    let mut memo = HashMap::new();
    module
        .entry_points
        .iter()
        .map(|e| size(module, &e.function.body, &mut memo))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::shaders::TRACE_MODULE;
    use crate::gpu::variant::{Variant, compact_constant, interleave_constant};
    use crate::params::TraceParams;

    fn calls(module: &Module) -> Vec<String> {
        module
            .functions
            .iter()
            .filter_map(|(_, f)| f.name.clone())
            .collect()
    }

    /// A decided `if` becomes the block it takes, a `loop`'s `break` inside it still leaves the
    /// loop, and a function only the cut branch called is gone.
    #[test]
    fn a_specialisation_cuts_the_branches_its_constants_decide() {
        let source = "
            override A: bool = true;
            override B: bool = true;
            fn only_a() -> u32 { return 1u; }
            fn always() -> u32 { return 2u; }
            @group(0) @binding(0) var<storage, read_write> out: array<u32>;
            @compute @workgroup_size(1)
            fn main(@builtin(global_invocation_id) id: vec3<u32>) {
                var x = 0u;
                if A && id.x > 3u { let named = only_a(); x = named; } else { x = always(); }
                loop {
                    if !B { break; }
                    x += 1u;
                    if x > 9u { break; }
                }
                out[id.x] = x;
            }";
        let parsed = Parsed::new(source, false).expect("parses");
        let generic = parsed.specialise("main", &[("A", 1.0)], None).unwrap();
        let cut = parsed
            .specialise("main", &[("A", 0.0), ("B", 0.0)], None)
            .unwrap();
        assert_eq!(calls(&generic), ["only_a", "always"]);
        assert_eq!(calls(&cut), ["always"]);
        let body = &cut.entry_points[0].function.body;
        let ifs = body
            .iter()
            .filter(|s| matches!(s, Statement::If { .. }))
            .count();
        assert_eq!(ifs, 0, "the first if is decided: {body:?}");
        // The loop keeps its `break`, now unconditional, inside a plain block.
        let Some(Statement::Loop {
            body: loop_body, ..
        }) = body.iter().find(|s| matches!(s, Statement::Loop { .. }))
        else {
            panic!("the loop stays: {body:?}");
        };
        assert!(
            matches!(&loop_body[0], Statement::Block(b) if matches!(b[0], Statement::Break)),
            "{loop_body:?}"
        );
        valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all())
            .validate(&cut)
            .expect("the cut module validates");
    }

    /// What the default scene's tracer hands the driver, against the whole kernel, counted as the
    /// driver meets it: every call inlined.
    #[test]
    fn the_default_scene_hands_the_driver_a_fraction_of_the_tracer() {
        let parsed = Parsed::new(&TRACE_MODULE.source(), false).expect("the tracer parses");
        let fixed = [interleave_constant(2), compact_constant(true)];
        let whole = parsed.specialise("main", &fixed, None).unwrap();
        let scene = crate::scene::Scene::default();
        let mut constants = Variant::of(&TraceParams::<f32>::new(&scene), true).constants();
        constants.extend_from_slice(&fixed);
        // The scene's features decided in the text, the rest by the constants.
        let (on, left) = crate::gpu::shaders::split_constants(&constants);
        let text = TRACE_MODULE.composed_with(&on).text;
        let scenes = Parsed::new(&text, false).expect("the scene's tracer parses");
        let cut = scenes.specialise("main", &left, None).unwrap();
        let (w, c) = (inlined_statements(&whole), inlined_statements(&cut));
        println!(
            "default scene: {c} statements inlined in {} functions, of the generic {w} in {}",
            cut.functions.len(),
            whole.functions.len()
        );
        let gone: Vec<String> = calls(&whole)
            .into_iter()
            .filter(|f| !calls(&cut).contains(f))
            .collect();
        println!("cut: {gone:?}");
        assert!(c < w, "{c} of {w}");
        // The default scene has shadows, but none soft, no occlusion, no orbit trap, no cut.
        for f in ["soft_shadow", "occlusion", "orbit_trap", "cut_plane"] {
            assert!(
                gone.iter().any(|g| g == f),
                "{f} is still handed over: {gone:?}"
            );
        }
        valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all())
            .validate(&cut)
            .expect("the cut module validates");
    }
}
