//! `scnc watch`: reading a file whose writer may still be writing it. The batching waits for
//! a modified file's writer to close it where the platform says so ([`super::batch`]); this is
//! the second guard, for every platform and for a writer the batching stopped waiting for: the
//! file's size and modification time are taken before and after the read, and the read is
//! made again (after a pause) while they moved or the bytes read are not the size.
//!
//! It cannot see a writer that pauses for the whole read (the file is then consistent, but
//! not finished); on Linux the close event covers that. A read that never settles (a file
//! written without end) gives its last bytes after [`ATTEMPTS`] reads; the writer's events
//! then bring another compile.

use std::fs::Metadata;
use std::io;
use std::path::Path;
use std::time::{Duration, SystemTime};

/// Reads made at most before the last one's bytes are taken as they are.
pub const ATTEMPTS: usize = 5;
/// Pause before a read is made again.
pub const PAUSE: Duration = Duration::from_millis(15);

/// What a read is compared by: the size and the modification time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
}

impl Stamp {
    fn of(meta: &Metadata) -> Stamp {
        Stamp {
            len: meta.len(),
            modified: meta.modified().ok(),
        }
    }
}

/// The bytes of `path`, read again while a writer was seen writing it during the read.
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    read_with(path, ATTEMPTS, PAUSE, |_| {})
}

/// [`read`] with its bounds; `between` runs after each read's bytes are in and before the
/// stamp after it is taken (a test's writer goes there).
fn read_with(
    path: &Path,
    attempts: usize,
    pause: Duration,
    mut between: impl FnMut(usize),
) -> io::Result<Vec<u8>> {
    let mut attempt = 0;
    loop {
        let before = Stamp::of(&std::fs::metadata(path)?);
        let bytes = std::fs::read(path)?;
        between(attempt);
        let after = std::fs::metadata(path).map(|m| Stamp::of(&m));
        let settled = after.is_ok_and(|a| a == before && a.len == bytes.len() as u64);
        attempt += 1;
        if settled || attempt >= attempts {
            return Ok(bytes);
        }
        std::thread::sleep(pause);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn temp(tag: &str) -> std::path::PathBuf {
        let p = std::env::temp_dir().join(format!("scnc-settled-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_file(&p);
        p
    }

    /// A writer appends after each of the first reads (as one still writing would): the read
    /// is made again until a read with nothing written during it, which has every byte.
    #[test]
    fn a_read_during_a_write_is_made_again() {
        let path = temp("again");
        std::fs::write(&path, "scnc 1\n").unwrap();
        let mut reads = 0;
        let bytes = read_with(&path, 10, Duration::from_millis(1), |attempt| {
            reads += 1;
            if attempt < 3 {
                let mut f = std::fs::OpenOptions::new()
                    .append(true)
                    .open(&path)
                    .unwrap();
                writeln!(f, "let k{attempt} = {attempt}").unwrap();
            }
        })
        .unwrap();
        assert_eq!(reads, 4);
        assert_eq!(bytes, std::fs::read(&path).unwrap());
        assert!(String::from_utf8(bytes).unwrap().ends_with("let k2 = 2\n"));
        let _ = std::fs::remove_file(&path);
    }

    /// A file truncated and written again between the stamps (same size, an in-place save of
    /// the same length) is told by its size while the writer is mid-way: read again.
    #[test]
    fn a_file_truncated_during_the_read_is_read_again() {
        let path = temp("trunc");
        std::fs::write(&path, "scnc 1\nlet a = 1\n").unwrap();
        let mut reads = 0;
        let bytes = read_with(&path, 10, Duration::from_millis(1), |attempt| {
            reads += 1;
            if attempt == 0 {
                // Truncated and half written: the writer paused here.
                std::fs::write(&path, "scnc 1\n").unwrap();
            }
        })
        .unwrap();
        assert_eq!(reads, 2);
        assert_eq!(bytes, b"scnc 1\n");
        let _ = std::fs::remove_file(&path);
    }

    /// A writer that never stops: the last read is taken after the bound.
    #[test]
    fn a_read_that_never_settles_is_bounded() {
        let path = temp("bounded");
        std::fs::write(&path, "x").unwrap();
        let mut reads = 0;
        let bytes = read_with(&path, 3, Duration::from_millis(1), |_| {
            reads += 1;
            let mut f = std::fs::OpenOptions::new()
                .append(true)
                .open(&path)
                .unwrap();
            f.write_all(b"x").unwrap();
        })
        .unwrap();
        assert_eq!(reads, 3);
        assert_eq!(bytes, b"xxx");
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn a_missing_file_is_an_error() {
        assert!(read(&temp("missing")).is_err());
    }
}
