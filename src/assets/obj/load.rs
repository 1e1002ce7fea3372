//! An OBJ file and its `mtllib`s, read through the [`Loader`] (stage 3, assets). The `.scn`
//! syntax is `mesh m = obj("m.obj")`, with `{ mtl false }` to skip the MTL files altogether.
//!
//! Paths in the OBJ are relative to the OBJ's directory. `mtllib a b.mtl` is ambiguous (one
//! name with a space, or two files): the whole argument is tried first, then each word. A
//! library that cannot be read, and a `usemtl` that no library defines, are warnings placed at
//! the OBJ line; the faces then use the default material.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::lexer::tokens;
use super::model::parse_obj;
use super::mtl::{parse_mtl, MtlLibrary};
use super::{Note, ObjError, ObjModel};
use crate::assets::Loader;

/// Which file a note is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileRef {
    /// The OBJ file itself.
    Obj,
    /// `LoadedObj::mtls[i]`.
    Mtl(usize),
}

/// A material library that was read.
#[derive(Debug, Clone)]
pub struct MtlSource {
    /// Where it was read from: the OBJ's directory joined with the written name.
    pub path: PathBuf,
    /// The name as the OBJ wrote it.
    pub written: String,
    /// The library's text (UTF-8; transcoded if it was UTF-16): its notes' places refer to it.
    pub text: Arc<[u8]>,
    /// The materials it defines.
    pub library: MtlLibrary,
}

/// Everything read for one OBJ mesh.
#[derive(Debug, Clone)]
pub struct LoadedObj {
    /// The triangles, normals, UVs and material runs.
    pub model: ObjModel,
    /// The OBJ's text (UTF-8; transcoded if the file was UTF-16): places refer to it.
    pub text: Arc<[u8]>,
    /// The libraries read, in `mtllib` order, each once; [`FileRef::Mtl`] indexes them.
    pub mtls: Vec<MtlSource>,
    /// Every warning, from the OBJ and its libraries, in file order.
    pub warnings: Vec<(FileRef, Note)>,
}

impl LoadedObj {
    /// The material `name` from the libraries (the first library that defines it wins, as in
    /// other renderers), as (library index, material index).
    pub fn find_material(&self, name: &str) -> Option<(usize, usize)> {
        self.mtls.iter().enumerate().find_map(|(l, src)| {
            src.library
                .materials
                .iter()
                .position(|m| m.name == name)
                .map(|m| (l, m))
        })
    }
}

/// Reads and parses `path` (already read as `bytes`) and, when `read_mtl`, its libraries.
pub fn load_obj(
    path: &Path,
    bytes: Arc<[u8]>,
    read_mtl: bool,
    loader: &dyn Loader,
) -> Result<LoadedObj, ObjError> {
    let (model, transcoded) = parse_obj(&bytes)?;
    let text: Arc<[u8]> = match transcoded {
        Some(t) => Arc::from(t),
        None => bytes,
    };
    let mut out = LoadedObj {
        warnings: model
            .warnings
            .iter()
            .map(|n| (FileRef::Obj, n.clone()))
            .collect(),
        model,
        text,
        mtls: Vec::new(),
    };
    if !read_mtl {
        return Ok(out);
    }
    let dir = path.parent().unwrap_or(Path::new(""));
    let libs = out.model.mtllibs.clone();
    for (written, at) in libs {
        let whole = dir.join(&written);
        let candidates: Vec<String> = match loader.read(&whole) {
            Ok(bytes) => {
                out.add_mtl(whole, written, bytes);
                continue;
            }
            Err(_) if written.contains(char::is_whitespace) => tokens(written.as_bytes())
                .map(|t| String::from_utf8_lossy(t).into_owned())
                .collect(),
            Err(_) => vec![written],
        };
        for name in candidates {
            let p = dir.join(&name);
            if out.mtls.iter().any(|m| m.path == p) {
                continue;
            }
            match loader.read(&p) {
                Ok(bytes) => out.add_mtl(p, name, bytes),
                Err(e) => out.warnings.push((
                    FileRef::Obj,
                    Note::warning(
                        "scnc::obj::missing_mtl",
                        format!("cannot read the material library `{name}` ({e}); its materials use the default"),
                        at,
                    )
                    .help(format!("put `{name}` beside the OBJ file, or write `mtl false` in the mesh's block to silence this")),
                )),
            }
        }
    }
    out.check_usemtl();
    Ok(out)
}

impl LoadedObj {
    fn add_mtl(&mut self, path: PathBuf, written: String, bytes: Arc<[u8]>) {
        let (text, _) = super::encoding::to_utf8_bytes(&bytes);
        let library = parse_mtl(&text);
        let text: Arc<[u8]> = Arc::from(text.into_owned());
        let i = self.mtls.len();
        self.warnings.extend(
            library
                .warnings
                .iter()
                .map(|n| (FileRef::Mtl(i), n.clone())),
        );
        self.mtls.push(MtlSource {
            path,
            written,
            text,
            library,
        });
    }

    /// A `usemtl` no library defines: one warning per name, at its first `usemtl`.
    fn check_usemtl(&mut self) {
        let mut seen: Vec<&str> = Vec::new();
        let mut notes = Vec::new();
        for run in &self.model.runs {
            let (Some(name), Some(at)) = (&run.name, run.at) else {
                continue;
            };
            if seen.contains(&name.as_str()) || self.find_material(name).is_some() {
                continue;
            }
            seen.push(name);
            let libs = if self.mtls.is_empty() {
                "no material library was read".to_string()
            } else {
                let names: Vec<&str> = self.mtls.iter().map(|m| m.written.as_str()).collect();
                format!("it is not in {}", names.join(", "))
            };
            notes.push((
                FileRef::Obj,
                Note::warning(
                    "scnc::obj::unknown_material",
                    format!("material `{name}` is not defined ({libs}); its faces use the default"),
                    at,
                ),
            ));
        }
        self.warnings.extend(notes);
    }
}
