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

/// What the pre-scan found.
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
    let mut s = Scanner {
        out: Scan::default(),
        state: State::Code,
        depth: 0,
    };
    let mut line_start = true;
    let mut i = 0;
    while i < bytes.len() {
        i = s.visit(bytes, i, &mut line_start);
    }
    s.out
}

/// The resynchronisation points of `text` from `start` on, for a text whose scan from its
/// start is at bracket depth 0 in code at `start` (a top-level statement's start in a file that
/// parses), up to the first of `stops` (ascending) that starts a line where the scan is so
/// again, or the end of the text: the points (`start` among them when it is one) and where the
/// scan stopped. From there on a scan of the whole text finds what a scan of the text it was
/// edited from found. `None` when nesting gets too deep before it stops.
pub fn resync_from(
    text: &str,
    start: usize,
    stops: &mut dyn Iterator<Item = usize>,
) -> Option<(Vec<usize>, usize)> {
    let bytes = text.as_bytes();
    let mut s = Scanner {
        out: Scan::default(),
        state: State::Code,
        depth: 0,
    };
    let before = bytes.get(..start)?;
    let mut line_start = (before.iter().rev())
        .take_while(|&&b| b != b'\n')
        .all(|b| matches!(b, b' ' | b'\t' | b'\r'));
    let mut stops = stops.peekable();
    let mut i = start;
    while i < bytes.len() {
        while stops.next_if(|&p| p < i).is_some() {}
        let settled = s.state == State::Code && s.depth == 0;
        if settled && i > start && stops.peek() == Some(&i) && bytes[i - 1] == b'\n' {
            break;
        }
        i = s.visit(bytes, i, &mut line_start);
    }
    let stop = i.min(bytes.len());
    s.out.too_deep_at.is_none().then_some((s.out.resync, stop))
}

/// Whether the first non-blank byte of a line, at `i`, may start a statement: a name at
/// bracket depth 0, or a top-level keyword in column 0 at any depth.
fn starts_statement(bytes: &[u8], i: usize, depth: usize) -> bool {
    if !is_ident_start(bytes[i]) {
        return false;
    }
    let column0 = i == 0 || bytes[i - 1] == b'\n';
    let word = word_at(bytes, i);
    // `object` and `group` also nest inside groups, so only the others resync inside brackets.
    let keyword = STATEMENT_KEYWORDS
        .iter()
        .any(|k| k.as_bytes() == word && !matches!(*k, "object" | "group"));
    depth == 0 || (column0 && keyword)
}

/// The scan's state between bytes.
struct Scanner {
    out: Scan,
    state: State,
    depth: usize,
}

impl Scanner {
    /// Scans the byte at `i` (`line_start`: whether only blanks precede it on its line),
    /// noting a resynchronisation point where a line's first byte may start a statement;
    /// returns the index of the next byte to scan.
    #[inline]
    fn visit(&mut self, bytes: &[u8], i: usize, line_start: &mut bool) -> usize {
        let b = bytes[i];
        if *line_start && self.state == State::Code && !matches!(b, b' ' | b'\t' | b'\r') {
            *line_start = false;
            if starts_statement(bytes, i, self.depth) {
                self.out.resync.push(i);
            }
        }
        let skip = self.step(b, bytes.get(i + 1).copied(), i);
        if b == b'\n' {
            *line_start = true;
        }
        let mut next = i + 1 + usize::from(skip);
        // In code inside a line, names, numbers and blanks change nothing: step over them.
        if self.state == State::Code && !*line_start {
            while bytes.get(next).is_some_and(|&b| !CODE_BYTES[b as usize]) {
                next += 1;
            }
        }
        next
    }

    /// Takes byte `b` at `i` (`next` follows it); true when `next` belongs to the same token
    /// (`//`, `/*`, `*/`, an escape) and is consumed too.
    fn step(&mut self, b: u8, next: Option<u8>, i: usize) -> bool {
        match self.state {
            State::Code => self.code(b, next, i),
            State::Str => match b {
                b'\\' => true,
                b'"' | b'\n' => {
                    self.state = State::Code;
                    false
                }
                _ => false,
            },
            State::LineComment => {
                if b == b'\n' {
                    self.state = State::Code;
                }
                false
            }
            State::BlockComment(n) => self.block_comment(n, b, next, i),
        }
    }

    fn code(&mut self, b: u8, next: Option<u8>, i: usize) -> bool {
        match b {
            b'"' => self.state = State::Str,
            b'/' if next == Some(b'/') => {
                self.state = State::LineComment;
                return true;
            }
            b'/' if next == Some(b'*') => {
                self.state = State::BlockComment(1);
                self.note_depth(self.depth + 1, i);
                return true;
            }
            b'(' | b'[' | b'{' => {
                self.depth += 1;
                self.note_depth(self.depth, i);
            }
            b')' | b']' | b'}' => self.depth = self.depth.saturating_sub(1),
            _ => {}
        }
        false
    }

