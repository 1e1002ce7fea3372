//! Stage 1, syntax (fast path): a hand-written parser for `grammar/scene.pest`'s statements,
//! producing the same AST (spans included) as pest plus the converter, with ≈ 12× fewer
//! instructions (docs/frontend-bench.md).
//!
//! pest stays the definition of the language and the only source of syntax errors: the fast
//! parser never backtracks and never reports; on any statement it does not accept whole (a
//! syntax error, or a rare form it leaves to pest, such as `object` used as a plain value or
//! an expression over the node limit) it hands that one statement to pest (`Rule::statement`)
//! and goes on after it. If pest fails on it too, the file has a syntax error and the caller's
//! error recovery (`parse_chunks`) reports it exactly as before. A PEG parses `statement*`
//! left to right with no look-behind, so a statement parsed at the position pest would reach
//! is the statement pest would parse there; `tests` (differential, against pest on every
//! example and on seeded mutations) holds the two parsers to identical output.

mod cursor;
mod decimal;
mod expr;

use pest::Parser;

use self::cursor::Cursor;
use super::ast::*;
use super::convert::Converter;
use super::{Rule, SceneParser};
use crate::diag::Diagnostic;
use crate::source::FileId;

/// Parses a whole file; `None` when it has a syntax error (pest failed on a statement) or
/// nests deeper than `scan::MAX_NESTING` (`scan::too_deep`, checked while parsing).
pub(super) fn parse(file: FileId, text: &str) -> Option<(Vec<Stmt>, Vec<Diagnostic>)> {
    let mut statements = Vec::new();
    let diags = parse_each(file, text, &mut |s| statements.push(s), Fallback::Whole)?;
    Some((statements, diags))
}

/// How [`parse_each`] hands pest a statement the fast parser does not accept.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Fallback {
    /// pest parses it in the whole text: `None` means a syntax error.
    Whole,
    /// pest first parses it within the text up to the next line that starts with a word in
    /// its first column, and `None` (giving up) when it fails there: a statement cut inside
    /// its braces is then not read by pest over every later `object` (as items of its open
    /// block) before it fails. For a caller that may always start over the plain way
    /// (`syntax::parse_each`); a statement that parses there is parsed again in the whole text.
    Line,
}

/// [`parse`], handing each statement to `each` as soon as it is parsed instead of gathering
/// them. On `None` (a syntax error, nesting too deep, or giving up under [`Fallback::Line`])
/// the statements before it were handed out already.
pub(super) fn parse_each(
    file: FileId,
    text: &str,
    each: &mut dyn FnMut(Stmt),
    fallback: Fallback,
) -> Option<Vec<Diagnostic>> {
    parse_each_from(Cursor::counting_depth(file, text), each, fallback)
}

/// [`parse_each`] with the cursor `c` at the start of its text: one that counts depth, or (for
/// the tests, as the parse was before the depth was counted while parsing) one over a text
/// scanned first.
fn parse_each_from(
    mut c: Cursor,
    each: &mut dyn FnMut(Stmt),
    fallback: Fallback,
) -> Option<Vec<Diagnostic>> {
    let (file, text) = (c.file, c.text);
    let mut diags = Vec::new();
    loop {
        c.skip();
        if c.too_deep {
            return None;
        }
        if c.pos >= text.len() {
            return Some(diags);
        }
        let start = c.pos;
        let parsed = c.statement();
        if c.too_deep {
            return None;
        }
        match parsed {
            Some(s) => each(s),
            None => {
                // pest is recursive: it parses nothing before the whole text's depth is known.
                if !c.scan_depth() {
                    return None;
                }
                match fallback {
                    Fallback::Line => {
                        pest_statement(file, within_line(text, start), start, &mut Vec::new())?;
                    }
                    Fallback::Whole if fails_over_a_run(file, text, start) => return None,
                    Fallback::Whole => {}
                }
                let (s, end) = pest_statement(file, text, start, &mut diags)?;
                each(s);
                c.pos = end;
            }
        }
    }
}

