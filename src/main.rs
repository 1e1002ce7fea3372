//! The `scnc` binary: a thin wrapper over `scnc::cli`.

fn main() -> std::process::ExitCode {
    scnc::cli::main()
}
