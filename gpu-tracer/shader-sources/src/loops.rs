//! The workaround for naga's loop-exit bug
//! ([gfx-rs/wgpu#4558](https://github.com/gfx-rs/wgpu/issues/4558)):
//! [`spill_break_conditions`].

use naga::Module;

/// Works around a naga 30 back-end bug that breaks rust-gpu's loops in GLSL,
/// HLSL and MSL (WGSL is unaffected).
///
/// Those writers emit a loop's `continuing` block and its `break if` at the
/// top of the next iteration (`if (!loop_init) { continuing; if (cond)
/// break; }`) and write the condition inline, re-reading the variables it
/// was computed from. rust-gpu's loops compute the exit condition in the
/// body from a phi variable that `continuing` then reassigns, so the
/// translated loop tests the *next* iteration's value and leaves one
/// iteration early (`take_cs` lost the last index of every chunk: found by
/// `conformance/tests/generated_shaders/` on GLSL). This stores each such
/// condition in a local variable where the body computes it, and makes the
/// `break if` load that variable, which every writer translates faithfully.
/// Upstream: <https://github.com/gfx-rs/wgpu/issues/4558>.
pub(crate) fn spill_break_conditions(module: &mut Module) {
    use naga::{Block, Expression, Span, Statement};
    fn walk(
        block: &mut Block,
        expressions: &mut naga::Arena<Expression>,
        locals: &mut naga::Arena<naga::LocalVariable>,
        bool_ty: &mut dyn FnMut() -> naga::Handle<naga::Type>,
    ) {
        for (statement, _) in block.span_iter_mut() {
            match statement {
                Statement::Block(inner) => walk(inner, expressions, locals, bool_ty),
                Statement::If { accept, reject, .. } => {
                    walk(accept, expressions, locals, bool_ty);
                    walk(reject, expressions, locals, bool_ty);
                }
                Statement::Switch { cases, .. } => {
                    for case in cases {
                        walk(&mut case.body, expressions, locals, bool_ty);
                    }
                }
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => {
                    walk(body, expressions, locals, bool_ty);
                    walk(continuing, expressions, locals, bool_ty);
                    let Some(condition) = *break_if else {
                        continue;
                    };
                    // The condition, or the operand of a `!condition` that
                    // `continuing` computes: emitted at the body's top level
                    // (the one place outside `continuing` it can come from).
                    let emitted_in = |block: &Block, e: naga::Handle<Expression>| {
                        block.iter().position(|s| {
                            matches!(s, Statement::Emit(range)
                                if range.index_range().contains(&(e.index() as u32)))
                        })
                    };
                    let (spilled, negate) = match expressions[condition] {
                        _ if emitted_in(body, condition).is_some() => (condition, false),
                        Expression::Unary {
                            op: naga::UnaryOperator::LogicalNot,
                            expr,
                        } if emitted_in(body, expr).is_some() => (expr, true),
                        _ => continue,
                    };
                    let k = emitted_in(body, spilled).expect("checked");
                    let local = locals.append(
                        naga::LocalVariable {
                            name: Some("break_condition".to_string()),
                            ty: bool_ty(),
                            init: None,
                        },
                        Span::UNDEFINED,
                    );
                    let pointer = expressions.append(Expression::LocalVariable(local), Span::UNDEFINED);
                    let store = Statement::Store {
                        pointer,
                        value: spilled,
                    };
                    body.splice(k + 1..k + 1, Block::from_vec(vec![store]));
                    let load = expressions.append(Expression::Load { pointer }, Span::UNDEFINED);
                    let mut last = load;
                    if negate {
                        last = expressions.append(
                            Expression::Unary {
                                op: naga::UnaryOperator::LogicalNot,
                                expr: load,
                            },
                            Span::UNDEFINED,
                        );
                    }
                    continuing.push(
                        Statement::Emit(naga::Range::new_from_bounds(load, last)),
                        Span::UNDEFINED,
                    );
                    *break_if = Some(last);
                }
                _ => {}
            }
        }
    }
    let types = &mut module.types;
    let mut bool_ty = || {
        types.insert(
            naga::Type {
                name: None,
                inner: naga::TypeInner::Scalar(naga::Scalar::BOOL),
            },
            Span::UNDEFINED,
        )
    };
    let functions = module
        .functions
        .iter_mut()
        .map(|(_, f)| f)
        .chain(module.entry_points.iter_mut().map(|ep| &mut ep.function));
    for function in functions {
        walk(
            &mut function.body,
            &mut function.expressions,
            &mut function.local_variables,
            &mut bool_ty,
        );
    }
}
