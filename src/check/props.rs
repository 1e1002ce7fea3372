//! Stage 2, check: a block's flat item list → properties (`key value*`).
//!
//! The grammar does not know which keys a block has, so a block is split here: an item that is
//! a known key of this block starts a property, and the following items up to the next known key
//! are its values. An unknown word in key position is reported once (did-you-mean, or the list of
//! valid keys) and skipped with its values, so the rest of the block is still checked. A call
//! whose name is a key (`image("sky.hdr")` in `environment`) is a property with the call's
//! arguments as values. The typed getters for the values are in `typed.rs`.

use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::source::Span;
use crate::syntax::{Block, Expr, ExprKind, GroupStmt, Item, ObjectStmt};

/// One `key value*` property.
#[derive(Debug)]
pub struct Prop<'a> {
    pub key: &'a str,
    pub key_span: Span,
    pub values: Vec<&'a Expr>,
}

impl Prop<'_> {
    /// The span from the key to its last value.
    pub fn span(&self) -> Span {
        self.values
            .last()
            .map_or(self.key_span, |v| self.key_span.join(v.span))
    }
}

/// A block split into properties and nested blocks.
#[derive(Debug, Default)]
pub struct Props<'a> {
    pub props: Vec<Prop<'a>>,
    pub transforms: Vec<&'a Block>,
    pub objects: Vec<&'a ObjectStmt>,
    pub groups: Vec<&'a GroupStmt>,
}

impl<'a> Props<'a> {
    /// The single property `key`, if present (duplicates were already reported).
    pub fn get(&self, key: &str) -> Option<&Prop<'a>> {
        self.props.iter().find(|p| p.key == key)
    }
}

impl Checker<'_> {
    /// Splits `block` (of kind `what`, e.g. "camera") by `keys`. `repeatable` keys may appear
    /// more than once; `nested` lists which nested blocks are allowed (`transform`, `object`,
    /// `group`).
    pub fn split<'a>(
        &mut self,
        block: &'a Block,
        what: &str,
        keys: &[&'static str],
        repeatable: &[&str],
        nested: &[&str],
    ) -> Props<'a> {
        let mut out = Props::default();
        // After an unknown key or a duplicate, its values are skipped up to the next key.
        let mut skipping = false;
        for item in &block.items {
            let Item::Value(e) = item else {
                skipping = false;
                self.nested_block(item, what, nested, &mut out);
                continue;
            };
            if let Some(key) = static_key(e, keys) {
                skipping = !self.start_property(e, key, what, repeatable, &mut out);
                continue;
            }
            if skipping {
                continue;
            }
            if let Some(last) = out.props.last_mut() {
                last.values.push(e);
                continue;
            }
            self.unknown_key(e, what, keys);
            skipping = true;
        }
        out
    }

    /// A nested `transform`/`object`/`group` block: kept if `nested` allows it here.
    fn nested_block<'a>(
        &mut self,
        item: &'a Item,
        what: &str,
        nested: &[&str],
        out: &mut Props<'a>,
    ) {
        let (kind, span) = match item {
            Item::Transform(b) => ("transform", b.span),
            Item::Object(o) => ("object", o.span),
            Item::Group(g) => ("group", g.span),
            Item::Value(_) => return,
        };
        if !nested.contains(&kind) {
            self.error(
                Diagnostic::error(
                    Code::CheckMisplacedBlock,
                    format!("`{kind}` is not allowed inside {what}"),
                )
                .at(span, "not allowed here"),
            );
            return;
        }
        match item {
            Item::Transform(b) => out.transforms.push(b),
            Item::Object(o) => out.objects.push(o),
            Item::Group(g) => out.groups.push(g),
            Item::Value(_) => {}
        }
    }

    /// Starts the property `key` (a call's arguments are its first values); false when it is a
    /// duplicate that is not `repeatable` (reported, and its values are to be skipped).
    fn start_property<'a>(
        &mut self,
        e: &'a Expr,
        key: &'static str,
        what: &str,
        repeatable: &[&str],
        out: &mut Props<'a>,
    ) -> bool {
        let key_span = match &e.kind {
            ExprKind::Call(call) => call.func.span,
            _ => e.span,
        };
        if !repeatable.contains(&key) {
            if let Some(first) = out.props.iter().find(|p| p.key == key) {
                self.error(
                    Diagnostic::error(
                        Code::CheckDuplicateKey,
                        format!("`{key}` is given twice in {what}"),
                    )
                    .at(key_span, "given again here")
                    .also(first.key_span, "first given here")
                    .help("remove one of them"),
                );
                return false;
            }
        }
        let values = match &e.kind {
            ExprKind::Call(call) => call.args.iter().collect(),
            _ => Vec::new(),
        };
        out.props.push(Prop {
            key,
            key_span,
            values,
        });
        true
    }

    /// Reports an item in key position that is not a key.
    fn unknown_key(&mut self, e: &Expr, what: &str, keys: &[&'static str]) {
        let d = match &e.kind {
            ExprKind::Name(n) => Diagnostic::error(
                Code::CheckUnknownKey,
                format!("unknown key `{n}` in {what}"),
            )
            .at(e.span, "not a key here")
            .help(suggest::help_for(n, keys, "keys")),
            _ => Diagnostic::error(
                Code::CheckExpectedKey,
                format!("expected a key in {what}, found a value"),
            )
            .at(e.span, "value without a key")
            .help(format!("valid keys: {}", suggest::list(keys))),
        };
        self.error(d);
    }

    /// Exactly `n` values, or an error at the property.
    pub fn arity<'a>(&mut self, p: &Prop<'a>, n: usize, form: &str) -> Option<Vec<&'a Expr>> {
        if p.values.len() == n {
            return Some(p.values.clone());
        }
        let found = p.values.len();
        let msg = if found == 0 {
            format!("`{}` needs a value", p.key)
        } else {
            format!("`{}` takes {n} value(s), found {found}", p.key)
        };
        self.error(
            Diagnostic::error(Code::CheckWrongArity, msg)
                .at(p.span(), "here")
                .help(format!("write `{form}`")),
        );
        None
    }

    /// The single value of `p`.
    pub fn one<'a>(&mut self, p: &Prop<'a>, form: &str) -> Option<&'a Expr> {
        self.arity(p, 1, form).map(|v| v[0])
    }
}

/// The static key an item names, if it is one of `keys`.
fn static_key(e: &Expr, keys: &[&'static str]) -> Option<&'static str> {
    let name = match &e.kind {
        ExprKind::Name(n) => n.as_str(),
        ExprKind::Call(call) => call.func.name.as_str(),
        _ => return None,
    };
    keys.iter().copied().find(|k| *k == name)
}
