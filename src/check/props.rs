//! Stage 2, check: a block's flat item list → properties (`key value*`).
//!
//! The grammar does not know which keys a block has, so a block is split here: an item that is
//! a known key of this block starts a property, and the following items up to the next known key
//! are its values. An unknown word in key position is reported once (did-you-mean, or the list of
//! valid keys) and skipped with its values, so the rest of the block is still checked. A call
//! whose name is a key (`image("sky.hdr")` in `environment`) is a property with the call's
//! arguments as values. The typed getters for the values are in `typed.rs`.

use smallvec::SmallVec;

use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::source::Span;
use crate::syntax::{Block, Expr, ExprKind, GroupStmt, Item, ObjectStmt};

/// One `key value*` property.
#[derive(Debug)]
pub struct Prop<'a> {
    pub key: &'a str,
    pub key_span: Span,
    pub values: Values<'a>,
    /// The index in the block's items just after the last value taken from them (a following
    /// value there extends `Values::Items` without allocating).
    next_item: usize,
}

/// A property's values, borrowed where they lie in the AST: a call's arguments, or a run of
/// consecutive block items; gathered into a `Vec` only in the rare other cases (a call key with
/// values after it, values interrupted by a nested block).
#[derive(Debug, Clone)]
pub enum Values<'a> {
    /// A key written as a call: its arguments.
    Args(&'a [Expr]),
    /// Consecutive block items, every one an `Item::Value`.
    Items(&'a [Item]),
    /// Anything else.
    Gathered(Vec<&'a Expr>),
}

impl<'a> Values<'a> {
    /// How many values.
    pub fn len(&self) -> usize {
        match self {
            Values::Args(a) => a.len(),
            Values::Items(i) => i.len(),
            Values::Gathered(g) => g.len(),
        }
    }

    /// True when there is no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values in order.
    pub fn iter(&self) -> impl Iterator<Item = &'a Expr> + '_ {
        let (args, items, gathered): (&'a [Expr], &'a [Item], &[&'a Expr]) = match self {
            Values::Args(a) => (a, &[], &[]),
            Values::Items(i) => (&[], i, &[]),
            Values::Gathered(g) => (&[], &[], g),
        };
        args.iter()
            .chain(items.iter().filter_map(|i| match i {
                Item::Value(e) => Some(e),
                _ => None,
            }))
            .chain(gathered.iter().copied())
    }

    /// The last value.
    pub fn last(&self) -> Option<&'a Expr> {
        match self {
            Values::Args(a) => a.last(),
            Values::Items(i) => match i.last() {
                Some(Item::Value(e)) => Some(e),
                _ => None,
            },
            Values::Gathered(g) => g.last().copied(),
        }
    }

    /// The values as a `Vec` (for matching on their number; allocates).
    pub fn to_vec(&self) -> Vec<&'a Expr> {
        self.iter().collect()
    }
}

impl<'a> Prop<'a> {
    /// The span from the key to its last value.
    pub fn span(&self) -> Span {
        self.values
            .last()
            .map_or(self.key_span, |v| self.key_span.join(v.span))
    }

    /// Appends the value `e`, which is `items[i]`.
    fn push(&mut self, items: &'a [Item], i: usize, e: &'a Expr) {
        if let Values::Items(run) = &self.values {
            if i == self.next_item {
                let start = i - run.len();
                self.values = Values::Items(&items[start..=i]);
                self.next_item = i + 1;
                return;
            }
        }
        let mut all = self.values.to_vec();
        all.push(e);
        self.values = Values::Gathered(all);
    }
}

/// A block split into properties and nested blocks, in inline storage: most blocks have a
/// few properties and at most a nested block or two, and a block is split for every statement
/// (as `Vec`s, ≈ 3 allocations per object of a statement-dense scene; docs/frontend-bench.md).
#[derive(Debug, Default)]
pub struct Props<'a> {
    pub props: SmallVec<[Prop<'a>; 4]>,
    pub transforms: SmallVec<[&'a Block; 2]>,
    pub objects: SmallVec<[&'a ObjectStmt; 2]>,
    pub groups: SmallVec<[&'a GroupStmt; 2]>,
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
        for (i, item) in block.items.iter().enumerate() {
            let Item::Value(e) = item else {
                skipping = false;
                self.nested_block(item, what, nested, &mut out);
                continue;
            };
            if let Some(key) = static_key(e, keys) {
                skipping = !self.start_property(e, key, i + 1, what, repeatable, &mut out);
                continue;
            }
            if skipping {
                continue;
            }
            if let Some(last) = out.props.last_mut() {
                last.push(&block.items, i, e);
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
    /// `next_item` is the index of the block item after `e`.
    #[allow(
        clippy::too_many_arguments,
        reason = "the split's state, passed down once"
    )]
    fn start_property<'a>(
        &mut self,
        e: &'a Expr,
        key: &'static str,
        next_item: usize,
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
            ExprKind::Call(call) => Values::Args(&call.args),
            _ => Values::Items(&[]),
        };
        out.props.push(Prop {
            key,
            key_span,
            values,
            next_item,
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

    /// Exactly `N` values, or an error at the property.
    pub fn arity<'a, const N: usize>(
        &mut self,
        p: &Prop<'a>,
        form: impl std::fmt::Display,
    ) -> Option<[&'a Expr; N]> {
        let n = N;
        let found = p.values.len();
        if found == n {
            let mut values = p.values.iter();
            return Some(std::array::from_fn(|_| match values.next() {
                Some(v) => v,
                None => unreachable!("counted above"),
            }));
        }
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
    pub fn one<'a>(&mut self, p: &Prop<'a>, form: impl std::fmt::Display) -> Option<&'a Expr> {
        self.arity::<1>(p, form).map(|[v]| v)
    }
}

/// The static key an item names, if it is one of `keys`.
fn static_key(e: &Expr, keys: &[&'static str]) -> Option<&'static str> {
    // Bytes, not `&str`: a `Name`'s `as_str` checks UTF-8 (`syntax::Name::as_bytes`).
    let name = match &e.kind {
        ExprKind::Name(n) => n.as_bytes(),
        ExprKind::Call(call) => call.func.name.as_bytes(),
        _ => return None,
    };
    keys.iter().copied().find(|k| k.as_bytes() == name)
}
