//! `scnc watch`: the file watcher. Wraps notify: watches the *directories* of the files the
//! last compile read (non-recursively), so that editors which save by renaming a temporary file
//! over the original, and files that do not exist yet, are seen. Events are filtered to the
//! recorded set; a change counts only if the file's content hash differs from the one of the
//! bytes the compile read (an event with unchanged content does nothing). Files whose directory
//! does not exist are polled.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::mpsc::Sender;
use std::sync::Arc;

use notify::{RecommendedWatcher, RecursiveMode, Watcher};

use super::batch::{Change, Msg};
use super::settled;
use crate::scene::cache::content_hash;

/// The watched set: absolute path → content hash of what was read (`None`: did not exist).
pub type FileSet = HashMap<PathBuf, Option<u64>>;

/// The notify watcher and the set of files it watches (through their directories, so files
/// that editors replace by rename, or that do not exist yet, are seen).
pub struct FileWatcher {
    notify: RecommendedWatcher,
    files: FileSet,
    dirs: BTreeSet<PathBuf>,
    /// The bytes (and their hash) of the changed files [`FileWatcher::confirm`] read, for the
    /// compile that follows ([`FileWatcher::take_read`]): an 8.8 MB scene is then read and
    /// hashed once per edit, not twice.
    read: Fresh,
}

/// Files just read: absolute path → bytes and their content hash.
pub type Fresh = HashMap<PathBuf, (Arc<[u8]>, u64)>;

impl FileWatcher {
    /// A watcher that sends the paths of every event to `tx`.
    pub fn new(tx: Sender<Msg>) -> notify::Result<FileWatcher> {
        let notify = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            if let Ok(event) = event {
                // The loop may have ended; then nobody needs the event.
                let _ = tx.send(Msg::Paths(change_of(&event.kind), event.paths));
            }
        })?;
        Ok(FileWatcher {
            notify,
            files: FileSet::new(),
            dirs: BTreeSet::new(),
            read: Fresh::new(),
        })
    }

    /// Replaces the watched set: directories no longer needed are unwatched, new ones watched.
    pub fn set(&mut self, files: FileSet) {
        self.files = files;
        let wanted: BTreeSet<PathBuf> = self.files.keys().filter_map(|p| parent(p)).collect();
        for gone in self.dirs.difference(&wanted).cloned().collect::<Vec<_>>() {
            // Unwatching a directory that was deleted fails harmlessly.
            let _ = self.notify.unwatch(&gone);
            self.dirs.remove(&gone);
        }
        self.watch_missing_dirs(&wanted);
    }

    /// Watches every wanted directory that exists and is not watched yet.
    fn watch_missing_dirs(&mut self, wanted: &BTreeSet<PathBuf>) {
        for dir in wanted.difference(&self.dirs.clone()) {
            if dir.is_dir() && self.notify.watch(dir, RecursiveMode::NonRecursive).is_ok() {
                self.dirs.insert(dir.clone());
            }
        }
    }

    /// Whether `path` (absolute) is in the watched set.
    pub fn is_watched(&self, path: &Path) -> bool {
        self.files.contains_key(path)
    }

    /// The hash of `path`'s content as last seen (`None`: missing or not watched).
    pub fn hash_of(&self, path: &Path) -> Option<u64> {
        self.files.get(&absolute(path)).copied().flatten()
    }

    /// How many files are watched.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Of `candidates`, the watched files whose content changed (stored hashes updated; their
    /// bytes kept for [`FileWatcher::take_read`]).
    pub fn confirm<'p>(
        &mut self,
        candidates: impl IntoIterator<Item = &'p PathBuf>,
    ) -> Vec<PathBuf> {
        let mut changed = Vec::new();
        for path in candidates {
            let Some(old) = self.files.get_mut(path) else {
                continue;
            };
            let bytes = settled::read(path).ok();
            let now = bytes.as_ref().map(|b| content_hash(b));
            if now != *old {
                *old = now;
                changed.push(path.clone());
                if let (Some(bytes), Some(hash)) = (bytes, now) {
                    self.read.insert(path.clone(), (bytes, hash));
                }
            }
        }
        changed
    }

    /// The changed files' bytes as [`FileWatcher::confirm`] read them, for the compile that
    /// follows it. Using them is using what was confirmed: a write after that read sends
    /// events of its own, and the next confirm compares the file with these bytes' hash.
    pub fn take_read(&mut self) -> Fresh {
        std::mem::take(&mut self.read)
    }

    /// Checks files that did not exist (and directories that were not there to watch): the
    /// changed ones, as [`FileWatcher::confirm`] would return them.
    pub fn poll(&mut self) -> Vec<PathBuf> {
        let wanted: BTreeSet<PathBuf> = self.files.keys().filter_map(|p| parent(p)).collect();
        self.watch_missing_dirs(&wanted);
        let missing: Vec<PathBuf> = self
            .files
            .iter()
            .filter(|(_, h)| h.is_none())
            .map(|(p, _)| p.clone())
            .filter(|p| p.exists())
            .collect();
        self.confirm(&missing)
    }
}

/// What an event says of its paths: a modification of content (its writer may still be
/// writing), the end of a write (closed after writing, or renamed into place), or neither.
fn change_of(kind: &notify::EventKind) -> Change {
    use notify::event::{AccessKind, AccessMode, ModifyKind, RenameMode};
    use notify::EventKind;
    match kind {
        EventKind::Access(AccessKind::Close(AccessMode::Write))
        | EventKind::Modify(ModifyKind::Name(RenameMode::To | RenameMode::Both)) => Change::Written,
        EventKind::Modify(ModifyKind::Data(_) | ModifyKind::Any) => Change::Writing,
        _ => Change::Named,
    }
}

fn parent(p: &Path) -> Option<PathBuf> {
    p.parent().map(Path::to_path_buf)
}

/// `path` made absolute against the current directory, `.` and `..` removed lexically (the
/// form notify reports for a watched absolute directory).
pub fn absolute(path: &Path) -> PathBuf {
    let joined = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(path)
    };
    let mut out = PathBuf::new();
    for c in joined.components() {
        match c {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absolute_removes_dots() {
        let a = absolute(Path::new("/x/./y/../z.scn"));
        assert_eq!(a, PathBuf::from("/x/z.scn"));
        assert!(absolute(Path::new("rel.scn")).is_absolute());
    }
}
