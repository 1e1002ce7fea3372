//! `scnc watch`: event batching. A burst of file-system events (an editor's write, truncate,
//! rename and chmod of one save; a `git checkout`) becomes one batch: after the first relevant
//! event, events are gathered until none has arrived for [`QUIET`], but for no longer than
//! [`CAP`] in all, so a steady storm cannot postpone the recompile forever.
//!
//! The quiet time is 40 ms rather than typst's 100: an editor's save is a burst of a few
//! microseconds to milliseconds, and the 60 ms saved are 40% of the 150 ms save-to-image budget
//! (docs/watch.md). A save split across a longer pause costs at worst one extra compile of
//! the partial file; changes are confirmed by content hash, so nothing compiles twice for
//! the same bytes.
//!
//! A file saved in place (opened with truncation and written, as `fs::write` and many editors
//! do) is modified for as long as its writer writes; on a loaded machine a writer of a large
//! file can pause for longer than the quiet time, and a compile then reads it half-written (a
//! false syntax error, and the incremental memo lost: docs/watch.md). Where the file watcher
//! reports a file closed after writing ([`CLOSE_EVENTS`]: inotify's `IN_CLOSE_WRITE`), a
//! modified file counts as being written until that event arrives, and the batch waits for it
//! (for no longer than [`WRITING_CAP`]: a writer may keep its file open).

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Quiet time that ends a batch.
pub const QUIET: Duration = Duration::from_millis(40);
/// Quiet time after a write was finished (the file closed after writing, or renamed into
/// place): the writer is done with that file, so only a burst of further files (a `git
/// checkout`) is waited for. Without it a one-line edit's diagnostics would wait the whole
/// [`QUIET`] (docs/watch.md); it is not used for a mere modification, because a large file
/// written by a script is modified for longer than a short quiet time lasts (a compile of
/// the half-written file would report errors that are not there).
pub const SETTLED: Duration = Duration::from_millis(4);
/// Longest a batch may gather while no watched file is being written.
pub const CAP: Duration = Duration::from_millis(500);
/// Longest a batch may wait for the writer of a modified file to close it (where
/// [`CLOSE_EVENTS`]). Longer than [`CAP`]: reading a file before its writer is done reports
/// errors that are not there; a writer that keeps its file open only delays each compile by
/// this much.
pub const WRITING_CAP: Duration = Duration::from_millis(2000);
/// Whether the platform's watcher reports a file closed after writing (inotify does; macOS's
/// FSEvents, Windows and kqueue do not: there a modification is waited out by quiet time alone).
pub const CLOSE_EVENTS: bool = cfg!(any(target_os = "linux", target_os = "android"));

/// What an event says of the paths it names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Change {
    /// Named (created, removed, attributes changed): nothing about a writer.
    Named,
    /// Content modified: the writer may still have the file open and be writing.
    Writing,
    /// The writer has finished: closed after writing, or renamed into place.
    Written,
}

/// What the watch loop receives: paths from the file watcher, or the request to stop.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Msg {
    /// Paths an event named, and what it says of them.
    Paths(Change, Vec<PathBuf>),
    Quit,
}

/// One batch of changed paths (not yet confirmed by content).
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Batch {
    /// The paths events named.
    pub paths: BTreeSet<PathBuf>,
    /// Ctrl-C arrived (or the watcher went away) while gathering.
    pub quit: bool,
    /// Paths modified whose writer had not closed them when the batch ended (it reached
    /// [`WRITING_CAP`]); empty where not [`CLOSE_EVENTS`].
    pub still_writing: BTreeSet<PathBuf>,
}

/// How long the gathering waits, and for what.
#[derive(Debug, Clone, Copy)]
pub struct Timing {
    /// Quiet time after a named or modified path.
    pub quiet: Duration,
    /// Longest gathering while no path is being written.
    pub cap: Duration,
    /// Longest gathering while a path is being written.
    pub writing_cap: Duration,
    /// Whether a modified path is being written until an event says it was closed.
    pub close_events: bool,
}

impl Timing {
    /// The watch loop's: [`QUIET`], [`CAP`], [`WRITING_CAP`], [`CLOSE_EVENTS`].
    pub const WATCH: Timing = Timing {
        quiet: QUIET,
        cap: CAP,
        writing_cap: WRITING_CAP,
        close_events: CLOSE_EVENTS,
    };
}

