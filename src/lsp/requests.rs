//! Language server: the requests about names and structure (definition, references, rename,
//! document symbols, folding ranges, semantic tokens), what the server announces for them, and
//! one table from method to the feature function that answers it.

use std::path::PathBuf;

use lsp_server::{ErrorCode, Request, Response};
use lsp_types::request::{
    DocumentSymbolRequest, FoldingRangeRequest, GotoDefinition, PrepareRenameRequest, References,
    Rename, Request as _, SemanticTokensFullRequest,
};
use lsp_types::{
    DocumentSymbolParams, DocumentSymbolResponse, FoldingRangeParams, GotoDefinitionParams,
    GotoDefinitionResponse, OneOf, ReferenceParams, RenameOptions, RenameParams,
    SemanticTokensFullOptions, SemanticTokensOptions, SemanticTokensParams,
    SemanticTokensServerCapabilities, ServerCapabilities, TextDocumentIdentifier,
    TextDocumentPositionParams,
};
use serde::de::DeserializeOwned;
use serde::Serialize;

use super::documents::Documents;
use super::{folding, navigation, outline, semantic};
use crate::assets::Loader;

/// LSP 3.17's `RequestFailed`: the request was valid but cannot be done (a refused rename).
const REQUEST_FAILED: i32 = -32803;

/// Announces the features answered here.
pub fn announce(capabilities: &mut ServerCapabilities) {
    capabilities.definition_provider = Some(OneOf::Left(true));
    capabilities.references_provider = Some(OneOf::Left(true));
    capabilities.rename_provider = Some(OneOf::Right(RenameOptions {
        prepare_provider: Some(true),
        work_done_progress_options: Default::default(),
    }));
    capabilities.document_symbol_provider = Some(OneOf::Left(true));
    capabilities.folding_range_provider = Some(true.into());
    capabilities.semantic_tokens_provider = Some(
        SemanticTokensServerCapabilities::SemanticTokensOptions(SemanticTokensOptions {
            legend: semantic::legend(),
            full: Some(SemanticTokensFullOptions::Bool(true)),
            range: None,
            work_done_progress_options: Default::default(),
        }),
    );
}

/// The response to `request` if it is one of the methods answered here, else the request back.
pub fn respond(documents: &Documents, request: Request) -> Result<Response, Request> {
    let d = documents;
    let answer = match request.method.as_str() {
        GotoDefinition::METHOD => run(&request, |p: GotoDefinitionParams| {
            let (path, at) = position(&p.text_document_position_params)?;
            Ok(navigation::definition(d, &path, at).map(GotoDefinitionResponse::Scalar))
        }),
        References::METHOD => run(&request, |p: ReferenceParams| {
            let (path, at) = position(&p.text_document_position)?;
            let with_declaration = p.context.include_declaration;
            Ok(navigation::references(d, &path, at, with_declaration))
        }),
        PrepareRenameRequest::METHOD => run(&request, |p: TextDocumentPositionParams| {
            let (path, at) = position(&p)?;
            Ok(navigation::prepare_rename(d, &path, at))
        }),
        Rename::METHOD => run(&request, |p: RenameParams| {
            let (path, at) = position(&p.text_document_position)?;
            navigation::rename(d, &path, at, &p.new_name).map_err(|why| (REQUEST_FAILED, why))
        }),
        DocumentSymbolRequest::METHOD => run(&request, |p: DocumentSymbolParams| {
            let text = text(d, &p.text_document)?;
            Ok(DocumentSymbolResponse::Nested(outline::symbols(&text)))
        }),
        FoldingRangeRequest::METHOD => run(&request, |p: FoldingRangeParams| {
            Ok(folding::ranges(&text(d, &p.text_document)?))
        }),
        SemanticTokensFullRequest::METHOD => run(&request, |p: SemanticTokensParams| {
            let path = file_path(&p.text_document)?;
            Ok(semantic::tokens(d, &path))
        }),
        _ => return Err(request),
    };
    Ok(match answer {
        Ok(value) => Response::new_ok(request.id, value),
        Err((code, message)) => Response::new_err(request.id, code, message),
    })
}

type Failure = (i32, String);

/// Decodes the parameters of `request` and answers with `f`.
fn run<P: DeserializeOwned, R: Serialize>(
    request: &Request,
    f: impl FnOnce(P) -> Result<R, Failure>,
) -> Result<serde_json::Value, Failure> {
    let params: P = serde_json::from_value(request.params.clone())
        .map_err(|e| (ErrorCode::InvalidParams as i32, e.to_string()))?;
    serde_json::to_value(f(params)?).map_err(|e| (ErrorCode::InternalError as i32, e.to_string()))
}

fn file_path(document: &TextDocumentIdentifier) -> Result<PathBuf, Failure> {
    document.uri.to_file_path().map_err(|()| {
        (
            ErrorCode::InvalidParams as i32,
            format!("{} is not a file", document.uri),
        )
    })
}

fn position(p: &TextDocumentPositionParams) -> Result<(PathBuf, lsp_types::Position), Failure> {
    Ok((file_path(&p.text_document)?, p.position))
}

/// The document's text: the editor's when open, else the file's.
fn text(documents: &Documents, document: &TextDocumentIdentifier) -> Result<String, Failure> {
    if let Some(open) = documents.get(&document.uri) {
        return Ok(open.text.clone());
    }
    let path = file_path(document)?;
    let bytes = documents
        .loader()
        .read(&path)
        .map_err(|e| (REQUEST_FAILED, format!("{}: {e}", path.display())))?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}
