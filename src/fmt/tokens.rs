//! Formatter, step 1: a comment-preserving token scan of `.scn` text.
//!
//! The grammar (grammar/scene.pest) makes whitespace and comments silent, so pest's pairs lose
//! them; the formatter needs both. This scan splits the text into the tokens pest sees plus
//! comments, and records the whitespace before each (newlines and spaces), which is all the
//! layout needs. It mirrors the grammar's atomic tokens (names, numbers with their unit suffix,
//! `#hex` colours, strings, the coarse `[ ... ]` array) so that re-spacing between tokens can
//! never change how pest reads them. It only runs on text that parsed.

/// What a token is, as far as layout cares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TokenKind {
    /// A name, keyword, number (with its unit) or `#hex` colour.
    Word,
    /// A string literal.
    Str,
    /// A coarse `[ ... ]` numeric array (may span lines).
    Array,
    /// `// ...` up to (not including) the end of the line.
    LineComment,
    /// `/* ... */`, nested as the grammar nests them (may span lines).
    BlockComment,
    /// One punctuation character: `{ } ( ) , = + - * /`.
    Punct(char),
}

/// One token with the whitespace that precedes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Token<'a> {
    /// Its kind.
    pub kind: TokenKind,
    /// Its text, exactly as written.
    pub text: &'a str,
    /// Byte offset of its first character.
    pub start: usize,
    /// Line breaks in the whitespace before it.
    pub newlines_before: usize,
    /// Whitespace characters before it on its own line (after the last line break).
    pub spaces_before: usize,
}

/// Splits `text` into tokens and comments.
pub fn tokenize(text: &str) -> Vec<Token<'_>> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let (newlines_before, spaces_before, next) = skip_whitespace(text, i);
        i = next;
        if i >= bytes.len() {
            break;
        }
        let (kind, end) = token_at(text, i);
        tokens.push(Token {
            kind,
            text: &text[i..end],
            start: i,
            newlines_before,
            spaces_before,
        });
        i = end;
    }
    tokens
}

/// Skips the grammar's whitespace (including a byte-order mark) from `i`: the line breaks, the
/// whitespace characters after the last one, and where the next token starts.
fn skip_whitespace(text: &str, mut i: usize) -> (usize, usize, usize) {
    let (mut newlines, mut spaces) = (0, 0);
    for c in text[i..].chars() {
        match c {
            '\n' => {
                newlines += 1;
                spaces = 0;
            }
            '\r' => {}
            ' ' | '\t' | '\u{FEFF}' => spaces += 1,
            _ => break,
        }
        i += c.len_utf8();
    }
    (newlines, spaces, i)
}

fn is_word_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The token starting at `i` (not whitespace) and where it ends.
fn token_at(text: &str, i: usize) -> (TokenKind, usize) {
    let bytes = text.as_bytes();
    let at = |k: usize| bytes.get(k).copied().unwrap_or(0);
    match at(i) {
        b'/' if at(i + 1) == b'/' => {
            let end = text[i..].find('\n').map_or(text.len(), |n| i + n);
            // A `\r` before the line break belongs to the line ending, not the comment.
            let end = if end > i && at(end - 1) == b'\r' {
                end - 1
            } else {
                end
            };
            (TokenKind::LineComment, end)
        }
        b'/' if at(i + 1) == b'*' => (TokenKind::BlockComment, block_comment_end(bytes, i)),
        b'"' => (TokenKind::Str, string_end(bytes, i)),
        b'[' => {
            let end = text[i..].find(']').map_or(text.len(), |n| i + n + 1);
            (TokenKind::Array, end)
        }
        b'#' => {
            let mut end = i + 1;
            while is_word_char(at(end)) {
                end += 1;
            }
            (TokenKind::Word, end)
        }
        b if b.is_ascii_digit() || (b == b'.' && at(i + 1).is_ascii_digit()) => {
            (TokenKind::Word, number_end(bytes, i))
        }
        b if is_word_char(b) => {
            let mut end = i + 1;
            while is_word_char(at(end)) {
                end += 1;
            }
            (TokenKind::Word, end)
        }
        _ => {
            let c = text[i..].chars().next().unwrap_or(' ');
            (TokenKind::Punct(c), i + c.len_utf8())
        }
    }
}

