//! Stage 2, check: `scnc render --define NAME=VALUE` replaces the value of `let NAME = …`
//! with `VALUE` (an expression, parsed as the right-hand side of a `let`), for parameter
//! sweeps. The new value must have the type of the scene's value (a number stays a number,
//! a colour a colour: `scnc::cli::define_type`), and a define that names no `let` of the
//! scene is `scnc::cli::unknown_define` (with a did-you-mean).

use super::value::Value;
use super::Checker;
use crate::diag::suggest::did_you_mean;
use crate::diag::{Code, Diagnostic};
use crate::syntax::Ident;

impl Checker<'_> {
    /// The value of `let name = …` whose scene value is `scene`: `--define`'s if given (and of
    /// the same type), else `scene`. `None` when the define is in error.
    pub(super) fn define_override(&mut self, name: &Ident, scene: Value) -> Option<Value> {
        let Some((expr, used)) = self.defines.get_mut(name.name.as_str()) else {
            return Some(scene);
        };
        *used = true;
        let expr = expr.clone();
        let given = self.eval(&expr)?;
        if std::mem::discriminant(&given) == std::mem::discriminant(&scene) {
            return Some(given);
        }
        self.error(
            Diagnostic::error(
                Code::CliDefineType,
                format!(
                    "`--define {}` gives {}, but the scene's `{}` is {}",
                    name.name,
                    given.type_name(),
                    name.name,
                    scene.type_name()
                ),
            )
            .at(expr.span, "given here")
            .also(name.span, "declared here")
            .help(format!("give {} for `{}`", scene.type_name(), name.name)),
        );
        None
    }

    /// A diagnostic for each `--define` no `let` used.
    pub(super) fn unused_defines(&mut self) {
        let mut unused: Vec<(String, crate::source::Span)> = self
            .defines
            .iter()
            .filter(|(_, (_, used))| !used)
            .map(|(name, (expr, _))| (name.clone(), expr.span))
            .collect();
        unused.sort_by(|a, b| a.0.cmp(&b.0));
        for (name, span) in unused {
            let lets: Vec<&str> = self.lets.keys().collect();
            let help = match did_you_mean(&name, lets.iter().copied()) {
                Some(best) => format!("did you mean `{best}`?"),
                None => "`--define` can only replace a `let` constant of the scene".to_string(),
            };
            self.error(
                Diagnostic::error(
                    Code::CliUnknownDefine,
                    format!("`--define {name}`: the scene has no `let {name}`"),
                )
                .at(span, "this value is not used")
                .help(help),
            );
        }
    }
}
