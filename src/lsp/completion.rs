//! Language server: completion at the cursor, from its [`context`](super::context) (a tolerant
//! scan, so it works while the text is mid-edit and does not parse), each item documented from
//! the language reference ([`crate::check::reference`]):
//!
//! - in a block, where a key goes: the block's keys not yet given (repeatable keys always) and
//!   the blocks it may nest (`transform`, `object`, `group`);
//! - after a key: its choices (`wrap` → `repeat clamp mirror`), `true`/`false`, the declared
//!   names of the kind it expects (`material` → materials, `mesh` → meshes, `camera` → cameras,
//!   `diffuse` → textures and constants), else constants and functions;
//! - in parentheses and after `let NAME =`: constants, functions, `true`, `false`, `frame`;
//! - after a number: the units (`30d` → `deg`);
//! - at the top level: statement keywords, the kinds after `KEYWORD NAME =`, meshes after
//!   `object`.

use lsp_types::{
    CompletionItem, CompletionItemKind, CompletionTextEdit, Documentation, MarkupContent,
    MarkupKind, TextEdit,
};

use super::blocks::{BlockKind, Expected};
use super::context::{self, end, Context};
use super::names::{completion_kind, Declared};
use super::position::LineIndex;
use super::symbols::SymbolKind;
use crate::check::reference::{function_doc, unit_doc, Block};
use crate::check::vocabulary as v;
use crate::check::FUNCTIONS;
use crate::fmt::tokens::TokenKind;
use crate::syntax::scan::STATEMENT_KEYWORDS;

/// The completions at byte `offset` of `text`, given the names declared where it is seen.
pub fn complete(text: &str, offset: usize, names: &[Declared]) -> Vec<CompletionItem> {
    let cx = context::at(text, offset);
    if cx.in_comment_or_string {
        return Vec::new();
    }
    let token = cx.token().filter(|t| t.kind == TokenKind::Word);
    // The replaced range: the word being typed, or nothing at the cursor.
    let (mut from, to) = token.map_or((offset, offset), |t| (t.start, end(t).max(offset)));
    let word = token.map_or("", |t| t.text);
    let items = if word.starts_with('#') {
        Vec::new()
    } else if word.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
        from += context::split_unit(word).0.len();
        units()
    } else {
        by_place(&cx, names)
    };
    let index = LineIndex::new(text);
    let range = index.range(from, to);
    items
        .into_iter()
        .map(|mut item| {
            item.text_edit = Some(CompletionTextEdit::Edit(TextEdit::new(
                range,
                item.label.clone(),
            )));
            item
        })
        .collect()
}

/// The items for a word at the cursor's place.
fn by_place(cx: &Context<'_>, names: &[Declared]) -> Vec<CompletionItem> {
    let after_let = cx.frames.is_empty()
        && cx.before.last() == Some(&"=")
        && cx.before.iter().rev().nth(2) == Some(&"let");
    if cx.in_parens || after_let {
        return expression(names);
    }
    if let Some(frame) = cx.frames.last() {
        let Some(block) = frame.block else {
            return Vec::new();
        };
        return match cx.value_of {
            Some(key) => values(block, key, names),
            None => keys(block, &frame.given),
        };
    }
    top_level(cx, names)
}

/// The keys of `block` not yet `given` (repeatable ones always), and its nested blocks.
fn keys(block: Block, given: &[&str]) -> Vec<CompletionItem> {
    let mut items: Vec<CompletionItem> = block
        .properties()
        .filter(|p| !given.contains(&p.key) || block.repeatable().contains(&p.key))
        .map(|p| {
            let kind = if block.nested().contains(&p.key) {
                CompletionItemKind::KEYWORD
            } else {
                CompletionItemKind::PROPERTY
            };
            item(p.key, kind, p.ty, p.markdown())
        })
        .collect();
    for nested in block.nested() {
        if block.property(nested).is_none() {
            let doc = format!("`{nested} {{ ... }}` nested in {}", block.what());
            items.push(item(nested, CompletionItemKind::KEYWORD, "block", doc));
        }
    }
    items
}

/// The values after `key` in `block`.
fn values(block: Block, key: &str, names: &[Declared]) -> Vec<CompletionItem> {
    let choices: &[&str] = match key {
        "normal_green" => v::GREEN_WORDS,
        "wrap" => v::WRAP_WORDS,
        "filter" => v::FILTER_WORDS,
        "encoding" => v::ENCODING_WORDS,
        "tonemap" => v::TONEMAP_WORDS,
        "samples" if block == Block::Render => v::SAMPLE_PATTERN_WORDS,
        "quality" => v::QUALITY_WORDS,
        "rotate" if block == Block::Transform => &["x", "y", "z"],
        _ => &[],
    };
    let ty = block.property(key).map_or("", |p| p.ty);
    if !choices.is_empty() {
        let doc = format!("a choice of `{key}`: {ty}");
        return choices
            .iter()
            .map(|w| item(w, CompletionItemKind::ENUM_MEMBER, key, doc.clone()))
            .collect();
    }
    if ty.contains("`true`") || ty == "boolean" {
        return booleans();
    }
    let kinds = match lsp_block(block).expected(key, 0) {
        Some(Expected::Name(kind)) => vec![kind],
        Some(Expected::ConstantOrTexture) => vec![SymbolKind::Texture, SymbolKind::Constant],
        None => return expression(names),
    };
    let mut items = declared(names, &kinds);
    if kinds.contains(&SymbolKind::Constant) {
        items.extend(functions());
    }
    items
}