    fn block_comment(&mut self, n: usize, b: u8, next: Option<u8>, i: usize) -> bool {
        if b == b'*' && next == Some(b'/') {
            self.state = if n == 1 {
                State::Code
            } else {
                State::BlockComment(n - 1)
            };
            return true;
        }
        if b == b'/' && next == Some(b'*') {
            self.note_depth(self.depth + n + 1, i);
            self.state = State::BlockComment(n + 1);
            return true;
        }
        false
    }

    /// Remembers the first place nesting goes past [`MAX_NESTING`].
    fn note_depth(&mut self, depth: usize, i: usize) {
        if depth > MAX_NESTING && self.out.too_deep_at.is_none() {
            self.out.too_deep_at = Some(i);
        }
    }
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
        } else if !DEPTH_BYTES[b as usize] {
            // Names, numbers and blanks change nothing.
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

/// [`Scan::too_deep_at`] alone, as [`scan`] finds it, without the resynchronisation points:
/// the check every parse runs before anything recursive sees the text. Runs of bytes that
/// change no state are skipped in tight loops (most of a file).
pub fn too_deep(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        // Names, numbers and blanks change nothing: step over them without the `match`.
        while i < bytes.len() && !DEPTH_BYTES[bytes[i] as usize] {
            i += 1;
        }
        let Some(&b) = bytes.get(i) else {
            break;
        };
        match b {
            b'"' => {
                i += 1;
                while i < bytes.len() {
                    match bytes[i] {
                        b'\\' => i += 2,
                        b'"' | b'\n' => break,
                        _ => i += 1,
                    }
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = memchr::memchr(b'\n', &bytes[i..]).map_or(bytes.len(), |n| i + n);
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => match comment_end(bytes, i, depth) {
                Ok(end) => {
                    i = end;
                    continue;
                }
                Err(at) => return at,
            },
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Some(i);
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        i += 1;
    }
    None
}

/// The bytes that can change [`Scanner`]'s state in code inside a line: those of
/// [`DEPTH_BYTES`] and the newline.
const CODE_BYTES: [bool; 256] = {
    let mut t = DEPTH_BYTES;
    t[b'\n' as usize] = true;
    t
};

/// The bytes that can change [`too_deep`]'s state: quotes, comment starts and brackets.
pub(crate) const DEPTH_BYTES: [bool; 256] = {
    let mut t = [false; 256];
    let mut k = 0;
    let interesting = b"\"/([{)]}";
    while k < interesting.len() {
        t[interesting[k] as usize] = true;
        k += 1;
    }
    t
};

/// Past the block comment opening at `start` (at bracket depth `depth`): `Ok(end)`, or
/// `Err(Some(at))` where its nesting goes too deep, `Err(None)` if it never closes (then the
/// rest of the text is comment, as [`scan`] sees it).
fn comment_end(bytes: &[u8], start: usize, depth: usize) -> Result<usize, Option<usize>> {
    let mut n = 0usize;
    let mut i = start;
    while i < bytes.len() {
        match (bytes[i], bytes.get(i + 1)) {
            (b'/', Some(b'*')) => {
                n += 1;
                if depth + n > MAX_NESTING {
                    return Err(Some(i));
                }
                i += 2;
            }
            (b'*', Some(b'/')) => {
                n -= 1;
                i += 2;
                if n == 0 {
                    return Ok(i);
                }
            }
            _ => i += 1,
        }
    }
    Err(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resync_from_stops_where_the_scan_is_at_depth_zero_again() {
        let text = "scnc 1\nobject a { material m\nobject b { }\nlet k = 1\n";
        let b = text.find("object b").unwrap_or(0);
        let k = text.find("let k").unwrap_or(0);
        // The `{` of `a` is open at `object b` (not a stop, nor a point: `object` nests), and
        // still at `let k`, a point (a column-0 keyword) but not a stop: the scan runs on to the
        // end of the text.
        let a = text.find("object a").unwrap_or(0);
        let from = resync_from(text, a, &mut [b, k].into_iter());
        assert_eq!(from, Some((vec![a, k], text.len())));
        // Closed, it stops at the first stop.
        let closed = text.replacen("material m", "material m }", 1);
        let b = closed.find("object b").unwrap_or(0);
        let k = closed.find("let k").unwrap_or(0);
        let from = resync_from(&closed, a, &mut [b, k].into_iter());
        assert_eq!(from, Some((vec![a], b)));
    }
}
