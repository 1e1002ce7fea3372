//! Stage 1, syntax (fast path): the byte cursor of the hand-written parser, with pest's implicit
//! whitespace and comments and the atomic tokens of `grammar/scene.pest` (names, numbers,
//! strings, colours, arrays) matched exactly as the grammar's atomic rules match them.
//!
//! Nothing here backtracks: a token that does not match is `None`, and the caller gives the
//! statement to pest.

use crate::source::{FileId, Span};
use crate::syntax::ast::{Ident, Item, Name};
use crate::syntax::scan::{too_deep, DEPTH_BYTES, MAX_NESTING};

/// Where the fast parser is in the text.
pub(super) struct Cursor<'t> {
    pub bytes: &'t [u8],
    pub text: &'t str,
    pub pos: usize,
    pub file: FileId,
    /// Expression nodes of the current top-level expression, counted at least as generously as
    /// the pest converter counts them (see [`crate::syntax::MAX_EXPR_NODES`]).
    pub nodes: usize,
    /// Items of the blocks being parsed, innermost last (see `block`).
    pub items: Vec<Item>,
    /// Brackets open at the cursor, as `scan::too_deep` counts them: `(`, `{` and `[` the parser
    /// has opened, within the statement being parsed (a parsed statement closes all it opens).
    pub depth: usize,
    /// Whether the nesting depth is still to be checked here ([`Cursor::counting_depth`]):
    /// until the whole text has been scanned, or the parser has passed every byte of it.
    pub counting: bool,
    /// Nesting went deeper than [`MAX_NESTING`] (as `scan::too_deep` finds it) at or before the
    /// cursor: the parse must give up, as it gave up before it began when the text was scanned
    /// first.
    pub too_deep: bool,
}

pub(super) fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

pub(super) fn is_ident_char(b: u8) -> bool {
    IDENT_CHARS[b as usize]
}

/// `ident_raw`'s bytes after the first (`ASCII_ALPHANUMERIC | "_"`), one load per byte.
const IDENT_CHARS: [bool; 256] = {
    let mut t = [false; 256];
    let mut b = 0;
    while b < 256 {
        t[b] = (b as u8).is_ascii_alphanumeric() || b == b'_' as usize;
        b += 1;
    }
    t
};

/// The bytes [`Cursor::skip`] may pass: blanks, and the first bytes of a comment and a BOM.
const SKIPPABLE: [bool; 256] = {
    let mut t = [false; 256];
    let starts = b" \n\t\r/\xEF";
    let mut k = 0;
    while k < starts.len() {
        t[starts[k] as usize] = true;
        k += 1;
    }
    t
};

impl<'t> Cursor<'t> {
    pub fn new(file: FileId, text: &'t str) -> Cursor<'t> {
        Cursor {
            bytes: text.as_bytes(),
            text,
            pos: 0,
            file,
            nodes: 0,
            items: Vec::new(),
            depth: 0,
            counting: false,
            too_deep: false,
        }
    }

    /// A cursor for a text whose nesting depth was not checked before: it counts brackets and
    /// block comments as it parses them and sets [`Cursor::too_deep`] exactly where
    /// `scan::too_deep` would find the text too deep, so the depth check costs no second pass
    /// over the text. Where the parser cannot tell (an array whose inside holds brackets,
    /// quotes or a `/`, a statement it does not accept, which pest would then parse), it
    /// scans the whole text once, as before, and counts no more ([`Cursor::scan_depth`]).
    pub fn counting_depth(file: FileId, text: &'t str) -> Cursor<'t> {
        Cursor {
            counting: true,
            ..Cursor::new(file, text)
        }
    }

    /// Opens a bracket (or the `[` of an array); `None` once nesting is too deep.
    pub fn open(&mut self) -> Option<()> {
        self.depth += 1;
        if self.counting && self.depth > MAX_NESTING {
            self.too_deep = true;
            return None;
        }
        Some(())
    }

    /// Closes a bracket.
    pub fn close(&mut self) {
        self.depth = self.depth.saturating_sub(1);
    }

    /// Whether the whole text nests no deeper than allowed, scanned once (`scan::too_deep`)
    /// the first time it is asked while counting; afterwards nothing is counted.
    pub fn scan_depth(&mut self) -> bool {
        if self.counting {
            self.counting = false;
            self.too_deep = too_deep(self.text).is_some();
        }
        !self.too_deep
    }

    pub fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    pub fn at(&self, i: usize) -> Option<u8> {
        self.bytes.get(i).copied()
    }

    pub fn span(&self, start: usize, end: usize) -> Span {
        Span::new(self.file, start, end)
    }

    /// Consumes `b` if it is next.
    pub fn eat(&mut self, b: u8) -> Option<()> {
        (self.peek() == Some(b)).then(|| self.pos += 1)
    }

    /// pest's implicit `(WHITESPACE | COMMENT)*`: an unterminated block comment is left in
    /// place (pest's skip fails on it too, and whatever comes next then fails at its `/`).
    ///
    /// Inlined up to the first byte: most calls stand on a token already.
    #[inline]
    pub fn skip(&mut self) {
        if self.peek().is_some_and(|b| SKIPPABLE[b as usize]) {
            self.skip_some();
        }
    }

    /// [`Cursor::skip`] past its first check.
    fn skip_some(&mut self) {
        loop {
            match self.peek() {
                Some(b' ' | b'\n' | b'\t' | b'\r') => self.pos += 1,
                Some(0xEF) if self.bytes[self.pos..].starts_with("\u{FEFF}".as_bytes()) => {
                    self.pos += 3;
                }
                Some(b'/') => match self.at(self.pos + 1) {
                    Some(b'/') => {
                        self.pos = memchr::memchr(b'\n', &self.bytes[self.pos..])
                            .map_or(self.bytes.len(), |n| self.pos + n);
                    }
                    Some(b'*') => match self.block_comment_end(self.pos) {
                        Some(end) if !self.too_deep => self.pos = end,
                        _ => return,
                    },
                    _ => return,
                },
                _ => return,
            }
        }
    }

    /// The end of the (nested) block comment opening at `start`, or `None` if it never closes.
    /// While counting depth, its nesting adds to the brackets open (as in `scan::too_deep`).
    fn block_comment_end(&mut self, start: usize) -> Option<usize> {
        let mut depth = 0usize;
        let mut i = start;
        while i + 1 < self.bytes.len() {
            match (self.bytes[i], self.bytes[i + 1]) {
                (b'/', b'*') => {
                    depth += 1;
                    if self.counting && self.depth + depth > MAX_NESTING {
                        self.too_deep = true;
                        return None;
                    }
                    i += 2;
                }
                (b'*', b'/') => {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        return Some(i);
                    }
                }
                _ => i += 1,
            }
        }
        None
    }

    /// `ident_raw`: the end of the name starting at `pos`, if one does.
    pub fn word_end(&self) -> Option<usize> {
        if !is_ident_start(self.peek()?) {
            return None;
        }
        let rest = &self.bytes[self.pos + 1..];
        let n = rest
            .iter()
            .position(|&b| !is_ident_char(b))
            .unwrap_or(rest.len());
        Some(self.pos + 1 + n)
    }

    /// The name at the cursor, if any (not consumed).
    pub fn word(&self) -> Option<&'t str> {
        self.word_end().map(|end| &self.text[self.pos..end])
    }

