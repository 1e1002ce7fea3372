//! The incremental compile's view of an edit: which bytes changed (common prefix and suffix of
//! the old and new text, compared at memcmp speed), which top-level statements must be parsed
//! again, and, once they are, which of them really changed.
//!
//! A top-level statement's parse reads the text from its start on: its own bytes, and past its
//! end only the blanks and the first token after it (to see that nothing continues it, as
//! `mesh m = quad` looks for a `{`). So the statements to parse again are those from the one
//! before the first statement the edit touches (its look past its end may now see other text)
//! up to the first statement that starts after the edited bytes, which, with all after it,
//! parses as before, moved. The region is parsed from that statement's start, where a parse of
//! the whole file arrives too, and must end exactly at the next kept statement's new start.

use std::ops::Range;

use crate::source::{FileId, Shift};
use crate::syntax::Stmt;

/// The part of the file to parse again after an edit.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Region {
    /// How spans after the edited bytes move.
    pub shift: Shift,
    /// The old statements (indices) the region replaces.
    pub stmts: Range<usize>,
    /// The region's bytes in the new text.
    pub bytes: Range<usize>,
}

/// The region to parse again when `old` became `new`; `spans` are the old statements' byte
/// ranges, in order. `None` when the texts are equal.
pub(super) fn region(file: FileId, old: &str, new: &str, spans: &[(u32, u32)]) -> Option<Region> {
    let (a, b) = (old.as_bytes(), new.as_bytes());
    let prefix = common_prefix(a, b);
    if prefix == a.len() && prefix == b.len() {
        return None;
    }
    let max_suffix = a.len().min(b.len()) - prefix;
    let suffix = common_suffix(&a[a.len() - max_suffix..], &b[b.len() - max_suffix..]);
    let (prefix, suffix) = at_line_start(a, b, prefix, suffix);
    let shift = Shift {
        file,
        start: prefix as u32,
        old_end: (a.len() - suffix) as u32,
        new_end: (b.len() - suffix) as u32,
    };
    // First statement the edit touches (its end at or past the first edited byte), and the one
    // before it; first statement that starts after the edited bytes.
    let touched = spans.partition_point(|&(_, end)| end < shift.start);
    let first = touched.saturating_sub(1);
    let after = spans.partition_point(|&(start, _)| start < shift.old_end);
    let after = after.max(first + 1).min(spans.len());
    let start = match spans.get(first) {
        Some(&(s, _)) if s <= shift.start => s as usize,
        _ => 0,
    };
    let end = match spans.get(after) {
        Some(&(s, _)) => (s - shift.old_end + shift.new_end) as usize,
        None => b.len(),
    };
    Some(Region {
        shift,
        stmts: first..after,
        bytes: start..end,
    })
}

/// `region` taken one statement further (`None` when it reaches the file's end): for an edit
/// that changes how the statement starting right after the edited bytes reads (`// ` typed
/// before a line comments that statement out), so the region's parse does not arrive at its
/// start. The statement after it starts after the edited bytes too, so the region up to it,
/// parsed to exactly its moved start, is as good a region (with one statement more).
pub(super) fn widened(region: &Region, spans: &[(u32, u32)], new_len: usize) -> Option<Region> {
    let after = region.stmts.end;
    if after >= spans.len() {
        return None;
    }
    let shift = &region.shift;
    // The statement after `after` starts after the edited bytes when `region` is `region()`'s
    // (spans are in order), so the subtraction cannot fail for it; a region made otherwise
    // is not widened (`None`: the caller's region stays, as at the file's end) rather than
    // wrapping in release builds or panicking in debug ones.
    let end = match spans.get(after + 1) {
        Some(&(s, _)) => s.checked_sub(shift.old_end)? as usize + shift.new_end as usize,
        None => new_len,
    };
    Some(Region {
        shift: *shift,
        stmts: region.stmts.start..after + 1,
        bytes: region.bytes.start..end,
    })
}

