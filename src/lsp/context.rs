//! Language server: what surrounds the cursor in `.scn` text, found by a tolerant token scan (not
//! a parse), so that hover and completion work while the text is mid-edit and does not parse.
//!
//! The text is split by the formatter's comment-keeping tokenizer ([`crate::fmt::tokens`], total
//! on any text); brackets are tracked on a stack whose `{` frames know which block they open
//! (from the statement header before the `{`: `mesh ball = sphere {` opens a sphere block,
//! `transform {` a transform), which keys of that block are already given (before and after the
//! cursor, up to the block's `}` or the next statement in column 0) and which key, if any, the
//! cursor's value belongs to. Unbalanced brackets close as far as they match.

use crate::check::reference::Block;
use crate::fmt::tokens::{tokenize, Token, TokenKind};
use crate::syntax::scan::STATEMENT_KEYWORDS;

/// An open `{` block around the cursor.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    /// The block kind, when the header before the `{` names one.
    pub block: Option<Block>,
    /// The keys of that block given in it (anywhere, not only before the cursor).
    pub given: Vec<&'static str>,
}

/// The cursor's surroundings.
#[derive(Debug, Clone)]
pub struct Context<'t> {
    /// Every token of the text (comments included).
    pub tokens: Vec<Token<'t>>,
    /// The index of the token the cursor is in or touches at its end (a word being typed),
    /// when it is a word, string or number.
    pub at: Option<usize>,
    /// Whether the cursor is inside a comment or a string (nothing is offered there).
    pub in_comment_or_string: bool,
    /// The open `{` blocks, outermost first.
    pub frames: Vec<Frame>,
    /// Whether the cursor is inside `( )` (an expression or call arguments).
    pub in_parens: bool,
    /// The code tokens before the cursor's token at the cursor's bracket level, nearest last
    /// (at most a few, enough to read a statement header or a key).
    pub before: Vec<&'t str>,
    /// The key of the innermost block that the word at the cursor is the value of: the key is
    /// the previous token at block level.
    pub value_of: Option<&'static str>,
    /// Whether the word at the cursor (or the cursor) stands in column 0, where a top-level
    /// statement starts.
    pub in_column_0: bool,
}

impl<'t> Context<'t> {
    /// The innermost open block, if the cursor is directly in one (not in parentheses).
    pub fn block(&self) -> Option<Block> {
        if self.in_parens {
            return None;
        }
        self.frames.last().and_then(|f| f.block)
    }

    /// The token at the cursor.
    pub fn token(&self) -> Option<&Token<'t>> {
        self.at.and_then(|i| self.tokens.get(i))
    }

    /// Whether the token at the cursor is directly followed by `(` (a call or a call key).
    pub fn is_called(&self) -> bool {
        let next = self.at.and_then(|i| self.tokens.get(i + 1));
        next.is_some_and(|t| t.kind == TokenKind::Punct('(') && t.newlines_before == 0)
    }
}

/// The end of a token.
pub fn end(t: &Token<'_>) -> usize {
    t.start + t.text.len()
}

/// A number token split into its digits and its unit suffix, as the tokenizer reads it.
pub fn split_unit(word: &str) -> (&str, &str) {
    let k = crate::fmt::tokens::numeral_end(word.as_bytes(), 0);
    word.split_at(k.min(word.len()))
}

fn is_code(t: &Token<'_>) -> bool {
    !matches!(t.kind, TokenKind::LineComment | TokenKind::BlockComment)
}

/// A bracket frame on the scan's stack.
enum Open {
    Brace(Frame),
    Paren,
}

/// Scans `text` for the surroundings of byte `offset`.
pub fn at(text: &str, offset: usize) -> Context<'_> {
    let tokens = tokenize(text);
    // The token containing the offset, or ending exactly at it (the word being typed).
    let at = tokens
        .iter()
        .position(|t| t.start <= offset && offset <= end(t) && t.start < end(t))
        .filter(|&i| {
            let t = &tokens[i];
            offset > t.start || !matches!(t.kind, TokenKind::Punct(_))
        });
    let in_comment_or_string = at.is_some_and(|i| {
        let t = &tokens[i];
        match t.kind {
            TokenKind::LineComment | TokenKind::BlockComment => offset > t.start,
            TokenKind::Str => offset > t.start && offset < end(&tokens[i]),
            _ => false,
        }
    });
    let at = at.filter(|&i| matches!(tokens[i].kind, TokenKind::Word | TokenKind::Str));
    // Tokens before the cursor's own token.
    let stop = at.unwrap_or_else(|| tokens.partition_point(|t| t.start < offset));
    let mut stack: Vec<Open> = Vec::new();
    let mut before: Vec<&str> = Vec::new();
    for (i, t) in tokens[..stop].iter().enumerate() {
        if !is_code(t) {
            continue;
        }
        match t.kind {
            TokenKind::Punct('{') => {
                let block = header_block(&tokens[..i]);
                stack.push(Open::Brace(Frame {
                    block,
                    given: Vec::new(),
                }));
                before.clear();
            }
            TokenKind::Punct('(') => {
                stack.push(Open::Paren);
                before.clear();
            }
            TokenKind::Punct(')') => {
                if matches!(stack.last(), Some(Open::Paren)) {
                    stack.pop();
                }
                before.push(t.text);
            }
            TokenKind::Punct('}') => {
                if let Some(k) = stack.iter().rposition(|o| matches!(o, Open::Brace(_))) {
                    stack.truncate(k);
                }
                before.clear();
            }
            _ => {
                if let Some(Open::Brace(frame)) = stack.last_mut() {
                    note_key(frame, t.text);
                }
                before.push(t.text);
            }
        }
        if before.len() > 8 {
            before.remove(0);
        }
    }
    let in_parens = matches!(stack.last(), Some(Open::Paren));
    if let Some(Open::Brace(frame)) = stack.last_mut() {
        keys_after(&tokens, at.map_or(stop, |i| i + 1), frame);
    }
    let frames: Vec<Frame> = stack
        .into_iter()
        .filter_map(|o| match o {
            Open::Brace(f) => Some(f),
            Open::Paren => None,
        })
        .collect();
    let value_of = match (in_parens, frames.last().and_then(|f| f.block)) {
        (false, Some(block)) => before
            .last()
            .and_then(|w| block.keys().iter().copied().find(|k| k == w)),
        _ => None,
    };
    let word_start = at.map_or(offset, |i| tokens[i].start).min(text.len());
    let in_column_0 = word_start == 0 || text.as_bytes().get(word_start - 1) == Some(&b'\n');
    Context {
        in_column_0,
        tokens,
        at,
        in_comment_or_string,
        frames,
        in_parens,
        before,
        value_of,
    }
}