/// What an expression may hold: constants, functions, booleans and `frame`.
fn expression(names: &[Declared]) -> Vec<CompletionItem> {
    let mut items = declared(names, &[SymbolKind::Constant]);
    items.extend(functions());
    items.extend(booleans());
    items.push(item(
        "frame",
        CompletionItemKind::CONSTANT,
        "number",
        "the frame being rendered (`scnc render --frame F`), 0 when not animating".into(),
    ));
    items
}

/// At the top level: kinds after `KEYWORD NAME =`, meshes after `object`, else keywords.
fn top_level(cx: &Context<'_>, names: &[Declared]) -> Vec<CompletionItem> {
    let last = cx.before.last().copied().unwrap_or_default();
    if last == "=" {
        let keyword = cx.before.iter().rev().nth(2).copied().unwrap_or_default();
        let kinds: &[&str] = match keyword {
            "material" => v::MATERIAL_KINDS,
            "texture" => v::TEXTURE_KINDS,
            "mesh" => v::MESH_KINDS,
            "light" => v::LIGHT_KINDS,
            _ => &[],
        };
        return kinds
            .iter()
            .filter_map(|k| Block::of_statement(keyword, k).map(|b| (k, b)))
            .map(|(k, b)| {
                let keys: Vec<String> = b.properties().map(|p| format!("`{}`", p.key)).collect();
                let doc = format!("{}; keys: {}", b.what(), keys.join(", "));
                item(k, CompletionItemKind::CLASS, keyword, doc)
            })
            .collect();
    }
    if last == "object" {
        return declared(names, &[SymbolKind::Mesh]);
    }
    let naming = STATEMENT_KEYWORDS.contains(&last) || last == "scnc" || last == "include";
    if naming && !cx.before.is_empty() {
        // A new name or a path is being written.
        return Vec::new();
    }
    STATEMENT_KEYWORDS
        .iter()
        .map(|k| {
            let doc = format!("the `{k}` statement (grammar/README.md, *Statements*)");
            item(k, CompletionItemKind::KEYWORD, "statement", doc)
        })
        .collect()
}

fn declared(names: &[Declared], kinds: &[SymbolKind]) -> Vec<CompletionItem> {
    names
        .iter()
        .filter(|d| kinds.contains(&d.kind))
        .map(|d| {
            item(
                &d.name,
                completion_kind(d.kind),
                d.kind.what(),
                d.summary.clone(),
            )
        })
        .collect()
}

fn functions() -> Vec<CompletionItem> {
    FUNCTIONS
        .iter()
        .filter_map(|f| function_doc(f).map(|d| (f, d)))
        .map(|(f, d)| {
            let doc = format!("{}\n\n{}", d.forms, d.takes);
            item(f, CompletionItemKind::FUNCTION, d.takes, doc)
        })
        .collect()
}

fn units() -> Vec<CompletionItem> {
    v::UNITS
        .iter()
        .map(|u| {
            let doc = unit_doc(u).unwrap_or_default().to_string();
            item(u, CompletionItemKind::UNIT, "unit", doc)
        })
        .collect()
}

fn booleans() -> Vec<CompletionItem> {
    v::BOOLEANS
        .iter()
        .map(|b| item(b, CompletionItemKind::CONSTANT, "boolean", String::new()))
        .collect()
}

/// The symbol index's name for a block kind (it knows which kind of name a key's values name).
fn lsp_block(block: Block) -> BlockKind {
    match block {
        Block::Camera => BlockKind::Camera,
        Block::Transform => BlockKind::Transform,
        Block::Phong => BlockKind::Material,
        Block::ImageTexture => BlockKind::ImageTexture,
        Block::Checker => BlockKind::CheckerTexture,
        Block::ConstantTexture => BlockKind::ConstantTexture,
        Block::ObjMesh => BlockKind::ObjMesh,
        Block::InlineMesh => BlockKind::InlineMesh,
        Block::Sphere => BlockKind::Sphere,
        Block::Icosphere => BlockKind::Icosphere,
        Block::Quad => BlockKind::Quad,
        Block::Box => BlockKind::Box,
        Block::Object => BlockKind::Object,
        Block::Group => BlockKind::Group,
        Block::PointLight => BlockKind::PointLight,
        Block::AreaLight => BlockKind::AreaLight,
        Block::EnvironmentLight => BlockKind::EnvironmentLight,
        Block::Render => BlockKind::Render,
    }
}

fn item(label: &str, kind: CompletionItemKind, detail: &str, doc: String) -> CompletionItem {
    CompletionItem {
        label: label.to_string(),
        kind: Some(kind),
        detail: (!detail.is_empty()).then(|| detail.to_string()),
        documentation: (!doc.is_empty()).then_some(Documentation::MarkupContent(MarkupContent {
            kind: MarkupKind::Markdown,
            value: doc,
        })),
        ..CompletionItem::default()
    }
}
