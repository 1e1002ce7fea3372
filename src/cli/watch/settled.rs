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

use std::fs::{File, Metadata};
use std::io::{self, Read};
use std::path::Path;
use std::sync::Arc;
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
pub fn read(path: &Path) -> io::Result<Arc<[u8]>> {
    read_with(path, ATTEMPTS, PAUSE, |_| {})
}

/// The bytes of `path` and its stamp when opened, read straight into the shared buffer the
/// loader hands on (sized by the stamp): `fs::read` and a copy into an `Arc` cost a second
/// 8.8 MB allocation and copy per edit of issue 22's scene (2026-11-26, seventh session). A
/// file cut or grown while read gives what was read.
fn read_shared(path: &Path) -> io::Result<(Arc<[u8]>, Stamp)> {
    let mut file = File::open(path)?;
    let stamp = Stamp::of(&file.metadata()?);
    let len = usize::try_from(stamp.len).unwrap_or(usize::MAX);
    let mut bytes: Arc<[u8]> = std::iter::repeat_n(0, len).collect();
    let Some(buf) = Arc::get_mut(&mut bytes) else {
        // Made here, shared with nobody: not reached; read as `fs::read` reads.
        return Ok((Arc::from(std::fs::read(path)?), stamp));
    };
    let mut filled = 0;
    while filled < len {
        match file.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    if filled < len {
        return Ok((Arc::from(&bytes[..filled]), stamp));
    }
    let mut rest = Vec::new();
    file.read_to_end(&mut rest)?;
    if rest.is_empty() {
        return Ok((bytes, stamp));
    }
    let mut all = bytes.to_vec();
    all.append(&mut rest);
    Ok((all.into(), stamp))
}

/// [`read`] with its bounds; `between` runs after each read's bytes are in and before the
/// stamp after it is taken (a test's writer goes there).
fn read_with(
    path: &Path,
    attempts: usize,
    pause: Duration,
    mut between: impl FnMut(usize),
) -> io::Result<Arc<[u8]>> {
    let mut attempt = 0;
    loop {
        let (bytes, before) = read_shared(path)?;
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
        assert_eq!(*bytes, *std::fs::read(&path).unwrap());
        assert!(std::str::from_utf8(&bytes)
            .unwrap()
            .ends_with("let k2 = 2\n"));
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
        assert_eq!(&*bytes, b"scnc 1\n");
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
        assert_eq!(&*bytes, b"xxx");
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn a_missing_file_is_an_error() {
        assert!(read(&temp("missing")).is_err());
    }
}
