//! Drives the real `scnc watch` binary on a temporary scene directory and reads its
//! `--events json` lines. Every wait is bounded (polling a channel with a deadline); the child
//! is killed and the directory removed when the guard drops, also when a test fails.

#![allow(dead_code)] // Each test binary uses a different part of this helper.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use serde_json::Value;

/// Longest any single expected event may take (generous: CI machines are slow and shared).
pub const DEADLINE: Duration = Duration::from_secs(30);
/// How long to make sure something does *not* happen: longer than the batching cap (500 ms)
/// plus a compile.
pub const QUIET: Duration = Duration::from_millis(1200);

/// A directory under the system temp dir, removed on drop.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(tag: &str) -> TempDir {
        static N: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "scnc-watch-{tag}-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    pub fn path(&self, rel: &str) -> PathBuf {
        self.0.join(rel)
    }

    pub fn write(&self, rel: &str, text: &str) {
        let p = self.path(rel);
        if let Some(d) = p.parent() {
            std::fs::create_dir_all(d).expect("create dir");
        }
        std::fs::write(p, text).expect("write file");
    }

    /// Saves as vim and many IDEs do: a temporary file in the same directory, renamed over.
    pub fn write_by_rename(&self, rel: &str, text: &str) {
        let tmp = self.path(&format!(".{rel}.swp~"));
        std::fs::write(&tmp, text).expect("write temp file");
        std::fs::rename(&tmp, self.path(rel)).expect("rename over");
    }

    pub fn read(&self, rel: &str) -> Vec<u8> {
        std::fs::read(self.path(rel)).unwrap_or_default()
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The running `scnc watch`; killed on drop.
pub struct Watch {
    child: Child,
    events: Receiver<Value>,
    /// Every event received so far (for failure messages).
    pub seen: Vec<Value>,
}

impl Watch {
    /// Starts `scnc watch FILE --events json --threads 1 --no-clear` in `dir`, plus `extra`.
    pub fn start(dir: &TempDir, file: &str, extra: &[&str]) -> Watch {
        let mut child = Command::new(env!("CARGO_BIN_EXE_scnc"))
            .current_dir(&dir.0)
            .args([
                "watch",
                file,
                "--events",
                "json",
                "--threads",
                "1",
                "--no-clear",
            ])
            .args(extra)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start scnc watch");
        let stdout = child.stdout.take().expect("stdout is piped");
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { return };
                let value = serde_json::from_str(&line)
                    .unwrap_or_else(|e| panic!("not a JSON event line ({e}): {line}"));
                if tx.send(value).is_err() {
                    return;
                }
            }
        });
        Watch {
            child,
            events: rx,
            seen: Vec::new(),
        }
    }

    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// The next event named `name` (earlier events of other names are skipped).
    pub fn expect(&mut self, name: &str) -> Value {
        self.expect_where(name, |_| true)
    }

    /// The next event named `name` satisfying `pred`.
    pub fn expect_where(&mut self, name: &str, pred: impl Fn(&Value) -> bool) -> Value {
        let end = Instant::now() + DEADLINE;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            match self.events.recv_timeout(left) {
                Ok(e) => {
                    self.seen.push(e.clone());
                    if e["event"] == name && pred(&e) {
                        return e;
                    }
                }
                Err(RecvTimeoutError::Timeout) => {
                    panic!(
                        "no `{name}` event within {DEADLINE:?}; seen: {:#?}",
                        self.seen
                    )
                }
                Err(RecvTimeoutError::Disconnected) => {
                    panic!(
                        "scnc watch ended before a `{name}` event; seen: {:#?}",
                        self.seen
                    )
                }
            }
        }
    }

    /// Waits for the first compile to be watched and its last pass written; returns the
    /// `compiled` event.
    pub fn ready(&mut self) -> Value {
        let compiled = self.expect("compiled");
        self.expect("watching");
        self.expect_where("pass", |e| e["final"] == true);
        compiled
    }

    /// Asserts that no event named `name` arrives within `within`; returns what did arrive.
    pub fn expect_none(&mut self, name: &str, within: Duration) -> Vec<Value> {
        let end = Instant::now() + within;
        let mut got = Vec::new();
        while let Some(left) = end.checked_duration_since(Instant::now()) {
            match self.events.recv_timeout(left) {
                Ok(e) => {
                    self.seen.push(e.clone());
                    assert_ne!(
                        e["event"], name,
                        "unexpected event {e}; seen: {:#?}",
                        self.seen
                    );
                    got.push(e);
                }
                Err(_) => break,
            }
        }
        got
    }

    /// Waits (bounded) for the process to exit; its success.
    pub fn wait_exit(&mut self) -> bool {
        let end = Instant::now() + DEADLINE;
        while Instant::now() < end {
            if let Ok(Some(status)) = self.child.try_wait() {
                return status.success();
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        panic!("scnc watch did not exit within {DEADLINE:?}")
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A small scene: a sphere and an OBJ triangle, a point light, 32×24 at 4 spp.
pub fn scene(eye_y: f32) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, {eye_y}, -4)  target (0, 0, 0)  up (0, 1, 0)  fov 40deg }}
material white = phong {{ diffuse rgb(0.8, 0.8, 0.8)  specular 0 }}
mesh ball = sphere {{ radius 1  segments 16 }}
mesh tri = obj(\"meshes/tri.obj\")
object ball {{ material white }}
object tri {{ material white  transform {{ translate (0, 0, 1) }} }}
light key = point {{ position (2, 4, -3)  intensity rgb(30, 30, 30) }}
render {{ resolution 32 x 24  samples rgss 4  output \"out.png\" }}
"
    )
}

pub const TRI_OBJ: &str = "v -2 -1 0\nv 2 -1 0\nv 0 2 0\nf 1 2 3\n";

/// A temp dir holding `scene.scn` (from [`scene`]) and `meshes/tri.obj`.
pub fn scene_dir(tag: &str) -> TempDir {
    let dir = TempDir::new(tag);
    dir.write("scene.scn", &scene(1.0));
    dir.write("meshes/tri.obj", TRI_OBJ);
    dir
}

/// Whether `path` holds a PNG.
pub fn is_png(path: &Path) -> bool {
    std::fs::read(path).is_ok_and(|b| b.starts_with(b"\x89PNG\r\n\x1a\n"))
}
