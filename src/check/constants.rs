//! Stage 2, check: the table of `let` constants evaluated so far (name → value and where it
//! was declared), shared by the check, the pre-check that evaluates `let`s while parsing, and
//! the incremental re-check.
//!
//! Kept compact because a generated scene may declare tens of thousands of constants: the hash
//! index holds a `Box<str>` and a `u32` per name (24 bytes a bucket), the values lie in a list
//! beside it in declaration order (48 bytes each, no spare buckets).

use std::collections::HashMap;

use foldhash::fast::FixedState;

use super::value::Value;
use crate::source::Span;

/// `let` constants: name → (value, the name's span in its `let`).
#[derive(Debug, Default)]
pub struct Constants {
    /// Name → index in `values` (foldhash, fixed seed: a `Constants` is made for every
    /// statement the pre-check offers, and the names never order anything the user sees).
    index: HashMap<Box<str>, u32, FixedState>,
    /// Values and spans, in the order they were inserted (names are the index's keys).
    values: Vec<(Value, Span)>,
}

impl Constants {
    /// The value and declaration span of `name`, if it was evaluated.
    pub fn get(&self, name: &str) -> Option<&(Value, Span)> {
        self.index.get(name).map(|&at| &self.values[at as usize])
    }

    /// Whether `name` was evaluated.
    pub fn contains_key(&self, name: &str) -> bool {
        self.index.contains_key(name)
    }

    /// Sets `name` (the first declaration wins in the check, which looks before inserting).
    pub fn insert(&mut self, name: &str, value: Value, span: Span) {
        match self.index.get(name) {
            Some(&at) => self.values[at as usize] = (value, span),
            None => {
                self.index.insert(name.into(), self.values.len() as u32);
                self.values.push((value, span));
            }
        }
    }

    /// Forgets `name` (the list's last entry takes its place).
    pub fn remove(&mut self, name: &str) {
        let Some(at) = self.index.remove(name) else {
            return;
        };
        let at = at as usize;
        self.values.swap_remove(at);
        if at < self.values.len() {
            let moved = self.values.len() as u32;
            if let Some(slot) = self.index.values_mut().find(|slot| **slot == moved) {
                *slot = at as u32;
            }
        }
    }

    /// Room for `more` constants without growing.
    pub fn reserve(&mut self, more: usize) {
        self.index.reserve(more);
        self.values.reserve_exact(more);
    }

    /// The names, in no particular order.
    pub fn keys(&self) -> impl Iterator<Item = &str> {
        self.index.keys().map(|name| &**name)
    }

    /// Every name with its declaration span, in no particular order.
    pub fn names_and_spans(&self) -> impl Iterator<Item = (&str, Span)> {
        self.index
            .iter()
            .map(|(name, &at)| (&**name, self.values[at as usize].1))
    }

    /// The declaration spans, to shift after an edit.
    pub fn spans_mut(&mut self) -> impl Iterator<Item = &mut Span> {
        self.values.iter_mut().map(|(_, span)| span)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::FileId;

    fn at(start: u32) -> Span {
        Span {
            file: FileId(0),
            start,
            end: start + 1,
        }
    }

    #[test]
    fn removing_a_constant_keeps_the_others_reachable() {
        let mut c = Constants::default();
        c.insert("a", Value::Num(1.0), at(0));
        c.insert("b", Value::Num(2.0), at(1));
        c.insert("c", Value::Num(3.0), at(2));
        c.remove("a");
        assert!(!c.contains_key("a"));
        assert_eq!(c.get("b"), Some(&(Value::Num(2.0), at(1))));
        assert_eq!(c.get("c"), Some(&(Value::Num(3.0), at(2))));
        c.remove("c");
        assert_eq!(c.get("b"), Some(&(Value::Num(2.0), at(1))));
        assert_eq!(c.keys().count(), 1);
        c.insert("b", Value::Bool(true), at(5));
        assert_eq!(c.get("b"), Some(&(Value::Bool(true), at(5))));
    }
}
