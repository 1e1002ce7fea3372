//! Lines and tokens of OBJ and MTL text (stage 3, asset decoding). No `.scn` syntax.
//!
//! Both formats are line-based: a keyword, then whitespace-separated arguments. Lines end in
//! `\n` or `\r\n` (or a lone `\r`, as old Mac tools wrote), the last may have no end at all, and a
//! line may be any length (the splitter uses `memchr`, so a megabyte line costs nothing extra).
//! A `#` at the start of a line or after whitespace starts a comment. A backslash at the end of
//! a line continues it on the next one (allowed by the OBJ specification, rare in practice): such
//! a line is joined into a buffer the caller provides. Whitespace is any run of spaces, tabs,
//! vertical tabs and form feeds.

/// One logical line: its 1-based number (of its first physical line), byte offset, content.
#[derive(Debug, Clone, Copy)]
pub struct Line<'a> {
    /// 1-based line number.
    pub number: u32,
    /// Byte offset of the line's first byte in the text.
    pub offset: usize,
    /// The line's bytes, without its terminator.
    pub text: &'a [u8],
}

/// Splits text into physical lines without their terminators.
#[derive(Debug)]
pub struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    number: u32,
}

impl<'a> Lines<'a> {
    /// Lines of `bytes`, the whole (UTF-8-compatible) text, numbered from 1.
    pub fn new(bytes: &'a [u8]) -> Lines<'a> {
        Lines {
            bytes,
            pos: 0,
            number: 0,
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = Line<'a>;

    fn next(&mut self) -> Option<Line<'a>> {
        let rest = self.bytes.get(self.pos..).filter(|r| !r.is_empty())?;
        let offset = self.pos;
        self.number = self.number.saturating_add(1);
        let (text, advance) = match memchr::memchr2(b'\n', b'\r', rest) {
            Some(i) => {
                let crlf = rest[i] == b'\r' && rest.get(i + 1) == Some(&b'\n');
                (&rest[..i], i + 1 + usize::from(crlf))
            }
            None => (rest, rest.len()),
        };
        self.pos += advance;
        Some(Line {
            number: self.number,
            offset,
            text,
        })
    }
}

/// Whether `c` is OBJ whitespace: space, tab, vertical tab or form feed.
pub fn is_space(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | 0x0B | 0x0C)
}

/// The line without its comment and surrounding whitespace.
pub fn strip_comment(text: &[u8]) -> &[u8] {
    let mut end = text.len();
    let mut prev_space = true;
    for (i, &c) in text.iter().enumerate() {
        if c == b'#' && prev_space {
            end = i;
            break;
        }
        prev_space = is_space(c);
    }
    trim(&text[..end])
}

/// `t` without leading and trailing whitespace.
pub fn trim(mut t: &[u8]) -> &[u8] {
    while let [c, rest @ ..] = t {
        if !is_space(*c) {
            break;
        }
        t = rest;
    }
    while let [rest @ .., c] = t {
        if !is_space(*c) {
            break;
        }
        t = rest;
    }
    t
}

/// The first token and the trimmed rest of the line.
pub fn keyword(text: &[u8]) -> (&[u8], &[u8]) {
    let end = text.iter().position(|&c| is_space(c)).unwrap_or(text.len());
    (&text[..end], trim(&text[end..]))
}

/// Whitespace-separated tokens.
pub fn tokens(text: &[u8]) -> impl Iterator<Item = &[u8]> {
    text.split(|&c| is_space(c)).filter(|t| !t.is_empty())
}

/// Whether the (comment-stripped) line continues on the next one.
pub fn continues(text: &[u8]) -> bool {
    text.last() == Some(&b'\\')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crlf_lone_cr_and_no_final_newline() {
        let lines: Vec<(u32, &[u8])> = Lines::new(b"a\r\nb\rc\n\nd")
            .map(|l| (l.number, l.text))
            .collect();
        let want: Vec<(u32, &[u8])> = vec![(1, b"a"), (2, b"b"), (3, b"c"), (4, b""), (5, b"d")];
        assert_eq!(lines, want);
    }

    #[test]
    fn comments_keywords_tokens() {
        assert_eq!(strip_comment(b"  v 1 2 3 # note"), b"v 1 2 3");
        assert_eq!(strip_comment(b"usemtl a#b"), b"usemtl a#b");
        assert_eq!(strip_comment(b"# all"), b"");
        assert_eq!(
            keyword(b"usemtl \t my mat "),
            (&b"usemtl"[..], &b"my mat"[..])
        );
        let t: Vec<&[u8]> = tokens(b"1 \t 2\x0c3").collect();
        assert_eq!(t, vec![&b"1"[..], b"2", b"3"]);
    }
}
