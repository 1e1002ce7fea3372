//! Text encodings of OBJ and MTL files (stage 3, asset decoding): what bytes mean before any
//! statement is read. No `.scn` syntax of its own.
//!
//! The formats are ASCII in practice, but tools write names in whatever their platform used:
//! UTF-8 today, Latin-1/Windows-1252 in older European tools, and some Windows tools save
//! UTF-16 with a byte-order mark. The parser works on bytes, so only names (materials, groups,
//! file names) need decoding: valid UTF-8 is taken as is, anything else is read as Latin-1
//! (every byte is a character, so nothing is rejected) and the caller warns once, at the first
//! line where it happened. A UTF-16 file (BOM `FF FE` or `FE FF`) is transcoded to UTF-8 up front;
//! a UTF-8 BOM is skipped.

use std::borrow::Cow;

/// The encoding a file was found to be in, for the warning that names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Encoding {
    /// UTF-8 or ASCII, with or without a BOM (names that are not UTF-8 are read as Latin-1).
    #[default]
    Utf8,
    /// UTF-16 with the BOM `FF FE`, transcoded to UTF-8 before parsing.
    Utf16Le,
    /// UTF-16 with the BOM `FE FF`, transcoded to UTF-8 before parsing.
    Utf16Be,
}

impl Encoding {
    /// The encoding's name as warnings print it.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Utf8 => "UTF-8",
            Encoding::Utf16Le => "UTF-16 little-endian",
            Encoding::Utf16Be => "UTF-16 big-endian",
        }
    }
}

/// The file's bytes as UTF-8-compatible text (borrowed unless it was UTF-16), and what it was.
/// Unpaired UTF-16 surrogates become U+FFFD; a trailing odd byte is dropped.
pub fn to_utf8_bytes(bytes: &[u8]) -> (Cow<'_, [u8]>, Encoding) {
    let (le, body) = match bytes {
        [0xFF, 0xFE, rest @ ..] => (true, rest),
        [0xFE, 0xFF, rest @ ..] => (false, rest),
        [0xEF, 0xBB, 0xBF, rest @ ..] => return (Cow::Borrowed(rest), Encoding::Utf8),
        _ => return (Cow::Borrowed(bytes), Encoding::Utf8),
    };
    let units = body.chunks_exact(2).map(|p| {
        if le {
            u16::from_le_bytes([p[0], p[1]])
        } else {
            u16::from_be_bytes([p[0], p[1]])
        }
    });
    let text: String = char::decode_utf16(units)
        .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
        .collect();
    let enc = if le {
        Encoding::Utf16Le
    } else {
        Encoding::Utf16Be
    };
    (Cow::Owned(text.into_bytes()), enc)
}

/// A name as text, and whether it had to be read as Latin-1 (not valid UTF-8).
pub fn decode_name(bytes: &[u8]) -> (String, bool) {
    match std::str::from_utf8(bytes) {
        Ok(s) => (s.to_owned(), false),
        Err(_) => (bytes.iter().map(|&b| char::from(b)).collect(), true),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin1_names_decode_and_are_flagged() {
        assert_eq!(decode_name("bæk".as_bytes()), ("bæk".into(), false));
        assert_eq!(decode_name(b"b\xe6k"), ("bæk".into(), true));
    }

    #[test]
    fn utf16_with_bom_is_transcoded() {
        let text = "v 1 2 3\nusemtl æ\n";
        let mut le = vec![0xFF, 0xFE];
        let mut be = vec![0xFE, 0xFF];
        for u in text.encode_utf16() {
            le.extend(u.to_le_bytes());
            be.extend(u.to_be_bytes());
        }
        for (bytes, enc) in [(le, Encoding::Utf16Le), (be, Encoding::Utf16Be)] {
            let (out, got) = to_utf8_bytes(&bytes);
            assert_eq!((&*out, got), (text.as_bytes(), enc));
        }
        assert_eq!(to_utf8_bytes(b"\xEF\xBB\xBFv 1").0.as_ref(), b"v 1");
    }
}
