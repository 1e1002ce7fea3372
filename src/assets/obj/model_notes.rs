//! The warnings an OBJ parse gives once, at the end (stage 3, asset decoding): the parser only
//! remembers the first place of each kind of problem (a Latin-1 name, skipped `l`/`p` elements,
//! a fanned polygon, statements it does not read), so a file with a million of them costs one
//! warning, not a million. No `.scn` syntax.

use super::encoding::Encoding;
use super::mtl::latin1_note;
use super::{Note, ObjModel, Place};
use crate::diag::Code;

/// What the parser saw that earns one warning at the end: the first place of each kind.
#[derive(Debug, Default)]
pub(super) struct Seen {
    /// The first `l` or `p` statement (all of them are counted in `ObjStats::lines_and_points`).
    pub(super) first_skipped: Option<Place>,
    /// The first name that was not UTF-8 and was read as Latin-1.
    pub(super) latin1: Option<Place>,
    /// The first polygon triangulated as a fan.
    pub(super) fanned: Option<Place>,
    /// Statements not read: keyword, how many times, first place (at most 32 keywords).
    pub(super) unsupported: Vec<(String, usize, Place)>,
}

impl Seen {
    /// Counts a statement the parser does not read; keywords past the 32nd are not listed.
    pub(super) fn unsupported_statement(&mut self, word: String, at: Place) {
        let full = self.unsupported.len() >= 32;
        match self.unsupported.iter_mut().find(|(w, _, _)| *w == word) {
            Some((_, n, _)) => *n += 1,
            None if !full => self.unsupported.push((word, 1, at)),
            None => {}
        }
    }

    /// Appends the end-of-file warnings to `m.warnings`.
    pub(super) fn notes(&self, m: &mut ObjModel) {
        if m.encoding != Encoding::Utf8 {
            m.warnings.push(
                Note::warning(
                    Code::ObjUtf16,
                    format!("this file is {}; it was transcoded", m.encoding.name()),
                    Place {
                        line: 1,
                        start: 0,
                        end: 0,
                    },
                )
                .help("OBJ files are normally ASCII or UTF-8"),
            );
        }
        if let Some(at) = self.latin1 {
            m.warnings.push(latin1_note(at));
        }
        if let Some(at) = self.first_skipped {
            m.warnings.push(
                Note::warning(
                    Code::ObjLinesSkipped,
                    format!(
                    "{} line (`l`) and point (`p`) elements skipped: only faces become surfaces",
                    m.stats.lines_and_points
                ),
                    at,
                )
                .help("convert polylines to faces (or tubes) in the modelling tool to render them"),
            );
        }
        if let Some(at) = self.fanned {
            m.warnings.push(Note::warning(
            Code::ObjPolygonFanned,
            format!(
                "a face with more than {} corners was triangulated as a fan (correct only if it is convex)",
                super::polygon::EAR_CLIP_MAX
            ),
            at,
        ));
        }
        if let Some((_, _, first)) = self.unsupported.first() {
            let list = super::report::unsupported_list(&self.unsupported);
            m.warnings.push(
            Note::warning(
                Code::ObjUnsupportedStatement,
                format!("OBJ statements scnc does not read were ignored: {}", list),
                *first,
            )
            .help("scnc reads polygonal faces (v, vt, vn, f) with their materials; curves and surfaces are not tessellated"),
        );
        }
    }
}
