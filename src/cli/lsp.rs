//! `scnc lsp`: the language server ([`crate::lsp`]) on stdin/stdout, for editors to start.
//! Exit 0 after the client's `shutdown` and `exit`; 1 on a protocol error (printed to stderr).

use std::process::ExitCode;

use clap::Args;
use lsp_server::Connection;

/// `scnc lsp`'s arguments (none: editors start it as is).
#[derive(Debug, Clone, Args)]
pub struct LspArgs {
    /// Accepted and ignored: some clients pass it to every server.
    #[arg(long)]
    pub stdio: bool,
}

/// `scnc lsp`: serve until the client exits.
pub fn run(_args: &LspArgs) -> ExitCode {
    let (connection, io_threads) = Connection::stdio();
    let served = crate::lsp::serve(&connection);
    drop(connection);
    let joined = io_threads.join();
    match (served, joined) {
        (Ok(()), Ok(())) => ExitCode::SUCCESS,
        (Err(e), _) => {
            eprintln!("error: scnc lsp: {e}");
            ExitCode::FAILURE
        }
        (Ok(()), Err(e)) => {
            eprintln!("error: scnc lsp: {e}");
            ExitCode::FAILURE
        }
    }
}
