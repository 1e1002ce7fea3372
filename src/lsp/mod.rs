//! Beside the pipeline: `scnc lsp`, the language server, over stdin/stdout.
//!
//! Open `.scn` documents → what an editor shows: the diagnostics of `scnc check` on the editor's
//! text ([`diagnostics`]: compile and build stages, same codes, UTF-16 ranges, related
//! locations, help, a link to the code's explanation); hover and completion ([`assist`]: the
//! language reference's entry of a key, a unit's normalised value, a colour's values; keys,
//! names, functions and units, on text mid-edit too); go to definition, references, rename,
//! outline, folding and semantic tokens from the [`symbols`] index (`requests.rs` dispatches
//! them); and formatting by [`crate::fmt`]. The protocol is `lsp-server` (the transport
//! rust-analyzer and ruff use) with `lsp-types`.
//!
//! Checks are debounced: a change marks the documents dirty, and they are checked once no new
//! message has arrived for [`DEBOUNCE`] (or [`DEBOUNCE_CAP`] after the first unchecked change,
//! during continuous typing); a run always checks the newest text, so no stale result is ever
//! published. Every open document is re-checked after any change, so editing an included file
//! re-checks the files that include it. An open document's text is read instead of the disk
//! ([`documents::OverlayLoader`]), for the document itself and for includes. Each document
//! keeps its [`Incremental`] front end, so a check after typing parses and checks again only
//! the statements that changed.

pub mod assist;
pub mod blocks;
pub mod completion;
pub mod context;
pub mod diagnostics;
pub mod documents;
pub mod folding;
pub mod hover;
pub mod names;
pub mod navigation;
pub mod outline;
pub mod position;
mod requests;
mod resolve;
pub mod semantic;
pub mod symbols;
pub mod workspace;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use crossbeam_channel::RecvTimeoutError;
use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument,
    Notification as _, PublishDiagnostics,
};
use lsp_types::request::{Formatting, Request as _};
use lsp_types::{
    DocumentFormattingParams, InitializeResult, PublishDiagnosticsParams, ServerCapabilities,
    ServerInfo, TextDocumentSyncCapability, TextDocumentSyncKind, TextEdit,
};

use documents::Documents;
use position::LineIndex;

use crate::compile::{Incremental, Overrides};
use crate::source::FileId;

/// Quiet time after a change before the documents are checked.
pub const DEBOUNCE: Duration = Duration::from_millis(15);
/// Longest a change waits for its check while changes keep arriving.
pub const DEBOUNCE_CAP: Duration = Duration::from_millis(150);

/// Why the server stopped other than by the client's `shutdown` + `exit`.
#[derive(Debug, thiserror::Error)]
pub enum LspError {
    /// The client broke the protocol (e.g. no `initialize` first).
    #[error("protocol error: {0}")]
    Protocol(#[from] lsp_server::ProtocolError),
    /// The connection to the client closed while a message was being sent.
    #[error("the client disconnected")]
    Disconnected,
    /// A message could not be encoded.
    #[error("cannot encode a message: {0}")]
    Json(#[from] serde_json::Error),
}

/// What the server can do, announced at `initialize`.
pub fn capabilities() -> ServerCapabilities {
    let mut capabilities = ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        document_formatting_provider: Some(lsp_types::OneOf::Left(true)),
        hover_provider: Some(lsp_types::HoverProviderCapability::Simple(true)),
        completion_provider: Some(lsp_types::CompletionOptions::default()),
        ..ServerCapabilities::default()
    };
    requests::announce(&mut capabilities);
    capabilities
}

/// Runs the server on `connection` until the client says `exit` (or disconnects).
pub fn serve(connection: &Connection) -> Result<(), LspError> {
    let initialize = InitializeResult {
        capabilities: capabilities(),
        server_info: Some(ServerInfo {
            name: "scnc".into(),
            version: Some(env!("CARGO_PKG_VERSION").into()),
        }),
    };
    let (id, _params) = connection.initialize_start()?;
    connection.initialize_finish(id, serde_json::to_value(initialize)?)?;
    Server {
        connection,
        documents: Documents::default(),
        fronts: BTreeMap::new(),
        dirty_since: None,
    }
    .run()
}

struct Server<'c> {
    connection: &'c Connection,
    documents: Documents,
    /// The incremental front end of each open document, by path (its last compile).
    fronts: BTreeMap<PathBuf, Incremental>,
    /// When the oldest unchecked change arrived.
    dirty_since: Option<Instant>,
}

