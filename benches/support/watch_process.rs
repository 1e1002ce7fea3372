//! A `scnc watch --events json` process driven by a benchmark: started in a directory on one
//! scene file, its JSON event lines read on a thread and timestamped on arrival, so that a
//! bench can time save → event. Shared by `benches/watch.rs` and `benches/incremental.rs`
//! (included with `#[path]`; not a bench target of its own).

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

use serde_json::Value;

/// A running `scnc watch`; killed when dropped.
pub struct WatchProcess {
    child: Child,
    events: Receiver<(Instant, Value)>,
    timeout: Duration,
}

impl WatchProcess {
    /// Starts `scnc watch SCENE --events json --no-serve --no-clear` in `dir`. `timeout` bounds
    /// each wait for an event.
    pub fn start(dir: &Path, scene: &str, timeout: Duration) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_scnc"))
            .current_dir(dir)
            .args([
                "watch",
                scene,
                "--events",
                "json",
                "--no-serve",
                "--no-clear",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start scnc watch");
        let stdout = child.stdout.take().expect("piped");
        let (tx, events) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                // Timed when the line is in, before the bench parses it (an `error` event of
                // 1,000 diagnostics is about 0.5 MB of JSON).
                let arrived = Instant::now();
                if let Ok(v) = serde_json::from_str::<Value>(&line) {
                    if tx.send((arrived, v)).is_err() {
                        return;
                    }
                }
            }
        });
        WatchProcess {
            child,
            events,
            timeout,
        }
    }

    /// Waits for the next event called `name` (only a final one when `final_only`), skipping
    /// others, and returns it with its arrival time. Panics on a timeout, and on an `error`
    /// event unless that is the one waited for: a benchmark of a scene that fails when it
    /// should not measures nothing.
    pub fn wait(&self, name: &str, final_only: bool) -> (Instant, Value) {
        loop {
            let (t, v) = self
                .events
                .recv_timeout(self.timeout)
                .expect("scnc watch answers");
            if v["event"] == "error" && name != "error" {
                panic!("the scene failed: {v}");
            }
            if v["event"] == name && (!final_only || v["final"] == true) {
                return (t, v);
            }
        }
    }
}

impl WatchProcess {
    /// CPU time (ns) the process's main thread (the watch loop: confirming a change, reading,
    /// compiling, the events) has used so far, from `/proc/PID/task/PID/schedstat`; 0 where
    /// that cannot be read.
    #[allow(
        dead_code,
        reason = "benches/watch.rs includes this file and does not use it"
    )]
    pub fn main_thread_cpu_ns(&self) -> u64 {
        let pid = self.child.id();
        std::fs::read_to_string(format!("/proc/{pid}/task/{pid}/schedstat"))
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse().ok())
            .unwrap_or(0)
    }
}

impl Drop for WatchProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