/// End of a nested block comment starting at `i` (the end of the text if it is unclosed).
fn block_comment_end(bytes: &[u8], i: usize) -> usize {
    let mut depth = 0usize;
    let mut k = i;
    while k + 1 < bytes.len() {
        match (bytes[k], bytes[k + 1]) {
            (b'/', b'*') => {
                depth += 1;
                k += 2;
            }
            (b'*', b'/') => {
                depth -= 1;
                k += 2;
                if depth == 0 {
                    return k;
                }
            }
            _ => k += 1,
        }
    }
    bytes.len()
}

/// End of a string starting at the `"` at `i`: `\` escapes any character.
fn string_end(bytes: &[u8], i: usize) -> usize {
    let mut k = i + 1;
    while k < bytes.len() {
        match bytes[k] {
            b'\\' => k += 2,
            b'"' => return k + 1,
            b'\n' => return k,
            _ => k += 1,
        }
    }
    bytes.len()
}

/// End of a number as the grammar's `number` reads it: digits, fraction, exponent, unit suffix.
fn number_end(bytes: &[u8], i: usize) -> usize {
    let mut k = numeral_end(bytes, i);
    let at = |k: usize| bytes.get(k).copied().unwrap_or(0);
    if at(k).is_ascii_alphabetic() || at(k) == b'_' {
        while is_word_char(at(k)) {
            k += 1;
        }
    }
    k
}

/// End of a number's numeral (digits, fraction, exponent) starting at `i`, before any unit
/// suffix; the language server splits number tokens with it.
pub fn numeral_end(bytes: &[u8], i: usize) -> usize {
    let at = |k: usize| bytes.get(k).copied().unwrap_or(0);
    let digits = |mut k: usize| {
        while at(k).is_ascii_digit() {
            k += 1;
        }
        k
    };
    let mut k = digits(i);
    if at(k) == b'.' {
        k = digits(k + 1);
    }
    if matches!(at(k), b'e' | b'E') {
        let sign = usize::from(matches!(at(k + 1), b'+' | b'-'));
        if at(k + 1 + sign).is_ascii_digit() {
            k = digits(k + 1 + sign);
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(TokenKind, &str)> {
        tokenize(text)
            .into_iter()
            .map(|t| (t.kind, t.text))
            .collect()
    }

    #[test]
    fn numbers_keep_their_exponent_and_unit() {
        assert_eq!(
            kinds("fov 1.5e-3deg -2"),
            vec![
                (TokenKind::Word, "fov"),
                (TokenKind::Word, "1.5e-3deg"),
                (TokenKind::Punct('-'), "-"),
                (TokenKind::Word, "2"),
            ]
        );
    }

    #[test]
    fn comments_strings_and_arrays_are_single_tokens() {
        assert_eq!(
            kinds("a \"x // y\" /* /* n */ */ [1 2\n 3] // end\r\nb"),
            vec![
                (TokenKind::Word, "a"),
                (TokenKind::Str, "\"x // y\""),
                (TokenKind::BlockComment, "/* /* n */ */"),
                (TokenKind::Array, "[1 2\n 3]"),
                (TokenKind::LineComment, "// end"),
                (TokenKind::Word, "b"),
            ]
        );
    }

    #[test]
    fn whitespace_before_is_counted() {
        let t = tokenize("a\n\n   b  c");
        assert_eq!((t[1].newlines_before, t[1].spaces_before), (2, 3));
        assert_eq!((t[2].newlines_before, t[2].spaces_before), (0, 2));
    }
}
