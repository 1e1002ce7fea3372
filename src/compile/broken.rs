//! The incremental compile of a text with a syntax error: what [`super::compile_with`] gives
//! for it, found from the memo of the last text that parsed.
//!
//! A full compile of a file with a syntax error parses it by chunks (cut where a line starts
//! a statement, `syntax::scan`), reports each chunk pest cannot parse, checks every statement
//! that did parse, keeps the check's diagnostics except those that only say something is
//! missing, unknown or unused (`super::is_cascade`), and gives no scene. After an edit of a
//! text that parsed, the chunks outside the edited part are those the old text's scan found;
//! when each of them is whole statements of the old text (no line inside a statement looks
//! like a statement's start, [`no_inner_resync`]), they parse as before, without a
//! diagnostic. So the chunks from the region's start to the first old statement where the
//! scan is at depth 0 again are parsed alone (`syntax::parse_recovering_from`), and their
//! diagnostics are the compile's when the statements they lose are top-level `object`s and
//! `group`s (whose loss the check answers only with cascades: a material or mesh now unused), or
//! `let`s, `material`s, `mesh`es and `texture`s whose names, once lost, resolve to nothing else
//! (what names them gets an unknown-name diagnostic, a cascade, and fails quietly:
//! [`lost_quietly_by_name`]), every other statement there parses again with its old text, and
//! the old check had no diagnostic but cascades. A chunk whose tail is those old statements (an object line cut inside its
//! braces leaves a `{` open over every `object` and `group` after it) is not parsed whole:
//! `syntax::parse_recovering_from` tells pest's error for it from the chunk's head and the
//! first of them (`src/syntax/tail.rs`). Anything else is declined (a full compile).

use super::dependents;
use super::edit::Region;
use super::{is_cascade, reading_order};
use crate::diag::Diagnostic;
use crate::syntax::{self, scan};

/// The diagnostics of a full compile of `text` (which has a syntax error in `region`), or
/// `None` when they cannot be told from the memo: `old` is the last text that parsed, `spans`
/// its statements' byte ranges (of the edited file, `region`'s), `old_diags` the check's
/// diagnostics of it, `by_name` whether a lost declaration may be lost quietly by name
/// ([`lost_quietly_by_name`]; a scene of one file: `Some`, with whether the compile has a
/// `--define`; `None`, only `object`s and `group`s). Also how many old
/// statements were parsed again (those of a chunk whose error was told without parsing them
/// not counted).
pub(super) fn diagnostics(
    text: &str,
    old: &str,
    spans: &[(u32, u32)],
    region: &Region,
    old_diags: &[Diagnostic],
    by_name: Option<bool>,
) -> Option<(Vec<Diagnostic>, usize)> {
    if !old_diags.iter().all(|d| is_cascade(d.code)) {
        return None;
    }
    let shift = &region.shift;
    let (old_end, new_end) = (shift.old_end as usize, shift.new_end as usize);
    // Old statements after the edited bytes, at their new places: where the chunks may stop.
    let later = &spans[region.stmts.end..];
    let moved = |&(s, e): &(u32, u32)| {
        (
            s as usize - old_end + new_end,
            e as usize - old_end + new_end,
        )
    };
    let kept: Vec<(usize, usize)> = later
        .iter()
        .map(moved)
        .filter(|&(s, _)| s > new_end)
        .collect();
    let start = region.bytes.start;
    let recovered = syntax::parse_recovering_from(shift.file, text, start, &kept)?;
    let (parsed, diags, stop) = (&recovered.statements, recovered.diagnostics, recovered.stop);
    if !diags.iter().any(Diagnostic::is_error) {
        return None;
    }
    // The old statements the parsed part replaces: up to the one now at `stop`.
    let end = if stop == text.len() {
        spans.len()
    } else {
        let at = later.partition_point(|&(s, _)| (s as usize) < stop - new_end + old_end);
        let k = region.stmts.end + at;
        let (s, _) = *spans.get(k)?;
        (s as usize - old_end + new_end == stop).then_some(k)?
    };
    // An old statement lost (not parsed again) must be one whose loss the check answers only
    // with cascades.
    let lost_quietly = |i: usize| {
        let (s, e) = spans[i];
        old.get(s as usize..e as usize).is_some_and(|was| {
            syntax::nests(was)
                || by_name.is_some_and(|defines| lost_quietly_by_name(old, spans, i, defines))
        })
    };
    let mut olds = region.stmts.start..end;
    for stmt in parsed {
        let span = stmt.span();
        let now = text.get(span.start as usize..span.end as usize)?;
        // Old statements passed over are lost.
        loop {
            let i = olds.next()?;
            let (s, e) = spans[i];
            if old.get(s as usize..e as usize)? == now {
                break;
            }
            if !lost_quietly(i) {
                return None;
            }
        }
    }
    if !olds.all(lost_quietly) {
        return None;
    }
    let mut diags = diags;
    reading_order(&mut diags);
    Some((diags, end - region.stmts.start - recovered.spared))
}

