//! Baking a scene's values into a kernel's module: each uniform member the scene sets (all but
//! the per-dispatch ones: the band, where it lands, the samples it adds) becomes a constant of
//! the module, so that the driver folds the scene's numbers and the branches they decide, as
//! Mesa 22.3's lavapipe did by itself when it inlined uniforms (at each bind, never freed).
//! Here it happens once per pipeline, which the kernel's bounded cache holds and drops.
//!
//! In naga's IR a member is read as `Load(AccessIndex(GlobalVariable(params), m))`, or through
//! a longer chain (`params.eye.x`, `params.c[k]`). The chain's root, `AccessIndex(params, m)`,
//! becomes `Constant(m's value)`; each `Access`/`AccessIndex` on it then indexes a value rather
//! than a pointer; and the `Load` at its end becomes the value itself (a copy of the chain's
//! last link, which names only earlier expressions). Constants are never emitted, so the
//! expressions that became constants leave the `Emit` ranges that held them.

use std::collections::{HashMap, HashSet};

use naga::{
    Block, Constant, Expression, Handle, Literal, Module, Scalar, ScalarKind, Span, Statement,
    TypeInner, VectorSize,
};

/// A uniform's bytes to bake: the global at `binding` (group 0), read as its struct lays out.
pub(crate) struct Baked<'a> {
    pub binding: u32,
    pub bytes: &'a [u8],
}

