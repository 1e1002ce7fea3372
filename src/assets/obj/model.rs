//! OBJ statements → [`ObjModel`] (stage 3, asset decoding). No `.scn` syntax.
//!
//! Read: `v x y z [w | r g b]` (vertex colours after the position are accepted and ignored),
//! `vt u [v [w]]`, `vn x y z`, `f` with `v`, `v/t`, `v//n`, `v/t/n` corners (negative indices
//! count back from the last element read), `usemtl`, `mtllib` (anywhere, names with spaces kept
//! whole: the loader decides between one name with spaces and several names), `o`/`g`/`s`
//! (accepted; groups do not split the mesh). `l` and `p` are skipped and counted in one
//! warning; every other statement (free-form curves and surfaces, `vp`, …) is listed once.
//!
//! Single indexing without a hash of every corner: vertex `i` is position `i` with the first
//! `(vt, vn)` pair a face used it with; only corners that pair a position with a *different*
//! `(vt, vn)` get an extra vertex (looked up in a small map), appended after the positions at the
//! end. A file whose faces use `v`, `v//v` or `v/v/v` consistently (nearly all) keeps exactly one
//! position array, grown in place: memory is the mesh plus 8 bytes per position while parsing.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::encoding::{decode_name, to_utf8_bytes, Encoding};
use super::lexer::{continues, keyword, strip_comment, tokens, Line, Lines};
use super::model_notes::Seen;
use super::normals::fill_missing_normals;
use super::number::{parse_f32, parse_index};
use super::polygon::{triangulate, Scratch};
use super::polygon_check::PolygonWarnings;
use super::{Note, ObjError, Place};
use crate::diag::Code;

/// Triangles `start..` (up to the next run) use material `name` (`None`: before any `usemtl`).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialRun {
    /// Index of the run's first triangle in [`ObjModel::triangles`].
    pub start: usize,
    /// The `usemtl` name; `None` before any `usemtl`.
    pub name: Option<String>,
    /// The `usemtl` line.
    pub at: Option<Place>,
}

/// Counts for `scnc inspect`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObjStats {
    /// `v` statements read.
    pub positions: usize,
    /// `vn` statements read.
    pub normals: usize,
    /// `vt` statements read.
    pub uvs: usize,
    /// `f` statements read (polygons, before triangulation).
    pub faces: usize,
    /// `l` and `p` statements, skipped.
    pub lines_and_points: usize,
    /// Triangles dropped for zero area or a non-finite corner.
    pub degenerate_dropped: usize,
    /// `o` and `g` statements (accepted; they do not split the mesh).
    pub groups: usize,
}

/// A decoded OBJ file: single-indexed triangles (object space), normals and UVs one per vertex
/// or empty, material runs in triangle order.
#[derive(Debug, Clone, Default)]
pub struct ObjModel {
    /// Vertex positions, object space: the file's `v`s, then a copy of each one a face used with a
    /// second `(vt, vn)` pair.
    pub positions: Vec<Vec3>,
    /// One normal per vertex, or empty when the file has no `vn` (gaps filled from face normals).
    pub normals: Vec<Vec3>,
    /// One UV per vertex, or empty when the file has no `vt`.
    pub uvs: Vec<Vec2>,
    /// Indices into `positions` (and `normals`, `uvs`), with the file's winding.
    pub triangles: Vec<[u32; 3]>,
    /// Which material each range of triangles uses, in order; never empty, the first starts at 0.
    pub runs: Vec<MaterialRun>,
    /// `mtllib` arguments as written, with their lines.
    pub mtllibs: Vec<(String, Place)>,
    /// Counts of what the file held, for `scnc inspect`.
    pub stats: ObjStats,
    /// The encoding the file was found in.
    pub encoding: Encoding,
    /// Notes about the OBJ itself ([`LoadedObj`](super::LoadedObj) adds its libraries').
    pub warnings: Vec<Note>,
}

const UNSET: u32 = u32::MAX - 1;
const NONE: u32 = u32::MAX;
const EXTRA: u32 = 1 << 31;

