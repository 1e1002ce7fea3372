//! Stage 1, syntax: pest's error for a chunk of the error recovery whose tail is kept `object`
//! and `group` statements, found without parsing that tail.
//!
//! After an edit that leaves a `{` open (`object a { material m⏎` cut inside its braces), the
//! recovery's chunk runs from the edited statement over every later statement that nests
//! (`object`, `group`) to the next line that starts a top-level-only statement or the end of
//! the file: `scan` cannot resynchronise inside the open block. pest parses that whole tail as
//! items of the block before it fails at the chunk's end; on a generated scene that is most of
//! the file. The chunk is `C = A T`, with `T = s1 w1 s2 … sn wn` the kept statements (each
//! known to parse alone, as the `object` or `group` rule, over exactly its bytes: the caller's
//! word) and the text between them and after the last (blanks and comments: the text they were
//! kept from parsed). pest is run on `A s1 wn` instead, and its error is `C`'s:
//!
//! - When `A` ends with a newline and `T` has no `]` and no `*/`, no token begun in `A` ends
//!   inside `T` (a string or line comment ends at the newline; an array or block comment runs
//!   to the end of the input in both), and no literal read before `s1` reaches into it: every
//!   decision made before `s1` is the same in both parses.
//! - The only rules that consume `s1` whole are `object` and `group` applied at its start (its
//!   `{` belongs to a block, and the rules with a block before it need a name where `s1` has
//!   its keyword or a name followed by `{`). At the top level that would make the parse of
//!   `A s1 wn` succeed; so when it fails, `s1` was consumed only as an item of a block, where
//!   `s2 … sn` are consumed as items too (each parses as its rule, reading nothing past its `}`)
//!   and the item and `}` tried after `wn` fail at the chunk's end: the farthest failure, with
//!   only blanks after it, so the diagnostic is "this `{` is never closed" at the bracket
//!   [`super::scan::unclosed`] finds open at the end of `C` (when there is none, this declines).
//! - When pest fails before the end of `s1`, no parse got past `s1`, nothing read past it
//!   (`s1` ends with `}`, which no longer literal starts with), and both parses are the same
//!   up to that failure: the error is `A s1 wn`'s, at the same place in `C`.
//!
//! When `A s1 wn` parses, or any condition fails, [`error`] declines and the chunk is parsed
//! whole. `tests` compare both on seeded cuts of object lines, nested groups among them.

use pest::Parser;

use super::{errors, Rule, SceneParser};
use crate::diag::Diagnostic;
use crate::source::FileId;

/// The diagnostic of the chunk `text[start..end]` (which pest fails to parse), when its tail
/// is statements of `kept` and their parse can be spared as above; `kept` are byte ranges of
/// statements after the edit, in order, each known to parse alone as a top-level statement
/// over exactly its range, the text between two of them and after the last (to the end of
/// `text`) only blanks and comments. `None` when it cannot tell: parse the chunk whole.
pub(super) fn error(
    file: FileId,
    text: &str,
    start: usize,
    end: usize,
    kept: &[(usize, usize)],
) -> Option<(Diagnostic, usize)> {
    let bytes = text.as_bytes();
    // `s1`: the first kept statement past the chunk's start on a line of its own; `sn`: the
    // last one inside the chunk. The chunk must end at the next kept one, or at the end of text.
    let first = kept.partition_point(|&(s, _)| s <= start);
    let last = kept.partition_point(|&(s, _)| s < end);
    let tail = kept.get(first..last).filter(|t| t.len() >= 2)?;
    let (p, s1_end) = tail[0];
    let (_, sn_end) = tail[tail.len() - 1];
    let ends_at_kept = kept.get(last).is_some_and(|&(s, _)| s == end);
    let ends_at_text_end = last == kept.len() && end == text.len();
    if bytes.get(p.checked_sub(1)?) != Some(&b'\n') || !(ends_at_kept || ends_at_text_end) {
        return None;
    }
    let nests = |&(s, e): &(usize, usize)| text.get(s..e).is_some_and(nests);
    let t = bytes.get(p..end)?;
    if !tail.iter().all(nests) || memchr::memchr(b']', t).is_some() {
        return None;
    }
    if memchr::memmem::find(t, b"*/").is_some() {
        return None;
    }
    let chunk = text.get(start..end)?;
    let short = [text.get(start..s1_end)?, text.get(sn_end..end)?].concat();
    let Err(e) = SceneParser::parse(Rule::file, &short) else {
        return None;
    };
    let at = errors::failure_pos(&short, &e);
    let diag = if at < s1_end - start {
        errors::from_pest(file, start, chunk, &e)
    } else {
        errors::unclosed_at_end(file, start, chunk)?
    };
    Some((diag, tail.len() - 1))
}