/// Bakes `values` into `module`, leaving the members named in `per_dispatch` read at run time.
/// A member whose value a literal cannot hold (not finite) stays read at run time too. Fails
/// where a uniform is used other than by loads of its members (nothing of ours does).
pub(crate) fn bake(
    module: &mut Module,
    values: &[Baked<'_>],
    per_dispatch: &[&str],
) -> Result<(), String> {
    // (global, member) -> its constant.
    let mut members: HashMap<(Handle<naga::GlobalVariable>, u32), Handle<Constant>> =
        HashMap::new();
    let globals: Vec<_> = module
        .global_variables
        .iter()
        .filter_map(|(h, g)| {
            let binding = g.binding.as_ref()?;
            let baked = values
                .iter()
                .find(|v| binding.group == 0 && binding.binding == v.binding)?;
            Some((h, g.ty, baked.bytes))
        })
        .collect();
    for (global, ty, bytes) in globals {
        let TypeInner::Struct {
            members: ref fields,
            ..
        } = module.types[ty].inner
        else {
            return Err(format!("binding of {global:?} is not a struct"));
        };
        let fields = fields.clone();
        for (m, field) in fields.iter().enumerate() {
            if field
                .name
                .as_deref()
                .is_some_and(|n| per_dispatch.contains(&n))
            {
                continue;
            }
            let Some(init) = value_of(module, field.ty, bytes, field.offset as usize) else {
                continue;
            };
            let constant = module.constants.append(
                Constant {
                    name: None,
                    ty: field.ty,
                    init,
                },
                Span::UNDEFINED,
            );
            members.insert((global, m as u32), constant);
        }
    }
    if members.is_empty() {
        return Ok(());
    }
    let bodies = module
        .functions
        .iter_mut()
        .map(|(_, f)| f)
        .chain(module.entry_points.iter_mut().map(|e| &mut e.function));
    for function in bodies {
        bake_function(function, &members)?;
    }
    Ok(())
}

/// One function's reads of the baked members made their values.
fn bake_function(
    function: &mut naga::Function,
    members: &HashMap<(Handle<naga::GlobalVariable>, u32), Handle<Constant>>,
) -> Result<(), String> {
    // Pointers into a baked member, now values.
    let mut valued: HashSet<Handle<Expression>> = HashSet::new();
    // Expressions made constants: no longer emitted.
    let mut constants: HashSet<Handle<Expression>> = HashSet::new();
    let handles: Vec<Handle<Expression>> = function.expressions.iter().map(|(h, _)| h).collect();
    for h in handles {
        let new = match function.expressions[h] {
            Expression::AccessIndex { base, index } => match function.expressions[base] {
                Expression::GlobalVariable(g) => members.get(&(g, index)).map(|&c| {
                    valued.insert(h);
                    Expression::Constant(c)
                }),
                _ => {
                    if valued.contains(&base) {
                        valued.insert(h);
                    }
                    None
                }
            },
            Expression::Access { base, .. } => {
                if valued.contains(&base) {
                    valued.insert(h);
                }
                None
            }
            Expression::Load { pointer } if valued.contains(&pointer) => {
                Some(function.expressions[pointer].clone())
            }
            _ => None,
        };
        if let Some(new) = new {
            if matches!(new, Expression::Constant(_)) {
                constants.insert(h);
            }
            *function.expressions.get_mut(h) = new;
        }
    }
    // A baked pointer reaches nothing but loads and further links of its chain.
    let mut misused = None;
    let mut check = |e: Handle<Expression>| {
        if valued.contains(&e) {
            misused = Some(e);
        }
    };
    super::walk::visit(&function.body, &mut |s| match *s {
        Statement::Store { pointer, .. } => check(pointer),
        Statement::Call { ref arguments, .. } => arguments.iter().for_each(|&a| check(a)),
        _ => {}
    });
    if let Some(e) = misused {
        return Err(format!("a uniform's member is used other than read: {e:?}"));
    }
    if !constants.is_empty() {
        let body = std::mem::take(&mut function.body);
        function.body = unemit(body, &constants);
    }
    Ok(())
}

/// The block with `gone` left out of its `Emit` ranges (each range split around them).
fn unemit(block: Block, gone: &HashSet<Handle<Expression>>) -> Block {
    let mut out = Block::with_capacity(block.len());
    for (statement, span) in block.span_into_iter() {
        match statement {
            Statement::Emit(range) => {
                let mut run: Option<(Handle<Expression>, Handle<Expression>)> = None;
                for h in range {
                    if gone.contains(&h) {
                        if let Some((a, b)) = run.take() {
                            out.push(Statement::Emit(naga::Range::new_from_bounds(a, b)), span);
                        }
                    } else {
                        run = Some(run.map_or((h, h), |(a, _)| (a, h)));
                    }
                }
                if let Some((a, b)) = run {
                    out.push(Statement::Emit(naga::Range::new_from_bounds(a, b)), span);
                }
            }
            Statement::Block(b) => out.push(Statement::Block(unemit(b, gone)), span),
            Statement::If {
                condition,
                accept,
                reject,
            } => out.push(
                Statement::If {
                    condition,
                    accept: unemit(accept, gone),
                    reject: unemit(reject, gone),
                },
                span,
            ),
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => out.push(
                Statement::Loop {
                    body: unemit(body, gone),
                    continuing: unemit(continuing, gone),
                    break_if,
                },
                span,
            ),
            Statement::Switch { selector, cases } => out.push(
                Statement::Switch {
                    selector,
                    cases: cases
                        .into_iter()
                        .map(|case| naga::SwitchCase {
                            body: unemit(case.body, gone),
                            ..case
                        })
                        .collect(),
                },
                span,
            ),
            other => out.push(other, span),
        }
    }
    out
}

/// The value of type `ty` at `offset` in `bytes`, as a global expression; None where a literal
/// cannot hold it (a float not finite) or the type is not one a uniform of ours has.
fn value_of(
    module: &mut Module,
    ty: Handle<naga::Type>,
    bytes: &[u8],
    offset: usize,
) -> Option<Handle<Expression>> {
    let expression = match module.types[ty].inner {
        TypeInner::Scalar(scalar) => Expression::Literal(literal(scalar, bytes, offset)?),
        TypeInner::Vector { size, scalar } => {
            let n = match size {
                VectorSize::Bi => 2,
                VectorSize::Tri => 3,
                VectorSize::Quad => 4,
            };
            let width = scalar.width as usize;
            let components = (0..n)
                .map(|k| {
                    let l = literal(scalar, bytes, offset + k * width)?;
                    Some(
                        module
                            .global_expressions
                            .append(Expression::Literal(l), Span::UNDEFINED),
                    )
                })
                .collect::<Option<Vec<_>>>()?;
            Expression::Compose { ty, components }
        }
        TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            stride,
        } => {
            let components = (0..n.get() as usize)
                .map(|k| value_of(module, base, bytes, offset + k * stride as usize))
                .collect::<Option<Vec<_>>>()?;
            Expression::Compose { ty, components }
        }
        _ => return None,
    };
    Some(
        module
            .global_expressions
            .append(expression, Span::UNDEFINED),
    )
}