/// Parses an OBJ file. `text` is returned transcoded when it was UTF-16 (places refer to it).
pub fn parse_obj(bytes: &[u8]) -> Result<(ObjModel, Option<Vec<u8>>), ObjError> {
    let (text, encoding) = to_utf8_bytes(bytes);
    let mut p = Parser::default();
    p.model.encoding = encoding;
    let mut joined: Vec<u8> = Vec::new();
    let mut joined_line: Option<Line<'_>> = None;
    for line in Lines::new(&text) {
        if continues(line.text) || joined_line.is_some() {
            // Rare `\` continuation: join into a buffer, parse when the line ends.
            let part = line.text.strip_suffix(b"\\").unwrap_or(line.text);
            joined.extend_from_slice(part);
            joined.push(b' ');
            let first = *joined_line.get_or_insert(line);
            if continues(line.text) {
                continue;
            }
            joined_line = None;
            let at = Place {
                line: first.number,
                start: first.offset,
                end: line.offset + line.text.len(),
            };
            let owned = std::mem::take(&mut joined);
            p.statement(strip_comment(&owned), at)?;
            continue;
        }
        let body = strip_comment(line.text);
        if !body.is_empty() {
            p.statement(body, Place::of_line(&line, body))?;
        }
    }
    let model = p.finish();
    let transcoded = match text {
        std::borrow::Cow::Owned(t) => Some(t),
        std::borrow::Cow::Borrowed(_) => None,
    };
    Ok((model, transcoded))
}

#[derive(Default)]
struct Parser {
    model: ObjModel,
    uv_raw: Vec<Vec2>,
    n_raw: Vec<Vec3>,
    /// Per position: the `(vt, vn)` of the vertex with the position's index.
    first: Vec<(u32, u32)>,
    extras: Vec<(u32, u32, u32)>,
    extra_ids: HashMap<(u32, u32, u32), u32>,
    any_uv: bool,
    any_normal: bool,
    corners: Vec<u32>,
    pts: Vec<Vec3>,
    local: Vec<[u32; 3]>,
    scratch: Scratch,
    seen: Seen,
    polygons: PolygonWarnings,
}

impl Parser {
    fn statement(&mut self, body: &[u8], at: Place) -> Result<(), ObjError> {
        let (kw, rest) = keyword(body);
        match kw {
            b"v" => {
                let p = self.floats::<3>(rest, 3, at, "a vertex `v x y z`")?;
                self.model.positions.push(Vec3::from(p));
                self.first.push((UNSET, UNSET));
                if self.model.positions.len() >= EXTRA as usize {
                    return Err(ObjError::new(
                        Code::ObjTooLarge,
                        "more than 2³¹ vertices",
                        at,
                    ));
                }
            }
            b"vt" => {
                let t = self.floats::<2>(rest, 1, at, "a texture coordinate `vt u v`")?;
                self.uv_raw.push(Vec2::from(t));
            }
            b"vn" => {
                let n = self.floats::<3>(rest, 3, at, "a normal `vn x y z`")?;
                self.n_raw.push(Vec3::from(n));
            }
            b"f" | b"fo" => self.face(rest, at)?,
            b"l" | b"p" => {
                self.model.stats.lines_and_points += 1;
                self.seen.first_skipped.get_or_insert(at);
            }
            b"usemtl" => {
                let name = self.name(rest, at);
                let start = self.model.triangles.len();
                if let Some(last) = self.model.runs.last_mut().filter(|r| r.start == start) {
                    last.name = Some(name);
                    last.at = Some(at);
                } else {
                    self.model.runs.push(MaterialRun {
                        start,
                        name: Some(name),
                        at: Some(at),
                    });
                }
            }
            b"mtllib" => {
                let name = self.name(rest, at);
                self.model.mtllibs.push((name, at));
            }
            b"o" | b"g" => {
                self.name(rest, at);
                self.model.stats.groups += 1;
            }
            b"s" => {}
            _ => {
                let (word, _) = decode_name(kw);
                self.seen.unsupported_statement(word, at);
            }
        }
        Ok(())
    }

    fn name(&mut self, rest: &[u8], at: Place) -> String {
        let (name, latin1) = decode_name(rest);
        if latin1 {
            self.seen.latin1.get_or_insert(at);
        }
        name
    }

    /// `N` numbers, at least `min` present (missing ones 0); extra numbers (vertex colours,
    /// `w`) ignored.
    fn floats<const N: usize>(
        &self,
        rest: &[u8],
        min: usize,
        at: Place,
        what: &str,
    ) -> Result<[f32; N], ObjError> {
        let mut out = [0.0; N];
        let mut count = 0;
        for tok in tokens(rest) {
            let Some(v) = parse_f32(tok) else {
                return Err(ObjError::new(
                    Code::ObjBadNumber,
                    format!("`{}` is not a number", decode_name(tok).0),
                    at,
                )
                .help(format!("this line should be {what}")));
            };
            if count < N {
                out[count] = v;
            }
            count += 1;
        }
        if count < min {
            return Err(ObjError::new(
                Code::ObjMissingNumber,
                format!("this line has {count} numbers; it should be {what}"),
                at,
            ));
        }
        Ok(out)
    }

