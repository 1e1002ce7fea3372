//! Stage 2, check: constant folding of expressions into [`Value`]s.
//!
//! Syntax covered: `+ - * /` on numbers, angles (`2 * 15deg`), vectors (componentwise, and
//! with a scalar), colours; unary minus; parentheses; names of earlier `let` constants and
//! `true`/`false`; the pure functions listed in [`FUNCTIONS`]. Every operation checks its
//! operand types and that its result is finite (`1/0`, `sqrt(-1)` are errors at the expression).
//! Recursion depth is bounded by the parser's caps on nesting and expression size.

use glam::{DVec2, DVec3};

use super::value::{parse_hex, srgb_to_linear, Value};
use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::syntax::{BinOp, Expr, ExprKind, Ident};

/// Every function callable in an expression.
pub const FUNCTIONS: &[&str] = &[
    "srgb",
    "rgb",
    "linear",
    "sin",
    "cos",
    "tan",
    "sqrt",
    "abs",
    "min",
    "max",
    "pow",
    "radians",
    "degrees",
    "normalize",
    "length",
    "dot",
    "cross",
];

impl Checker<'_> {
    /// Folds an expression; reports and returns `None` on any error (once per error).
    pub fn eval(&mut self, e: &Expr) -> Option<Value> {
        let v = self.eval_inner(e)?;
        if !v.is_finite() {
            self.error(
                Diagnostic::error(
                    Code::CheckNotFinite,
                    "this expression is not a finite number",
                )
                .at(e.span, "evaluates to infinity or NaN")
                .help("check for a division by zero or a square root of a negative number"),
            );
            return None;
        }
        Some(v)
    }

    fn eval_inner(&mut self, e: &Expr) -> Option<Value> {
        match &e.kind {
            ExprKind::Error => None,
            ExprKind::Number { value, suffix } => match suffix {
                None => Some(Value::Num(*value)),
                Some(s) if s.as_bytes() == b"deg" => Some(Value::Angle(value.to_radians())),
                Some(s) if s.as_bytes() == b"rad" => Some(Value::Angle(*value)),
                Some(_) => {
                    if let Some(s) = e.suffix() {
                        self.unknown_unit(&s);
                    }
                    None
                }
            },
            ExprKind::HexColor(hex) => match parse_hex(hex) {
                Some(c) => Some(Value::Color(c)),
                None => {
                    self.error(
                        Diagnostic::error(Code::CheckBadColor, format!("`#{hex}` is not a colour"))
                            .at(e.span, "expected 3 or 6 hex digits")
                            .help("write `#rgb` or `#rrggbb`, e.g. `#ff8800`"),
                    );
                    None
                }
            },
            ExprKind::Str(s) => Some(Value::Str(s.clone())),
            ExprKind::Name(n) => self.lookup(n, e),
            ExprKind::Paren(inner) => self.eval_inner(inner),
            ExprKind::Tuple(parts) => self.tuple(parts, e),
            ExprKind::Neg(inner) => self.negate(inner, e),
            ExprKind::Binary { op, lhs, rhs } => self.binary_op(*op, lhs, rhs, e),
            ExprKind::Call(call) => self.call(&call.func.name, call.func.span, &call.args, e),
            ExprKind::Array => {
                self.error(
                    Diagnostic::error(Code::CheckUnexpectedArray, "an array is not allowed here")
                        .at(e.span, "array")
                        .help("`[ ... ]` is only for inline mesh data and `matrix`"),
                );
                None
            }
        }
    }

    /// A suffix that is no unit, with help for the usual slips (`640x480`, `30degs`).
    fn unknown_unit(&mut self, s: &Ident) {
        let help = if s.name.starts_with('x') {
            "write the two sizes apart: `512 x 512`".to_string()
        } else if s.name.starts_with("deg") {
            "write `deg`, e.g. `30deg`".to_string()
        } else if s.name.starts_with("rad") {
            "write `rad`, e.g. `0.5rad`".to_string()
        } else {
            suggest::help_for(&s.name, super::vocabulary::UNITS, "units")
        };
        self.error(
            Diagnostic::error(Code::CheckUnknownUnit, format!("unknown unit `{}`", s.name))
                .at(s.span, "not a unit")
                .help(help),
        );
    }

    /// `-x` of a number, angle, vector or colour.
    fn negate(&mut self, inner: &Expr, e: &Expr) -> Option<Value> {
        match self.eval_inner(inner)? {
            Value::Num(x) => Some(Value::Num(-x)),
            Value::Angle(x) => Some(Value::Angle(-x)),
            Value::Vec2(v) => Some(Value::Vec2(-v)),
            Value::Vec3(v) => Some(Value::Vec3(-v)),
            Value::Color(v) => Some(Value::Color(-v)),
            other => {
                self.type_error(e, "a number, angle or vector", &other);
                None
            }
        }
    }

    /// `a op b`, or an error naming both operand types.
    fn binary_op(&mut self, op: BinOp, lhs: &Expr, rhs: &Expr, e: &Expr) -> Option<Value> {
        let a = self.eval_inner(lhs)?;
        let b = self.eval_inner(rhs)?;
        let r = binary(op, &a, &b);
        if r.is_none() {
            self.error(
                Diagnostic::error(
                    Code::CheckBadOperands,
                    format!(
                        "cannot apply `{}` to {} and {}",
                        op.symbol(),
                        a.type_name(),
                        b.type_name()
                    ),
                )
                .at(e.span, "in this expression"),
            );
        }
        r
    }

    fn lookup(&mut self, name: &str, e: &Expr) -> Option<Value> {
        match name {
            "true" => return Some(Value::Bool(true)),
            "false" => return Some(Value::Bool(false)),
            "frame" => return Some(Value::Num(self.frame)),
            _ => {}
        }
        if let Some((v, _)) = self.lets.get(name) {
            return Some(v.clone());
        }
        if self.poisoned.contains(name) {
            return None;
        }
        let candidates: Vec<&str> = self.lets.keys().collect();
        let help = match suggest::did_you_mean(name, candidates.iter().copied()) {
            Some(best) => format!("did you mean `{best}`?"),
            None => "constants must be declared with `let` before they are used".to_string(),
        };
        self.error(
            Diagnostic::error(Code::CheckUnknownName, format!("unknown name `{name}`"))
                .at(e.span, "not declared")
                .help(help),
        );
        None
    }

    fn tuple(&mut self, parts: &[Expr], e: &Expr) -> Option<Value> {
        let mut nums = Vec::with_capacity(parts.len());
        let mut ok = true;
        for p in parts {
            match self.eval_inner(p) {
                Some(Value::Num(x)) => nums.push(x),
                Some(other) => {
                    self.type_error(p, "a number (vector components are plain numbers)", &other);
                    ok = false;
                }
                None => ok = false,
            }
        }
        if !ok {
            return None;
        }
        match nums[..] {
            [x, y] => Some(Value::Vec2(DVec2::new(x, y))),
            [x, y, z] => Some(Value::Vec3(DVec3::new(x, y, z))),
            _ => {
                self.error(
                    Diagnostic::error(
                        Code::CheckBadVector,
                        format!("a vector has 2 or 3 components, found {}", nums.len()),
                    )
                    .at(e.span, "this vector"),
                );
                None
            }
        }
    }

    /// Reports a value of the wrong type where `expected` was wanted.
    pub fn type_error(&mut self, e: &Expr, expected: &str, found: &Value) {
        self.error(
            Diagnostic::error(
                Code::CheckWrongType,
                format!("expected {expected}, found {}", found.type_name()),
            )
            .at(e.span, format!("this is {}", found.type_name())),
        );
    }

    fn call(
        &mut self,
        name: &str,
        name_span: crate::source::Span,
        args: &[Expr],
        e: &Expr,
    ) -> Option<Value> {
        let arity = match name {
            "srgb" | "rgb" | "linear" => {
                if args.len() == 1 {
                    1
                } else {
                    3
                }
            }
            "min" | "max" | "pow" | "dot" | "cross" => 2,
            _ if FUNCTIONS.contains(&name) => 1,
            _ => {
                let help = if name == "image" {
                    "`image(...)` is only a texture or environment source".to_string()
                } else {
                    suggest::help_for(name, FUNCTIONS, "functions")
                };
                self.error(
                    Diagnostic::error(
                        Code::CheckUnknownFunction,
                        format!("unknown function `{name}`"),
                    )
                    .at(name_span, "not a function")
                    .help(help),
                );
                return None;
            }
        };
        if args.len() != arity {
            self.error(
                Diagnostic::error(
                    Code::CheckWrongArity,
                    format!("`{name}` takes {arity} argument(s), found {}", args.len()),
                )
                .at(e.span, "this call"),
            );
            return None;
        }
        let mut vals = Vec::with_capacity(args.len());
        for a in args {
            vals.push(self.eval_inner(a)?);
        }
        let result = apply(name, &vals);
        if result.is_none() {
            let types: Vec<&str> = vals.iter().map(Value::type_name).collect();
            self.error(
                Diagnostic::error(
                    Code::CheckWrongType,
                    format!("`{name}` cannot take {}", types.join(" and ")),
                )
                .at(e.span, "this call")
                .help(function_help(name)),
            );
        }
        result
    }
}

