//! Formatter, step 2: lays the tokens of a parsed file out canonically.
//!
//! The rules (the examples' style):
//! - two spaces of indentation per open `{` or `(`; a line that starts with a closer is
//!   indented as its opener's line;
//! - every top-level statement starts a line; at most one blank line in a row, none at the
//!   start of the file, at the start of a block or before its `}`; one `\n` at the end;
//! - a block written on one line stays on one line as `{ a 1  b 2 }` (`{}` when empty); a block
//!   that spans lines has its `{` end a line (a trailing `//` comment may follow it) and its `}`
//!   start one; the line breaks between its items are the author's;
//! - one space after `,` and around `=`, `+`, `*`, `/` and inside `{ }`; none inside `( )`,
//!   before `,` or `)`; a call keeps its `(` glued to the name and a `-` keeps being glued to its
//!   operand when it was; two or more spaces between tokens are kept (they align columns and
//!   separate properties); comments stay where they are;
//! - lines inside a multi-line `[ ... ]` array are re-indented one level deeper; the text of
//!   block comments is untouched.
//!
//! Only whitespace between tokens changes, and never between two tokens whose meaning depends
//! on it (a name and its `(`), so the formatted file parses to the same statements.

use super::tokens::{Token, TokenKind};

/// Lays out `tokens`; `statement_starts` are the byte offsets where top-level statements start.
pub fn layout(text: &str, tokens: &[Token<'_>], statement_starts: &[usize]) -> String {
    let multiline = multiline_blocks(text, tokens);
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    let mut depth = 0usize;
    for (i, token) in tokens.iter().enumerate() {
        let prev = i.checked_sub(1).map(|p| &tokens[p]);
        let newlines = newlines_before(i, tokens, &multiline, statement_starts);
        if let Some(prev) = prev {
            if newlines == 0 {
                out.push_str(&" ".repeat(gap(prev, token)));
            } else {
                out.push_str(&"\n".repeat(newlines));
            }
        }
        let opens_line = prev.is_none() || newlines > 0;
        let closes = matches!(token.kind, TokenKind::Punct('}' | ')'));
        if closes {
            depth = depth.saturating_sub(1);
        }
        if opens_line {
            out.push_str(&"  ".repeat(depth));
        }
        push_token(&mut out, token, depth);
        if matches!(token.kind, TokenKind::Punct('{' | '(')) {
            depth += 1;
        }
    }
    if !tokens.is_empty() {
        out.push('\n');
    }
    out
}

/// Appends a token's text: arrays have their continuation lines re-indented one level deeper
/// than `depth`; everything else is copied as written.
fn push_token(out: &mut String, token: &Token<'_>, depth: usize) {
    if token.kind != TokenKind::Array || !token.text.contains('\n') {
        out.push_str(token.text);
        return;
    }
    for (n, line) in token.text.split('\n').enumerate() {
        if n == 0 {
            out.push_str(line.trim_end());
            continue;
        }
        out.push('\n');
        let line = line.trim();
        if !line.is_empty() {
            let extra = usize::from(!line.starts_with(']'));
            out.push_str(&"  ".repeat(depth + extra));
            out.push_str(line);
        }
    }
}

/// For each token, whether it is a `{` or `}` of a block that spans lines in `text`.
fn multiline_blocks(text: &str, tokens: &[Token<'_>]) -> Vec<bool> {
    let mut multiline = vec![false; tokens.len()];
    let mut open: Vec<usize> = Vec::new();
    for (i, token) in tokens.iter().enumerate() {
        match token.kind {
            TokenKind::Punct('{') => open.push(i),
            TokenKind::Punct('}') => {
                if let Some(o) = open.pop() {
                    let spans_lines = text[tokens[o].start..token.start].contains('\n');
                    multiline[o] = spans_lines;
                    multiline[i] = spans_lines;
                }
            }
            _ => {}
        }
    }
    multiline
}

/// How many line breaks go before token `i` (0: same line as `prev`).
fn newlines_before(
    i: usize,
    tokens: &[Token<'_>],
    multiline: &[bool],
    statement_starts: &[usize],
) -> usize {
    let (Some(token), Some(prev)) = (tokens.get(i), i.checked_sub(1).and_then(|p| tokens.get(p)))
    else {
        return 0;
    };
    let mut newlines = token.newlines_before;
    // A `//` comment after a `{` on its line still counts as the start of the block.
    let after_open = prev.kind == TokenKind::Punct('{')
        || (prev.kind == TokenKind::LineComment
            && prev.newlines_before == 0
            && i >= 2
            && tokens[i - 2].kind == TokenKind::Punct('{'));
    let before_close = token.kind == TokenKind::Punct('}');
    let in_open_block = prev.kind == TokenKind::Punct('{') && multiline[i - 1];
    if (in_open_block && token.kind != TokenKind::LineComment)
        || (before_close && multiline[i])
        || statement_starts.binary_search(&token.start).is_ok()
        || prev.kind == TokenKind::LineComment
    {
        newlines = newlines.max(1);
    }
    let limit = if after_open || before_close { 1 } else { 2 };
    newlines.min(limit)
}

/// Spaces between two tokens on one line.
fn gap(prev: &Token<'_>, token: &Token<'_>) -> usize {
    use TokenKind::Punct;
    let written = token.spaces_before;
    match (prev.kind, token.kind) {
        (Punct('{'), Punct('}')) => 0,
        (Punct('('), _) | (_, Punct(')' | ',')) => 0,
        // `f(x)` is a call, `f (x)` a name and a vector: keep whichever was written.
        (TokenKind::Word, Punct('(')) if written == 0 => 0,
        // A `-` glued to its operand (`-1`, `a-b`) stays glued: it reads as written.
        (Punct('-'), TokenKind::Word | Punct('(')) if written == 0 => 0,
        (TokenKind::Word | Punct(')'), Punct('-')) if written == 0 => 0,
        _ => written.max(1),
    }
}
