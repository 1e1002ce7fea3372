//! The preview server of `scnc watch`: the page, the image, and server-sent events that
//! announce passes and broken edits (issue 6). Plain HTTP over `std::net`, bounded waits.

mod watch_common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::time::Instant;

use serde_json::Value;
use watch_common::{scene, scene_dir, Watch, DEADLINE};

/// `http://127.0.0.1:PORT/` → `127.0.0.1:PORT`.
fn host(url: &str) -> String {
    url.trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string()
}

fn connect(host: &str, path: &str) -> TcpStream {
    let mut s = TcpStream::connect(host).expect("connect to the preview server");
    s.set_read_timeout(Some(DEADLINE)).expect("set timeout");
    write!(s, "GET {path} HTTP/1.1\r\nHost: {host}\r\n\r\n").expect("send request");
    s
}

/// (status line, headers, body) of a plain GET.
fn get(host: &str, path: &str) -> (String, String, Vec<u8>) {
    let mut bytes = Vec::new();
    connect(host, path)
        .read_to_end(&mut bytes)
        .expect("read response");
    let split = bytes
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a header block");
    let head = String::from_utf8_lossy(&bytes[..split]).into_owned();
    let (status, headers) = head.split_once("\r\n").unwrap_or((&head, ""));
    (
        status.to_string(),
        headers.to_string(),
        bytes[split + 4..].to_vec(),
    )
}

/// Reads server-sent events until one satisfies `pred`.
fn next_sse(reader: &mut impl BufRead, pred: impl Fn(&Value) -> bool) -> Value {
    let end = Instant::now() + DEADLINE;
    let mut line = String::new();
    while Instant::now() < end {
        line.clear();
        if reader.read_line(&mut line).expect("read event stream") == 0 {
            panic!("event stream closed");
        }
        if let Some(data) = line.strip_prefix("data: ") {
            let v: Value = serde_json::from_str(data.trim()).expect("JSON event");
            if pred(&v) {
                return v;
            }
        }
    }
    panic!("no matching event within {DEADLINE:?}")
}

#[test]
fn the_preview_serves_page_image_and_live_events() {
    let dir = scene_dir("server");
    let mut w = Watch::start(&dir, "scene.scn", &[]);
    let serving = w.expect("serving");
    let url = serving["url"].as_str().expect("a URL").to_string();
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    let host = host(&url);
    w.ready();

    let (status, headers, body) = get(&host, "/");
    assert!(status.contains("200"), "{status}");
    assert!(headers.contains("text/html"), "{headers}");
    let page = String::from_utf8_lossy(&body);
    assert!(page.contains("EventSource(\"/events\")") && page.contains("overlay"));

    let (status, headers, body) = get(&host, "/image.png");
    assert!(
        status.contains("200") && headers.contains("image/png"),
        "{status} {headers}"
    );
    assert!(body.starts_with(b"\x89PNG\r\n\x1a\n"));
    assert!(get(&host, "/nope").0.contains("404"));

    // A new client first gets the current state, then every new event.
    let stream = connect(&host, "/events");
    let mut sse = BufReader::new(stream);
    let first = next_sse(&mut sse, |e| e["event"] == "pass");
    let shown = first["image"].as_u64().expect("image version");

    dir.write("scene.scn", &scene(2.0));
    let pass = next_sse(&mut sse, |e| {
        e["event"] == "pass" && e["image"].as_u64().is_some_and(|v| v > shown)
    });
    let (_, _, newer) = get(&host, &format!("/image.png?v={}", pass["image"]));
    assert!(newer.starts_with(b"\x89PNG") && newer != body);

    dir.write(
        "scene.scn",
        &scene(2.0).replace("{ material white }", "{ material nope }"),
    );
    let err = next_sse(&mut sse, |e| e["event"] == "error");
    assert!(err["text"].as_str().unwrap_or("").contains("nope"), "{err}");
    // The last good image is still served under the overlay.
    let (status, _, still) = get(&host, "/image.png");
    assert!(status.contains("200") && still.starts_with(b"\x89PNG"));
}