/// Whether pest's `Rule::statement` fails at `start` of `text`, told without parsing the run
/// `run` (byte ranges of statements after `start`, each known to parse as the `object` or
/// `group` rule at its place over exactly its range, with only blanks and comments between
/// them): the whole-file parse of a statement cut inside its braces, whose open `{` would have
/// pest read every later `object` as its items. With `A` the text from `start` to the first of
/// the run, `T = s1 w1 … sn` the run and `R` the rest of the text (`wn` and all after it), pest
/// is run on `A s1 R` instead of `A T R`, and the two fail alike (the argument of [`error`],
/// with `R` in place of the chunk's end): when `A` ends with a newline and `T` has no `]`, `*/`
/// or `/*`, a token begun in `A` either ends before `s1` or (an array, a block comment) runs
/// through `T` into `R` and ends at the same place of `R` in both; otherwise the only rules
/// that consume `s1` are `object` and `group` at its start, as an item of a block (the `{` of
/// `s1` belongs to a block, whose rules need before it what `s1` has not), and then `w1 s2 …
/// sn` are consumed as items of that block too, each as its rule, so both parses reach `R`
/// in the same state and go on alike; a parse that does not consume `s1` reads nothing past
/// it. `false` when it cannot tell (fewer than two in the run, a condition unmet, or the
/// shortened statement parses): the caller parses the whole text.
pub(super) fn statement_fails(text: &str, start: usize, run: &[(usize, usize)]) -> bool {
    let bytes = text.as_bytes();
    let (Some(&(p, s1_end)), Some(&(_, sn_end))) = (run.first(), run.last()) else {
        return false;
    };
    if run.len() < 2 || p <= start || p.checked_sub(1).and_then(|i| bytes.get(i)) != Some(&b'\n') {
        return false;
    }
    let Some(t) = bytes.get(p..sn_end) else {
        return false;
    };
    let crosses = memchr::memchr(b']', t).is_some()
        || memchr::memmem::find(t, b"*/").is_some()
        || memchr::memmem::find(t, b"/*").is_some();
    let (Some(head), Some(rest)) = (text.get(start..s1_end), text.get(sn_end..)) else {
        return false;
    };
    !crosses && SceneParser::parse(Rule::statement, &[head, rest].concat()).is_err()
}

/// Whether a statement's text is an `object` or a `group`: the statements that also parse as
/// items of a block.
pub(crate) fn nests(stmt: &str) -> bool {
    let keyword = |word: &str| {
        stmt.strip_prefix(word)
            .is_some_and(|rest| !rest.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_'))
    };
    keyword("object") || keyword("group")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::SplitMix64;

    /// A scene whose objects (some inside groups, some with arrays, comments between) run to
    /// the end.
    fn scene(rng: &mut SplitMix64) -> String {
        let mut s = String::from("scnc 1\nmaterial m = phong { diffuse #fff }\n");
        // Half the scenes have arrays (one token to pest, up to its `]`) and block comments.
        let tokens = rng.below(2) == 0;
        for i in 0..12 {
            match rng.below(6) {
                2 if tokens => s.push_str("object box { points [1 2 3] }\n"),
                3 if tokens => s.push_str("/* a block comment */\n"),
                0 => s.push_str(&format!(
                    "group g{i} {{ transform {{ translate (0, {i}, 0) }}\n  object ball {{ material m }}\n  group h {{ object box {{ }} }} }}\n"
                )),
                1 => s.push_str("// a comment between\n"),
                _ => {}
            }
            s.push_str(&format!(
                "object box {{ material m  transform {{ rotate y {i}deg  translate ({i}, 1, 2) }} }}\n"
            ));
        }
        s
    }

    /// The statements' byte ranges in `text` (which parses).
    fn spans(text: &str) -> Vec<(usize, usize)> {
        let (file, _) = super::super::parse(FileId(0), text).into_parts();
        let statements = file.map(|f| f.statements).unwrap_or_default();
        let span = |s: &super::super::Stmt| (s.span().start as usize, s.span().end as usize);
        statements.iter().map(span).collect()
    }

    /// Seeded cuts of a statement's text, each left with the statements after it: pest's
    /// error on the whole chunk and [`error`]'s (when it answers) are the same.
    #[test]
    fn the_spared_tail_gives_pests_error() {
        // pest's error detail is one process-wide switch that recoveries in other tests turn
        // on and off: keep it on for both parses compared here.
        let _detail = super::super::ErrorDetail::on();
        let mut rng = SplitMix64(0x5EED_7A11);
        let (mut answered, mut at_end) = (0, 0);
        for _ in 0..300 {
            let old = scene(&mut rng);
            let kept_old = spans(&old);
            let k = 2 + rng.below(kept_old.len() - 4);
            let (s, e) = kept_old[k];
            let cut = s + 1 + rng.below(e - s - 1);
            let mut new = old[..cut].to_string();
            let extra = [
                "",
                " (1, 2",
                " [1 2",
                " /* c",
                " \"str",
                " =",
                " }",
                " object q {",
            ];
            new.push_str(extra[rng.below(extra.len())]);
            new.push('\n');
            let delta = new.len() as isize - e as isize;
            new.push_str(&old[e..]);
            let moved = |(a, b): (usize, usize)| {
                ((a as isize + delta) as usize, (b as isize + delta) as usize)
            };
            let kept: Vec<(usize, usize)> = kept_old[k + 1..].iter().map(|&r| moved(r)).collect();
            let start = kept_old[k - 1].0;
            let whole = SceneParser::parse(Rule::file, &new[start..]);
            let Some((got, _)) = error(FileId(0), &new, start, new.len(), &kept) else {
                continue;
            };
            let want = match whole {
                Err(e) => errors::from_pest(FileId(0), start, &new[start..], &e),
                Ok(_) => panic!("answered for a chunk that parses:\n{new}"),
            };
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "on\n{new}");
            answered += 1;
            at_end += usize::from(got.code == crate::diag::Code::SyntaxUnclosedDelimiter);
        }
        eprintln!("{answered} of 300 answered, {at_end} at the chunk's end");
        assert!(
            answered >= 100 && at_end >= 30,
            "{answered} answered, {at_end} at the end"
        );
    }
}