/// Gathers the batch that `first` (already relevant paths, and what their event said) starts.
/// `relevant` filters later events: only they extend the quiet period, to `timing.quiet`, or
/// to [`SETTLED`] after a [`Change::Written`]. While a relevant path is being written (with
/// `timing.close_events`), the batch lasts until it is written, up to `timing.writing_cap`.
pub fn gather(
    rx: &Receiver<Msg>,
    first: (Change, Vec<PathBuf>),
    timing: Timing,
    relevant: impl Fn(&PathBuf) -> bool,
) -> Batch {
    let start = Instant::now();
    let mut batch = Batch::default();
    let mut deadline = start + timing.quiet;
    let mut msg = Some(Msg::Paths(first.0, first.1));
    loop {
        match msg.take() {
            Some(Msg::Paths(change, paths)) => {
                let paths: Vec<PathBuf> = paths.into_iter().filter(|p| relevant(p)).collect();
                if !paths.is_empty() {
                    deadline = Instant::now()
                        + match change {
                            Change::Written => SETTLED.min(timing.quiet),
                            Change::Named | Change::Writing => timing.quiet,
                        };
                    note(&mut batch, change, paths, timing.close_events);
                }
            }
            Some(Msg::Quit) => {
                batch.quit = true;
                return batch;
            }
            None => {}
        }
        let cap = if batch.still_writing.is_empty() {
            timing.cap
        } else {
            timing.writing_cap.max(timing.cap)
        };
        let end = if batch.still_writing.is_empty() {
            deadline.min(start + cap)
        } else {
            start + cap
        };
        let now = Instant::now();
        if now >= end {
            return batch;
        }
        match rx.recv_timeout(end - now) {
            Ok(m) => msg = Some(m),
            Err(RecvTimeoutError::Disconnected) => msg = Some(Msg::Quit),
            Err(RecvTimeoutError::Timeout) => {}
        }
    }
}

