//! The one result shape of every pipeline stage: [`Staged`], a value (if the stage could make
//! one) and every diagnostic collected so far.
//!
//! `syntax::parse`, `check::check`, `compile::compile_file`, `scene::build` and `film::write`
//! all return it, so a driver chains stages with [`Staged::and_then`] and reports the
//! accumulated diagnostics once, at the end (`cli::report`).
//!
//! Why not `Result<Warned<T>, Vec<Diagnostic>>` (typst's `SourceResult` + `Warned`): a stage
//! that fails still has warnings, and one that succeeds still has diagnostics, so both arms
//! would carry the same list; one struct with an optional value says that directly, and the
//! chain needs no conversions between the two arms.

use super::Diagnostic;

/// A stage's output: `value` is `None` when the stage could not produce one (then at least
/// one diagnostic is an error; a stage that recovers, as the parser does, may also return a
/// partial value beside errors); `diagnostics` holds every error and warning so far, in the
/// order they should be reported.
#[derive(Debug, Clone)]
#[must_use = "a stage's diagnostics must be reported"]
pub struct Staged<T> {
    /// What the stage made; `None` when it failed.
    pub value: Option<T>,
    /// Errors and warnings of this stage and of every stage before it in the chain.
    pub diagnostics: Vec<Diagnostic>,
}

impl<T> Staged<T> {
    /// A value with the diagnostics (warnings) found while making it.
    pub fn new(value: Option<T>, diagnostics: Vec<Diagnostic>) -> Staged<T> {
        Staged { value, diagnostics }
    }

    /// A value without any diagnostic.
    pub fn ok(value: T) -> Staged<T> {
        Staged::new(Some(value), Vec::new())
    }

    /// No value: the stage failed with these diagnostics (at least one an error).
    pub fn failed(diagnostics: Vec<Diagnostic>) -> Staged<T> {
        Staged::new(None, diagnostics)
    }

    /// A value, or one diagnostic saying why there is none.
    pub fn from_result(result: Result<T, Diagnostic>) -> Staged<T> {
        match result {
            Ok(value) => Staged::ok(value),
            Err(d) => Staged::failed(vec![d]),
        }
    }

    /// Whether any diagnostic so far is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// Transforms the value, keeping the diagnostics.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Staged<U> {
        Staged::new(self.value.map(f), self.diagnostics)
    }

    /// Runs the next stage on the value (if there is one); its diagnostics follow this
    /// stage's. Without a value the next stage does not run and the diagnostics pass through.
    pub fn and_then<U>(self, next: impl FnOnce(T) -> Staged<U>) -> Staged<U> {
        let Staged {
            value,
            mut diagnostics,
        } = self;
        match value {
            None => Staged::failed(diagnostics),
            Some(value) => {
                let later = next(value);
                diagnostics.extend(later.diagnostics);
                Staged::new(later.value, diagnostics)
            }
        }
    }

    /// Appends diagnostics found outside the stage (they do not remove the value).
    pub fn with_diagnostics(mut self, more: impl IntoIterator<Item = Diagnostic>) -> Staged<T> {
        self.diagnostics.extend(more);
        self
    }

    /// The value and the diagnostics, apart.
    pub fn into_parts(self) -> (Option<T>, Vec<Diagnostic>) {
        (self.value, self.diagnostics)
    }

    /// The value and its warnings, or every diagnostic when there is no value (for callers
    /// that only want to know whether the stage succeeded, as tests do).
    pub fn into_result(self) -> Result<(T, Vec<Diagnostic>), Vec<Diagnostic>> {
        match self.value {
            Some(value) => Ok((value, self.diagnostics)),
            None => Err(self.diagnostics),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Staged;
    use crate::diag::Diagnostic;

    fn warning(message: &str) -> Diagnostic {
        Diagnostic::warning("scnc::build::degenerate_triangles", message)
    }

    #[test]
    fn and_then_appends_the_next_stages_diagnostics() {
        let chained = Staged::new(Some(1), vec![warning("a")])
            .and_then(|v| Staged::new(Some(v + 1), vec![warning("b")]));
        assert_eq!(chained.value, Some(2));
        let messages: Vec<_> = chained
            .diagnostics
            .iter()
            .map(|d| d.message.as_str())
            .collect();
        assert_eq!(messages, ["a", "b"]);
    }

    #[test]
    fn a_failed_stage_stops_the_chain() {
        let failed: Staged<i32> = Staged::failed(vec![Diagnostic::error("scnc::io::read", "x")]);
        let chained = failed.and_then(|_| -> Staged<i32> { unreachable!("not run") });
        assert!(chained.value.is_none());
        assert!(chained.has_errors());
    }
}
