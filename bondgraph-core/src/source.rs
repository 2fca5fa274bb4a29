//! Model source text and positions in it.
//!
//! Every error a user can cause must point at the line that caused it, long after parsing:
//! a causal conflict found in the third stage still names the element's line in the file.
//! So the loader keeps the text of each model file in a [`SourceFile`], and every validated
//! element, bond and parameter carries the [`Span`] (byte range) it came from.

use std::fmt;
use std::sync::Arc;

/// A half-open byte range `start..end` in a [`SourceFile`]'s text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    /// Byte offset of the first byte.
    pub start: usize,
    /// Byte offset one past the last byte.
    pub end: usize,
}

impl Span {
    /// The span `start..end`.
    pub const fn new(start: usize, end: usize) -> Self {
        Self { start, end }
    }

    /// Whether `offset` lies in `start..end` (or equals `start` for an empty span).
    pub fn contains(&self, offset: usize) -> bool {
        (self.start <= offset && offset < self.end) || (self.start == offset && self.end == offset)
    }

    /// Number of bytes covered.
    pub fn len(&self) -> usize {
        self.end.saturating_sub(self.start)
    }

    /// Whether the span covers no bytes.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The span shifted right by `offset` bytes (for a sub-span inside a string literal).
    pub fn shifted(&self, offset: usize) -> Self {
        Self::new(self.start + offset, self.end + offset)
    }
}

/// The name and full text of one model file, with a line index for turning byte offsets
/// into 1-based line and column numbers.
#[derive(Debug, PartialEq, Eq)]
pub struct SourceFile {
    name: String,
    text: String,
    line_starts: Vec<usize>,
    in_code: bool,
}

impl SourceFile {
    /// Wraps `text`, read from the file called `name` (a path as the user gave it).
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Arc<Self> {
        let text = text.into();
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Arc::new(Self {
            name: name.into(),
            text,
            line_starts,
            in_code: false,
        })
    }

    /// A source with no text, for a model built in code ([`crate::model::Builder`]):
    /// nothing in it has a line, so diagnostics about it name their element and no place
    /// ([`Location::is_in_code`]).
    pub fn in_code(name: impl Into<String>) -> Arc<Self> {
        Arc::new(Self {
            name: name.into(),
            text: String::new(),
            line_starts: vec![0],
            in_code: true,
        })
    }

    /// Whether this source was built in code rather than read from a file.
    pub fn is_in_code(&self) -> bool {
        self.in_code
    }

    /// The file name as given by the user.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The whole text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// 1-based line and column (in characters) of byte `offset`; offsets past the end
    /// are clamped to the end of the text.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let line_index = match self.line_starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i - 1,
        };
        let line_start = self.line_starts[line_index];
        let column = self.text[line_start..offset].chars().count() + 1;
        (line_index + 1, column)
    }

    /// Byte offset of 1-based `line` and `column` (in characters), clamped to the text.
    pub fn offset(&self, line: usize, column: usize) -> usize {
        let Some(&line_start) = self.line_starts.get(line.saturating_sub(1)) else {
            return self.text.len();
        };
        let line_text = self.line(line);
        let within: usize = line_text
            .chars()
            .take(column.saturating_sub(1))
            .map(char::len_utf8)
            .sum();
        line_start + within
    }

    /// The text of 1-based `line`, without its line ending; empty past the end.
    pub fn line(&self, line: usize) -> &str {
        let Some(&start) = self.line_starts.get(line.saturating_sub(1)) else {
            return "";
        };
        let end = self
            .line_starts
            .get(line)
            .copied()
            .unwrap_or(self.text.len());
        self.text[start..end].trim_end_matches(['\n', '\r'])
    }

    /// The location of `span` in this file.
    pub fn locate(&self, span: Span) -> Location {
        let (line, column) = if self.in_code {
            (0, 0)
        } else {
            self.line_col(span.start)
        };
        Location {
            file: self.name.clone(),
            line,
            column,
            span,
        }
    }
}

/// Where a diagnostic points: file, 1-based line and column, and the byte span. In a
/// source built in code ([`SourceFile::in_code`]) the line and column are 0.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Location {
    /// The file name as given by the user.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// Byte range in the file.
    pub span: Span,
}

impl Location {
    /// Whether this is a place in a source built in code, which has no lines to point at.
    pub fn is_in_code(&self) -> bool {
        self.line == 0
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based_and_count_characters() {
        let file = SourceFile::new("m.ron", "ab\ncdé f\n\nlast");
        assert_eq!(file.line_col(0), (1, 1));
        assert_eq!(file.line_col(1), (1, 2));
        assert_eq!(file.line_col(3), (2, 1));
        // 'é' is two bytes; the space after it is column 4.
        assert_eq!(file.line_col(7), (2, 4));
        assert_eq!(file.line_col(10), (3, 1));
        assert_eq!(file.line_col(11), (4, 1));
        assert_eq!(file.line_col(1000), (4, 5));
        assert_eq!(file.line(2), "cdé f");
        assert_eq!(file.line(9), "");
        assert_eq!(file.offset(2, 4), 7);
        assert_eq!(file.offset(4, 1), 11);
    }
}