/// `text` up to the first line after `start` that starts with a word in its first column (all of
/// it when there is none): where [`Fallback::Line`] has pest parse a statement first.
fn within_line(text: &str, start: usize) -> &str {
    let line = |n: usize| text.as_bytes().get(start + n + 1);
    let word = |n: &usize| line(*n).is_some_and(u8::is_ascii_alphabetic);
    let next = text[start..].match_indices('\n').map(|(n, _)| n).find(word);
    next.map_or(text, |n| &text[..start + n + 1])
}

/// Whether pest fails on the statement at `start` (one the fast parser does not accept) in
/// the whole `text`, told without pest reading the `object`s and `group`s after it: when it
/// fails within [`within_line`] and leaves a bracket open before the run of them from the
/// first line after `start` that starts with one ([`nesting_run`], the fast parser alone),
/// which a `{` left open at `start` would take as its items, that run is spared as
/// `tail::statement_fails` argues. `false` when it cannot tell (pest parses it whole).
fn fails_over_a_run(file: FileId, text: &str, start: usize) -> bool {
    if pest_statement(file, within_line(text, start), start, &mut Vec::new()).is_some() {
        return false;
    }
    let mut from = start;
    let first = loop {
        let Some(line) = text.get(from..).and_then(|t| t.find('\n')) else {
            return false;
        };
        from += line + 1;
        if super::tail::nests(&text[from..]) {
            break from;
        }
    };
    // With nothing left open before the run, pest fails before it (a stray `=`) or reads past
    // it for another reason: the run would be parsed for nothing.
    if super::scan::unclosed(&text[start..first]).is_none() {
        return false;
    }
    let mut c = Cursor::new(file, text);
    let (run, _) = nesting_run(&mut c, first, &mut |_| None);
    super::tail::statement_fails(text, start, &run)
}

/// The run of `object` and `group` statements from `from` (where one starts), each parsed at
/// its place by the fast parser or, when it does not accept one, `fallback` (its end, or
/// `None`), with only blanks and comments between them: their byte ranges, and where the run
/// stops (past the blanks and comments after the last: the end of the text, or the first byte
/// that does not continue the run).
fn nesting_run(
    c: &mut Cursor,
    from: usize,
    fallback: &mut dyn FnMut(usize) -> Option<usize>,
) -> (Vec<(usize, usize)>, usize) {
    let mut run = Vec::new();
    c.pos = from;
    loop {
        c.skip();
        let at = c.pos;
        if at >= c.text.len() || !super::tail::nests(&c.text[at..]) {
            return (run, at);
        }
        let after = match c.statement() {
            Some(_) => c.pos,
            None => match fallback(at) {
                Some(after) => after,
                None => return (run, at),
            },
        };
        run.push((at, after));
        c.pos = after;
    }
}

/// The statements of `text[start..end]` as a parse of the whole of `text` finds them when it
/// reaches `start` (a statement's parse reads the text from its start on, and a top-level
/// statement's start is all the state the parser carries): `None` unless each one parses and
/// the last one is followed by nothing but whitespace and comments up to `end` exactly, or when
/// a statement had a diagnostic (the caller then parses the whole file), or when they do not
/// parse within `text[..end]` alone: a statement with a `{` left open must not have the
/// parsers read every later statement as its block's items before they fail at the end of the
/// file (declining is always allowed; a region that parses alone is parsed again as the whole
/// file's parse reads it, past `end` as far as its statements look).
pub(super) fn parse_region(
    file: FileId,
    text: &str,
    start: usize,
    end: usize,
) -> Option<Vec<Stmt>> {
    statements_between(file, text.get(..end.min(text.len()))?, start, end)?;
    statements_between(file, text, start, end)
}

/// The statements of the chunk `text[start..end]` of the error recovery, exactly as pest's
/// parse of the chunk alone as a file (`Rule::file`) finds them, their spans in `text`; `None`
/// when that parse fails or has a diagnostic (or the fast parser cannot tell): the caller lets
/// pest parse the chunk. The chunk is parsed within `text[..end]`, so nothing past its end is
/// read, as pest reads nothing past it; a PEG looks behind nothing, so the text before `start`
/// plays no part either.
pub(super) fn chunk(file: FileId, text: &str, start: usize, end: usize) -> Option<Vec<Stmt>> {
    statements_between(file, text.get(..end)?, start, end)
}

