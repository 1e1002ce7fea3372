//! Language server: byte offsets in `.scn` text ↔ LSP positions (line, UTF-16 column), as the
//! protocol requires: `é` before an error moves its column by one, `𝛼` by two.

use lsp_types::{Position, Range};

/// Where each line of a text starts, for converting offsets both ways.
#[derive(Debug, Clone)]
pub struct LineIndex<'a> {
    text: &'a str,
    line_starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    /// Indexes `text`'s lines (split at `\n`).
    pub fn new(text: &'a str) -> LineIndex<'a> {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        LineIndex { text, line_starts }
    }

    /// The position of byte `offset` (clamped to the text, and back to a character boundary).
    pub fn position(&self, offset: usize) -> Position {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let column: usize = self.text[start..offset].chars().map(char::len_utf16).sum();
        Position::new(line as u32, column as u32)
    }

    /// The range of bytes `start..end`.
    pub fn range(&self, start: usize, end: usize) -> Range {
        Range::new(self.position(start), self.position(end))
    }

    /// The byte offset of `position` (clamped to its line and to the text).
    pub fn offset(&self, position: Position) -> usize {
        let Some(&start) = self.line_starts.get(position.line as usize) else {
            return self.text.len();
        };
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |n| start + n);
        let mut column = 0usize;
        for (i, c) in self.text[start..line_end].char_indices() {
            if column >= position.character as usize {
                return start + i;
            }
            column += c.len_utf16();
        }
        line_end
    }

    /// The text indexed.
    pub fn text(&self) -> &'a str {
        self.text
    }

    /// The range covering the whole text.
    pub fn whole(&self) -> Range {
        self.range(0, self.text.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_count_utf16_units() {
        let text = "ab\n// é𝛼 x\n";
        let index = LineIndex::new(text);
        let x = text.find('x').unwrap_or(0);
        // `// ` 3 units, `é` 1, `𝛼` 2, ` ` 1.
        assert_eq!(index.position(x), Position::new(1, 7));
        assert_eq!(index.offset(Position::new(1, 7)), x);
        assert_eq!(index.position(text.len()), Position::new(2, 0));
        assert_eq!(index.offset(Position::new(9, 0)), text.len());
    }
}
