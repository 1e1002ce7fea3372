//! Language server: the open documents, and the [`Loader`] that reads them instead of the disk,
//! so that a check sees what the editor shows (an unsaved include too).

use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use lsp_types::Url;

use crate::assets::{FsLoader, Loader};

/// One open document.
#[derive(Debug, Clone)]
pub struct Document {
    /// Its path on disk (what includes and diagnostics name).
    pub path: PathBuf,
    /// The editor's text.
    pub text: String,
    /// The editor's version number of that text.
    pub version: i32,
}

/// Every open document by URI.
#[derive(Debug, Default)]
pub struct Documents {
    open: BTreeMap<Url, Document>,
}

impl Documents {
    /// Opens or replaces a document; `None` when the URI is not a file path.
    pub fn set(&mut self, uri: Url, text: String, version: i32) -> Option<()> {
        let path = uri.to_file_path().ok()?;
        self.open.insert(
            uri,
            Document {
                path,
                text,
                version,
            },
        );
        Some(())
    }

    /// Closes a document.
    pub fn close(&mut self, uri: &Url) {
        self.open.remove(uri);
    }

    /// A document by URI.
    pub fn get(&self, uri: &Url) -> Option<&Document> {
        self.open.get(uri)
    }

    /// Every open document.
    pub fn iter(&self) -> impl Iterator<Item = (&Url, &Document)> {
        self.open.iter()
    }

    /// A loader that reads open documents from the editor and the rest from disk.
    pub fn loader(&self) -> OverlayLoader {
        OverlayLoader {
            open: self
                .open
                .values()
                .map(|d| (d.path.clone(), Arc::from(d.text.as_bytes())))
                .collect(),
            disk: FsLoader::new(),
        }
    }
}

/// Reads open documents as the editor has them, everything else from disk.
#[derive(Debug)]
pub struct OverlayLoader {
    open: BTreeMap<PathBuf, Arc<[u8]>>,
    disk: FsLoader,
}

impl Loader for OverlayLoader {
    fn read(&self, path: &Path) -> io::Result<Arc<[u8]>> {
        match self.open.get(path) {
            Some(bytes) => Ok(bytes.clone()),
            None => self.disk.read(path),
        }
    }

    /// The files read from disk (the server does not watch files, so open ones are left out).
    fn recorded(&self) -> Vec<PathBuf> {
        self.disk.recorded()
    }
}