/// The byte ranges of the `object` and `group` statements that end the chunk
/// `text[start..end]` of the error recovery, for `tail::error` to spare their parse when the
/// chunk fails: a run of statements, the first at the start of a line past `start`, each
/// parsed at its place within `text[..end]` (so over exactly its range, reading nothing past
/// it: an `object` or `group` ends with its `}`), with only blanks and comments between them
/// and after the last up to `end`. Empty when there is none. The run is looked for left to
/// right, starting again past any statement that fails or does not nest, so each byte is
/// parsed about once.
pub(super) fn nesting_tail(
    file: FileId,
    text: &str,
    start: usize,
    end: usize,
) -> Vec<(usize, usize)> {
    let Some(text) = text.get(..end) else {
        return Vec::new();
    };
    let mut c = Cursor::new(file, text);
    let mut from = start;
    let mut diags = Vec::new();
    let mut pest = |at: usize| pest_statement(file, text, at, &mut diags).map(|(_, after)| after);
    loop {
        // The next line start past `from` with an `object` or `group` on it.
        let Some(line) = text.get(from..).and_then(|t| t.find('\n')) else {
            return Vec::new();
        };
        from += line + 1;
        if !super::tail::nests(&text[from..]) {
            continue;
        }
        let (run, stop) = nesting_run(&mut c, from, &mut pest);
        if stop == end {
            return run;
        }
        from = stop;
    }
}

/// [`parse_region`]'s statements as a parse of all of `text` finds them.
fn statements_between(file: FileId, text: &str, start: usize, end: usize) -> Option<Vec<Stmt>> {
    let mut c = Cursor::new(file, text);
    c.pos = start;
    let mut statements = Vec::new();
    let mut diags = Vec::new();
    loop {
        c.skip();
        if c.pos == end.min(text.len()) {
            return Some(statements);
        }
        if c.pos > end {
            return None;
        }
        let at = c.pos;
        match c.statement() {
            Some(s) => statements.push(s),
            None => {
                if fails_over_a_run(file, text, at) {
                    return None;
                }
                let (s, after) = pest_statement(file, text, at, &mut diags)?;
                if !diags.is_empty() {
                    return None;
                }
                statements.push(s);
                c.pos = after;
            }
        }
    }
}

/// One statement at `start` parsed by pest and converted; its end offset.
fn pest_statement(
    file: FileId,
    text: &str,
    start: usize,
    diags: &mut Vec<Diagnostic>,
) -> Option<(Stmt, usize)> {
    let mut pairs = SceneParser::parse(Rule::statement, &text[start..]).ok()?;
    let pair = pairs.next()?;
    let end = start + pair.as_span().end();
    let conv = Converter::new(file, start);
    let stmt = conv.statement(pair);
    diags.extend(conv.errors.into_inner());
    Some((stmt, end))
}

