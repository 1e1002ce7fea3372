//! Stage 2, check: the values expressions fold to, with their type names and colour encodings.
//!
//! Syntax covered: `1.5`, `30deg`, `0.5rad`, `(x, y)`, `(x, y, z)`, `"text"`, `true`/`false`,
//! `#rgb`, `#rrggbb`, `srgb(r, g, b)` (sRGB-encoded, converted to linear here), `rgb(...)` and
//! `linear(...)` (linear). All arithmetic is in f64; the IR stores f32.

use glam::{DVec2, DVec3};

/// A folded constant. Colours are always linear RGB; angles always radians.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A plain number.
    Num(f64),
    /// Radians.
    Angle(f64),
    /// `(u, v)`.
    Vec2(DVec2),
    /// `(x, y, z)`.
    Vec3(DVec3),
    /// Linear RGB.
    Color(DVec3),
    /// A string.
    Str(String),
    /// `true` or `false`.
    Bool(bool),
}

impl Value {
    /// The type as diagnostics name it.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Num(_) => "a number",
            Value::Angle(_) => "an angle",
            Value::Vec2(_) => "a 2-vector",
            Value::Vec3(_) => "a 3-vector",
            Value::Color(_) => "a colour",
            Value::Str(_) => "a string",
            Value::Bool(_) => "a boolean",
        }
    }

    /// Whether every number in it is finite.
    pub fn is_finite(&self) -> bool {
        match self {
            Value::Num(x) | Value::Angle(x) => x.is_finite(),
            Value::Vec2(v) => v.is_finite(),
            Value::Vec3(v) | Value::Color(v) => v.is_finite(),
            Value::Str(_) | Value::Bool(_) => true,
        }
    }
}

/// The sRGB transfer function, decoded: an sRGB-encoded channel in [0, 1] → linear.
pub fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// `#rgb` or `#rrggbb` (text after `#`) → linear RGB; `None` if malformed.
pub fn parse_hex(hex: &str) -> Option<DVec3> {
    if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let channel = |s: &str| u8::from_str_radix(s, 16).ok().map(f64::from);
    let (r, g, b) = match hex.len() {
        3 => {
            let d = |i: usize| channel(&hex[i..i + 1]).map(|v| v * 17.0);
            (d(0)?, d(1)?, d(2)?)
        }
        6 => (
            channel(&hex[0..2])?,
            channel(&hex[2..4])?,
            channel(&hex[4..6])?,
        ),
        _ => return None,
    };
    Some(DVec3::new(
        srgb_to_linear(r / 255.0),
        srgb_to_linear(g / 255.0),
        srgb_to_linear(b / 255.0),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_decoding_matches_the_standard() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert_eq!(srgb_to_linear(1.0), 1.0);
        // Linear segment below the knee.
        assert!((srgb_to_linear(0.04) - 0.04 / 12.92).abs() < 1e-15);
        // 0.5 encoded is 0.21404114 linear.
        assert!((srgb_to_linear(0.5) - 0.214_041_140_482_232_5).abs() < 1e-12);
        // #808080 = 128/255.
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_860_500_113_899_26).abs() < 1e-12);
    }

    #[test]
    fn hex_colours() {
        assert_eq!(parse_hex("fff"), Some(DVec3::ONE));
        assert_eq!(parse_hex("000000"), Some(DVec3::ZERO));
        let c = parse_hex("ff8000").expect("valid");
        assert_eq!(c.x, 1.0);
        assert!((c.y - srgb_to_linear(128.0 / 255.0)).abs() < 1e-15);
        assert_eq!(c.z, 0.0);
        assert_eq!(parse_hex("12345"), None);
        assert_eq!(parse_hex("ggg"), None);
    }
}