/// The scalar at `offset`; None for a float that is not finite, or a kind no uniform of ours
/// holds.
fn literal(scalar: Scalar, bytes: &[u8], offset: usize) -> Option<Literal> {
    let word = |n: usize| bytes.get(offset..offset + n);
    let literal = match (scalar.kind, scalar.width) {
        (ScalarKind::Float, 4) => {
            Literal::F32(f32::from_le_bytes(word(4)?.try_into().ok()?)).finite()?
        }
        (ScalarKind::Float, 8) => {
            Literal::F64(f64::from_le_bytes(word(8)?.try_into().ok()?)).finite()?
        }
        (ScalarKind::Uint, 4) => Literal::U32(u32::from_le_bytes(word(4)?.try_into().ok()?)),
        (ScalarKind::Sint, 4) => Literal::I32(i32::from_le_bytes(word(4)?.try_into().ok()?)),
        _ => return None,
    };
    Some(literal)
}

/// A float literal only where it is finite (naga's literals may not be NaN or infinite).
trait Finite: Sized {
    fn finite(self) -> Option<Self>;
}

impl Finite for Literal {
    fn finite(self) -> Option<Self> {
        match self {
            Literal::F32(x) if !x.is_finite() => None,
            Literal::F64(x) if !x.is_finite() => None,
            other => Some(other),
        }
    }
}

/// The byte ranges, in a dispatch's uniform bytes, of the members named in `keeps` of the
/// uniforms at these (binding, where its bytes start): what a baked pipeline still reads.
pub(crate) fn kept_ranges(
    module: &Module,
    uniforms: &[(u32, usize)],
    keeps: &[&str],
) -> Vec<std::ops::Range<usize>> {
    let mut ranges = Vec::new();
    for (_, global) in module.global_variables.iter() {
        let Some(binding) = &global.binding else {
            continue;
        };
        let Some(&(_, start)) = uniforms
            .iter()
            .find(|(b, _)| binding.group == 0 && *b == binding.binding)
        else {
            continue;
        };
        let TypeInner::Struct { ref members, .. } = module.types[global.ty].inner else {
            continue;
        };
        for m in members {
            if m.name.as_deref().is_some_and(|n| keeps.contains(&n)) {
                let size = module.types[m.ty].inner.size(module.to_ctx()) as usize;
                let offset = start + m.offset as usize;
                ranges.push(offset..offset + size);
            }
        }
    }
    ranges
}

#[cfg(test)]
mod tests {
    use super::*;
    use naga::valid;

    const SOURCE: &str = "
        struct P {
            c: array<vec4<f32>, 2>,
            eye: vec3<f32>,
            scale: f32,
            count: u32,
            row: u32,
        }
        @group(0) @binding(0) var<uniform> p: P;
        @group(0) @binding(1) var<storage, read_write> out: array<f32>;
        fn twice() -> f32 { return 2.0 * p.scale; }
        @compute @workgroup_size(1)
        fn main(@builtin(global_invocation_id) id: vec3<u32>) {
            var s = p.eye.y + twice();
            for (var k = 0u; k < p.count; k++) {
                s += p.c[k % 2u].z + p.c[1].w;
            }
            if p.count > 3u { s += p.eye.x; }
            out[p.row + id.x] = s;
        }";

