//! Stage 1, syntax: a linear pre-scan of the raw text, run before pest sees it.
//!
//! It finds (1) where nesting of `( [ {` and block comments gets deeper than [`MAX_NESTING`]
//! (pest's parser is recursive: an adversarial `((((...` must become a diagnostic, never a stack
//! overflow), (2) the resynchronisation points used for syntax-error recovery: starts of lines
//! that begin with a name at bracket depth 0, or in column 0 with a keyword that only starts
//! top-level statements (not `object`/`group`, which nest), and (3)
//! the innermost unclosed bracket at the end of a region, for "this `{` is never closed".

/// Deepest nesting of brackets and block comments accepted.
pub const MAX_NESTING: usize = 48;

/// Keywords that start a top-level statement.
pub const STATEMENT_KEYWORDS: &[&str] = &[
    "scnc", "include", "let", "camera", "material", "texture", "mesh", "light", "object", "group",
    "render",
];

#[derive(Debug, Default)]
pub struct Scan {
    /// Byte offset of the first bracket or `/*` that nests deeper than [`MAX_NESTING`].
    pub too_deep_at: Option<usize>,
    /// Offsets (line starts after indentation) where a statement may begin; sorted.
    pub resync: Vec<usize>,
}

#[derive(Clone, Copy, PartialEq)]
enum State {
    Code,
    Str,
    LineComment,
    BlockComment(usize),
}

fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

fn word_at(bytes: &[u8], i: usize) -> &[u8] {
    let end = bytes[i..]
        .iter()
        .position(|&b| !is_ident_char(b))
        .map_or(bytes.len(), |n| i + n);
    &bytes[i..end]
}

/// Scans the whole text once.
pub fn scan(text: &str) -> Scan {
    let bytes = text.as_bytes();
    let mut out = Scan::default();
    let mut state = State::Code;
    let mut depth = 0usize;
    let mut line_start = true;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if line_start && state == State::Code && b != b' ' && b != b'\t' && b != b'\r' {
            line_start = false;
            if is_ident_start(b) {
                let column0 = i == 0 || bytes[i - 1] == b'\n';
                let word = word_at(bytes, i);
                // `object` and `group` also nest inside groups, so only the others resync
                // inside brackets.
                let keyword = STATEMENT_KEYWORDS
                    .iter()
                    .any(|k| k.as_bytes() == word && !matches!(*k, "object" | "group"));
                if depth == 0 || (column0 && keyword) {
                    out.resync.push(i);
                }
            }
        }
        let next = bytes.get(i + 1).copied();
        match state {
            State::Code => match b {
                b'"' => state = State::Str,
                b'/' if next == Some(b'/') => {
                    state = State::LineComment;
                    i += 1;
                }
                b'/' if next == Some(b'*') => {
                    state = State::BlockComment(1);
                    if depth + 1 > MAX_NESTING && out.too_deep_at.is_none() {
                        out.too_deep_at = Some(i);
                    }
                    i += 1;
                }
                b'(' | b'[' | b'{' => {
                    depth += 1;
                    if depth > MAX_NESTING && out.too_deep_at.is_none() {
                        out.too_deep_at = Some(i);
                    }
                }
                b')' | b']' | b'}' => depth = depth.saturating_sub(1),
                _ => {}
            },
            State::Str => match b {
                b'\\' => i += 1,
                b'"' | b'\n' => state = State::Code,
                _ => {}
            },
            State::LineComment => {
                if b == b'\n' {
                    state = State::Code;
                }
            }
            State::BlockComment(n) => {
                if b == b'*' && next == Some(b'/') {
                    state = if n == 1 {
                        State::Code
                    } else {
                        State::BlockComment(n - 1)
                    };
                    i += 1;
                } else if b == b'/' && next == Some(b'*') {
                    if depth + n + 1 > MAX_NESTING && out.too_deep_at.is_none() {
                        out.too_deep_at = Some(i);
                    }
                    state = State::BlockComment(n + 1);
                    i += 1;
                }
            }
        }
        if b == b'\n' {
            line_start = true;
        }
        i += 1;
    }
    out
}

/// The innermost bracket (or block comment start) still open at the end of `text`, as a byte
/// offset into `text` and the opening token.
pub fn unclosed(text: &str) -> Option<(usize, &'static str)> {
    let bytes = text.as_bytes();
    let mut stack: Vec<(usize, &'static str)> = Vec::new();
    let mut in_str = false;
    let mut in_line_comment = false;
    let mut comment_depth = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        let next = bytes.get(i + 1).copied();
        if in_line_comment {
            in_line_comment = b != b'\n';
        } else if comment_depth > 0 {
            if b == b'*' && next == Some(b'/') {
                comment_depth -= 1;
                stack.pop();
                i += 1;
            } else if b == b'/' && next == Some(b'*') {
                comment_depth += 1;
                stack.push((i, "/*"));
                i += 1;
            }
        } else if in_str {
            match b {
                b'\\' => i += 1,
                b'"' | b'\n' => in_str = false,
                _ => {}
            }
        } else {
            match b {
                b'"' => in_str = true,
                b'/' if next == Some(b'/') => in_line_comment = true,
                b'/' if next == Some(b'*') => {
                    comment_depth += 1;
                    stack.push((i, "/*"));
                    i += 1;
                }
                b'(' => stack.push((i, "(")),
                b'[' => stack.push((i, "[")),
                b'{' => stack.push((i, "{")),
                b')' | b']' | b'}' => {
                    stack.pop();
                }
                _ => {}
            }
        }
        i += 1;
    }
    stack.pop()
}
