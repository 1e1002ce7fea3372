//! Stage 2, check: hand parser for inline numeric arrays (`positions [(0,0,0) (1,0,0)]`,
//! `indices [0 1 2]`, `matrix [1 0 0 0 ...]`).
//!
//! The grammar matches a whole `[ ... ]` as one token; here its text is read once, byte by byte,
//! straight into the IR's vectors: no per-number tokens or AST nodes, so a million-vertex mesh
//! costs little more than its final arrays. Numbers are separated by whitespace and/or commas;
//! vectors are parenthesised. Errors point at the offending bytes.

use glam::{Vec2, Vec3};

use crate::source::Span;

/// An array parse error: message and the byte range (relative to the array's text).
#[derive(Debug, Clone, PartialEq)]
pub struct ArrayError {
    /// What is wrong, as a sentence.
    pub message: String,
    /// Byte range within the array's text.
    pub start: usize,
    /// End of that range (exclusive).
    pub end: usize,
}

impl ArrayError {
    /// The error's span, given the span of the whole array.
    pub fn span(&self, array: Span) -> Span {
        let start = array.start as usize + self.start;
        let end = (array.start as usize + self.end).min(array.end as usize);
        Span::new(array.file, start, end.max(start))
    }
}

/// The end of the (UTF-8) character starting at `start`, so error spans never split one.
fn char_end(b: &[u8], start: usize) -> usize {
    let mut end = (start + 1).min(b.len()).max(start);
    while end < b.len() && (b[end] & 0xC0) == 0x80 {
        end += 1;
    }
    end
}

struct Reader<'a> {
    b: &'a [u8],
    i: usize,
}

impl<'a> Reader<'a> {
    /// `text` must start with `[` and end with `]` (the grammar guarantees it).
    fn new(text: &'a str) -> Reader<'a> {
        Reader {
            b: text.as_bytes(),
            i: 1,
        }
    }

    fn end(&self) -> usize {
        self.b.len().saturating_sub(1)
    }

    fn skip_separators(&mut self) {
        while self.i < self.end() && matches!(self.b[self.i], b' ' | b'\t' | b'\r' | b'\n' | b',') {
            self.i += 1;
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip_separators();
        self.i >= self.end()
    }

    fn err(&self, start: usize, message: impl Into<String>) -> ArrayError {
        let end = char_end(self.b, start);
        ArrayError {
            message: message.into(),
            start,
            end,
        }
    }

    fn number(&mut self) -> Result<f32, ArrayError> {
        self.skip_separators();
        let start = self.i;
        while self.i < self.end()
            && matches!(
                self.b[self.i],
                b'0'..=b'9' | b'.' | b'-' | b'+' | b'e' | b'E'
            )
        {
            self.i += 1;
        }
        if start == self.i {
            return Err(self.err(start, "expected a number"));
        }
        // ok: the slice holds only ASCII bytes checked above.
        let text = std::str::from_utf8(&self.b[start..self.i]).unwrap_or("");
        match text.parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(ArrayError {
                message: format!("`{text}` is not a finite number"),
                start,
                end: self.i,
            }),
        }
    }

    fn tuple<const N: usize>(&mut self) -> Result<[f32; N], ArrayError> {
        self.skip_separators();
        let start = self.i;
        if self.b.get(self.i) != Some(&b'(') || self.i >= self.end() {
            return Err(self.err(start, format!("expected a {N}-vector `(...)`")));
        }
        self.i += 1;
        let mut out = [0.0; N];
        for slot in &mut out {
            *slot = self.number()?;
        }
        self.skip_separators();
        if self.b.get(self.i) != Some(&b')') {
            return Err(self.err(self.i, format!("expected `)` after {N} numbers")));
        }
        self.i += 1;
        Ok(out)
    }
}

/// `[(x, y, z) ...]`.
pub fn vec3s(text: &str) -> Result<Vec<Vec3>, ArrayError> {
    let mut r = Reader::new(text);
    let mut out = Vec::with_capacity(text.len() / 24);
    while !r.at_end() {
        out.push(Vec3::from_array(r.tuple::<3>()?));
    }
    Ok(out)
}

/// `[(u, v) ...]`.
pub fn vec2s(text: &str) -> Result<Vec<Vec2>, ArrayError> {
    let mut r = Reader::new(text);
    let mut out = Vec::with_capacity(text.len() / 12);
    while !r.at_end() {
        out.push(Vec2::from_array(r.tuple::<2>()?));
    }
    Ok(out)
}

/// `[n ...]`: plain numbers.
pub fn numbers(text: &str) -> Result<Vec<f32>, ArrayError> {
    let mut r = Reader::new(text);
    let mut out = Vec::new();
    while !r.at_end() {
        out.push(r.number()?);
    }
    Ok(out)
}

/// `[0 1 2  0 2 3]` or `[(0 1 2) (0 2 3)]`: whole numbers, three per triangle.
pub fn triangles(text: &str) -> Result<Vec<[u32; 3]>, ArrayError> {
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(text.len() / 12);
    let mut tri = [0u32; 3];
    let mut n = 0;
    let mut i = 1;
    let end = b.len().saturating_sub(1);
    while i < end {
        match b[i] {
            b' ' | b'\t' | b'\r' | b'\n' | b',' | b'(' | b')' => i += 1,
            b'0'..=b'9' => {
                let start = i;
                let mut v: u64 = 0;
                while i < end && b[i].is_ascii_digit() {
                    v = v * 10 + u64::from(b[i] - b'0');
                    if v > u64::from(u32::MAX) {
                        return Err(ArrayError {
                            message: "index too large".into(),
                            start,
                            end: i + 1,
                        });
                    }
                    i += 1;
                }
                tri[n] = v as u32;
                n += 1;
                if n == 3 {
                    out.push(tri);
                    n = 0;
                }
            }
            _ => {
                return Err(ArrayError {
                    message: "expected a whole, non-negative index".into(),
                    start: i,
                    end: char_end(b, i),
                })
            }
        }
    }
    if n != 0 {
        return Err(ArrayError {
            message: format!("{} indices left over: indices come in threes", n),
            start: end,
            end: char_end(b, end),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_vectors_and_indices() {
        let v = vec3s("[(0,0,0) (1, 2.5, -3e1)\n(0 1 0)]").expect("valid");
        assert_eq!(v, vec![Vec3::ZERO, Vec3::new(1.0, 2.5, -30.0), Vec3::Y]);
        assert_eq!(vec2s("[(0,1),(2,3)]").expect("valid").len(), 2);
        assert_eq!(
            triangles("[0 1 2, 0 2 3]").expect("valid"),
            vec![[0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(triangles("[(0 1 2)]").expect("valid"), vec![[0, 1, 2]]);
        assert_eq!(numbers("[1 -2 3.5]").expect("valid"), vec![1.0, -2.0, 3.5]);
    }

    #[test]
    fn reports_errors_with_positions() {
        let e = vec3s("[(0,0,0) (1,x,0)]").expect_err("bad number");
        assert_eq!(e.start, 12);
        let e = vec3s("[(0,0)]").expect_err("too short");
        assert!(e.message.contains("expected a number"), "{e:?}");
        let e = triangles("[0 1]").expect_err("left over");
        assert!(e.message.contains("left over"));
        assert!(triangles("[0 -1 2]").is_err());
        assert!(vec3s("[(1e39, 0, 0)]").is_err());
    }
}
