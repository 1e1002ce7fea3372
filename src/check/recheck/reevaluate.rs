//! Stage 2, check, incrementally: a `let` evaluated again after its value was edited, as the
//! check evaluates it (against the constants declared before it), with what the check leaves
//! for a value that fails (the constant poisoned) — for [`super::redo`], and the test an added
//! `let` passes ([`super::lets`]): every constant it names declared before it.

use super::super::{Checker, Constants};
use super::decls::Dependents;
use crate::diag::Diagnostic;
use crate::syntax::{Expr, ExprKind, Stmt};

/// When a `let` checked again may come to fail or stop failing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Failing {
    /// Never (another error stands: an unknown name's did-you-mean lists the constants).
    Declined,
    /// When no other error stands, and not with an unknown name (its did-you-mean lists the
    /// constants declared before it, not all of them).
    Clean,
    /// Always, with unknown names too: every statement with an unknown-name diagnostic is
    /// checked again with it (a `let` renamed, [`super::let_renamed`]). The value is
    /// evaluated as the check evaluates it, against the constants declared before it.
    Unknowns,
}

/// Evaluates the `let` of `name` again: whether its value changed (`None`: decline). Its
/// diagnostics are left in `cx`. A value that fails (an error, or a constant it names that
/// failed) leaves the constant poisoned, as the check does: later names of it fail quietly.
/// That, and a constant poisoned before the edit, is taken only as `failing` allows.
pub(super) fn reevaluate(
    cx: &mut Checker,
    name: &crate::syntax::Ident,
    value: &Expr,
    failing: Failing,
    dependents: &mut dyn Dependents,
) -> Option<bool> {
    let clean = failing != Failing::Declined;
    let old = match cx.lets.get(&name.name) {
        Some((old, at)) => (*at == name.span).then(|| Some(old.clone()))?,
        // Failed before: the first `let` of its name (another would be in the table).
        None if clean && cx.poisoned.contains(name.name.as_str()) => None,
        None => return None,
    };
    let overridden = cx.defines.contains_key(name.name.as_str());
    if overridden {
        return None;
    }
    let new = if failing == Failing::Unknowns {
        eval_as_declared(cx, value, name.span, dependents)?
    } else if names_only_earlier(cx, value, name.span) {
        cx.eval(value)
    } else {
        return None;
    };
    let unknown = |d: &Diagnostic| d.code == crate::diag::Code::CheckUnknownName;
    let failed = new.is_none() || old.is_none();
    let unknowns = failing != Failing::Unknowns && cx.diags.iter().any(unknown);
    if (failed && !clean) || unknowns {
        return None;
    }
    // Bit for bit (`-0` is not `0` in the IR), not `==`.
    if format!("{new:?}") == format!("{old:?}") {
        return Some(false);
    }
    match new {
        Some(new) => {
            cx.poisoned.remove(name.name.as_str());
            cx.lets.insert(&name.name, new, name.span);
        }
        None => {
            cx.lets.remove(&name.name);
            cx.poisoned.insert(name.name.as_str().to_owned());
        }
    }
    Some(true)
}

/// Whether every constant `e` names was declared before `before` (in the full check, a later
/// one is unknown to it; across included files in the compile's reading order), and `e`
/// holds no array (read from the text by its own parser).
pub(super) fn names_only_earlier(cx: &Checker, e: &Expr, before: crate::source::Span) -> bool {
    match &e.kind {
        ExprKind::Name(n) => cx
            .lets
            .get(n)
            .is_none_or(|(_, at)| cx.order.before(*at, before)),
        ExprKind::Paren(e) | ExprKind::Neg(e) => names_only_earlier(cx, e, before),
        ExprKind::Tuple(es) => es.iter().all(|e| names_only_earlier(cx, e, before)),
        ExprKind::Call(c) => c.args.iter().all(|e| names_only_earlier(cx, e, before)),
        ExprKind::Binary { lhs, rhs, .. } => {
            names_only_earlier(cx, lhs, before) && names_only_earlier(cx, rhs, before)
        }
        ExprKind::Array | ExprKind::Error => false,
        ExprKind::Number { .. } | ExprKind::HexColor(_) | ExprKind::Str(_) => true,
    }
}

/// `e` evaluated as the check evaluates the value of a `let` at `before`: against the
/// constants declared before it (an unknown name's did-you-mean lists those), a constant that
/// failed naming quietly only when it was declared before it (found by the whole-word search:
/// `None` when it cannot be).
fn eval_as_declared(
    cx: &mut Checker,
    e: &Expr,
    before: crate::source::Span,
    dependents: &mut dyn Dependents,
) -> Option<Option<super::super::value::Value>> {
    let mut named = Vec::new();
    names_in(e, &mut named);
    let mut poisoned = std::collections::HashSet::new();
    for n in named.into_iter().filter(|n| cx.poisoned.contains(*n)) {
        let declared = dependents
            .naming(n)?
            .into_iter()
            .find_map(|(_, s)| match s {
                Stmt::Let { name, .. } if name.name == n => Some(name.span),
                _ => None,
            });
        if cx.order.before(declared?, before) {
            poisoned.insert(n.to_string());
        }
    }
    let mut earlier = Constants::default();
    for (n, at) in cx.lets.names_and_spans() {
        if cx.order.before(at, before) {
            let (v, _) = cx.lets.get(n)?;
            earlier.insert(n, v.clone(), at);
        }
    }
    let all = std::mem::replace(&mut cx.lets, earlier);
    let all_poisoned = std::mem::replace(&mut cx.poisoned, poisoned);
    let value = cx.eval(e);
    cx.lets = all;
    cx.poisoned = all_poisoned;
    Some(value)
}

/// The names `e` holds (constants, or unknown ones).
fn names_in<'e>(e: &'e Expr, out: &mut Vec<&'e str>) {
    match &e.kind {
        ExprKind::Name(n) => out.push(n),
        ExprKind::Paren(e) | ExprKind::Neg(e) => names_in(e, out),
        ExprKind::Tuple(es) => es.iter().for_each(|e| names_in(e, out)),
        ExprKind::Call(c) => c.args.iter().for_each(|e| names_in(e, out)),
        ExprKind::Binary { lhs, rhs, .. } => {
            names_in(lhs, out);
            names_in(rhs, out);
        }
        ExprKind::Array
        | ExprKind::Error
        | ExprKind::Number { .. }
        | ExprKind::HexColor(_)
        | ExprKind::Str(_) => {}
    }
}
