//! Language server: semantic tokens (full document), so that an editor colours every name by
//! what it names, whatever its grammar knows.
//!
//! The text is cut into tokens by the formatter's comment-keeping scan ([`tokenize`]); each is
//! classified by the document's [`SymbolIndex`] (names by kind, with the `declaration` modifier
//! where declared; keys, kinds, functions, words), else by its spelling (keywords, numbers with
//! their unit, `#hex` colours, strings, comments). Block comments over several lines are one
//! token per line, as clients without multi-line token support need. Columns are UTF-16.
//!
//! | token type    | what                                   |
//! |---------------|----------------------------------------|
//! | `variable`    | constant (`let`), modifier `readonly`  |
//! | `struct`      | material                               |
//! | `typeParameter` | texture                              |
//! | `class`       | mesh                                   |
//! | `event`       | light                                  |
//! | `interface`   | camera                                 |
//! | `namespace`   | group                                  |
//! | `property`    | a block's key (`diffuse`)              |
//! | `type`        | a declaration's kind (`phong`)         |
//! | `function`    | a built-in function, `defaultLibrary`  |
//! | `enumMember`  | a word value (`repeat`, `true`)        |
//! | `keyword`, `number`, `string`, `comment` | as spelled  |

use std::path::Path;

use lsp_types::{
    SemanticToken, SemanticTokenModifier as Modifier, SemanticTokenType as Type, SemanticTokens,
    SemanticTokensLegend,
};

use super::documents::Documents;
use super::position::LineIndex;
use super::symbols::{Role, SymbolIndex, SymbolKind};
use crate::fmt::tokens::{tokenize, Token, TokenKind};
use crate::source::FileId;

/// The token types, in legend order (a token's type is its index here).
const TYPES: [Type; 15] = [
    Type::VARIABLE,
    Type::STRUCT,
    Type::TYPE_PARAMETER,
    Type::CLASS,
    Type::EVENT,
    Type::INTERFACE,
    Type::NAMESPACE,
    Type::PROPERTY,
    Type::TYPE,
    Type::FUNCTION,
    Type::ENUM_MEMBER,
    Type::KEYWORD,
    Type::NUMBER,
    Type::STRING,
    Type::COMMENT,
];
/// The modifiers, in legend order (bit `i` of a token's set is modifier `i`).
const MODIFIERS: [Modifier; 3] = [
    Modifier::DECLARATION,
    Modifier::READONLY,
    Modifier::DEFAULT_LIBRARY,
];
const DECLARATION: u32 = 1;
const READONLY: u32 = 2;
const DEFAULT_LIBRARY: u32 = 4;

/// The legend announced in the server's capabilities.
pub fn legend() -> SemanticTokensLegend {
    SemanticTokensLegend {
        token_types: TYPES.to_vec(),
        token_modifiers: MODIFIERS.to_vec(),
    }
}

fn type_index(t: &Type) -> u32 {
    TYPES.iter().position(|x| x == t).unwrap_or(0) as u32
}

/// The semantic tokens of the document at `path` (its editor text when open).
pub fn tokens(documents: &Documents, path: &Path) -> SemanticTokens {
    let index = SymbolIndex::build(path, &documents.loader());
    let Some(file) = index.file(path) else {
        return SemanticTokens::default();
    };
    let text = index.sources().get(file).text.clone();
    let lines = LineIndex::new(&text);
    let mut out = Encoder::default();
    for token in tokenize(&text) {
        match token.kind {
            TokenKind::BlockComment => {
                let mut start = token.start;
                for part in token.text.split_inclusive('\n') {
                    let piece = part.trim_end_matches(['\n', '\r']);
                    out.push(&lines, start, piece, &Type::COMMENT, 0);
                    start += part.len();
                }
            }
            _ => {
                if let Some((t, modifiers)) = classify(&index, file, &token) {
                    out.push(&lines, token.start, token.text, &t, modifiers);
                }
            }
        }
    }
    SemanticTokens {
        result_id: None,
        data: out.data,
    }
}

/// The type and modifiers of a one-line token, if it gets one.
fn classify(index: &SymbolIndex, file: FileId, token: &Token<'_>) -> Option<(Type, u32)> {
    let first = token.text.bytes().next()?;
    match token.kind {
        TokenKind::LineComment | TokenKind::BlockComment => return Some((Type::COMMENT, 0)),
        TokenKind::Str => return Some((Type::STRING, 0)),
        TokenKind::Array | TokenKind::Punct(_) => return None,
        TokenKind::Word => {}
    }
    if first.is_ascii_digit() || first == b'.' || first == b'#' {
        return Some((Type::NUMBER, 0));
    }
    if let Some(o) = index.at(file, token.start) {
        if o.span.start as usize == token.start {
            let declared = if o.declaration { DECLARATION } else { 0 };
            let (t, readonly) = match index.symbol(o.symbol).kind {
                SymbolKind::Constant => (Type::VARIABLE, READONLY),
                SymbolKind::Material => (Type::STRUCT, 0),
                SymbolKind::Texture => (Type::TYPE_PARAMETER, 0),
                SymbolKind::Mesh => (Type::CLASS, 0),
                SymbolKind::Light => (Type::EVENT, 0),
                SymbolKind::Camera => (Type::INTERFACE, 0),
                SymbolKind::Group => (Type::NAMESPACE, 0),
            };
            return Some((t, declared | readonly));
        }
    }
    if let Some(m) = index.mark_at(file, token.start) {
        if m.span.start as usize == token.start {
            return Some(match m.role {
                Role::Key => (Type::PROPERTY, 0),
                Role::Kind => (Type::TYPE, 0),
                Role::Function => (Type::FUNCTION, DEFAULT_LIBRARY),
                Role::Word => (Type::ENUM_MEMBER, 0),
            });
        }
    }
    super::blocks::is_keyword(token.text).then_some((Type::KEYWORD, 0))
}

/// Encodes tokens as the protocol's relative (line, start) deltas.
#[derive(Default)]
struct Encoder {
    data: Vec<SemanticToken>,
    line: u32,
    column: u32,
}

impl Encoder {
    fn push(&mut self, lines: &LineIndex<'_>, start: usize, text: &str, t: &Type, modifiers: u32) {
        let length: usize = text.chars().map(char::len_utf16).sum();
        if length == 0 {
            return;
        }
        let at = lines.position(start);
        let delta_line = at.line - self.line;
        let delta_start = if delta_line == 0 {
            at.character - self.column
        } else {
            at.character
        };
        self.data.push(SemanticToken {
            delta_line,
            delta_start,
            length: length as u32,
            token_type: type_index(t),
            token_modifiers_bitset: modifiers,
        });
        (self.line, self.column) = (at.line, at.character);
    }
}