/// Which old statements of `region` changed, and what replaced them: the region's statements
/// as parsed again (`parsed`) less those at its ends that are the old ones (same bytes, same
/// extent), before or after the edited bytes.
pub(super) fn changed(
    region: &Region,
    spans: &[(u32, u32)],
    mut parsed: Vec<Stmt>,
) -> (Range<usize>, Vec<Stmt>) {
    let shift = &region.shift;
    let mut old = region.stmts.clone();
    let mut keep_front = 0;
    while keep_front < parsed.len() && old.start < old.end {
        let (s, e) = spans[old.start];
        let span = parsed[keep_front].span();
        if e > shift.start || (span.start, span.end) != (s, e) {
            break;
        }
        keep_front += 1;
        old.start += 1;
    }
    let mut keep_back = parsed.len();
    while keep_back > keep_front && old.start < old.end {
        let (s, e) = spans[old.end - 1];
        if s < shift.old_end {
            break;
        }
        let span = parsed[keep_back - 1].span();
        let moved = (
            s - shift.old_end + shift.new_end,
            e - shift.old_end + shift.new_end,
        );
        if (span.start, span.end) != moved {
            break;
        }
        keep_back -= 1;
        old.end -= 1;
    }
    parsed.truncate(keep_back);
    parsed.drain(..keep_front);
    (old, parsed)
}

/// The common prefix and suffix again, for a pure insertion or deletion that can as well be
/// placed at a line's start: the same edit, at the start of the line it adds or removes.
///
/// The common prefix runs as far as it can, so a line `let q = 1` inserted before a line
/// `light …` is found as `et q = 1⏎l` inserted after that line's `l`, and the statement on it
/// seems edited. The inserted (or deleted) bytes slide left while the byte before them equals
/// their last one (the text stays the same); the first place so reached that follows a newline
/// is taken (at most `SLIDE` bytes back), else the edit stays where it was.
fn at_line_start(a: &[u8], b: &[u8], prefix: usize, suffix: usize) -> (usize, usize) {
    const SLIDE: usize = 4096;
    let (old_end, new_end) = (a.len() - suffix, b.len() - suffix);
    // The text that has the edited bytes (the other has none).
    let (text, end) = match (old_end == prefix, new_end == prefix) {
        (true, false) => (b, new_end),
        (false, true) => (a, old_end),
        _ => return (prefix, suffix),
    };
    let len = end - prefix;
    let mut start = prefix;
    for _ in 0..SLIDE {
        if start > 0 && text[start - 1] == b'\n' {
            return (start, suffix + (prefix - start));
        }
        if start == 0 || text[start - 1] != text[start + len - 1] {
            break;
        }
        start -= 1;
    }
    (prefix, suffix)
}

/// Length of the common prefix, compared in 4 KiB blocks, then 64-byte ones (memcmp), before
/// the tail: 64-byte blocks alone were one memcmp call each, 0.7 ms for the common suffix of
/// an 8.8 MB scene (2026-11-26, seventh session).
fn common_prefix(a: &[u8], b: &[u8]) -> usize {
    let n = a.len().min(b.len());
    let mut i = 0;
    for block in [4096, 64] {
        while i + block <= n && a[i..i + block] == b[i..i + block] {
            i += block;
        }
    }
    while i < n && a[i] == b[i] {
        i += 1;
    }
    i
}

