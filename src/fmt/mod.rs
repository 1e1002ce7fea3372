//! Beside the pipeline, on stage 1 (syntax): `scnc fmt` formats `.scn` text canonically.
//!
//! `.scn` text → the same text laid out in the examples' style, every comment kept. The text is
//! parsed first ([`crate::syntax::parse`]): a file with syntax errors is not formatted, and its
//! diagnostics are the result. A file that parses is scanned into tokens with comments
//! ([`tokens`]) and laid out ([`layout`], which documents the rules); only whitespace between
//! tokens changes, so the formatted file means the same (its IR equals the original's, a test
//! over every example and test scene), and formatting twice changes nothing.
//!
//! ```text
//! let red=rgb(0.63,0.065,0.05)        let red = rgb(0.63, 0.065, 0.05)
//! material m = phong {diffuse red     material m = phong {
//!     specular 0 }            ──▶       diffuse red
//!                                       specular 0
//!                                     }
//! ```

pub mod layout;
pub mod tokens;

use crate::diag::Staged;
use crate::source::FileId;
use crate::syntax;

/// Formats `text` (file `file`, for the spans of its diagnostics): the formatted text, or no
/// value and the syntax errors when it does not parse.
pub fn format(file: FileId, text: &str) -> Staged<String> {
    let (parsed, diagnostics) = syntax::parse(file, text).into_parts();
    if diagnostics.iter().any(|d| d.is_error()) {
        return Staged::new(None, diagnostics);
    }
    let mut statement_starts: Vec<usize> = parsed
        .map(|p| {
            p.statements
                .iter()
                .map(|s| s.span().start as usize)
                .collect()
        })
        .unwrap_or_default();
    statement_starts.sort_unstable();
    let tokens = tokens::tokenize(text);
    Staged::new(
        Some(layout::layout(text, &tokens, &statement_starts)),
        diagnostics,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(text: &str) -> String {
        match format(FileId(0), text).value {
            Some(t) => t,
            None => panic!("does not parse: {text}"),
        }
    }

    #[test]
    fn blocks_on_one_line_stay_on_one_line() {
        assert_eq!(
            fmt("scnc 1\nmaterial m=phong{diffuse (1,1,1)  specular 0}"),
            "scnc 1\nmaterial m = phong { diffuse (1, 1, 1)  specular 0 }\n"
        );
    }

    #[test]
    fn multi_line_blocks_open_and_close_lines() {
        assert_eq!(
            fmt("scnc 1 let a = 1\n\n\n\nobject o { // the o\n\n  mesh m\n    material x }"),
            "scnc 1\nlet a = 1\n\nobject o { // the o\n  mesh m\n  material x\n}\n"
        );
    }

    #[test]
    fn calls_and_signs_keep_their_gluing() {
        assert_eq!(
            fmt("scnc 1\nlet a = rgb( 1 ,2,3 )\nlet c = -a-1 - -2"),
            "scnc 1\nlet a = rgb(1, 2, 3)\nlet c = -a-1 - -2\n"
        );
    }

    #[test]
    fn syntax_errors_are_not_formatted() {
        let formatted = format(FileId(0), "scnc 1\nobject o {");
        assert!(formatted.value.is_none());
        assert!(formatted.has_errors());
    }
}
