//! MTL material libraries (stage 3, asset decoding): `newmtl`, `Kd`, `Ks`, `Ns`, `Ka`, `Ke`,
//! `map_Kd`, `map_Ks`, `map_Ns`, `map_Bump`/`bump`/`norm` → [`MtlMaterial`]s. No `.scn` syntax
//! (the `.scn` side is `mesh m = obj("m.obj") { … }`, see `check/mesh.rs`).
//!
//! MTL is a Phong format, so each statement maps onto scnc's Phong material (the mapping itself
//! is in `scene/obj_materials.rs`). Statements scnc cannot honour (`d`, `Tr`, `Ni`, `Tf`,
//! `illum` with reflection or refraction (3 and above), `map_d`, `refl`, PBR extensions …) are
//! collected and reported once per file, with how often each occurs and its first line.
//! Texture statements take options before the file name (`map_Kd -s 2 2 1 -bm 0.5 wood tex.png`):
//! known options are skipped with their arguments (`-bm` is kept), and the rest of the line is the
//! file name, spaces included.

use glam::Vec3;

use super::encoding::decode_name;
use super::lexer::{keyword, strip_comment, tokens, Line, Lines};
use super::number::parse_f32;
use super::{Note, Place};
use crate::diag::Code;

/// A texture named by an MTL statement.
#[derive(Debug, Clone, PartialEq)]
pub struct TexRef {
    /// The file name as written (relative to the MTL file's directory).
    pub file: String,
    /// `-bm` of bump maps (1 when absent).
    pub bump_multiplier: f32,
    /// The statement's line.
    pub at: Place,
}

/// How a bump statement was written: a height map (`bump`, `map_Bump`) or a normal map (`norm`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BumpKind {
    /// Grey heights (`bump`, `map_Bump`).
    Height,
    /// Tangent-space normals (`norm`).
    Normal,
}

/// One `newmtl` block.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MtlMaterial {
    /// The material's name (`usemtl` refers to it).
    pub name: String,
    /// The `newmtl` line.
    pub at: Place,
    /// `Kd`: diffuse colour.
    pub kd: Option<Vec3>,
    /// `Ks`: specular colour.
    pub ks: Option<Vec3>,
    /// `Ka`: ambient colour.
    pub ka: Option<Vec3>,
    /// `Ke`: emitted colour.
    pub ke: Option<Vec3>,
    /// `Ns`: specular exponent.
    pub ns: Option<f32>,
    /// `map_Kd`: diffuse texture.
    pub map_kd: Option<TexRef>,
    /// `map_Ks`: specular texture.
    pub map_ks: Option<TexRef>,
    /// `map_Ns`: exponent texture.
    pub map_ns: Option<TexRef>,
    /// `bump`/`map_Bump`/`norm`: the last one given.
    pub bump: Option<(BumpKind, TexRef)>,
}

/// A parsed library and what it could not honour.
#[derive(Debug, Clone, Default)]
pub struct MtlLibrary {
    /// Every `newmtl`, in file order.
    pub materials: Vec<MtlMaterial>,
    /// What was skipped or guessed.
    pub warnings: Vec<Note>,
}

/// Texture options and how many arguments each takes (`-o`, `-s`, `-t` take one to three).
const TEX_OPTIONS: &[(&[u8], usize)] = &[
    (b"-blendu", 1),
    (b"-blendv", 1),
    (b"-bm", 1),
    (b"-boost", 1),
    (b"-cc", 1),
    (b"-clamp", 1),
    (b"-imfchan", 1),
    (b"-mm", 2),
    (b"-o", 3),
    (b"-s", 3),
    (b"-t", 3),
    (b"-texres", 1),
    (b"-type", 1),
];

/// Parses an MTL file: every `newmtl` with the statements scnc reads, and warnings (never
/// errors: a bad statement is skipped with a note).
pub fn parse_mtl(text: &[u8]) -> MtlLibrary {
    let mut reader = MtlReader::default();
    for line in Lines::new(text) {
        reader.line(&line);
    }
    reader.finish()
}

