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
/// Longest a batch may gather.
pub const CAP: Duration = Duration::from_millis(500);

/// What the watch loop receives: paths from the file watcher, or the request to stop.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Msg {
    /// Paths an event named (their content may still be changing).
    Paths(Vec<PathBuf>),
    /// Paths whose writer has finished: closed after writing, or renamed into place.
    Written(Vec<PathBuf>),
    Quit,
}

/// One batch of changed paths (not yet confirmed by content).
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Batch {
    /// The paths events named.
    pub paths: BTreeSet<PathBuf>,
    /// Ctrl-C arrived (or the watcher went away) while gathering.
    pub quit: bool,
}

/// Gathers the batch that `first` (already relevant paths; `first_written`: they came in a
/// [`Msg::Written`]) starts. `relevant` filters later events: only they extend the quiet
/// period, to `quiet`, or to [`SETTLED`] after a `Written`.
pub fn gather(
    rx: &Receiver<Msg>,
    first: Vec<PathBuf>,
    first_written: bool,
    quiet: Duration,
    cap: Duration,
    relevant: impl Fn(&PathBuf) -> bool,
) -> Batch {
    let start = Instant::now();
    let mut batch = Batch {
        paths: first.into_iter().collect(),
        quit: false,
    };
    let mut deadline = start
        + if first_written {
            SETTLED.min(quiet)
        } else {
            quiet
        };
    loop {
        let now = Instant::now();
        let end = deadline.min(start + cap);
        if now >= end {
            return batch;
        }
        match rx.recv_timeout(end - now) {
            Ok(Msg::Paths(paths)) => {
                if add_relevant(&mut batch, paths, &relevant) {
                    deadline = Instant::now() + quiet;
                }
            }
            Ok(Msg::Written(paths)) => {
                if add_relevant(&mut batch, paths, &relevant) {
                    deadline = Instant::now() + SETTLED.min(quiet);
                }
            }
            Ok(Msg::Quit) | Err(RecvTimeoutError::Disconnected) => {
                batch.quit = true;
                return batch;
            }
            Err(RecvTimeoutError::Timeout) => {}
        }
    }
}

/// Adds the relevant ones of `paths` to the batch; whether there was one.
fn add_relevant(
    batch: &mut Batch,
    paths: Vec<PathBuf>,
    relevant: &impl Fn(&PathBuf) -> bool,
) -> bool {
    let mut any = false;
    for p in paths.into_iter().filter(|p| relevant(p)) {
        any = true;
        batch.paths.insert(p);
    }
    any
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;

    fn p(s: &str) -> PathBuf {
        PathBuf::from(s)
    }

    #[test]
    fn a_burst_is_one_batch_and_irrelevant_paths_are_dropped() {
        let (tx, rx) = channel();
        tx.send(Msg::Paths(vec![p("a.scn"), p("out.png")])).unwrap();
        tx.send(Msg::Paths(vec![p("b.obj")])).unwrap();
        let b = gather(&rx, vec![p("a.scn")], false, QUIET, CAP, |x| {
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
                if tx.send(Msg::Paths(vec![p("a.scn")])).is_err() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        });
        let start = Instant::now();
        let b = gather(
            &rx,
            vec![p("a.scn")],
            false,
            Duration::from_millis(50),
            Duration::from_millis(200),
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
    fn a_finished_write_ends_the_batch_sooner_but_a_modification_does_not() {
        let (tx, rx) = channel();
        // Modified (still being written): the whole quiet time is waited.
        let quiet = Duration::from_millis(300);
        let start = Instant::now();
        let b = gather(&rx, vec![p("a.scn")], false, quiet, CAP, |_| true);
        assert!(start.elapsed() >= quiet, "{:?}", start.elapsed());
        assert_eq!(b.paths.len(), 1);
        // Written (closed after writing): only SETTLED.
        let start = Instant::now();
        let b = gather(&rx, vec![p("a.scn")], true, quiet, CAP, |_| true);
        assert!(start.elapsed() < quiet, "{:?}", start.elapsed());
        assert_eq!(b.paths.len(), 1);
        // A modification after the write restores the full quiet time from then on.
        tx.send(Msg::Written(vec![p("b.obj")])).unwrap();
        tx.send(Msg::Paths(vec![p("c.png")])).unwrap();
        let start = Instant::now();
        let b = gather(&rx, vec![p("a.scn")], true, quiet, CAP, |_| true);
        assert!(start.elapsed() >= quiet, "{:?}", start.elapsed());
        assert_eq!(b.paths.len(), 3);
    }

    #[test]
    fn quit_ends_the_batch() {
        let (tx, rx) = channel();
        tx.send(Msg::Quit).unwrap();
        let b = gather(&rx, vec![], false, QUIET, CAP, |_| true);
        assert!(b.quit);
    }
}
