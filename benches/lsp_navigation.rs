//! Language-server request latency for the name and structure features (a program, not a
//! test): `cargo bench --bench lsp_navigation`.
//!
//! Runs `scnc::lsp::serve` in-process on an in-memory connection, opens each example, and times
//! 20 of each request, from sending it to receiving its response: semantic tokens, document
//! symbols, folding ranges, and definition and references of the first declared name (these
//! index the document, each open document and each `.scn` file beside it, to reach includers).
//! Prints the median per example and request. Figures go to docs/lsp.md by hand.

use std::path::Path;
use std::time::{Duration, Instant};

use lsp_server::{Connection, Message, Notification, Request, RequestId};
use serde_json::{json, Value};

const REQUESTS: [&str; 5] = [
    "textDocument/semanticTokens/full",
    "textDocument/documentSymbol",
    "textDocument/foldingRange",
    "textDocument/definition",
    "textDocument/references",
];

struct Client {
    connection: Connection,
    next_id: i32,
}

impl Client {
    fn notify(&self, method: &str, params: Value) {
        let n = Notification::new(method.into(), params);
        self.connection
            .sender
            .send(Message::Notification(n))
            .expect("the server is running");
    }

    /// Milliseconds from sending the request to its response.
    fn time(&mut self, method: &str, params: Value) -> f64 {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        let start = Instant::now();
        let request = Request::new(id.clone(), method.into(), params);
        self.connection
            .sender
            .send(Message::Request(request))
            .expect("send");
        loop {
            let message = self
                .connection
                .receiver
                .recv_timeout(Duration::from_secs(10))
                .expect("the server answers");
            if let Message::Response(r) = message {
                if r.id == id {
                    assert!(r.error.is_none(), "{method}: {:?}", r.error);
                    return start.elapsed().as_secs_f64() * 1e3;
                }
            }
        }
    }
}

/// The (line, UTF-16 column) of the first `let`, `material` or `mesh` name in `text`.
fn first_name(text: &str) -> (usize, usize) {
    for (line, l) in text.lines().enumerate() {
        for keyword in ["let ", "material ", "mesh "] {
            if l.starts_with(keyword) {
                return (line, keyword.len());
            }
        }
    }
    (0, 0)
}

fn main() {
    let (server, connection) = Connection::memory();
    let thread = std::thread::spawn(move || scnc::lsp::serve(&server));
    let mut client = Client {
        connection,
        next_id: 0,
    };
    client.time("initialize", json!({ "capabilities": {} }));
    client.notify("initialized", json!({}));

    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut paths: Vec<_> = std::fs::read_dir(&examples)
        .expect("examples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "scn"))
        .collect();
    paths.sort();
    println!("median ms of 20 requests each, from request sent to response received");
    println!(
        "{:<20} {:>7} {:>9} {:>9} {:>9} {:>11} {:>11}",
        "example", "bytes", "tokens", "symbols", "folding", "definition", "references"
    );
    for path in paths {
        let text = std::fs::read_to_string(&path).expect("an example");
        let uri = format!("file://{}", path.display());
        client.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "scn", "version": 1, "text": text } }),
        );
        let (line, character) = first_name(&text);
        let document = json!({ "textDocument": { "uri": uri } });
        let at = json!({ "textDocument": { "uri": uri },
                         "position": { "line": line, "character": character },
                         "context": { "includeDeclaration": true } });
        let mut medians = Vec::new();
        for method in REQUESTS {
            let params = if method.ends_with("definition") || method.ends_with("references") {
                &at
            } else {
                &document
            };
            let mut times: Vec<f64> = (0..20)
                .map(|_| client.time(method, params.clone()))
                .collect();
            times.sort_by(f64::total_cmp);
            medians.push(times[times.len() / 2]);
        }
        client.notify(
            "textDocument/didClose",
            json!({ "textDocument": { "uri": uri } }),
        );
        println!(
            "{:<20} {:>7} {:>9.2} {:>9.2} {:>9.2} {:>11.2} {:>11.2}",
            path.file_name().expect("a name").to_string_lossy(),
            text.len(),
            medians[0],
            medians[1],
            medians[2],
            medians[3],
            medians[4]
        );
    }
    client.time("shutdown", Value::Null);
    client.notify("exit", Value::Null);
    drop(client);
    let _ = thread.join();
}
