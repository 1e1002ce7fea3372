//! Language server: the assist requests — hover and completion — answered from an open
//! document's text at the requested position ([`super::hover`], [`super::completion`]) and its
//! [`SymbolIndex`] (the names it and its includes declare: a name's hover says what it is and
//! where it is declared; completion offers the names of the kind a key expects).

use lsp_server::{ErrorCode, Request, Response};
use lsp_types::request::{Completion, HoverRequest, Request as _};
use lsp_types::{
    CompletionParams, CompletionResponse, Hover, HoverContents, HoverParams, MarkupContent,
    MarkupKind, TextDocumentPositionParams,
};

use super::documents::{Document, Documents};
use super::position::LineIndex;
use super::symbols::SymbolIndex;
use super::{completion, hover, names};

/// The response to `request` when it is an assist request; the request back otherwise.
pub fn handle(documents: &Documents, request: Request) -> Result<Response, Request> {
    match request.method.as_str() {
        HoverRequest::METHOD => Ok(answer(request, |p: HoverParams| {
            hover_at(documents, &p.text_document_position_params)
        })),
        Completion::METHOD => Ok(answer(request, |p: CompletionParams| {
            completion_at(documents, &p.text_document_position)
        })),
        _ => Err(request),
    }
}

/// Decodes the parameters, runs `f`, encodes its answer (`null` for `None`).
fn answer<P: serde::de::DeserializeOwned, R: serde::Serialize>(
    request: Request,
    f: impl FnOnce(P) -> Option<R>,
) -> Response {
    let id = request.id.clone();
    match serde_json::from_value::<P>(request.params) {
        Ok(params) => Response::new_ok(id, f(params)),
        Err(e) => Response::new_err(id, ErrorCode::InvalidParams as i32, e.to_string()),
    }
}

/// The open document and the byte offset of a position in it.
fn locate<'d>(
    documents: &'d Documents,
    at: &TextDocumentPositionParams,
) -> Option<(&'d Document, usize)> {
    let document = documents.get(&at.text_document.uri)?;
    let offset = LineIndex::new(&document.text).offset(at.position);
    Some((document, offset))
}

fn hover_at(documents: &Documents, at: &TextDocumentPositionParams) -> Option<Hover> {
    let (document, offset) = locate(documents, at)?;
    let found =
        name_hover(documents, document, offset).or_else(|| hover::hover(&document.text, offset))?;
    let index = LineIndex::new(&document.text);
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: found.markdown,
        }),
        range: Some(index.range(found.start, found.end)),
    })
}

/// The hover of a declared name at `offset`: what it is and where it is declared.
fn name_hover(documents: &Documents, document: &Document, offset: usize) -> Option<hover::Hover> {
    let index = SymbolIndex::build(&document.path, &documents.loader());
    let file = index.file(&document.path)?;
    let occurrence = index.at(file, offset)?;
    let symbol = index.symbol(occurrence.symbol);
    Some(hover::Hover {
        start: occurrence.span.start as usize,
        end: occurrence.span.end as usize,
        markdown: names::summary(symbol, index.sources()),
    })
}

fn completion_at(
    documents: &Documents,
    at: &TextDocumentPositionParams,
) -> Option<CompletionResponse> {
    let (document, offset) = locate(documents, at)?;
    let declared = names::declared(&SymbolIndex::build(&document.path, &documents.loader()));
    let items = completion::complete(&document.text, offset, &declared);
    Some(CompletionResponse::Array(items))
}
