//! Stage 1, syntax (fast path): the value of a number literal's digits (`30`, `0.25`, `1.5`)
//! without the standard library's general decimal conversion, for the short literals that make
//! up nearly every number of a scene (docs/frontend-bench.md: `f64::from_str` was ≈ 5 % of the
//! front end's instructions on the dense generated scene).
//!
//! The result is bit for bit the one `str::parse::<f64>` gives: with at most 15 digits the
//! digits as an integer `w` are below 2^53 and the fraction's power of ten `10^k` (k ≤ 15)
//! is below 2^53 too, so both are exact `f64`s and one IEEE division rounds `w / 10^k`, the
//! literal's exact value, correctly: the correctly rounded value is unique (Clinger's fast
//! path, the one `core::num::dec2flt` takes first). Anything else (more digits, an exponent)
//! goes to `str::parse`.

/// Powers of ten up to 10^15, each exact in an `f64`.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The value of `digits`, a literal the grammar's `digits` rule matched (digits with at most
/// one `.`, maybe an exponent), as `str::parse::<f64>` reads it (NaN if it cannot, as the
/// converter does).
pub(super) fn value(digits: &str) -> f64 {
    short(digits.as_bytes()).unwrap_or_else(|| digits.parse::<f64>().unwrap_or(f64::NAN))
}

/// `digits` of at most 15 decimal digits and one `.`, no exponent: their exact value, rounded
/// once; `None` for anything else.
fn short(digits: &[u8]) -> Option<f64> {
    if digits.len() > 16 {
        return None;
    }
    let mut whole: u64 = 0;
    let mut count = 0usize;
    let mut fraction: Option<usize> = None;
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                whole = whole * 10 + u64::from(b - b'0');
                count += 1;
            }
            b'.' if fraction.is_none() => fraction = Some(count),
            _ => return None,
        }
    }
    if count == 0 || count > 15 {
        return None;
    }
    let scale = POW10.get(count - fraction.unwrap_or(count))?;
    // `whole` < 10^15 < 2^53: exact, as is `scale`; the one division rounds correctly.
    Some(whole as f64 / scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small seeded generator (xorshift), so the test is the same on every run.
    fn next(state: &mut u64) -> u64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        *state
    }

    #[test]
    fn equals_the_standard_conversion_bit_for_bit() {
        let fixed = [
            "0",
            "0.",
            ".5",
            "5.",
            "30",
            "0.25",
            "1.25",
            "000123.4500",
            "999999999999999",
            "99999999999999.9",
            ".999999999999999",
            "9007199254740993",
            "0.1",
            "0.3",
            "123456789012345",
            "1234567890123456",
            "1e5",
            "2.5e-3",
            "1E+2",
            "0.000000000000001",
        ];
        let mut texts: Vec<String> = fixed.iter().map(|s| s.to_string()).collect();
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..200_000 {
            let len = 1 + (next(&mut state) % 18) as usize;
            let mut s: String = (0..len)
                .map(|_| char::from(b'0' + (next(&mut state) % 10) as u8))
                .collect();
            let dot = (next(&mut state) % (len as u64 + 2)) as usize;
            if dot <= len {
                s.insert(dot, '.');
            }
            texts.push(s);
        }
        for text in &texts {
            let want = text.parse::<f64>().unwrap_or(f64::NAN);
            let got = value(text);
            assert_eq!(got.to_bits(), want.to_bits(), "{text}");
        }
    }
}
