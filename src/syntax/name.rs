//! Stage 1 output: a name as the AST holds it (an [`crate::syntax::Ident`]'s text, a bare
//! name in an expression: `diffuse`, `leaf12`, `deg`).
//!
//! Names of up to [`INLINE`] bytes (nearly all of them: keys, units, declared names) are held
//! in the node itself, longer ones in a `Box<str>`. A statement-dense scene has several names
//! per statement, and as owned `String`s each was an allocation and a free: the allocator was
//! the largest single item of the front end's profile (docs/frontend-bench.md, nineteenth
//! session). The type is as large as a `String` (24 bytes), so no AST node grows.

use std::borrow::Borrow;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::ops::Deref;

/// The longest name held inline.
const INLINE: usize = 22;

/// A name's text: read it as a `&str` (`Deref`, [`Name::as_str`]). To own it, write
/// `as_str().to_owned()`: `to_string()` goes through `Display` and may leave spare capacity
/// (the IR's names are kept to the peak heap's byte).
#[derive(Clone)]
pub struct Name(Repr);

#[derive(Clone)]
enum Repr {
    /// The text in `bytes[..len]`, the rest zero.
    Inline { len: u8, bytes: [u8; INLINE] },
    /// Longer than [`INLINE`] bytes.
    Heap(Box<str>),
}

impl Name {
    /// `text` as a name.
    pub fn new(text: &str) -> Name {
        if text.len() <= INLINE {
            let mut bytes = [0; INLINE];
            bytes[..text.len()].copy_from_slice(text.as_bytes());
            Name(Repr::Inline {
                len: text.len() as u8,
                bytes,
            })
        } else {
            Name(Repr::Heap(text.into()))
        }
    }

    /// The text's bytes, read without the UTF-8 check [`Name::as_str`] makes: for hot
    /// comparisons (a block's keys, the name tables), where that check cost more than the
    /// comparison.
    pub fn as_bytes(&self) -> &[u8] {
        match &self.0 {
            Repr::Inline { len, bytes } => bytes.get(..*len as usize).unwrap_or_default(),
            Repr::Heap(s) => s.as_bytes(),
        }
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        match &self.0 {
            // The bytes are a whole `&str`'s (`new`), so they are UTF-8: the check cannot fail
            // (and reads at most 22 bytes, mostly ASCII's fast path).
            Repr::Inline { len, bytes } => bytes
                .get(..*len as usize)
                .and_then(|b| std::str::from_utf8(b).ok())
                .unwrap_or_default(),
            Repr::Heap(s) => s,
        }
    }
}

impl Default for Name {
    fn default() -> Name {
        Name::new("")
    }
}

impl Deref for Name {
    type Target = str;
    fn deref(&self) -> &str {
        self.as_str()
    }
}

impl AsRef<str> for Name {
    fn as_ref(&self) -> &str {
        self.as_str()
    }
}

impl Borrow<str> for Name {
    fn borrow(&self) -> &str {
        self.as_str()
    }
}

impl From<&str> for Name {
    fn from(text: &str) -> Name {
        Name::new(text)
    }
}

impl From<String> for Name {
    fn from(text: String) -> Name {
        Name::new(&text)
    }
}

impl From<Name> for String {
    fn from(name: Name) -> String {
        name.as_str().to_string()
    }
}

impl PartialEq for Name {
    fn eq(&self, other: &Name) -> bool {
        self.as_bytes() == other.as_bytes()
    }
}

impl Eq for Name {}

impl PartialEq<str> for Name {
    fn eq(&self, other: &str) -> bool {
        self.as_bytes() == other.as_bytes()
    }
}

impl PartialEq<&str> for Name {
    fn eq(&self, other: &&str) -> bool {
        self.as_bytes() == other.as_bytes()
    }
}

impl PartialEq<String> for Name {
    fn eq(&self, other: &String) -> bool {
        self.as_bytes() == other.as_bytes()
    }
}

impl Hash for Name {
    fn hash<H: Hasher>(&self, state: &mut H) {
        // As `str` hashes, so that `Borrow<str>` look-ups find it.
        self.as_str().hash(state);
    }
}

/// As a `String`'s: the AST's debug dumps are unchanged.
impl fmt::Debug for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl fmt::Display for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::Name;

    #[test]
    fn short_and_long_names_read_back_as_written() {
        for text in [
            "",
            "y",
            "leaf12",
            "exactly_twenty_two_chr",
            "é_ünïcode",
            &"n".repeat(23),
        ] {
            let name = Name::new(text);
            assert_eq!(name.as_str(), text);
            assert_eq!(format!("{name:?}"), format!("{text:?}"));
            assert_eq!(name, Name::from(text.to_string()));
        }
        assert_eq!(std::mem::size_of::<Name>(), std::mem::size_of::<String>());
    }
}