fn function_help(name: &str) -> &'static str {
    match name {
        "srgb" | "rgb" | "linear" => "colours take three numbers (r, g, b) or one grey value",
        "sin" | "cos" | "tan" => "trigonometry takes an angle: write `sin(30deg)`",
        "degrees" => "`degrees` takes an angle and gives a number",
        "radians" => "`radians` takes a number of degrees and gives an angle",
        "normalize" | "length" => "takes a 2- or 3-vector",
        "dot" => "takes two vectors of the same size",
        "cross" => "takes two 3-vectors",
        _ => "takes numbers",
    }
}

fn apply(name: &str, v: &[Value]) -> Option<Value> {
    use Value::*;
    Some(match (name, v) {
        ("srgb", [Num(r), Num(g), Num(b)]) => Color(DVec3::new(
            srgb_to_linear(*r),
            srgb_to_linear(*g),
            srgb_to_linear(*b),
        )),
        ("srgb", [Num(x)]) => Color(DVec3::splat(srgb_to_linear(*x))),
        ("rgb" | "linear", [Num(r), Num(g), Num(b)]) => Color(DVec3::new(*r, *g, *b)),
        ("rgb" | "linear", [Num(x)]) => Color(DVec3::splat(*x)),
        ("sin", [Angle(a)]) => Num(a.sin()),
        ("cos", [Angle(a)]) => Num(a.cos()),
        ("tan", [Angle(a)]) => Num(a.tan()),
        ("sqrt", [Num(x)]) => Num(x.sqrt()),
        ("abs", [Num(x)]) => Num(x.abs()),
        ("abs", [Angle(x)]) => Angle(x.abs()),
        ("min", [Num(a), Num(b)]) => Num(a.min(*b)),
        ("max", [Num(a), Num(b)]) => Num(a.max(*b)),
        ("pow", [Num(a), Num(b)]) => Num(a.powf(*b)),
        ("radians", [Num(x)]) => Angle(x.to_radians()),
        ("degrees", [Angle(x)]) => Num(x.to_degrees()),
        ("normalize", [Vec2(a)]) => Vec2(*a / a.length()),
        ("normalize", [Vec3(a)]) => Vec3(*a / a.length()),
        ("length", [Vec2(a)]) => Num(a.length()),
        ("length", [Vec3(a)]) => Num(a.length()),
        ("dot", [Vec2(a), Vec2(b)]) => Num(a.dot(*b)),
        ("dot", [Vec3(a), Vec3(b)]) => Num(a.dot(*b)),
        ("cross", [Vec3(a), Vec3(b)]) => Vec3(a.cross(*b)),
        _ => return None,
    })
}