    /// `ident`.
    pub fn ident(&mut self) -> Option<Ident> {
        let start = self.pos;
        let end = self.word_end()?;
        self.pos = end;
        Some(Ident {
            name: Name::new(&self.text[start..end]),
            span: self.span(start, end),
        })
    }

    /// `digits`: the end of the decimal literal at `pos`, if one starts there.
    pub fn digits_end(&self) -> Option<usize> {
        let digit = |i: usize| self.at(i).is_some_and(|b| b.is_ascii_digit());
        let mut i = self.pos;
        if digit(i) {
            while digit(i) {
                i += 1;
            }
            if self.at(i) == Some(b'.') {
                i += 1;
                while digit(i) {
                    i += 1;
                }
            }
        } else if self.at(i) == Some(b'.') && digit(i + 1) {
            i += 1;
            while digit(i) {
                i += 1;
            }
        } else {
            return None;
        }
        if matches!(self.at(i), Some(b'e' | b'E')) {
            let mut j = i + 1;
            if matches!(self.at(j), Some(b'+' | b'-')) {
                j += 1;
            }
            if digit(j) {
                while digit(j) {
                    j += 1;
                }
                i = j;
            }
        }
        Some(i)
    }

    /// `string`'s inside (`str_inner`) as written, the cursor left after the closing quote.
    pub fn string_raw(&mut self) -> Option<&'t str> {
        let start = self.pos + 1;
        let mut i = start;
        loop {
            match self.at(i)? {
                b'"' => break,
                b'\n' => return None,
                b'\\' => {
                    self.at(i + 1)?;
                    i += 2;
                }
                _ => i += 1,
            }
        }
        self.pos = i + 1;
        // A `\` before a multi-byte character steps into it by one byte; the scan only stops
        // at ASCII bytes, so `i` is a character boundary again by the closing quote.
        self.text.get(start..i)
    }

    /// `array`: `[` up to the first `]`; the cursor left after it.
    pub fn array(&mut self) -> Option<()> {
        let n = memchr::memchr(b']', &self.bytes[self.pos..])?;
        if self.counting {
            // The `[` nests like a bracket; an inside that `scan::too_deep` reads as more than
            // numbers (a bracket, a quote, a comment) is left to the scan of the whole text.
            self.open()?;
            self.close();
            let inside = &self.bytes[self.pos + 1..self.pos + n];
            if inside.iter().any(|&b| DEPTH_BYTES[b as usize]) && !self.scan_depth() {
                return None;
            }
        }
        self.pos += n + 1;
        Some(())
    }

    /// `hex_color`: `#` and letters or digits; the text after `#`.
    pub fn hex_color(&mut self) -> &'t str {
        let start = self.pos + 1;
        let rest = &self.bytes[start..];
        let n = rest
            .iter()
            .position(|b| !b.is_ascii_alphanumeric())
            .unwrap_or(rest.len());
        self.pos = start + n;
        &self.text[start..start + n]
    }
}
