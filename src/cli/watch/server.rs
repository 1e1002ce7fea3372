//! `scnc watch`: the preview server, HTTP/1.1 on 127.0.0.1 only (hand-written over
//! `std::net::TcpListener`: three routes need no framework, and nothing is exposed beyond this
//! machine).
//!
//! - `GET /` — the page (`page.html`): shows the image, swaps it in place when a pass arrives
//!   (preloads the new image, then swaps: no reload, no flicker), overlays the diagnostics of a
//!   broken edit on the last good image, shows render stats.
//! - `GET /image.png` — the latest finished pass, PNG.
//! - `GET /events` — server-sent events: the same JSON events `--events json` prints.

use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

const PAGE: &str = include_str!("page.html");
/// Events kept for clients that are between two reads.
const BACKLOG: usize = 64;

#[derive(Default)]
struct State {
    png: Option<Arc<Vec<u8>>>,
    image_version: u64,
    /// (sequence number, JSON text) of recent events.
    events: VecDeque<(u64, String)>,
    next_seq: u64,
    /// The last `compiled` or `error` event and the last `pass` event: what a new client
    /// needs to show the current state.
    last_outcome: Option<String>,
    last_pass: Option<String>,
}

/// What the page shows, shared by the watch loop (writer) and the connections (readers).
#[derive(Default)]
pub struct Preview {
    state: Mutex<State>,
    changed: Condvar,
}

impl Preview {
    /// Stores the PNG of a finished pass (call before the `pass` event that announces it).
    pub fn set_image(&self, png: Vec<u8>) {
        if let Ok(mut s) = self.state.lock() {
            s.png = Some(Arc::new(png));
            s.image_version += 1;
        }
    }

    /// How many images were set so far (the page asks for a new one when it changes).
    pub fn image_version(&self) -> u64 {
        self.state.lock().map_or(0, |s| s.image_version)
    }

    /// Passes a status event to the connected pages: its JSON `text`, called `name` (its
    /// `"event"`).
    pub fn event_line(&self, name: &str, text: String) {
        let Ok(mut s) = self.state.lock() else {
            return;
        };
        match name {
            "compiled" | "error" => s.last_outcome = Some(text.clone()),
            "pass" => s.last_pass = Some(text.clone()),
            _ => {}
        }
        let seq = s.next_seq;
        s.next_seq += 1;
        s.events.push_back((seq, text));
        if s.events.len() > BACKLOG {
            s.events.pop_front();
        }
        self.changed.notify_all();
    }
}

/// Binds 127.0.0.1:`port` (0: any free port), serves in background threads, and returns the
/// page's URL.
pub fn serve(preview: Arc<Preview>, port: u16) -> std::io::Result<String> {
    let listener = TcpListener::bind(("127.0.0.1", port))?;
    let url = format!("http://{}/", listener.local_addr()?);
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let preview = preview.clone();
            std::thread::spawn(move || {
                // A client that goes away mid-answer is not an error worth reporting.
                let _ = handle(stream, &preview);
            });
        }
    });
    Ok(url)
}

fn handle(stream: TcpStream, preview: &Preview) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(5)))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request = String::new();
    reader.read_line(&mut request)?;
    // Skip the headers: no route needs them.
    let mut line = String::new();
    while reader.read_line(&mut line)? > 2 {
        line.clear();
    }
    let mut parts = request.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let path = target.split('?').next().unwrap_or("");
    let mut out = stream;
    match (method, path) {
        ("GET", "/") => respond(
            &mut out,
            "200 OK",
            "text/html; charset=utf-8",
            PAGE.as_bytes(),
        ),
        ("GET", "/image.png") => {
            let png = preview.state.lock().ok().and_then(|s| s.png.clone());
            match png {
                Some(png) => respond(&mut out, "200 OK", "image/png", &png),
                None => respond(&mut out, "404 Not Found", "text/plain", b"no image yet"),
            }
        }
        ("GET", "/events") => events(out, preview),
        ("GET", _) => respond(&mut out, "404 Not Found", "text/plain", b"not found"),
        _ => respond(
            &mut out,
            "405 Method Not Allowed",
            "text/plain",
            b"GET only",
        ),
    }
}

fn respond(out: &mut TcpStream, status: &str, kind: &str, body: &[u8]) -> std::io::Result<()> {
    write!(
        out,
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    )?;
    out.write_all(body)?;
    out.flush()
}

/// Streams events until the client goes away: first the current state, then each new event.
fn events(mut out: TcpStream, preview: &Preview) -> std::io::Result<()> {
    out.write_all(
        b"HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
          Connection: keep-alive\r\n\r\n",
    )?;
    let (mut next, snapshot) = {
        let s = preview
            .state
            .lock()
            .map_err(|_| std::io::ErrorKind::Other)?;
        let snapshot: Vec<String> = [&s.last_outcome, &s.last_pass]
            .into_iter()
            .flatten()
            .cloned()
            .collect();
        (s.next_seq, snapshot)
    };
    for e in snapshot {
        write!(out, "data: {e}\n\n")?;
    }
    out.flush()?;
    loop {
        let batch: Vec<String> = {
            let s = preview
                .state
                .lock()
                .map_err(|_| std::io::ErrorKind::Other)?;
            let (s, _) = preview
                .changed
                .wait_timeout_while(s, Duration::from_secs(10), |s| s.next_seq == next)
                .map_err(|_| std::io::ErrorKind::Other)?;
            let batch = s
                .events
                .iter()
                .filter(|(seq, _)| *seq >= next)
                .map(|(_, e)| e.clone())
                .collect();
            next = s.next_seq;
            batch
        };
        if batch.is_empty() {
            // Keeps the connection alive and finds clients that went away.
            out.write_all(b": ping\n\n")?;
        }
        for e in batch {
            write!(out, "data: {e}\n\n")?;
        }
        out.flush()?;
    }
}
