//! The registry of diagnostic codes: every [`Code`] any stage can emit, written once.
//!
//! Each code has a stable string (`scnc::check::unknown_material`: editors, tests and the JSON
//! output key on it, so it never changes), a one-line summary (`scnc explain --list`) and a
//! longer explanation with an example of the mistake and its fix (`scnc explain CODE`, as
//! `rustc --explain`). The explanation of `scnc::STAGE::NAME` is the Markdown file
//! `src/diag/explain/STAGE/NAME.md`, included at compile time, so a code without one does not
//! build. The table itself is [`codes!`]'s single invocation in `codes.rs`.

use std::fmt;

use serde::{Serialize, Serializer};

pub use super::codes::Code;

/// Defines [`Code`] from one table: per stage, `Variant = name: "summary"`. The stable
/// string is `scnc::stage::name`; the explanation is `explain/stage/name.md`.
macro_rules! codes {
    ($( $(#[$stage_doc:meta])* $stage:ident {
        $( $variant:ident = $name:ident : $summary:literal, )*
    } )*) => {
        /// A diagnostic code: one variant per code, grouped by the stage that emits it (the
        /// variant's prefix).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code {
            $($(
                #[doc = concat!("`scnc::", stringify!($stage), "::", stringify!($name), "`: ", $summary)]
                $variant,
            )*)*
        }

        impl Code {
            /// Every code, grouped by stage in pipeline order.
            pub const ALL: &'static [Code] = &[$($(Code::$variant,)*)*];

            /// The stable string: `scnc::check::unknown_material`.
            pub const fn as_str(self) -> &'static str {
                match self {
                    $($(Code::$variant => concat!(
                        "scnc::", stringify!($stage), "::", stringify!($name)
                    ),)*)*
                }
            }

            /// One line saying what the code means (`scnc explain --list`).
            pub const fn summary(self) -> &'static str {
                match self {
                    $($(Code::$variant => $summary,)*)*
                }
            }

            /// The long explanation in Markdown: what is wrong, an example of the mistake
            /// (a ```` ```scn ```` block) and the fix.
            pub const fn explanation(self) -> &'static str {
                match self {
                    $($(Code::$variant => include_str!(concat!(
                        "explain/", stringify!($stage), "/", stringify!($name), ".md"
                    )),)*)*
                }
            }

            /// The stage that emits it: `check` for `scnc::check::unknown_material`.
            pub const fn stage(self) -> &'static str {
                match self {
                    $($(Code::$variant => stringify!($stage),)*)*
                }
            }
        }
    };
}

pub(crate) use codes;

impl Code {
    /// The last segment of the code: `unknown_material`.
    pub fn name(self) -> &'static str {
        let s = self.as_str();
        s.rsplit("::").next().unwrap_or(s)
    }

    /// The code whose stable string is exactly `s`.
    pub fn from_str_exact(s: &str) -> Option<Code> {
        Code::ALL.iter().copied().find(|c| c.as_str() == s)
    }

    /// The codes a user's query names: the full code, or a unique tail of it
    /// (`check::unknown_material`, `unknown_material`). Several codes when the tail is shared
    /// (`unknown_material` is both a check and an OBJ code); none when nothing matches.
    pub fn lookup(query: &str) -> Vec<Code> {
        let query = query.trim();
        if let Some(c) = Code::from_str_exact(query) {
            return vec![c];
        }
        let tail = format!("::{query}");
        Code::ALL
            .iter()
            .copied()
            .filter(|c| c.as_str().ends_with(&tail))
            .collect()
    }

    /// The line a rendered diagnostic ends with, pointing at [`Code::explanation`].
    pub fn explain_hint(self) -> String {
        format!("run `scnc explain {}` for more", self.as_str())
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Serialised as its stable string, so JSON output is what it was when codes were strings.
impl Serialize for Code {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

/// Lets tests and tools compare a code with its stable string.
impl PartialEq<str> for Code {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

/// Lets tests and tools compare a code with its stable string.
impl PartialEq<&str> for Code {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_are_unique_and_well_formed() {
        let mut seen = std::collections::BTreeSet::new();
        for c in Code::ALL {
            assert!(seen.insert(c.as_str()), "{c} twice");
            let parts: Vec<&str> = c.as_str().split("::").collect();
            assert_eq!(parts.len(), 3, "{c}");
            assert_eq!(parts[0], "scnc");
            assert_eq!(parts[1], c.stage());
            assert!(
                parts[2]
                    .chars()
                    .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_'),
                "{c}"
            );
        }
    }

    #[test]
    fn every_explanation_shows_a_mistake_and_a_fix() {
        for c in Code::ALL {
            let e = c.explanation();
            assert!(
                !c.summary().is_empty() && !c.summary().ends_with('.'),
                "{c}"
            );
            assert!(e.contains("```"), "{c}: no example");
            assert!(e.lines().count() >= 3, "{c}: too short");
        }
    }

    #[test]
    fn lookup_takes_full_codes_and_unique_tails() {
        assert_eq!(
            Code::lookup("scnc::check::unknown_material"),
            [Code::CheckUnknownMaterial]
        );
        assert_eq!(
            Code::lookup("check::unknown_material"),
            [Code::CheckUnknownMaterial]
        );
        assert_eq!(Code::lookup("unknown_mesh"), [Code::CheckUnknownMesh]);
        assert_eq!(Code::lookup("unknown_material").len(), 2);
        assert!(Code::lookup("no_such_code").is_empty());
        assert!(
            Code::lookup("material").is_empty(),
            "tails are whole segments"
        );
    }

    #[test]
    fn serialises_and_compares_as_its_string() {
        let json = serde_json::to_string(&Code::SyntaxEmpty).unwrap();
        assert_eq!(json, "\"scnc::syntax::empty\"");
        assert_eq!(Code::SyntaxEmpty, "scnc::syntax::empty");
        assert_eq!(Code::SyntaxEmpty.to_string(), "scnc::syntax::empty");
        assert_eq!(Code::SyntaxEmpty.name(), "empty");
    }
}