impl Cursor<'_> {
    /// A top-level statement, the cursor on its keyword.
    fn statement(&mut self) -> Option<Stmt> {
        let start = self.pos;
        let kw = self.word()?;
        self.pos += kw.len();
        self.skip();
        let stmt = match kw {
            "object" => Stmt::Object(self.object_rest(start)?),
            "group" => Stmt::Group(self.group_rest(start)?),
            "material" => Stmt::Decl(Box::new(self.decl_rest(DeclKind::Material, start)?)),
            "texture" => Stmt::Decl(Box::new(self.decl_rest(DeclKind::Texture, start)?)),
            "mesh" => Stmt::Decl(Box::new(self.decl_rest(DeclKind::Mesh, start)?)),
            "light" => Stmt::Decl(Box::new(self.decl_rest(DeclKind::Light, start)?)),
            "let" => {
                let name = self.ident()?;
                self.skip();
                self.eat(b'=')?;
                self.skip();
                let value = self.top_expr()?;
                // The statement ends at its value's last token, not at the blanks and
                // comments the look for a further operator passed over.
                let end = value.span.end as usize;
                Stmt::Let {
                    name,
                    value,
                    span: self.span(start, end),
                }
            }
            "camera" => {
                let name = self.ident()?;
                self.skip();
                let body = self.block()?;
                Stmt::Camera {
                    name,
                    body,
                    span: self.span(start, self.pos),
                }
            }
            "render" => {
                let body = self.block()?;
                Stmt::Render {
                    body,
                    span: self.span(start, self.pos),
                }
            }
            "include" => {
                let path = self.top_term()?;
                Stmt::Include {
                    path,
                    span: self.span(start, self.pos),
                }
            }
            "scnc" => {
                let value = self.top_term()?;
                Stmt::Version {
                    value,
                    span: self.span(start, self.pos),
                }
            }
            _ => return None,
        };
        Some(stmt)
    }

    /// `object MESH { ... }` after its keyword (and the whitespace after it).
    fn object_rest(&mut self, start: usize) -> Option<ObjectStmt> {
        let mesh = self.ident()?;
        self.skip();
        let body = self.block()?;
        Some(ObjectStmt {
            mesh,
            body,
            span: self.span(start, self.pos),
        })
    }

    /// `group NAME { ... }` after its keyword.
    fn group_rest(&mut self, start: usize) -> Option<GroupStmt> {
        let name = self.ident()?;
        self.skip();
        let body = self.block()?;
        Some(GroupStmt {
            name,
            body,
            span: self.span(start, self.pos),
        })
    }

    /// `NAME = CTOR { ... }?` after a declaration's keyword.
    fn decl_rest(&mut self, kind: DeclKind, start: usize) -> Option<Decl> {
        let name = self.ident()?;
        self.skip();
        self.eat(b'=')?;
        self.skip();
        let ctor = self.ctor()?;
        self.skip();
        let body = if self.peek() == Some(b'{') {
            Some(self.block()?)
        } else {
            None
        };
        // Without a block the statement ends at its constructor, not at the blanks and
        // comments the look for a `{` passed over.
        let end = body.as_ref().map_or(ctor.span.end, |b| b.span.end) as usize;
        Some(Decl {
            kind,
            name,
            ctor,
            body,
            span: self.span(start, end),
        })
    }

    /// `ctor = call | ident`.
    fn ctor(&mut self) -> Option<Ctor> {
        let start = self.pos;
        let end = self.word_end()?;
        let name = self.ident()?;
        let args = if self.at(end) == Some(b'(') {
            self.nodes = 0;
            Some(self.call_args()?)
        } else {
            None
        };
        Some(Ctor {
            name,
            args,
            span: self.span(start, self.pos),
        })
    }

    /// `block = "{" ~ item* ~ "}"`.
    ///
    /// Items gather on one scratch stack shared by all blocks (nested ones above their
    /// parent's) and each block gets one allocation of exactly its size.
    fn block(&mut self) -> Option<Block> {
        let start = self.pos;
        self.eat(b'{')?;
        self.open()?;
        let mark = self.items.len();
        loop {
            self.skip();
            if self.eat(b'}').is_some() {
                self.close();
                return Some(Block {
                    items: self.items.drain(mark..).collect(),
                    span: self.span(start, self.pos),
                });
            }
            match self.item() {
                Some(item) => self.items.push(item),
                None => {
                    self.items.truncate(mark);
                    return None;
                }
            }
        }
    }

    /// `item`: `transform { }`, a nested `object` or `group`, or a term.
    fn item(&mut self) -> Option<Item> {
        let start = self.pos;
        let Some(end) = self.word_end() else {
            return Some(Item::Value(self.top_term()?));
        };
        let word = &self.text[start..end];
        if !matches!(word, "transform" | "object" | "group") && self.at(end) != Some(b'(') {
            // A bare name, as `top_term` parses it (no sign before it, not a call), without
            // reading the word again.
            self.pos = end;
            return Some(Item::Value(Expr {
                kind: ExprKind::Name(Name::new(word)),
                span: self.span(start, end),
            }));
        }
        let word = Some(word);
        let keyword = |this: &mut Self, kw: &str| {
            this.pos += kw.len();
            this.skip();
        };
        Some(match word {
            Some("transform") => {
                keyword(self, "transform");
                Item::Transform(self.block()?)
            }
            Some("object") => {
                keyword(self, "object");
                Item::Object(Box::new(self.object_rest(start)?))
            }
            Some("group") => {
                keyword(self, "group");
                Item::Group(Box::new(self.group_rest(start)?))
            }
            _ => Item::Value(self.top_term()?),
        })
    }
}

#[cfg(test)]
mod tests;
