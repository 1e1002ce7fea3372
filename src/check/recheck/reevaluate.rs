//! Stage 2, check, incrementally: a `let` evaluated again after its value was edited, as the
//! check evaluates it (against the constants declared before it), with what the check leaves
//! for a value that fails (the constant poisoned) — for [`super::redo`], and the test an added
//! `let` passes ([`super::lets`]): every constant it names declared before it.

use super::super::Checker;
use crate::diag::Diagnostic;
use crate::syntax::{Expr, ExprKind};

/// Evaluates the `let` of `name` again: whether its value changed (`None`: decline). Its
/// diagnostics are left in `cx`. A value that fails (an error, or a constant it names that
/// failed) leaves the constant poisoned, as the check does: later names of it fail quietly.
/// That, and a constant poisoned before the edit, is taken only in a scene with no other
/// error (`clean`), and not when the value names an unknown constant (its did-you-mean would
/// list constants declared after it, which the check has not evaluated yet).
pub(super) fn reevaluate(
    cx: &mut Checker,
    name: &crate::syntax::Ident,
    value: &Expr,
    clean: bool,
) -> Option<bool> {
    let old = match cx.lets.get(&name.name) {
        Some((old, at)) => (*at == name.span).then(|| Some(old.clone()))?,
        // Failed before: the first `let` of its name (another would be in the table).
        None if clean && cx.poisoned.contains(&name.name) => None,
        None => return None,
    };
    let overridden = cx.defines.contains_key(&name.name);
    if overridden || !names_only_earlier(cx, value, name.span) {
        return None;
    }
    let new = cx.eval(value);
    let unknown = |d: &Diagnostic| d.code == crate::diag::Code::CheckUnknownName;
    let failed = new.is_none() || old.is_none();
    if (failed && !clean) || cx.diags.iter().any(unknown) {
        return None;
    }
    // Bit for bit (`-0` is not `0` in the IR), not `==`.
    if format!("{new:?}") == format!("{old:?}") {
        return Some(false);
    }
    match new {
        Some(new) => {
            cx.poisoned.remove(&name.name);
            cx.lets.insert(&name.name, new, name.span);
        }
        None => {
            cx.lets.remove(&name.name);
            cx.poisoned.insert(name.name.clone());
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
