//! `--frame F` and `--define NAME=VALUE` for the commands that compile a scene without
//! rendering it once (`scnc check`, `scnc ir`, `scnc watch`), so a scene can be checked,
//! dumped and previewed exactly as `scnc render` with the same flags would compile it.
//! (`scnc render` has its own, beside `--frames`.)

use clap::Args;

use super::parse::{parse_define, parse_frame};
use crate::compile::Overrides;

/// The command line's values for the scene's language.
#[derive(Debug, Clone, Default, Args)]
pub struct OverrideArgs {
    /// The value of the predefined constant `frame` (default 0).
    #[arg(long, value_name = "F", value_parser = parse_frame, allow_hyphen_values = true)]
    pub frame: Option<f64>,
    /// Replace the value of the scene's `let NAME = …` (same type); repeatable.
    #[arg(long, value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
}

impl OverrideArgs {
    /// What compile applies.
    pub fn overrides(&self) -> Overrides {
        Overrides {
            frame: self.frame.unwrap_or(0.0),
            defines: self.define.clone(),
        }
    }
}
