//! OBJ/MTL number parsing (stage 3, asset decoding): the numbers of `v 1.5 -2e+3 +.25`,
//! `vt 2. 0`, `f 1/2/3 -1//-2`.
//!
//! Floats are read by hand because `str::parse` needs valid UTF-8 and a separate scan for the
//! token's end, and it dominates a large OBJ's load time. The fast path (Clinger 1990) reads
//! up to 19 significant digits into an integer `m` and a decimal exponent `e`; when `m < 2⁵³`
//! and `|e| ≤ 22`, `m·10^e` is one correctly rounded f64 operation. Rounding that f64 to f32 is
//! then exact unless the f64 landed exactly on an f32 rounding midpoint (double rounding): that
//! case, subnormal results and everything outside the fast path go to `str::parse::<f32>`, so
//! every result is the correctly rounded f32 of the decimal text. Accepted forms: optional sign
//! (`+1`), `2.`, `.5`, exponent `e`/`E` with optional sign (`1e+2`), `inf`/`nan` (any case).

/// Powers of ten exactly representable in f64.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Parses one whole token as an f32; `None` if it is not a number.
pub fn parse_f32(tok: &[u8]) -> Option<f32> {
    let (neg, rest) = match tok.first() {
        Some(b'-') => (true, &tok[1..]),
        Some(b'+') => (false, &tok[1..]),
        _ => (false, tok),
    };
    let mut i = 0;
    let mut mantissa: u64 = 0;
    let mut digits = 0u32; // significant digits kept in `mantissa`
    let mut dropped = false; // digits beyond 19 (the fast path cannot use them)
    let mut exp: i64 = 0;
    let mut any = false;
    while let Some(&c) = rest.get(i) {
        if !c.is_ascii_digit() {
            break;
        }
        any = true;
        accumulate(&mut mantissa, &mut digits, &mut dropped, &mut exp, c, false);
        i += 1;
    }
    if rest.get(i) == Some(&b'.') {
        i += 1;
        while let Some(&c) = rest.get(i) {
            if !c.is_ascii_digit() {
                break;
            }
            any = true;
            accumulate(&mut mantissa, &mut digits, &mut dropped, &mut exp, c, true);
            i += 1;
        }
    }
    if !any {
        return special(rest).map(|v| if neg { -v } else { v });
    }
    if let Some(b'e' | b'E') = rest.get(i) {
        i += 1;
        let eneg = match rest.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        let mut e: i64 = 0;
        while let Some(&c) = rest.get(i) {
            if !c.is_ascii_digit() {
                break;
            }
            // Saturate: an exponent of a million digits is still just "huge".
            e = (e * 10 + i64::from(c - b'0')).min(1_000_000);
            i += 1;
        }
        if i == start {
            return None;
        }
        exp += if eneg { -e } else { e };
    }
    if i != rest.len() {
        return None;
    }
    let value = if dropped || mantissa >= 1 << 53 || exp.abs() > 22 {
        None
    } else if mantissa == 0 {
        Some(0.0)
    } else {
        fast(mantissa, exp)
    };
    let v = match value {
        Some(v) => v,
        None => slow(rest)?,
    };
    Some(if neg { -v } else { v })
}

fn accumulate(m: &mut u64, digits: &mut u32, dropped: &mut bool, exp: &mut i64, c: u8, frac: bool) {
    let d = u64::from(c - b'0');
    if *digits == 0 && d == 0 {
        // Leading zeros carry no significance.
        if frac {
            *exp -= 1;
        }
        return;
    }
    if *digits < 19 {
        *m = *m * 10 + d;
        *digits += 1;
        if frac {
            *exp -= 1;
        }
    } else {
        *dropped = true;
        if !frac {
            *exp += 1;
        }
    }
}