/// The library read so far and what to warn about at the end.
#[derive(Default)]
struct MtlReader {
    lib: MtlLibrary,
    /// Statements scnc does not render: (word, count, first place).
    unsupported: Vec<(String, usize, Place)>,
    /// The first material name that was not UTF-8.
    latin1: Option<Place>,
    bad: Vec<Note>,
}

impl MtlReader {
    fn line(&mut self, line: &Line) {
        let body = strip_comment(line.text);
        if body.is_empty() {
            return;
        }
        let at = Place::of_line(line, body);
        let (kw, rest) = keyword(body);
        if kw == b"newmtl" {
            let (name, was_latin1) = decode_name(rest);
            if was_latin1 && self.latin1.is_none() {
                self.latin1 = Some(at);
            }
            self.lib.materials.push(MtlMaterial {
                name,
                at,
                ..MtlMaterial::default()
            });
            return;
        }
        let Some(m) = self.lib.materials.last_mut() else {
            self.bad.push(Note::warning(
                Code::ObjMtlOutsideMaterial,
                "this statement comes before any `newmtl` and is ignored",
                at,
            ));
            return;
        };
        match statement(m, kw, rest, at) {
            Statement::Read => {}
            Statement::Unsupported => self.count_unsupported(kw, rest, at),
            Statement::Malformed => self.bad.push(
                Note::warning(
                    Code::ObjBadMtlStatement,
                    format!(
                        "cannot read this `{}` statement; it is ignored",
                        decode_name(kw).0
                    ),
                    at,
                )
                .help("colours are `Kd r g b` (or one grey value), `Ns` one number, maps `map_Kd [options] file`"),
            ),
        }
    }

    fn count_unsupported(&mut self, kw: &[u8], rest: &[u8], at: Place) {
        let word = if kw == b"illum" {
            format!("illum {}", decode_name(rest).0)
        } else {
            decode_name(kw).0
        };
        match self.unsupported.iter_mut().find(|(w, _, _)| *w == word) {
            Some((_, n, _)) => *n += 1,
            None => self.unsupported.push((word, 1, at)),
        }
    }

    fn finish(mut self) -> MtlLibrary {
        if let Some(at) = self.latin1 {
            self.lib.warnings.push(latin1_note(at));
        }
        self.lib.warnings.extend(self.bad);
        if let Some((_, _, first)) = self.unsupported.first() {
            let list = super::report::unsupported_list(&self.unsupported);
            self.lib.warnings.push(
                Note::warning(
                    Code::ObjUnsupportedMtl,
                    format!("MTL statements scnc does not render were ignored: {}", list),
                    *first,
                )
                .help("scnc renders Kd, Ks, Ns, Ka, Ke and their maps; transparency, refraction and mirror reflection are not modelled"),
            );
        }
        self.lib
    }
}

/// What became of one statement inside a material.
enum Statement {
    Read,
    Malformed,
    Unsupported,
}

/// Reads `kw rest` into `m`.
fn statement(m: &mut MtlMaterial, kw: &[u8], rest: &[u8], at: Place) -> Statement {
    let read = match kw {
        b"Kd" => color(rest).map(|c| m.kd = Some(c)),
        b"Ks" => color(rest).map(|c| m.ks = Some(c)),
        b"Ka" => color(rest).map(|c| m.ka = Some(c)),
        b"Ke" => color(rest).map(|c| m.ke = Some(c)),
        b"Ns" => parse_f32(rest).map(|n| m.ns = Some(n)),
        b"map_Kd" => texture(rest, at).map(|t| m.map_kd = Some(t)),
        b"map_Ks" => texture(rest, at).map(|t| m.map_ks = Some(t)),
        b"map_Ns" => texture(rest, at).map(|t| m.map_ns = Some(t)),
        b"map_Bump" | b"map_bump" | b"bump" => {
            texture(rest, at).map(|t| m.bump = Some((BumpKind::Height, t)))
        }
        b"norm" | b"map_norm" => texture(rest, at).map(|t| m.bump = Some((BumpKind::Normal, t))),
        b"illum" if matches!(rest, b"0" | b"1" | b"2") => Some(()),
        _ => return Statement::Unsupported,
    };
    match read {
        Some(()) => Statement::Read,
        None => Statement::Malformed,
    }
}