/// Length of the common suffix of two slices of equal length (blocks as [`common_prefix`]).
fn common_suffix(a: &[u8], b: &[u8]) -> usize {
    let n = a.len().min(b.len());
    let mut k = 0;
    for block in [4096, 64] {
        while k + block <= n
            && a[a.len() - k - block..a.len() - k] == b[b.len() - k - block..b.len() - k]
        {
            k += block;
        }
    }
    while k < n && a[a.len() - k - 1] == b[b.len() - k - 1] {
        k += 1;
    }
    k
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The spans of `text`'s statements (none when it does not parse).
    pub(in crate::compile) fn spans_of(text: &str) -> Vec<(u32, u32)> {
        let (file, _) = crate::syntax::parse(FileId(0), text).into_parts();
        file.map(|f| {
            f.statements
                .iter()
                .map(|s| (s.span().start, s.span().end))
                .collect()
        })
        .unwrap_or_default()
    }

    #[test]
    fn equal_texts_have_no_region() {
        assert_eq!(region(FileId(0), "scnc 1\n", "scnc 1\n", &[(0, 6)]), None);
    }

    #[test]
    fn an_edit_inside_one_statement_parses_it_and_the_one_before() {
        let old = "scnc 1\nlet a = 1\nlet b = 2\nlet c = 3\n";
        let new = "scnc 1\nlet a = 1\nlet b = 42\nlet c = 3\n";
        let spans = spans_of(old);
        let r = region(FileId(0), old, new, &spans).expect("an edit");
        assert_eq!(r.stmts, 1..3);
        assert_eq!(&new[r.bytes.clone()], "let a = 1\nlet b = 42\n");
        let parsed = crate::syntax::parse_region(FileId(0), new, r.bytes.start, r.bytes.end)
            .expect("parses");
        let (old_range, replaced) = changed(&r, &spans, parsed);
        assert_eq!(old_range, 2..3);
        assert_eq!(replaced.len(), 1);
        assert_eq!(replaced[0].span().start, 17);
    }

    #[test]
    fn an_edit_at_the_end_reaches_the_end() {
        let old = "scnc 1\nlet a = 1\n";
        let new = "scnc 1\nlet a = 1\nlet b = 2\n";
        let spans = spans_of(old);
        let r = region(FileId(0), old, new, &spans).expect("an edit");
        // The `let`'s span ends at its value (not at the newline after it, as pest's does);
        // it is the statement before the edit, parsed again for its look past its end.
        assert_eq!(spans[1], (7, 16));
        assert_eq!(r.stmts, 1..2);
        assert_eq!(r.bytes, 7..new.len());
    }

    #[test]
    fn an_inserted_line_starts_at_a_line_start() {
        let old = "scnc 1\nlet a = 1\nlight l = point { position (0, 1, 0) }\n";
        let new = "scnc 1\nlet a = 1\nlet q = 2\nlight l = point { position (0, 1, 0) }\n";
        let r = region(FileId(0), old, new, &spans_of(old)).expect("an edit");
        assert_eq!(
            (r.shift.start, r.shift.old_end, r.shift.new_end),
            (17, 17, 27)
        );
        let deleted = region(FileId(0), new, old, &spans_of(new)).expect("an edit");
        assert_eq!(deleted.shift.start, 17);
        assert_eq!((deleted.shift.old_end, deleted.shift.new_end), (27, 17));
    }

    #[test]
    fn a_line_commented_out_is_parsed_in_a_region_one_statement_wider() {
        let old = "scnc 1\nlet a = 1\nlet b = 2\nlet c = 3\n";
        let new = "scnc 1\nlet a = 1\n// let b = 2\nlet c = 3\n";
        let spans = spans_of(old);
        let r = region(FileId(0), old, new, &spans).expect("an edit");
        // The region ends where `let b` starts, moved: inside the comment.
        let parse =
            |r: &Region| crate::syntax::parse_region(FileId(0), new, r.bytes.start, r.bytes.end);
        assert!(parse(&r).is_none());
        let wider = widened(&r, &spans, new.len()).expect("a statement after it");
        assert!(new[wider.bytes.clone()].ends_with("let a = 1\n// let b = 2\n"));
        let (old_range, replaced) = changed(&wider, &spans, parse(&wider).expect("parses"));
        // `let a`'s span ends at its value, so the comment after it leaves it as it was: only
        // `let b` changed (removed).
        assert_eq!(old_range, 2..3);
        assert!(replaced.is_empty());
    }

    #[test]
    fn a_region_whose_next_statement_starts_inside_the_edit_is_not_widened() {
        let spans = [(0, 6), (7, 16), (17, 26)];
        let region = Region {
            shift: Shift {
                file: FileId(0),
                start: 10,
                old_end: 20,
                new_end: 12,
            },
            stmts: 0..1,
            bytes: 0..7,
        };
        assert_eq!(widened(&region, &spans, 40), None);
    }

    #[test]
    fn prefix_and_suffix_never_overlap() {
        assert_eq!(common_prefix(b"aaaa", b"aaaaaa"), 4);
        let (old, new) = ("scnc 1\nlet a = 1\n", "scnc 1\nlet a = 1\nlet a = 1\n");
        let r = region(FileId(0), old, new, &spans_of(old)).expect("an edit");
        assert!(r.shift.start <= r.shift.old_end && r.shift.start <= r.shift.new_end);
    }
}
