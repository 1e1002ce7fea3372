//! The command line's choices shared by `scnc render` and `scnc watch`: which camera
//! (`--camera NAME`) and where the picture goes (`-o`, else the scene's `render { output … }`,
//! else `<scene name>.png` in the current directory).

use std::path::{Path, PathBuf};

use crate::diag::suggest::did_you_mean;
use crate::diag::{Code, Diagnostic};
use crate::ir::SceneDesc;
use crate::source::Span;

/// The index of the camera `--camera NAME` names, or a diagnostic listing the cameras (with a
/// did-you-mean for a near miss).
pub fn camera_index(desc: &SceneDesc, name: &str) -> Result<usize, Box<Diagnostic>> {
    desc.camera_by_name(name).ok_or_else(|| {
        let names: Vec<&str> = desc.cameras.iter().map(|c| c.name.as_str()).collect();
        let d = Diagnostic::error(
            Code::CliUnknownCamera,
            format!("the scene has no camera named `{name}`"),
        );
        Box::new(match did_you_mean(name, names.iter().copied()) {
            Some(s) => d.help(format!("did you mean `{s}`? cameras: {}", names.join(", "))),
            None => d.help(format!("cameras: {}", names.join(", "))),
        })
    })
}

/// Where to write: `output` (from `-o`), else the scene's outputs, else `<scene stem>.png` in
/// the current directory. Scene outputs keep their span so that a write error points at the
/// `output` string.
pub fn output_targets(
    output: Option<&Path>,
    scene_file: &Path,
    desc: &SceneDesc,
) -> Vec<(PathBuf, Option<Span>)> {
    if let Some(o) = output {
        return vec![(o.to_path_buf(), None)];
    }
    if !desc.render.outputs.is_empty() {
        return desc
            .render
            .outputs
            .iter()
            .map(|o| (o.file.path.clone(), Some(o.file.span)))
            .collect();
    }
    let stem = scene_file
        .file_stem()
        .unwrap_or(std::ffi::OsStr::new("scene"));
    vec![(Path::new(stem).with_extension("png"), None)]
}