/// `r g b` or one grey value.
fn color(rest: &[u8]) -> Option<Vec3> {
    let v: Vec<f32> = tokens(rest).map(parse_f32).collect::<Option<_>>()?;
    match v[..] {
        [r] => Some(Vec3::splat(r)),
        [r, g, b] => Some(Vec3::new(r, g, b)),
        _ => None,
    }
}

/// The note for names that were not UTF-8 and were read as Latin-1.
pub fn latin1_note(at: Place) -> Note {
    Note::warning(
        Code::ObjNotUtf8,
        "this file is not valid UTF-8; its names were read as Latin-1",
        at,
    )
    .help("re-save the file as UTF-8 if a name looks wrong")
}

/// `[options] file name with spaces` → the file and `-bm`.
fn texture(rest: &[u8], at: Place) -> Option<TexRef> {
    let mut bump_multiplier = 1.0;
    let mut r = rest;
    loop {
        let (word, after) = keyword(r);
        let Some(&(_, max)) = TEX_OPTIONS.iter().find(|(o, _)| *o == word) else {
            break;
        };
        r = after;
        for k in 0..max {
            let (arg, after) = keyword(r);
            // `-o`, `-s`, `-t` take one to three numbers; `-clamp on`, `-imfchan r` take a word.
            let numeric = parse_f32(arg).is_some();
            if arg.is_empty() || (k > 0 && !numeric) {
                break;
            }
            if word == b"-bm" {
                bump_multiplier = parse_f32(arg).unwrap_or(1.0);
            }
            r = after;
        }
    }
    if r.is_empty() {
        return None;
    }
    Some(TexRef {
        file: decode_name(r).0,
        bump_multiplier,
        at,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phong_statements_and_maps() {
        let lib = parse_mtl(
            b"# c\nnewmtl roof tiles\nKd 0.5 0.25 1\nKs 0.1\nNs 32\nKe 0 0 0\n\
              map_Kd -s 2 2 1 -clamp on my tex.png\nbump -bm 0.3 h.png\nd 0.5\nd 1\nillum 2\nillum 4\n",
        );
        let m = &lib.materials[0];
        assert_eq!(m.name, "roof tiles");
        assert_eq!(m.kd, Some(Vec3::new(0.5, 0.25, 1.0)));
        assert_eq!(m.ks, Some(Vec3::splat(0.1)));
        assert_eq!(m.ns, Some(32.0));
        assert_eq!(
            m.map_kd.as_ref().map(|t| t.file.as_str()),
            Some("my tex.png")
        );
        let (kind, bump) = m.bump.clone().expect("bump");
        assert_eq!(
            (kind, bump.bump_multiplier, bump.file.as_str()),
            (BumpKind::Height, 0.3, "h.png")
        );
        assert_eq!(lib.warnings.len(), 1, "{:?}", lib.warnings);
        let w = &lib.warnings[0].message;
        assert!(
            w.contains("`d` (2×, first on line 9)") && w.contains("`illum 4` (line 12)"),
            "{w}"
        );
    }

    #[test]
    fn bad_and_orphan_statements_warn_at_their_line() {
        let lib = parse_mtl(b"Kd 1 1 1\nnewmtl a\nKd x y z\nmap_Kd\n");
        let lines: Vec<u32> = lib.warnings.iter().map(|w| w.at.line).collect();
        assert_eq!(lines, vec![1, 3, 4]);
    }
}