/// Records `word` as given in `frame` when it is one of its block's keys.
fn note_key(frame: &mut Frame, word: &str) {
    let Some(block) = frame.block else { return };
    if let Some(key) = block.keys().iter().copied().find(|k| *k == word) {
        if !frame.given.contains(&key) {
            frame.given.push(key);
        }
    }
}

/// Adds the keys given after the cursor (from token `from` on) to the innermost `frame`: words at
/// its level up to its `}`, or to a statement keyword in column 0 when it is never closed.
fn keys_after(tokens: &[Token<'_>], from: usize, frame: &mut Frame) {
    let mut depth = 0usize;
    for t in tokens.iter().skip(from).filter(|t| is_code(t)) {
        match t.kind {
            TokenKind::Punct('{' | '(') => depth += 1,
            TokenKind::Punct('}' | ')') => {
                if depth == 0 {
                    return;
                }
                depth -= 1;
            }
            TokenKind::Word if t.newlines_before > 0 && t.spaces_before == 0 => {
                if STATEMENT_KEYWORDS.contains(&t.text) {
                    return;
                }
                if depth == 0 {
                    note_key(frame, t.text);
                }
            }
            _ if depth == 0 => note_key(frame, t.text),
            _ => {}
        }
    }
}

/// The block a `{` opens, read from the code tokens before it: `transform {`, `render {`,
/// `camera NAME {`, `object MESH {`, `group NAME {`, `KEYWORD NAME = KIND {` and
/// `KEYWORD NAME = KIND("file") {`.
fn header_block(before: &[Token<'_>]) -> Option<Block> {
    let mut code = before.iter().rev().filter(|t| is_code(t)).map(|t| t.text);
    let mut last = code.next()?;
    if last == ")" {
        // Skip back over the call's arguments to its name.
        let mut depth = 1usize;
        for w in code.by_ref() {
            match w {
                ")" => depth += 1,
                "(" => depth -= 1,
                _ => {}
            }
            if depth == 0 {
                break;
            }
        }
        last = code.next()?;
    }
    if matches!(last, "transform" | "render") {
        return Block::of_statement(last, "");
    }
    let second = code.next()?;
    if matches!(second, "camera" | "object" | "group") {
        return Block::of_statement(second, "");
    }
    if second != "=" {
        return None;
    }
    let _name = code.next()?;
    let keyword = code.next()?;
    Block::of_statement(keyword, last)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cursor(marked: &str) -> (String, usize) {
        let at = marked.find('|').unwrap_or(marked.len());
        (marked.replacen('|', "", 1), at)
    }

    #[test]
    fn blocks_and_given_keys_around_the_cursor() {
        let (text, offset) =
            cursor("scnc 1\ncamera c { eye (0, 0, 1)  f|  target (0, 0, 0) }\nlet a = 1\n");
        let c = at(&text, offset);
        assert_eq!(c.block(), Some(Block::Camera));
        assert_eq!(c.frames[0].given, vec!["eye", "target"]);
        assert_eq!(c.token().map(|t| t.text), Some("f"));
        assert_eq!(c.value_of, None);
    }

    #[test]
    fn headers_with_calls_and_nested_blocks() {
        let (text, offset) = cursor("mesh m = obj(\"a.obj\") { mtl | }");
        assert_eq!(at(&text, offset).block(), Some(Block::ObjMesh));
        assert_eq!(at(&text, offset).value_of, Some("mtl"));
        let (text, offset) = cursor("group g { object m { transform { rotate y | } } }");
        assert_eq!(at(&text, offset).block(), Some(Block::Transform));
        assert_eq!(at(&text, offset).frames.len(), 3);
        let (text, offset) = cursor("light l = area { radiance rgb(1, |");
        let c = at(&text, offset);
        assert!(c.in_parens);
        assert_eq!(c.frames[0].block, Some(Block::AreaLight));
    }

    #[test]
    fn unclosed_blocks_end_at_the_next_statement() {
        let (text, offset) = cursor("material m = phong { diffuse 1 |\nrender { seed 1 }\n");
        let c = at(&text, offset);
        assert_eq!(c.block(), Some(Block::Phong));
        assert_eq!(c.frames[0].given, vec!["diffuse"]);
    }

    #[test]
    fn comments_and_strings_are_inert() {
        let (text, offset) = cursor("camera c { // ey| \n }");
        assert!(at(&text, offset).in_comment_or_string);
        let (text, offset) = cursor("render { output \"a|.png\" }");
        assert!(at(&text, offset).in_comment_or_string);
    }
}
