//! Language-server latency benchmark (a program, not a test): `cargo bench --bench lsp`.
//!
//! Runs `scnc::lsp::serve` in-process on an in-memory connection, opens each example, and
//! times 40 edits per example from sending `didChange` to receiving the diagnostics published
//! for that version: the debounce (`scnc::lsp::DEBOUNCE`) plus the full `scnc check` of the
//! text (compile and build, assets read from disk). Reports median and maximum per example and
//! the check time alone (the latency less the debounce floor). Figures go to docs/lsp.md by
//! hand.

use std::path::Path;
use std::time::{Duration, Instant};

use lsp_server::{Connection, Message, Notification, Request, RequestId};
use serde_json::{json, Value};

fn notify(client: &Connection, method: &str, params: Value) {
    client
        .sender
        .send(Message::Notification(Notification::new(
            method.into(),
            params,
        )))
        .expect("the server is running");
}

fn published_version(client: &Connection, uri: &str, version: i64) {
    loop {
        match client
            .receiver
            .recv_timeout(Duration::from_secs(10))
            .expect("the server answers")
        {
            Message::Notification(n)
                if n.method == "textDocument/publishDiagnostics"
                    && n.params["uri"] == uri
                    && n.params["version"] == version =>
            {
                return
            }
            _ => {}
        }
    }
}

fn main() {
    let (server, client) = Connection::memory();
    let thread = std::thread::spawn(move || scnc::lsp::serve(&server));
    client
        .sender
        .send(Message::Request(Request::new(
            RequestId::from(1),
            "initialize".into(),
            json!({ "capabilities": {} }),
        )))
        .expect("send");
    let _ = client.receiver.recv();
    notify(&client, "initialized", json!({}));

    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut paths: Vec<_> = std::fs::read_dir(&examples)
        .expect("examples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "scn"))
        .collect();
    paths.sort();
    println!(
        "debounce {} ms; latency = didChange sent → diagnostics published",
        scnc::lsp::DEBOUNCE.as_millis()
    );
    println!(
        "{:<20} {:>7} {:>12} {:>10} {:>14}",
        "example", "bytes", "median ms", "max ms", "check ms (med)"
    );
    for path in paths {
        let text = std::fs::read_to_string(&path).expect("an example");
        let uri = format!("file://{}", path.display());
        notify(
            &client,
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "scn", "version": 1, "text": text } }),
        );
        published_version(&client, &uri, 1);
        let mut times = Vec::new();
        for version in 2..42 {
            // A real edit each time: a trailing comment that changes.
            let edited = format!("{text}// edit {version}\n");
            let start = Instant::now();
            notify(
                &client,
                "textDocument/didChange",
                json!({ "textDocument": { "uri": uri, "version": version },
                        "contentChanges": [{ "text": edited }] }),
            );
            published_version(&client, &uri, version);
            times.push(start.elapsed().as_secs_f64() * 1e3);
        }
        notify(
            &client,
            "textDocument/didClose",
            json!({ "textDocument": { "uri": uri } }),
        );
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let max = times[times.len() - 1];
        let debounce = scnc::lsp::DEBOUNCE.as_secs_f64() * 1e3;
        println!(
            "{:<20} {:>7} {:>12.1} {:>10.1} {:>14.1}",
            path.file_name().expect("a name").to_string_lossy(),
            text.len(),
            median,
            max,
            median - debounce
        );
    }
    client
        .sender
        .send(Message::Request(Request::new(
            RequestId::from(2),
            "shutdown".into(),
            Value::Null,
        )))
        .expect("send");
    let _ = client.receiver.recv();
    notify(&client, "exit", Value::Null);
    drop(client);
    let _ = thread.join();
}