/// `m·10^e` as f32 when the f64 product is correctly rounded and its rounding to f32 is too.
fn fast(m: u64, exp: i64) -> Option<f32> {
    let pow = POW10[exp.unsigned_abs() as usize];
    let v = if exp < 0 {
        m as f64 / pow
    } else {
        m as f64 * pow
    };
    // The 29 low mantissa bits are what f32 rounding drops; exactly half of that range is a
    // midpoint, where the first rounding may have decided the second.
    let dropped = v.to_bits() & ((1 << 29) - 1);
    let f = v as f32;
    if dropped == 1 << 28 || !f.is_normal() {
        return None;
    }
    Some(f)
}

fn slow(tok: &[u8]) -> Option<f32> {
    std::str::from_utf8(tok).ok()?.parse::<f32>().ok()
}

fn special(rest: &[u8]) -> Option<f32> {
    if rest.eq_ignore_ascii_case(b"inf") || rest.eq_ignore_ascii_case(b"infinity") {
        Some(f32::INFINITY)
    } else if rest.eq_ignore_ascii_case(b"nan") {
        Some(f32::NAN)
    } else {
        None
    }
}

/// Parses an OBJ index token (`7`, `-1`, `+3`) as a signed integer; `None` if not an integer or
/// beyond ±2³¹ (no file has that many vertices, and the caller reports the line).
pub fn parse_index(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok.first() {
        Some(b'-') => (true, &tok[1..]),
        Some(b'+') => (false, &tok[1..]),
        _ => (false, tok),
    };
    if digits.is_empty() || digits.len() > 12 {
        return None;
    }
    let mut v: i64 = 0;
    for &c in digits {
        if !c.is_ascii_digit() {
            return None;
        }
        v = v * 10 + i64::from(c - b'0');
    }
    if v > i64::from(i32::MAX) {
        return None;
    }
    Some(if neg { -v } else { v })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms_that_tools_write() {
        let cases: &[(&str, f32)] = &[
            ("0", 0.0),
            ("+1", 1.0),
            ("2.", 2.0),
            (".5", 0.5),
            ("-0.25", -0.25),
            ("1e+2", 100.0),
            ("1E2", 100.0),
            ("1e-2", 0.01),
            ("-1.5E-3", -0.0015),
            ("0.000001", 1e-6),
            ("123456.79", 123_456.79),
        ];
        for &(s, want) in cases {
            assert_eq!(parse_f32(s.as_bytes()), Some(want), "{s}");
        }
        assert!(parse_f32(b"nan").is_some_and(f32::is_nan));
        assert_eq!(parse_f32(b"-inf"), Some(f32::NEG_INFINITY));
        assert_eq!(parse_f32(b"1e999"), Some(f32::INFINITY));
        for bad in [
            "", "-", "+", ".", "e5", "1e", "1e+", "1.2.3", "1x", "--1", "0x10",
        ] {
            assert_eq!(parse_f32(bad.as_bytes()), None, "{bad:?}");
        }
    }

    #[test]
    fn matches_std_on_seeded_random_decimals() {
        let mut s = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..200_000 {
            let r = next();
            let digits = 1 + (r % 21) as usize;
            let mut text = String::new();
            if r & (1 << 40) != 0 {
                text.push('-');
            }
            let mut m = next();
            for k in 0..digits {
                if k == (r >> 8) as usize % (digits + 1) {
                    text.push('.');
                }
                text.push(char::from(b'0' + (m % 10) as u8));
                m /= 10;
            }
            if r & (1 << 41) != 0 {
                text.push_str(&format!("e{}", (r >> 20) as i64 % 50 - 25));
            }
            let want = text.parse::<f32>().ok();
            let got = parse_f32(text.as_bytes());
            assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{text}");
        }
    }

    #[test]
    fn indices() {
        assert_eq!(parse_index(b"7"), Some(7));
        assert_eq!(parse_index(b"-1"), Some(-1));
        assert_eq!(parse_index(b"+3"), Some(3));
        assert_eq!(parse_index(b"99999999999"), None);
        assert_eq!(parse_index(b"1.5"), None);
        assert_eq!(parse_index(b""), None);
    }
}