/// Typed arithmetic; `None` when the operand types do not combine.
pub fn binary(op: BinOp, a: &Value, b: &Value) -> Option<Value> {
    use Value::*;
    let num = |x: f64, y: f64| match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
    };
    macro_rules! vv {
        ($x:expr, $y:expr) => {
            match op {
                BinOp::Add => $x + $y,
                BinOp::Sub => $x - $y,
                BinOp::Mul => $x * $y,
                BinOp::Div => $x / $y,
            }
        };
    }
    let scales = matches!(op, BinOp::Mul | BinOp::Div);
    Some(match (a, b) {
        (Num(x), Num(y)) => Num(num(*x, *y)),
        (Angle(x), Angle(y)) => match op {
            BinOp::Add | BinOp::Sub => Angle(num(*x, *y)),
            BinOp::Div => Num(x / y),
            BinOp::Mul => return None,
        },
        (Angle(x), Num(y)) if scales => Angle(num(*x, *y)),
        (Num(x), Angle(y)) if op == BinOp::Mul => Angle(x * y),
        (Vec2(x), Vec2(y)) => Vec2(vv!(*x, *y)),
        (Vec3(x), Vec3(y)) => Vec3(vv!(*x, *y)),
        (Color(x), Color(y)) => Color(vv!(*x, *y)),
        (Vec2(x), Num(y)) if scales => Vec2(vv!(*x, DVec2::splat(*y))),
        (Vec3(x), Num(y)) if scales => Vec3(vv!(*x, DVec3::splat(*y))),
        (Color(x), Num(y)) if scales => Color(vv!(*x, DVec3::splat(*y))),
        (Num(x), Vec2(y)) if op == BinOp::Mul => Vec2(*x * *y),
        (Num(x), Vec3(y)) if op == BinOp::Mul => Vec3(*x * *y),
        (Num(x), Color(y)) if op == BinOp::Mul => Color(*x * *y),
        _ => return None,
    })
}