impl Server<'_> {
    fn run(&mut self) -> Result<(), LspError> {
        loop {
            let message = match self.dirty_since {
                None => match self.connection.receiver.recv() {
                    Ok(m) => m,
                    Err(_) => return Ok(()),
                },
                Some(since) => {
                    let wait = DEBOUNCE.min(DEBOUNCE_CAP.saturating_sub(since.elapsed()));
                    match self.connection.receiver.recv_timeout(wait) {
                        Ok(m) => m,
                        Err(RecvTimeoutError::Timeout) => {
                            self.publish_all()?;
                            continue;
                        }
                        Err(RecvTimeoutError::Disconnected) => return Ok(()),
                    }
                }
            };
            match message {
                Message::Request(request) => {
                    if self.connection.handle_shutdown(&request)? {
                        return Ok(());
                    }
                    let response = self.respond(request);
                    self.send(Message::Response(response))?;
                }
                Message::Notification(notification) => self.notified(notification)?,
                Message::Response(_) => {}
            }
        }
    }

    fn send(&self, message: Message) -> Result<(), LspError> {
        self.connection
            .sender
            .send(message)
            .map_err(|_| LspError::Disconnected)
    }

    fn notified(&mut self, n: Notification) -> Result<(), LspError> {
        match n.method.as_str() {
            DidOpenTextDocument::METHOD => {
                if let Ok(p) =
                    n.extract::<lsp_types::DidOpenTextDocumentParams>(DidOpenTextDocument::METHOD)
                {
                    let d = p.text_document;
                    self.documents.set(d.uri, d.text, d.version);
                    self.changed();
                }
            }
            DidChangeTextDocument::METHOD => {
                if let Ok(p) = n.extract::<lsp_types::DidChangeTextDocumentParams>(
                    DidChangeTextDocument::METHOD,
                ) {
                    // Full sync: the last change holds the whole text.
                    if let Some(change) = p.content_changes.into_iter().last() {
                        self.documents.set(
                            p.text_document.uri,
                            change.text,
                            p.text_document.version,
                        );
                        self.changed();
                    }
                }
            }
            DidCloseTextDocument::METHOD => {
                if let Ok(p) =
                    n.extract::<lsp_types::DidCloseTextDocumentParams>(DidCloseTextDocument::METHOD)
                {
                    if let Some(d) = self.documents.get(&p.text_document.uri) {
                        self.fronts.remove(&d.path);
                    }
                    self.documents.close(&p.text_document.uri);
                    self.publish(p.text_document.uri, Vec::new(), None)?;
                    self.changed();
                }
            }
            // Saving changes no text the server does not have, but assets beside it may have
            // changed on disk.
            DidSaveTextDocument::METHOD => self.changed(),
            _ => {}
        }
        Ok(())
    }

    fn changed(&mut self) {
        self.dirty_since.get_or_insert_with(Instant::now);
    }

    /// Checks every open document and publishes its diagnostics (an empty list clears them).
    fn publish_all(&mut self) -> Result<(), LspError> {
        self.dirty_since = None;
        let loader = self.documents.loader();
        let mut published = Vec::new();
        for (uri, document) in self.documents.iter() {
            let front = self
                .fronts
                .entry(document.path.clone())
                .or_insert_with(|| Incremental::new(Overrides::default()));
            let (found, sources) = diagnostics::check_incremental(front, &document.path, &loader);
            let lsp = diagnostics::to_lsp(&document.path, &found, &sources);
            published.push((uri.clone(), lsp, document.version));
        }
        for (uri, lsp, version) in published {
            self.publish(uri, lsp, Some(version))?;
        }
        Ok(())
    }

    /// Publishes `diagnostics` for `uri` (at the document's `version`).
    fn publish(
        &self,
        uri: lsp_types::Url,
        diagnostics: Vec<lsp_types::Diagnostic>,
        version: Option<i32>,
    ) -> Result<(), LspError> {
        let params = PublishDiagnosticsParams::new(uri, diagnostics, version);
        self.send(Message::Notification(Notification::new(
            PublishDiagnostics::METHOD.into(),
            params,
        )))
    }

    fn respond(&self, request: Request) -> Response {
        let request = match requests::respond(&self.documents, request) {
            Ok(response) => return response,
            Err(other) => other,
        };
        let request = match assist::handle(&self.documents, request) {
            Ok(response) => return response,
            Err(request) => request,
        };
        let id = request.id.clone();
        match request.method.as_str() {
            Formatting::METHOD => match request
                .extract::<DocumentFormattingParams>(Formatting::METHOD)
            {
                Ok((id, params)) => {
                    let edits = self.format(&params.text_document.uri);
                    Response::new_ok(id, edits)
                }
                Err(e) => Response::new_err(id, ErrorCode::InvalidParams as i32, format!("{e:?}")),
            },
            other => Response::new_err(
                id,
                ErrorCode::MethodNotFound as i32,
                format!("scnc lsp does not handle {other}"),
            ),
        }
    }

    /// One edit replacing the whole text when it is not formatted; none when it is; `None` (no
    /// answer, the editor keeps its text) when it has syntax errors or is not open.
    fn format(&self, uri: &lsp_types::Url) -> Option<Vec<TextEdit>> {
        let document = self.documents.get(uri)?;
        let formatted = crate::fmt::format(FileId(0), &document.text).value?;
        if formatted == document.text {
            return Some(Vec::new());
        }
        let range = LineIndex::new(&document.text).whole();
        Some(vec![TextEdit::new(range, formatted)])
    }
}
