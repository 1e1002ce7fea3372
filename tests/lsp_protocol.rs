//! `scnc lsp` driven over a pipe as an editor drives it: initialize, diagnostics published on
//! open and change (exact UTF-16 ranges after non-ASCII text, codes, help, related locations,
//! cleared when fixed), includers re-checked when an included document changes, formatting,
//! shutdown and exit.

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::Duration;

use serde_json::{json, Value};

struct Client {
    child: Child,
    stdin: ChildStdin,
    incoming: Receiver<Value>,
    next_id: i64,
}

impl Client {
    fn start() -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_scnc"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("scnc lsp starts");
        let stdin = child.stdin.take().expect("stdin is piped");
        let stdout = child.stdout.take().expect("stdout is piped");
        let (send, incoming) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            loop {
                let mut length = None;
                loop {
                    let mut line = String::new();
                    if reader.read_line(&mut line).unwrap_or(0) == 0 {
                        return;
                    }
                    let line = line.trim_end();
                    if line.is_empty() {
                        break;
                    }
                    if let Some(n) = line.strip_prefix("Content-Length: ") {
                        length = n.parse::<usize>().ok();
                    }
                }
                let mut body = vec![0; length.expect("a Content-Length header")];
                if reader.read_exact(&mut body).is_err() {
                    return;
                }
                let value = serde_json::from_slice(&body).expect("the server sends JSON");
                if send.send(value).is_err() {
                    return;
                }
            }
        });
        let mut client = Client {
            child,
            stdin,
            incoming,
            next_id: 0,
        };
        let init = client.request("initialize", json!({ "capabilities": {} }));
        assert_eq!(
            init["result"]["capabilities"]["documentFormattingProvider"],
            true
        );
        client.notify("initialized", json!({}));
        client
    }

    fn send(&mut self, message: Value) {
        let body = message.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("write");
        self.stdin.flush().expect("flush");
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    /// Sends a request and waits for its response (notifications in between are dropped).
    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        loop {
            let message = self.receive();
            if message["id"] == id {
                return message;
            }
        }
    }

    fn receive(&mut self) -> Value {
        self.incoming
            .recv_timeout(Duration::from_secs(20))
            .expect("the server answers within 20 s")
    }

    /// The next diagnostics published for `uri`.
    fn diagnostics_for(&mut self, uri: &str) -> Vec<Value> {
        loop {
            let message = self.receive();
            if message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == uri
            {
                return message["params"]["diagnostics"]
                    .as_array()
                    .expect("a list")
                    .clone();
            }
        }
    }

    fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "scn", "version": 1, "text": text } }),
        );
    }

    fn change(&mut self, uri: &str, version: i64, text: &str) {
        self.notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": uri, "version": version },
                    "contentChanges": [{ "text": text }] }),
        );
    }

    fn shutdown(mut self) {
        let response = self.request("shutdown", Value::Null);
        assert!(response.get("error").is_none(), "{response}");
        self.notify("exit", Value::Null);
        let status = self.child.wait().expect("the server exits");
        assert!(status.success(), "{status}");
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-lsp-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn uri(path: &Path) -> String {
    format!("file://{}", path.display())
}

fn range(d: &Value) -> (u64, u64, u64, u64) {
    let r = &d["range"];
    let n = |v: &Value| v.as_u64().expect("a number");
    (
        n(&r["start"]["line"]),
        n(&r["start"]["character"]),
        n(&r["end"]["line"]),
        n(&r["end"]["character"]),
    )
}

const CAMERA: &str = "camera c { eye (0, 0, -1)  target (0, 0, 0) }\n";

#[test]
fn diagnostics_have_utf16_ranges_codes_help_and_clear_when_fixed() {
    let dir = temp_dir("diag");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    // `𝛼` is two UTF-16 units and four bytes: the error is at UTF-16 column 23.
    client.open(
        &main,
        &format!("scnc 1\nlet s = \"é𝛼\"  let b = nope + 1\n{CAMERA}"),
    );
    let diags = client.diagnostics_for(&main);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(range(&diags[0]), (1, 23, 1, 27));
    assert_eq!(diags[0]["code"], "scnc::check::unknown_name");
    assert_eq!(diags[0]["severity"], 1);
    let message = diags[0]["message"].as_str().expect("a message");
    assert!(message.starts_with("unknown name `nope`"), "{message}");
    assert!(
        message.contains("\nhelp: constants must be declared"),
        "{message}"
    );

    // A duplicate: the first declaration is a related location.
    client.change(&main, 2, &format!("scnc 1\nlet a = 1\nlet a = 2\n{CAMERA}"));
    let diags = client.diagnostics_for(&main);
    let duplicate = diags
        .iter()
        .find(|d| d["code"] == "scnc::check::duplicate_name")
        .unwrap_or_else(|| panic!("a duplicate_name diagnostic in {diags:?}"));
    let related = &duplicate["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], main.as_str());
    assert_eq!(related["location"]["range"]["start"]["line"], 1);

    client.change(&main, 3, &format!("scnc 1\nlet a = 1\n{CAMERA}"));
    let diags = client.diagnostics_for(&main);
    assert!(
        diags.iter().all(|d| d["severity"] != 1),
        "errors left after the fix: {diags:?}"
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn build_stage_diagnostics_report_a_missing_mesh_file() {
    let dir = temp_dir("build");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    let text = format!(
        "scnc 1\n{CAMERA}mesh m = obj(\"missing.obj\")\nmaterial w = phong {{ diffuse rgb(0.5, 0.5, 0.5) }}\nobject m {{ material w }}\n"
    );
    client.open(&main, &text);
    let diags = client.diagnostics_for(&main);
    let missing = diags
        .iter()
        .find(|d| d["code"] == "scnc::build::missing_file")
        .unwrap_or_else(|| panic!("a missing_file diagnostic in {diags:?}"));
    assert_eq!(range(missing), (2, 13, 2, 26));
    assert_eq!(diags.len(), 1, "{diags:?}");
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn editing_an_included_document_rechecks_its_includer() {
    let dir = temp_dir("include");
    let (main_path, lib_path) = (dir.join("main.scn"), dir.join("lib.scn"));
    std::fs::write(&lib_path, "scnc 1\nlet k = 1\n").expect("write");
    let (main, lib) = (uri(&main_path), uri(&lib_path));
    let mut client = Client::start();
    client.open(
        &main,
        &format!("scnc 1\ninclude \"lib.scn\"\nlet b = k\n{CAMERA}"),
    );
    assert!(client.diagnostics_for(&main).is_empty());
    // The unsaved editor text of lib.scn is what main.scn includes.
    client.open(&lib, "scnc 1\nlet renamed = 1\n");
    let diags = client.diagnostics_for(&main);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(diags[0]["code"], "scnc::check::unknown_name");
    assert_eq!(range(&diags[0]), (2, 8, 2, 9));
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn formatting_replaces_the_document_or_refuses_syntax_errors() {
    let dir = temp_dir("format");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    client.open(&main, "scnc 1\n// é\nlet a=1\n");
    let params = json!({ "textDocument": { "uri": main }, "options": { "tabSize": 2, "insertSpaces": true } });
    let edits = client.request("textDocument/formatting", params.clone());
    assert_eq!(
        edits["result"],
        json!([{ "range": { "start": { "line": 0, "character": 0 }, "end": { "line": 3, "character": 0 } },
                 "newText": "scnc 1\n// é\nlet a = 1\n" }])
    );
    client.change(&main, 2, "scnc 1\n// é\nlet a = 1\n");
    assert_eq!(
        client.request("textDocument/formatting", params.clone())["result"],
        json!([])
    );
    client.change(&main, 3, "scnc 1\nobject o {\n");
    assert_eq!(
        client.request("textDocument/formatting", params)["result"],
        Value::Null
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}