/// Adds relevant `paths` to the batch and notes which are being written. A path named by
/// another event (removed, moved away, its attributes changed) is no longer waited for: the
/// close of a file no longer in its directory is not reported there.
fn note(batch: &mut Batch, change: Change, paths: Vec<PathBuf>, close_events: bool) {
    for p in paths {
        match change {
            Change::Writing if close_events => {
                batch.still_writing.insert(p.clone());
            }
            Change::Writing => {}
            Change::Written | Change::Named => {
                batch.still_writing.remove(&p);
            }
        }
        batch.paths.insert(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;

    fn p(s: &str) -> PathBuf {
        PathBuf::from(s)
    }

    fn named(paths: &[&str]) -> Msg {
        Msg::Paths(Change::Named, paths.iter().map(|s| p(s)).collect())
    }

    fn timing(quiet_ms: u64, cap_ms: u64, writing_cap_ms: u64) -> Timing {
        Timing {
            quiet: Duration::from_millis(quiet_ms),
            cap: Duration::from_millis(cap_ms),
            writing_cap: Duration::from_millis(writing_cap_ms),
            close_events: true,
        }
    }

    #[test]
    fn a_burst_is_one_batch_and_irrelevant_paths_are_dropped() {
        let (tx, rx) = channel();
        tx.send(named(&["a.scn", "out.png"])).unwrap();
        tx.send(named(&["b.obj"])).unwrap();
        let b = gather(&rx, (Change::Named, vec![p("a.scn")]), Timing::WATCH, |x| {
            x.extension().is_some_and(|e| e != "png")
        });
        assert!(!b.quit);
        assert_eq!(b.paths, [p("a.scn"), p("b.obj")].into_iter().collect());
    }

    #[test]
    fn a_storm_is_cut_at_the_cap() {
        let (tx, rx) = channel();
        let storm = std::thread::spawn(move || {
            for _ in 0..200 {
                if tx.send(named(&["a.scn"])).is_err() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        });
        let start = Instant::now();
        let b = gather(
            &rx,
            (Change::Named, vec![p("a.scn")]),
            timing(50, 200, 2000),
            |_| true,
        );
        let took = start.elapsed();
        assert!(took >= Duration::from_millis(200), "{took:?}");
        assert!(took < Duration::from_millis(900), "{took:?}");
        assert_eq!(b.paths.len(), 1);
        drop(rx);
        storm.join().unwrap();
    }

    #[test]
    fn a_finished_write_ends_the_batch_sooner_but_a_name_does_not() {
        let (tx, rx) = channel();
        // Named (created, attributes): the whole quiet time is waited.
        let t = timing(300, 500, 2000);
        let start = Instant::now();
        let b = gather(&rx, (Change::Named, vec![p("a.scn")]), t, |_| true);
        assert!(start.elapsed() >= t.quiet, "{:?}", start.elapsed());
        assert_eq!(b.paths.len(), 1);
        // Written (closed after writing): only SETTLED.
        let start = Instant::now();
        let b = gather(&rx, (Change::Written, vec![p("a.scn")]), t, |_| true);
        assert!(start.elapsed() < t.quiet, "{:?}", start.elapsed());
        assert_eq!(b.paths.len(), 1);
        // A name after the write restores the full quiet time from then on.
        tx.send(Msg::Paths(Change::Written, vec![p("b.obj")]))
            .unwrap();
        tx.send(named(&["c.png"])).unwrap();
        let start = Instant::now();
        let b = gather(&rx, (Change::Written, vec![p("a.scn")]), t, |_| true);
        assert!(start.elapsed() >= t.quiet, "{:?}", start.elapsed());
        assert_eq!(b.paths.len(), 3);
    }

    /// A writer that pauses for longer than the quiet time (a loaded machine) between the
    /// modifications of one in-place save: the batch waits for the close, not the quiet time.
    #[test]
    fn a_modified_file_is_waited_for_until_its_writer_closes_it() {
        let (tx, rx) = channel();
        let writer = std::thread::spawn(move || {
            for _ in 0..3 {
                std::thread::sleep(Duration::from_millis(150));
                tx.send(Msg::Paths(Change::Writing, vec![p("a.scn")]))
                    .unwrap();
            }
            std::thread::sleep(Duration::from_millis(150));
            tx.send(Msg::Paths(Change::Written, vec![p("a.scn")]))
                .unwrap();
            tx
        });
        let start = Instant::now();
        let b = gather(
            &rx,
            (Change::Writing, vec![p("a.scn")]),
            timing(40, 500, 5000),
            |_| true,
        );
        let took = start.elapsed();
        // Four pauses of 150 ms, each longer than the quiet time; then SETTLED.
        assert!(took >= Duration::from_millis(600), "{took:?}");
        assert!(b.still_writing.is_empty(), "{b:?}");
        let _tx = writer.join().unwrap();
        // Without close events the quiet time alone ends it (the first pause).
        let (tx, rx) = channel::<Msg>();
        let start = Instant::now();
        let t = Timing {
            close_events: false,
            ..timing(40, 500, 5000)
        };
        let b = gather(&rx, (Change::Writing, vec![p("a.scn")]), t, |_| true);
        assert!(start.elapsed() < Duration::from_millis(500), "{b:?}");
        drop(tx);
    }

    #[test]
    fn a_writer_that_keeps_its_file_open_is_waited_for_up_to_the_writing_cap() {
        let (tx, rx) = channel::<Msg>();
        let start = Instant::now();
        let b = gather(
            &rx,
            (Change::Writing, vec![p("a.scn")]),
            timing(40, 100, 400),
            |_| true,
        );
        let took = start.elapsed();
        assert!(took >= Duration::from_millis(400), "{took:?}");
        assert!(took < Duration::from_millis(1500), "{took:?}");
        assert_eq!(b.still_writing, [p("a.scn")].into_iter().collect());
        // A file removed while written is not waited for.
        tx.send(named(&["a.scn"])).unwrap();
        let start = Instant::now();
        let b = gather(
            &rx,
            (Change::Writing, vec![p("a.scn")]),
            timing(40, 100, 2000),
            |_| true,
        );
        assert!(start.elapsed() < Duration::from_millis(400), "{b:?}");
        assert!(b.still_writing.is_empty());
    }

    #[test]
    fn quit_ends_the_batch() {
        let (tx, rx) = channel();
        tx.send(Msg::Quit).unwrap();
        let b = gather(&rx, (Change::Named, vec![]), Timing::WATCH, |_| true);
        assert!(b.quit);
    }
}
