//! Stage 2, check: one expression as the type a key wants, or a diagnostic.
//!
//! Getters for property values: numbers (in a range, whole), angles (`30deg`: a bare number
//! is an error), vectors, colours (`rgb(...)`, `srgb(...)`, `#rrggbb` or a grey number; never
//! negative), booleans, strings and the closed word lists of `vocabulary.rs` (`wrap repeat`).
//! Each reports what it wanted and what it found, at the expression.

use glam::{DVec2, DVec3};

use super::value::Value;
use super::vocabulary::Word;
use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::source::Span;
use crate::syntax::Expr;

impl Checker<'_> {
    /// A number (`expected` names it in the error otherwise).
    pub fn num(&mut self, e: &Expr, expected: &str) -> Option<f64> {
        match self.eval(e)? {
            Value::Num(x) => Some(x),
            other => {
                self.type_error(e, expected, &other);
                None
            }
        }
    }

    /// A number in `[lo, hi]`.
    pub fn num_in(&mut self, e: &Expr, lo: f64, hi: f64, what: &str) -> Option<f64> {
        let x = self.num(e, "a number")?;
        if x < lo || x > hi {
            self.out_of_range(
                e.span,
                &format!("{what} must be in [{lo}, {hi}], found {x}"),
            );
            return None;
        }
        Some(x)
    }

    /// A whole number in `lo..=hi`.
    pub fn int_in(&mut self, e: &Expr, lo: u64, hi: u64, what: &str) -> Option<u64> {
        let x = self.num(e, "a whole number")?;
        if x.fract() != 0.0 {
            self.error(
                Diagnostic::error(
                    Code::CheckNotInteger,
                    format!("{what} must be a whole number, found {x}"),
                )
                .at(e.span, "not a whole number"),
            );
            return None;
        }
        if x < lo as f64 || x > hi as f64 {
            self.out_of_range(e.span, &format!("{what} must be in {lo}..={hi}, found {x}"));
            return None;
        }
        Some(x as u64)
    }

    /// Reports a number outside its range; `msg` says which range.
    pub fn out_of_range(&mut self, span: Span, msg: &str) {
        self.error(
            Diagnostic::error(Code::CheckOutOfRange, msg.to_string()).at(span, "out of range"),
        );
    }

    /// An angle in radians: a number with `deg` or `rad` (a bare number is an error).
    pub fn angle(&mut self, e: &Expr) -> Option<f64> {
        match self.eval(e)? {
            Value::Angle(a) => Some(a),
            Value::Num(x) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckAngleWithoutUnit,
                        format!("angle `{x}` has no unit"),
                    )
                    .at(e.span, "expected an angle")
                    .help(format!("write {x}deg or {:.2}rad", x.to_radians())),
                );
                None
            }
            other => {
                self.type_error(e, "an angle such as 30deg", &other);
                None
            }
        }
    }

    /// A 3-vector `(x, y, z)`.
    pub fn vec3(&mut self, e: &Expr) -> Option<DVec3> {
        match self.eval(e)? {
            Value::Vec3(v) => Some(v),
            other => {
                self.type_error(e, "a 3-vector such as (0, 1, 0)", &other);
                None
            }
        }
    }

    /// A 2-vector, or one number for both components.
    pub fn vec2_or_num(&mut self, e: &Expr) -> Option<DVec2> {
        match self.eval(e)? {
            Value::Vec2(v) => Some(v),
            Value::Num(x) => Some(DVec2::splat(x)),
            other => {
                self.type_error(e, "a 2-vector such as (2, 1) or a number", &other);
                None
            }
        }
    }

    /// A 3-vector, or one number for all three components.
    pub fn vec3_or_num(&mut self, e: &Expr) -> Option<DVec3> {
        match self.eval(e)? {
            Value::Vec3(v) => Some(v),
            Value::Num(x) => Some(DVec3::splat(x)),
            other => {
                self.type_error(e, "a 3-vector such as (1, 2, 1) or a number", &other);
                None
            }
        }
    }

    /// A linear colour: a colour value, or a number meaning grey. Must be non-negative.
    pub fn color(&mut self, e: &Expr) -> Option<DVec3> {
        let c = match self.eval(e)? {
            Value::Color(c) => c,
            Value::Num(x) => DVec3::splat(x),
            Value::Vec3(v) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckWrongType,
                        "expected a colour, found a 3-vector",
                    )
                    .at(e.span, "a vector does not say its encoding")
                    .help(format!(
                        "write rgb({}, {}, {}) for linear values or srgb(...) for sRGB-encoded ones",
                        v.x, v.y, v.z
                    )),
                );
                return None;
            }
            other => {
                self.type_error(e, "a colour such as rgb(1, 0.5, 0) or #ff8800", &other);
                return None;
            }
        };
        if c.min_element() < 0.0 {
            self.error(
                Diagnostic::error(Code::CheckNegativeColor, "colours must not be negative")
                    .at(e.span, "has a negative channel"),
            );
            return None;
        }
        Some(c)
    }

    /// `true` or `false`.
    pub fn boolean(&mut self, e: &Expr) -> Option<bool> {
        match self.eval(e)? {
            Value::Bool(b) => Some(b),
            other => {
                self.type_error(e, "`true` or `false`", &other);
                None
            }
        }
    }

    /// A string literal.
    pub fn string(&mut self, e: &Expr) -> Option<String> {
        match self.eval(e)? {
            Value::Str(s) => Some(s),
            other => {
                self.type_error(e, "a string in double quotes", &other);
                None
            }
        }
    }

    /// One of the words of `T` (`wrap repeat`), converted to its value.
    pub fn choice<T: Word>(&mut self, e: &Expr, what: &str) -> Option<T> {
        self.word(e, T::WORDS, what).and_then(T::from_word)
    }

    /// One of a closed set of words (`repeat`, `clamp`, ...).
    pub fn word<'k>(&mut self, e: &Expr, choices: &[&'k str], what: &str) -> Option<&'k str> {
        if let Some(n) = e.as_name() {
            if let Some(c) = choices.iter().find(|c| **c == n) {
                return Some(c);
            }
            self.error(
                Diagnostic::error(Code::CheckUnknownChoice, format!("unknown {what} `{n}`"))
                    .at(e.span, format!("not a {what}"))
                    .help(suggest::help_for(n, choices, "choices")),
            );
            return None;
        }
        self.error(
            Diagnostic::error(Code::CheckWrongType, format!("expected a {what}"))
                .at(e.span, "expected a word")
                .help(format!("choose one of {}", suggest::list(choices))),
        );
        None
    }
}
