//! Language server: go to definition, find references, and rename (with prepareRename) of
//! declared names, across includes ([`Workspace`]). A rename edits every file the name is
//! written in, and is refused, saying why, when the new name is no identifier, is a keyword or
//! reserved word, is already declared in the same name space, would be shadowed by a constant
//! (or shadow a texture) where a material reads it, or is a key of a block that uses the name.

use std::collections::HashMap;
use std::path::Path;

use lsp_types::{Location, Position, PrepareRenameResponse, TextEdit, Url, WorkspaceEdit};

use super::documents::Documents;
use super::symbols::SymbolKind;
use super::workspace::{Place, SymbolKey, Workspace};

/// Where the name at `position` of the document at `path` is declared.
pub fn definition(documents: &Documents, path: &Path, position: Position) -> Option<Location> {
    let workspace = Workspace::around(documents, path);
    let (key, _) = workspace.at(position)?;
    workspace.declaration(&key)?.location()
}

/// Every place the name at `position` is written, declarations only if `declarations`.
pub fn references(
    documents: &Documents,
    path: &Path,
    position: Position,
    declarations: bool,
) -> Option<Vec<Location>> {
    let workspace = Workspace::around(documents, path);
    let (key, _) = workspace.at(position)?;
    Some(
        workspace
            .places(&key)
            .iter()
            .filter(|p| declarations || !p.declaration)
            .filter_map(Place::location)
            .collect(),
    )
}

/// The range of the name at `position` and the name, when it can be renamed.
pub fn prepare_rename(
    documents: &Documents,
    path: &Path,
    position: Position,
) -> Option<PrepareRenameResponse> {
    let workspace = Workspace::around(documents, path);
    let (_, place) = workspace.at(position)?;
    Some(PrepareRenameResponse::RangeWithPlaceholder {
        range: place.range(),
        placeholder: place.text.get(place.span.range())?.to_string(),
    })
}

/// The edits renaming the name at `position` to `new_name` in every file, or why not.
pub fn rename(
    documents: &Documents,
    path: &Path,
    position: Position,
    new_name: &str,
) -> Result<WorkspaceEdit, String> {
    let workspace = Workspace::around(documents, path);
    let (key, _) = workspace
        .at(position)
        .ok_or("there is no declared name here to rename")?;
    let places = workspace.places(&key);
    refusal(&workspace, &key, &places, new_name).map_or(Ok(()), Err)?;
    let mut changes: HashMap<Url, Vec<TextEdit>> = HashMap::new();
    for place in &places {
        if let Some(location) = place.location() {
            changes
                .entry(location.uri)
                .or_default()
                .push(TextEdit::new(location.range, new_name.to_string()));
        }
    }
    Ok(WorkspaceEdit::new(changes))
}

/// Why `new` cannot replace the name of `key` (written at `places`), if it cannot.
fn refusal(workspace: &Workspace, key: &SymbolKey, places: &[Place], new: &str) -> Option<String> {
    let kind = key.kind.what();
    if !is_identifier(new) {
        return Some(format!(
            "`{new}` is not a name: a name is a letter or `_` followed by letters, digits or `_`"
        ));
    }
    if super::blocks::is_keyword(new) {
        return Some(format!("`{new}` is a keyword of the language"));
    }
    if key.kind == SymbolKind::Constant && matches!(new, "true" | "false" | "frame") {
        return Some(format!("`{new}` is a reserved word"));
    }
    let old = places
        .iter()
        .find(|p| p.declaration && p.span.start == key.start);
    let same = old.and_then(|p| p.text.get(p.span.range())) == Some(new);
    if same {
        return None;
    }
    if let Some(taken) = workspace.declared(key.kind, new) {
        return Some(format!("{kind} `{new}` is already declared{}", at(&taken)));
    }
    let rival = match key.kind {
        SymbolKind::Constant => Some(SymbolKind::Texture),
        SymbolKind::Texture => Some(SymbolKind::Constant),
        _ => None,
    };
    if let Some(taken) = rival.and_then(|r| workspace.declared(r, new)) {
        return Some(format!(
            "{} `{new}` is declared{}: where a material names a texture, a constant of the same \
             name is read instead",
            rival.map_or("", SymbolKind::what),
            at(&taken)
        ));
    }
    let used_as_key = places
        .iter()
        .filter_map(|p| p.block)
        .find(|b| b.keys().contains(&new));
    if used_as_key.is_some() {
        return Some(format!(
            "`{new}` is a key of a block that uses this {kind}: it would be read as the key"
        ));
    }
    None
}

/// ` at FILE:LINE` for a declaration (lines from 1).
fn at(place: &Place) -> String {
    let line = place.range().start.line + 1;
    let file = place.path.file_name().map_or_else(
        || place.path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    format!(" at {file}:{line}")
}

/// Whether `name` is an identifier of the grammar (`[A-Za-z_][A-Za-z0-9_]*`).
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}
