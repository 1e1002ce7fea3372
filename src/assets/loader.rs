//! The [`Loader`] seam: reads files for every stage and records which ones were read.

use std::collections::{BTreeSet, HashMap};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Reads files by path. Implementations record every path requested (including ones that do not
/// exist: creating such a file later must trigger a recompile in `scnc watch`).
pub trait Loader: Send + Sync {
    /// The whole file's bytes.
    fn read(&self, path: &Path) -> io::Result<Arc<[u8]>>;

    /// Every path requested so far, in sorted order.
    fn recorded(&self) -> Vec<PathBuf>;
}

/// Reads from the file system.
#[derive(Debug, Default)]
pub struct FsLoader {
    read_paths: Mutex<BTreeSet<PathBuf>>,
}

impl FsLoader {
    /// A loader that has recorded nothing yet.
    pub fn new() -> FsLoader {
        FsLoader::default()
    }
}

impl Loader for FsLoader {
    fn read(&self, path: &Path) -> io::Result<Arc<[u8]>> {
        if let Ok(mut paths) = self.read_paths.lock() {
            paths.insert(path.to_path_buf());
        }
        std::fs::read(path).map(Arc::from)
    }

    fn recorded(&self) -> Vec<PathBuf> {
        self.read_paths
            .lock()
            .map(|p| p.iter().cloned().collect())
            .unwrap_or_default()
    }
}

/// Serves files from memory (tests, fuzzing, the preview server's in-editor buffers).
#[derive(Debug, Default)]
pub struct MemLoader {
    files: HashMap<PathBuf, Arc<[u8]>>,
    read_paths: Mutex<BTreeSet<PathBuf>>,
}

impl MemLoader {
    /// An empty in-memory loader; add files with [`MemLoader::insert`].
    pub fn new() -> MemLoader {
        MemLoader::default()
    }

    /// Adds (or replaces) a file.
    pub fn insert(
        &mut self,
        path: impl Into<PathBuf>,
        bytes: impl Into<Vec<u8>>,
    ) -> &mut MemLoader {
        self.files.insert(path.into(), Arc::from(bytes.into()));
        self
    }
}

impl Loader for MemLoader {
    fn read(&self, path: &Path) -> io::Result<Arc<[u8]>> {
        if let Ok(mut paths) = self.read_paths.lock() {
            paths.insert(path.to_path_buf());
        }
        self.files.get(path).cloned().ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::NotFound,
                format!("{} is not in the in-memory loader", path.display()),
            )
        })
    }

    fn recorded(&self) -> Vec<PathBuf> {
        self.read_paths
            .lock()
            .map(|p| p.iter().cloned().collect())
            .unwrap_or_default()
    }
}