    /// The bytes of P: c = [(1,2,3,4), (5,6,7,8)], eye = (9,10,11), scale 12, count 3, row 7.
    fn bytes() -> Vec<u8> {
        let mut b = Vec::new();
        for x in [
            1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0,
        ] {
            b.extend(x.to_le_bytes());
        }
        b.extend(3u32.to_le_bytes());
        b.extend(7u32.to_le_bytes());
        b.resize(64, 0);
        b
    }

    /// Bakes `bytes` into binding 0 of `module`, all but `row`.
    fn bake_all_but_row(module: &mut Module, bytes: &[u8]) {
        let values = [Baked { binding: 0, bytes }];
        bake(module, &values, &["row"]).expect("bakes");
    }

    /// The loads left in a module's functions whose pointer starts at a uniform's member, by
    /// the member's index.
    fn loaded_members(module: &Module) -> Vec<u32> {
        let mut found = Vec::new();
        let bodies = module
            .functions
            .iter()
            .map(|(_, f)| f)
            .chain(module.entry_points.iter().map(|e| &e.function));
        for f in bodies {
            for (_, e) in f.expressions.iter() {
                let Expression::Load { mut pointer } = *e else {
                    continue;
                };
                loop {
                    match f.expressions[pointer] {
                        Expression::AccessIndex { base, index } => {
                            if let Expression::GlobalVariable(g) = f.expressions[base]
                                && module.global_variables[g].space == naga::AddressSpace::Uniform
                            {
                                found.push(index);
                                break;
                            }
                            pointer = base;
                        }
                        Expression::Access { base, .. } => pointer = base,
                        _ => break,
                    }
                }
            }
        }
        found.sort();
        found
    }

    /// Every member but the kept one is read from constants, through whole loads, components,
    /// a constant index and a dynamic one, in the entry point and in a function it calls; the
    /// module validates; the constants hold the bytes' values.
    #[test]
    fn a_baked_module_reads_only_the_kept_members() {
        let mut module = naga::front::wgsl::parse_str(SOURCE).expect("parses");
        assert_eq!(loaded_members(&module), [0, 0, 1, 1, 2, 3, 3, 4]);
        let bytes = bytes();
        bake_all_but_row(&mut module, &bytes);
        assert_eq!(loaded_members(&module), [4], "only `row` is read");
        valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all())
            .validate(&module)
            .expect("the baked module validates");
        let literals: Vec<String> = module
            .global_expressions
            .iter()
            .filter_map(|(_, e)| match *e {
                Expression::Literal(l) => Some(format!("{l:?}")),
                _ => None,
            })
            .collect();
        for want in ["F32(7.0)", "F32(11.0)", "F32(12.0)", "U32(3)"] {
            assert!(literals.iter().any(|l| l == want), "{want}: {literals:?}");
        }
        assert!(!literals.iter().any(|l| l == "U32(7)"), "`row` is kept");
    }

    /// A float that a literal cannot hold stays read at run time; the rest is baked.
    #[test]
    fn a_value_not_finite_stays_a_uniform() {
        let mut module = naga::front::wgsl::parse_str(SOURCE).expect("parses");
        let mut bytes = bytes();
        bytes[44..48].copy_from_slice(&f32::INFINITY.to_le_bytes());
        bake_all_but_row(&mut module, &bytes);
        assert_eq!(loaded_members(&module), [2, 4], "scale and row are read");
        valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all())
            .validate(&module)
            .expect("validates");
    }

    /// The kept members' bytes are found where the struct lays them out, past the start of
    /// their uniform in the dispatch's bytes.
    #[test]
    fn the_kept_ranges_are_the_kept_members_bytes() {
        let module = naga::front::wgsl::parse_str(SOURCE).expect("parses");
        assert_eq!(
            kept_ranges(&module, &[(0, 0)], &["row", "eye"]),
            [32..44, 52..56]
        );
        assert_eq!(
            kept_ranges(&module, &[(0, 256)], &["count"]),
            vec![(304..308)]
        );
        assert!(kept_ranges(&module, &[(3, 0)], &["count"]).is_empty());
    }
}