    fn face(&mut self, rest: &[u8], at: Place) -> Result<(), ObjError> {
        self.model.stats.faces += 1;
        self.corners.clear();
        self.pts.clear();
        for tok in tokens(rest) {
            let mut parts = tok.splitn(3, |&c| c == b'/');
            let v = parts.next().unwrap_or_default();
            let t = parts.next().unwrap_or_default();
            let n = parts.next().unwrap_or_default();
            let p = resolve(v, self.model.positions.len(), at, "vertex")?;
            let t = match t {
                [] => NONE,
                t => resolve(t, self.uv_raw.len(), at, "texture coordinate")?,
            };
            let n = match n {
                [] => NONE,
                n => resolve(n, self.n_raw.len(), at, "normal")?,
            };
            self.any_uv |= t != NONE;
            self.any_normal |= n != NONE;
            let id = self.vertex(p, t, n);
            self.corners.push(id);
            self.pts.push(self.model.positions[p as usize]);
        }
        if self.corners.len() < 3 {
            return Err(ObjError::new(
                Code::ObjShortFace,
                format!(
                    "a face needs at least 3 corners, this one has {}",
                    self.corners.len()
                ),
                at,
            ));
        }
        self.local.clear();
        let o = triangulate(&self.pts, &mut self.local, &mut self.scratch);
        self.model.stats.degenerate_dropped += o.dropped;
        if o.fanned {
            self.seen.fanned.get_or_insert(at);
        }
        let corners = self.corners.len();
        self.polygons
            .record(at, corners, o.loop_len, o.area_mismatch);
        let corners = &self.corners;
        self.model
            .triangles
            .extend(self.local.iter().map(|t| t.map(|i| corners[i as usize])));
        Ok(())
    }

    /// The vertex id of corner `(p, t, n)`.
    fn vertex(&mut self, p: u32, t: u32, n: u32) -> u32 {
        let slot = &mut self.first[p as usize];
        if *slot == (UNSET, UNSET) {
            *slot = (t, n);
        }
        if *slot == (t, n) {
            return p;
        }
        let next = self.extras.len() as u32;
        let id = *self.extra_ids.entry((p, t, n)).or_insert(next);
        if id == next {
            self.extras.push((p, t, n));
        }
        EXTRA | id
    }

    fn finish(mut self) -> ObjModel {
        let mut m = std::mem::take(&mut self.model);
        m.stats.positions = m.positions.len();
        m.stats.normals = self.n_raw.len();
        m.stats.uvs = self.uv_raw.len();
        let base = m.positions.len() as u32;
        for t in &mut m.triangles {
            for i in t {
                if *i & EXTRA != 0 {
                    *i = base + (*i & !EXTRA);
                }
            }
        }
        m.positions.reserve_exact(self.extras.len());
        for &(p, _, _) in &self.extras {
            let q = m.positions[p as usize];
            m.positions.push(q);
        }
        let pairs = || {
            self.first
                .iter()
                .copied()
                .chain(self.extras.iter().map(|e| (e.1, e.2)))
        };
        if self.any_uv {
            let uv = |t: u32| self.uv_raw.get(t as usize).copied().unwrap_or(Vec2::ZERO);
            m.uvs = pairs().map(|(t, _)| uv(t)).collect();
        }
        if self.any_normal {
            let nrm = |n: u32| self.n_raw.get(n as usize).copied().unwrap_or(Vec3::ZERO);
            m.normals = pairs().map(|(_, n)| nrm(n)).collect();
            fill_missing_normals(&m.positions, &m.triangles, &mut m.normals);
        }
        if m.runs.first().is_some_and(|r| r.start > 0) {
            m.runs.insert(
                0,
                MaterialRun {
                    start: 0,
                    name: None,
                    at: None,
                },
            );
        }
        if m.runs.is_empty() {
            m.runs.push(MaterialRun {
                start: 0,
                name: None,
                at: None,
            });
        }
        m.runs
            .retain(|r| r.start < m.triangles.len() || r.start == 0);
        self.seen.notes(&mut m);
        m.warnings.extend(self.polygons.notes());
        m
    }
}

/// A 1-based (or negative, relative) OBJ index → 0-based, checked against `len` read so far.
fn resolve(tok: &[u8], len: usize, at: Place, what: &str) -> Result<u32, ObjError> {
    let Some(i) = parse_index(tok) else {
        return Err(ObjError::new(
            Code::ObjBadIndex,
            format!("`{}` is not a {what} index", decode_name(tok).0),
            at,
        )
        .help(
            "face corners are `v`, `v/vt`, `v//vn` or `v/vt/vn` with 1-based or negative indices",
        ));
    };
    let resolved = if i < 0 { len as i64 + i } else { i - 1 };
    if i == 0 || resolved < 0 || resolved >= len as i64 {
        return Err(ObjError::new(
            Code::ObjIndexOutOfRange,
            format!("{what} index {i} does not exist: {len} read so far"),
            at,
        )
        .help("indices count from 1; negative ones count back from the last one read"));
    }
    Ok(resolved as u32)
}
