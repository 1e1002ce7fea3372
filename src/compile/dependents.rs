//! The incremental compile's look-up of what names something: the top-level statements of the
//! new text in which a name occurs as a whole word (letters, digits and `_` on neither side),
//! each parsed alone, for [`crate::check::CheckMemo::recheck_decls`] to check again those
//! that name a constant whose value an edit changed.
//!
//! A text search (memchr's `memmem`, some GB/s) instead of a record of every statement's
//! names: it costs a few milliseconds on the 8.8 MB scene of issue 22, keeps no index between
//! edits, and can only find too much (the word in a comment or a string), never too little.
//! A statement parsed from its start to the next statement's start parses as in the whole
//! file (`edit.rs`).

use std::borrow::Cow;

use crate::source::FileId;
use crate::syntax::{self, Stmt};

/// One scene file as the search sees it: its text, its statements' byte ranges in order, and
/// their indices in the check's statement list (`None`: the same, the scene being one file).
pub(super) struct FileText<'a> {
    pub file: FileId,
    pub text: &'a str,
    pub spans: Cow<'a, [(u32, u32)]>,
    pub list: Option<Vec<usize>>,
}

/// The scene's files as the re-check reads them ([`crate::check::Dependents`]): what names a
/// name, and a statement by its index in the list.
pub(super) struct SceneStatements<'a>(pub Vec<FileText<'a>>);

impl crate::check::Dependents for SceneStatements<'_> {
    fn naming(&mut self, name: &str) -> Option<Vec<(usize, Stmt)>> {
        naming(&self.0, name)
    }

    fn statement(&mut self, i: usize) -> Option<Stmt> {
        for f in &self.0 {
            let at = match &f.list {
                Some(list) => list.binary_search(&i).ok(),
                None => Some(i),
            };
            if let Some(at) = at {
                return parse_one(f.file, f.text, &f.spans, at);
            }
        }
        None
    }
}

/// The statements of the scene's `files` in which `name` occurs as a word: index in the
/// statement list and statement, in list order; `None` when one of them does not parse alone
/// into one statement.
pub(super) fn naming(files: &[FileText], name: &str) -> Option<Vec<(usize, Stmt)>> {
    let mut found = Vec::new();
    for f in files {
        for i in statements_naming(f.text, &f.spans, name) {
            let at = match &f.list {
                Some(list) => *list.get(i)?,
                None => i,
            };
            found.push((at, parse_one(f.file, f.text, &f.spans, i)?));
        }
    }
    if files.len() > 1 {
        found.sort_by_key(|&(i, _)| i);
    }
    Some(found)
}

/// The indices of the statements of `text` (at `spans`) in which `name` occurs as a word, in
/// order, not parsed.
pub(super) fn statements_naming(text: &str, spans: &[(u32, u32)], name: &str) -> Vec<usize> {
    let bytes = text.as_bytes();
    let word = |b: Option<&u8>| b.is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_');
    let mut found: Vec<usize> = Vec::new();
    for at in memchr::memmem::find_iter(bytes, name.as_bytes()) {
        let before = at.checked_sub(1).and_then(|i| bytes.get(i));
        if word(before) || word(bytes.get(at + name.len())) {
            continue;
        }
        let i = spans.partition_point(|&(_, end)| end as usize <= at);
        let inside = spans.get(i).is_some_and(|&(start, _)| start as usize <= at);
        if inside && found.last() != Some(&i) {
            found.push(i);
        }
    }
    found
}

/// Top-level statement `i` of `text` (the file `file`), parsed alone.
fn parse_one(file: FileId, text: &str, spans: &[(u32, u32)], i: usize) -> Option<Stmt> {
    let start = spans.get(i)?.0 as usize;
    let end = spans.get(i + 1).map_or(text.len(), |&(s, _)| s as usize);
    let mut parsed = syntax::parse_region(file, text, start, end)?;
    match parsed.len() {
        1 => parsed.pop(),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::edit::tests::spans_of;
    use super::*;

    #[test]
    fn finds_the_statements_that_name_a_word_and_no_others() {
        let text = "scnc 1\nlet k = 2\nlet kk = k * 2\n// k in a comment\nlet j = kk\n\
                    object box { transform { translate (k, 0, 0) } }\n";
        let files = [FileText {
            file: FileId(0),
            text,
            spans: Cow::Owned(spans_of(text)),
            list: None,
        }];
        let found: Vec<usize> = naming(&files, "k")
            .expect("parses")
            .into_iter()
            .map(|(i, _)| i)
            .collect();
        assert_eq!(found, vec![1, 2, 4]);
        let found = naming(&files, "kk").expect("parses");
        assert_eq!(found.len(), 2);
        assert!(matches!(&found[1].1, Stmt::Let { name, .. } if name.name == "j"));
    }
}
