//! Tree-sitter grammar for scnc scene files (`.scn`): the generated parser and the queries.
//!
//! ```ignore
//! let mut parser = tree_sitter::Parser::new();
//! parser.set_language(&tree_sitter_scn::LANGUAGE.into())?;
//! let tree = parser.parse("scnc 1", None);
//! ```

use tree_sitter_language::LanguageFn;

extern "C" {
    fn tree_sitter_scn() -> *const ();
}

/// The tree-sitter language of `.scn` files.
// SAFETY: `tree_sitter_scn` is the generated parser's constructor, which takes no arguments and
// returns a pointer to a static `TSLanguage`.
pub const LANGUAGE: LanguageFn = unsafe { LanguageFn::from_raw(tree_sitter_scn) };

/// Syntax highlighting (standard capture names).
pub const HIGHLIGHTS_QUERY: &str = include_str!("../../queries/highlights.scm");
/// Code folding.
pub const FOLDS_QUERY: &str = include_str!("../../queries/folds.scm");
/// Indentation (nvim-treesitter capture names).
pub const INDENTS_QUERY: &str = include_str!("../../queries/indents.scm");
/// The node types of the grammar, as JSON.
pub const NODE_TYPES: &str = include_str!("../../src/node-types.json");