/// Whether old statement `i` (of `old`, statements at `spans`) is a `let`, `material`, `mesh`
/// or `texture` whose loss the check answers only with cascades (dropped from a compile with
/// a syntax error). A statement that names a lost constant or declaration gets an unknown-name
/// diagnostic (a cascade, did-you-mean and all) and its value fails quietly; a `let` naming it
/// fails too and is poisoned, so what names that one fails quietly in turn. That holds while a
/// name that comes to fail resolves to nothing else: declined when another statement declares
/// one of those names (as any kind: a material's `diffuse t` names a texture `t` only when no
/// constant `t` exists), when there are more than [`MAX_FAILING`] of them, and for a lost `let`
/// when there is a `--define` (it may name it, and an unused define is an error whose
/// did-you-mean lists the constants). Found by whole-word searches of `old`, each found
/// statement's head read (its keyword and the name it declares).
fn lost_quietly_by_name(old: &str, spans: &[(u32, u32)], i: usize, defines: bool) -> bool {
    let Some((keyword, Some(name))) = head(old, spans, i) else {
        return false;
    };
    if !matches!(keyword, "let" | "material" | "mesh" | "texture") || (defines && keyword == "let")
    {
        return false;
    }
    // The statements whose names come to fail, with those names.
    let mut failing = vec![(i, name)];
    let mut next = 0;
    while let Some(&(declared_by, name)) = failing.get(next) {
        next += 1;
        for j in dependents::statements_naming(old, spans, name) {
            if j == declared_by {
                continue;
            }
            let Some((keyword, declares)) = head(old, spans, j) else {
                return false;
            };
            if keyword != "object" && declares == Some(name) {
                return false;
            }
            if let ("let", Some(poisoned)) = (keyword, declares) {
                if !failing.iter().any(|&(k, _)| k == j) {
                    if failing.len() == MAX_FAILING {
                        return false;
                    }
                    failing.push((j, poisoned));
                }
            }
        }
    }
    true
}

/// Most names [`lost_quietly_by_name`] follows (a lost constant and the `let`s that come to
/// fail with it); past that, a full compile.
const MAX_FAILING: usize = 64;

/// Statement `i`'s keyword and the name after it (the name a declaration declares; an
/// `object`'s mesh), or `None` for a name there that is not read (a comment between).
fn head<'t>(text: &'t str, spans: &[(u32, u32)], i: usize) -> Option<(&'t str, Option<&'t str>)> {
    let (s, e) = *spans.get(i)?;
    let stmt = text.get(s as usize..e as usize)?;
    let word = |t: &'t str| {
        let len = t
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(t.len());
        &t[..len]
    };
    let keyword = word(stmt);
    let rest = &stmt[keyword.len()..];
    let name = word(rest.trim_start_matches([' ', '\t']));
    let names = !matches!(keyword, "scnc" | "include" | "render");
    if !names {
        return Some((keyword, None));
    }
    let read = !name.is_empty()
        && rest.starts_with([' ', '\t'])
        && !name.starts_with(|c: char| c.is_ascii_digit());
    read.then_some((keyword, Some(name)))
}

/// Whether no line inside a statement of `text` (statements at `spans`) starts where the
/// error recovery's scan would cut a chunk: every resynchronisation point is a statement's
/// start.
pub(super) fn no_inner_resync(text: &str, spans: &[(u32, u32)]) -> bool {
    let points = scan::scan(text).resync;
    let mut starts = spans.iter().map(|&(s, _)| s as usize).peekable();
    points.into_iter().all(|p| {
        while starts.next_if(|&s| s < p).is_some() {}
        starts.peek() == Some(&p)
    })
}

/// Whether a statement's text `stmt` has no resynchronisation point but its start.
pub(super) fn whole(stmt: &str) -> bool {
    scan::scan(stmt).resync.iter().all(|&p| p == 0)
}
