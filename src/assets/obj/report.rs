//! OBJ/MTL problems as [`Diagnostic`]s with both places (stage 3, asset decoding → diagnostics):
//! the line of the OBJ or MTL file, with a snippet, and the `.scn` span that named the file
//! (`mesh m = obj("m.obj")`); `scnc inspect` has no `.scn` and shows the file's line alone.

use std::path::Path;

use super::load::{FileRef, LoadedObj};
use super::{Note, ObjError, Place};
use crate::diag::{Diagnostic, ExternalLabel};
use crate::source::Span;

/// The line around `at` in `text`, as a label.
pub fn line_label(file: &str, text: &[u8], at: Place, message: &str) -> ExternalLabel {
    let start = at.start.min(text.len());
    let line_start = text[..start]
        .iter()
        .rposition(|&c| c == b'\n' || c == b'\r')
        .map_or(0, |i| i + 1);
    // Long lines are cut: a diagnostic shows at most a few hundred bytes of context.
    let line_end = memchr::memchr2(b'\n', b'\r', &text[start..])
        .map_or(text.len(), |i| start + i)
        .min(line_start + 400);
    let raw = &text[line_start..line_end.max(start)];
    let (line_text, _) = super::encoding::decode_name(raw);
    // Column offsets are in bytes of the decoded text; Latin-1 bytes grow when decoded, so
    // recompute from the decoded prefix.
    let prefix = super::encoding::decode_name(&raw[..start - line_start])
        .0
        .len();
    let len = super::encoding::decode_name(&text[start..at.end.clamp(start, line_end.max(start))])
        .0
        .len();
    ExternalLabel {
        file: file.to_string(),
        line: at.line,
        text: line_text,
        start: prefix as u32,
        end: (prefix + len) as u32,
        message: message.to_string(),
    }
}

/// The display name of an OBJ's library: beside the OBJ as the `.scn` wrote it.
pub fn mtl_display_name(obj_written: &str, mtl_written: &str) -> String {
    match Path::new(obj_written).parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(mtl_written).display().to_string(),
        _ => mtl_written.to_string(),
    }
}

/// A fatal OBJ error: an error diagnostic at its line (and at `scn`, if any).
pub fn error_diagnostic(
    e: &ObjError,
    obj_written: &str,
    text: &[u8],
    scn: Option<Span>,
) -> Diagnostic {
    let mut d = Diagnostic::error(
        e.code,
        format!("`{obj_written}` cannot be loaded: {}", e.message),
    )
    .in_file(line_label(obj_written, text, e.at, "here"));
    if let Some(span) = scn {
        d = d.at(span, "the OBJ file named here");
    }
    if let Some(h) = &e.help {
        d = d.help(h.clone());
    }
    d
}

/// Every warning of a loaded OBJ as a diagnostic.
pub fn warning_diagnostics(
    obj: &LoadedObj,
    obj_written: &str,
    scn: Option<Span>,
) -> Vec<Diagnostic> {
    obj.warnings
        .iter()
        .map(|(file, note)| note_diagnostic(obj, *file, note, obj_written, scn))
        .collect()
}

fn note_diagnostic(
    obj: &LoadedObj,
    file: FileRef,
    note: &Note,
    obj_written: &str,
    scn: Option<Span>,
) -> Diagnostic {
    let (name, text): (String, &[u8]) = match file {
        FileRef::Obj => (obj_written.to_string(), &obj.text),
        FileRef::Mtl(i) => match obj.mtls.get(i) {
            Some(m) => (mtl_display_name(obj_written, &m.written), &m.text),
            None => (obj_written.to_string(), &obj.text),
        },
    };
    let mut d = Diagnostic::warning(note.code, note.message.clone())
        .in_file(line_label(&name, text, note.at, "here"));
    if let Some(span) = scn {
        d = d.at(span, "the OBJ file named here");
    }
    if let Some(h) = &note.help {
        d = d.help(h.clone());
    }
    d
}

/// The statements an OBJ or MTL file used that scnc ignores, for one warning: each keyword
/// with its count and first line, e.g. "`s` (12×, first on line 4), `mg` (line 9)".
pub fn unsupported_list(unsupported: &[(String, usize, Place)]) -> String {
    unsupported
        .iter()
        .map(|(w, n, at)| match n {
            1 => format!("`{w}` (line {})", at.line),
            _ => format!("`{w}` ({n}×, first on line {})", at.line),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_cut_the_line_and_handle_latin1() {
        let text = b"v 1 2 3\r\nusemtl b\xe6r\nf 1 2 3";
        let at = Place {
            line: 2,
            start: 9,
            end: 19,
        };
        let l = line_label("m.obj", text, at, "here");
        assert_eq!((l.text.as_str(), l.start, l.end), ("usemtl bær", 0, 11));
        let last = Place {
            line: 3,
            start: 20,
            end: 27,
        };
        assert_eq!(line_label("m.obj", text, last, "").text, "f 1 2 3");
        assert_eq!(
            mtl_display_name("meshes/a.obj", "a b.mtl"),
            "meshes/a b.mtl"
        );
    }
}
