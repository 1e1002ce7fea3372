//! Stage 5: [`write`] a film to a file chosen by extension, atomically.
//!
//! Syntax: `render { output "out.png" }` or `scnc render -o out.exr`. The bytes are encoded in
//! memory first, then written to a temporary file next to the target (same directory, so the
//! rename cannot cross file systems), fsynced ([`Durability::Synced`]) and renamed over the
//! target. On any error the temporary file is removed and the previous image, if any, is
//! untouched; an interrupted run leaves at worst a stray `.NAME.*.tmp` file, never a truncated
//! image. `scnc watch`'s previews skip the syncs ([`Durability::Replaced`]): the rename alone
//! keeps them whole against an interrupted run, and a sync, tens of milliseconds to seconds on
//! a busy disk, would hold back the next preview.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::{encode, Film};
use crate::diag::{Code, Diagnostic, Staged};
use crate::ir::{OutputFormat, RenderSettings, ToneMap};
use crate::source::Span;

/// How radiance becomes 8-bit values (PNG only; float formats store radiance as is).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WriteSettings {
    /// Stops: radiance is multiplied by 2^exposure.
    pub exposure: f32,
    /// The curve from scaled radiance to [0, 1].
    pub tonemap: ToneMap,
}

impl WriteSettings {
    /// The scene's `exposure` and `tonemap`.
    pub fn from_render(settings: &RenderSettings) -> WriteSettings {
        WriteSettings {
            exposure: settings.exposure,
            tonemap: settings.tonemap,
        }
    }
}

impl Default for WriteSettings {
    fn default() -> WriteSettings {
        WriteSettings {
            exposure: 0.0,
            tonemap: ToneMap::Clamp,
        }
    }
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The extension names no format scnc writes.
    #[error("cannot tell the image format of `{}` (use .png, .exr, .hdr or .pfm)", path.display())]
    UnknownFormat {
        /// The output path.
        path: PathBuf,
    },
    /// The encoder refused the image.
    #[error("cannot encode `{}`: {message}", path.display())]
    Encode {
        /// The output path.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// The file system refused the write (or the rename over the target).
    #[error("cannot write `{}`: {source}", path.display())]
    Io {
        /// The output path.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
}

impl WriteError {
    /// The diagnostic code of this error.
    pub fn code(&self) -> Code {
        match self {
            WriteError::UnknownFormat { .. } => Code::WriteUnknownFormat,
            WriteError::Encode { .. } => Code::WriteEncode,
            WriteError::Io { .. } => Code::WriteIo,
        }
    }

    /// As a diagnostic, labelled at the `output "…"` literal when the path came from the scene.
    pub fn to_diagnostic(&self, span: Option<Span>) -> Diagnostic {
        let mut d = Diagnostic::error(self.code(), self.to_string());
        if let Some(span) = span {
            d = d.at(span, "output written here");
        }
        if let WriteError::UnknownFormat { .. } = self {
            d = d.help("the extension chooses the format: .png, .exr, .hdr or .pfm");
        }
        d
    }
}

/// The format an output path asks for, by its extension (case-insensitive).
pub fn format_for_path(path: &Path) -> Option<OutputFormat> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "png" => Some(OutputFormat::Png),
        "exr" => Some(OutputFormat::Exr),
        "hdr" => Some(OutputFormat::Hdr),
        "pfm" => Some(OutputFormat::Pfm),
        _ => None,
    }
}

/// Stage entry: [`write_image`] as a pipeline stage, its error a diagnostic labelled at
/// `span` (the scene's `output "…"` literal, when the path came from there).
pub fn write(
    film: &Film,
    path: &Path,
    settings: &WriteSettings,
    durability: Durability,
    span: Option<Span>,
) -> Staged<()> {
    Staged::from_result(
        write_image(film, path, settings, durability).map_err(|e| e.to_diagnostic(span)),
    )
}

/// Encodes `film` in the format `path`'s extension names and writes it atomically.
pub fn write_image(
    film: &Film,
    path: &Path,
    settings: &WriteSettings,
    durability: Durability,
) -> Result<(), WriteError> {
    let format = format_for_path(path).ok_or_else(|| WriteError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let encoded = match format {
        OutputFormat::Png => encode::png(film, settings),
        OutputFormat::Exr => encode::exr(film),
        OutputFormat::Hdr => encode::hdr(film),
        OutputFormat::Pfm => Ok(encode::pfm(film)),
    };
    let bytes = encoded.map_err(|message| WriteError::Encode {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomic_with(path, durability, |f| f.write_all(&bytes)).map_err(|source| WriteError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Whether a written file is forced to the disk around the rename that puts it in place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// The file is fsynced before the rename and its directory after it: from the moment the
    /// call returns the new file survives a power loss or an OS crash, and until then the old
    /// one does. For what a run leaves behind (`render`, `merge`, tiles, `fmt`, bench caches).
    Synced,
    /// The rename alone: an interrupted process still never leaves a half-written file at the
    /// path, but a power loss or OS crash soon after may lose the new file (on file systems
    /// that do not order a replacing rename after its data, leave it empty). For `watch`'s
    /// previews, written again at every edit, whose syncs measured 0.05-2.4 s per image on a
    /// busy disk (docs/watch.md, sixteenth session) and would delay the next preview.
    Replaced,
}

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically: `fill` writes a fresh temporary file in the same directory, which
/// is then fsynced (when `durability` asks) and renamed over `path`. If `fill`, the sync or the
/// rename fails, the temporary file is removed and `path` is left as it was.
pub fn write_atomic_with(
    path: &Path,
    durability: Durability,
    fill: impl FnOnce(&mut File) -> io::Result<()>,
) -> io::Result<()> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(io::ErrorKind::InvalidInput, "the output path names no file")
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let temp = dir.join(format!(
        ".{}.{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let mut file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)?;
    let synced = durability == Durability::Synced;
    let result = fill(&mut file)
        .and_then(|()| if synced { file.sync_all() } else { Ok(()) })
        .and_then(|()| {
            drop(file);
            fs::rename(&temp, path)
        });
    if let Err(e) = result {
        // Best effort: the error that matters is the one being returned.
        let _ = fs::remove_file(&temp);
        return Err(e);
    }
    // Make the rename itself durable where the platform allows syncing a directory.
    if synced {
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}
