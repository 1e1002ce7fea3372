//! Language server: hover. What the word under the cursor is, in Markdown, read from the cursor's
//! [`context`](super::context) (so it works on text that does not parse):
//!
//! - a property key: its type, unit, default and description, from the language reference's
//!   tables ([`crate::check::reference`], the data grammar/README.md is rendered from);
//! - a number with a unit: its normalised value (`30deg` → `0.5236 rad`);
//! - a colour (`#ff8800`, `srgb(...)`, `rgb(...)`, `linear(...)` with literal arguments): its
//!   linear and sRGB values;
//! - a built-in function, a kind word (`sphere`) or a unit: its reference entry.

use glam::DVec3;

use super::context::{self, end, split_unit, Context};
use crate::check::reference::{function_doc, unit_doc, Block, PROPERTIES};
use crate::check::value::{parse_hex, srgb_to_linear};
use crate::check::vocabulary::UNITS;
use crate::fmt::tokens::TokenKind;

/// A hover: the byte range it describes and its Markdown.
#[derive(Debug, Clone, PartialEq)]
pub struct Hover {
    /// Byte offsets of the word described.
    pub start: usize,
    /// End of that word.
    pub end: usize,
    /// What it is.
    pub markdown: String,
}

/// The hover at byte `offset` of `text`, if the word there is one of those above.
pub fn hover(text: &str, offset: usize) -> Option<Hover> {
    let cx = context::at(text, offset);
    if cx.in_comment_or_string {
        return None;
    }
    let token = cx.token()?;
    if token.kind != TokenKind::Word {
        return None;
    }
    let (start, word) = (token.start, token.text);
    let markdown = if word.starts_with('#') {
        hex_colour(word)?
    } else if word.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
        number(word)?
    } else {
        word_hover(&cx, word)?
    };
    let end = match cx.at {
        // A colour call covers its arguments too.
        Some(i) if markdown.starts_with("colour") && cx.is_called() => call_end(&cx, i),
        _ => start + word.len(),
    };
    Some(Hover {
        start,
        end,
        markdown,
    })
}

/// A name-like word: a key of the block it stands in, a function, a kind word.
fn word_hover(cx: &Context<'_>, word: &str) -> Option<String> {
    if let Some(block) = cx.block() {
        if let Some(p) = block.property(word) {
            return Some(p.markdown());
        }
    }
    if cx.is_called() {
        if let Some(colour) = colour_call(cx, word) {
            return Some(colour);
        }
        if let Some(f) = function_doc(word) {
            return Some(format!("{}\n\n{}", f.forms, f.takes));
        }
    }
    if cx.before.last() == Some(&"=") {
        let keyword = cx.before.iter().rev().nth(2).copied().unwrap_or_default();
        if let Some(block) = Block::of_statement(keyword, word) {
            let keys: Vec<String> = block.properties().map(|p| format!("`{}`", p.key)).collect();
            return Some(format!(
                "`{word}`: {}\n\nkeys: {}",
                block.what(),
                keys.join(", ")
            ));
        }
    }
    // A word that is a key somewhere else says where it belongs (a key typed in the wrong block).
    let elsewhere: Vec<&str> = PROPERTIES
        .iter()
        .filter(|p| p.key == word && cx.block().is_some())
        .map(|p| p.block.what())
        .collect();
    (!elsewhere.is_empty()).then(|| format!("`{word}` is a key of {}", elsewhere.join(", ")))
}

/// `30deg` → its value in radians; `0.5rad` → also in degrees.
fn number(word: &str) -> Option<String> {
    let (digits, unit) = split_unit(word);
    let value: f64 = digits.parse().ok()?;
    if !UNITS.contains(&unit) {
        return None;
    }
    let about = unit_doc(unit).unwrap_or_default();
    Some(match unit {
        "deg" => format!("`{word}` = {} rad\n\n{about}", fixed(value.to_radians())),
        _ => format!(
            "`{word}` = {} rad = {}°\n\n{about}",
            fixed(value),
            fixed(value.to_degrees())
        ),
    })
}

/// A number with 4 decimals, without trailing zeros (`0.5236`, `0.5`, `30`).
fn fixed(x: f64) -> String {
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn hex_colour(word: &str) -> Option<String> {
    let linear = parse_hex(word.strip_prefix('#')?)?;
    Some(colour("sRGB-encoded", linear))
}

/// `srgb(r, g, b)`, `rgb(...)`, `linear(...)` with one or three literal numbers.
fn colour_call(cx: &Context<'_>, word: &str) -> Option<String> {
    let i = cx.at?;
    let args = literal_args(cx, i)?;
    let written = match args.as_slice() {
        [g] => DVec3::splat(*g),
        [r, g, b] => DVec3::new(*r, *g, *b),
        _ => return None,
    };
    match word {
        "srgb" => Some(colour("sRGB-encoded", written.map(srgb_to_linear))),
        "rgb" | "linear" => Some(colour("linear", written)),
        _ => None,
    }
}

/// The numbers of the call whose name is token `i`, when they are all literal (`-` allowed).
fn literal_args(cx: &Context<'_>, i: usize) -> Option<Vec<f64>> {
    let mut args = Vec::new();
    let mut negative = false;
    for t in cx.tokens.iter().skip(i + 2) {
        match t.kind {
            TokenKind::Punct(')') => return Some(args),
            TokenKind::Punct(',') => {}
            TokenKind::Punct('-') => negative = !negative,
            TokenKind::Word => {
                let x: f64 = t.text.parse().ok()?;
                args.push(if negative { -x } else { x });
                negative = false;
            }
            _ => return None,
        }
    }
    None
}

/// The end of the call whose name is token `i` (its `)`, or the name's end).
fn call_end(cx: &Context<'_>, i: usize) -> usize {
    let name_end = cx.tokens.get(i).map_or(0, end);
    cx.tokens
        .iter()
        .skip(i + 1)
        .find(|t| t.kind == TokenKind::Punct(')'))
        .map_or(name_end, end)
}

/// The encoding sRGB applies to a linear channel in [0, 1].
fn linear_to_srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// A colour's linear and sRGB values (`written` says how it was written).
fn colour(written: &str, linear: DVec3) -> String {
    let triple = |v: DVec3| format!("({}, {}, {})", fixed(v.x), fixed(v.y), fixed(v.z));
    let mut out = format!("colour ({written})\n\nlinear {}", triple(linear));
    if linear.min_element() >= 0.0 && linear.max_element() <= 1.0 {
        let srgb = linear.map(linear_to_srgb);
        let byte = |c: f64| (c * 255.0).round() as u8;
        out.push_str(&format!(
            " · sRGB {} · #{:02x}{:02x}{:02x}",
            triple(srgb),
            byte(srgb.x),
            byte(srgb.y),
            byte(srgb.z)
        ));
    } else {
        out.push_str(" · no sRGB value (a channel is outside [0, 1]: a radiance or intensity)");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(marked: &str) -> Option<String> {
        let offset = marked.find('|').unwrap_or(0);
        hover(&marked.replacen('|', "", 1), offset).map(|h| h.markdown)
    }

    #[test]
    fn numbers_with_units_are_normalised() {
        let md = at("camera c { fov 3|0deg }").unwrap_or_default();
        assert!(md.starts_with("`30deg` = 0.5236 rad"), "{md}");
        let md = at("let a = 0.5ra|d").unwrap_or_default();
        assert!(md.starts_with("`0.5rad` = 0.5 rad = 28.6479°"), "{md}");
        assert_eq!(at("let a = 1|2"), None);
        assert_eq!(at("let a = 1e|3"), None);
        assert_eq!(at("let a = 1px|"), None);
    }

    #[test]
    fn colours_show_linear_and_srgb() {
        let md = at("let c = #80|8080").unwrap_or_default();
        assert!(
            md.contains("linear (0.2159, 0.2159, 0.2159) · sRGB (0.502, 0.502, 0.502) · #808080"),
            "{md}"
        );
        let md = at("let c = sr|gb(0.5, 1, 0)").unwrap_or_default();
        assert!(md.contains("linear (0.214, 1, 0)"), "{md}");
        let md = at("let c = r|gb(17, 12, 4)").unwrap_or_default();
        assert!(md.contains("linear (17, 12, 4) · no sRGB value"), "{md}");
        assert_eq!(
            at("let c = rg|b(a, 1, 1)").map(|m| m.starts_with("`rgb(")),
            Some(true)
        );
    }

    #[test]
    fn keys_of_the_block_show_their_reference_row() {
        let md = at("camera c { f|ov 30deg }").unwrap_or_default();
        assert!(
            md.starts_with("`fov` in a camera\n\ntype: angle · unit: `deg` or `rad`"),
            "{md}"
        );
        let md = at("light l = environment { ima|ge(\"a.hdr\") }").unwrap_or_default();
        assert!(
            md.starts_with("`image(\"file\")` in an environment light"),
            "{md}"
        );
        let md = at("mesh m = sph|ere { }").unwrap_or_default();
        assert!(md.starts_with("`sphere`: a sphere mesh"), "{md}");
    }
}
