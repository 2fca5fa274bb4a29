//! Rendering diagnostics for people, in the style of rustc.
//!
//! The library reports problems as data ([`Diagnostic`]); how they look on a terminal is
//! the program's business. A user fixing a model file wants the file, line and column, the
//! offending line itself and a marker under the exact text, so each diagnostic is shown as
//! a rustc-style block:
//!
//! ```text
//! error: element 'mass': inertance m = 0 must be positive
//!   --> models/bad.ron:12:5
//!    |
//! 12 |     "mass": I(inertance: "m"),
//!    |     ^^^^^^
//!    = note: ...
//! ```
//!
//! Output is plain text without colour codes, so it reads the same in a terminal, a log
//! file or a test's expected string.

use bondgraph_core::diagnostics::Diagnostic;
use bondgraph_core::source::{Location, SourceFile};

/// Renders `diagnostic` as a rustc-style block, without a trailing newline.
///
/// With a location and the `source` it points into (same file name), the block shows the
/// line and a caret under the span's extent on that line: at least one caret, and a span
/// running past the end of the line is cut there. Without a location, or without the
/// source, only the message, the location (if any) and the notes are shown.
pub fn render(diagnostic: &Diagnostic, source: Option<&SourceFile>) -> String {
    let mut out = format!("error: {}", diagnostic.message);
    let Some(location) = &diagnostic.location else {
        for note in &diagnostic.notes {
            out.push_str(&format!("\n  = note: {note}"));
        }
        return out;
    };
    let width = location.line.to_string().len();
    let gutter = " ".repeat(width);
    out.push_str(&format!("\n{gutter}--> {location}"));
    if let Some(source) = source.filter(|s| s.name() == location.file) {
        let (text, carets) = snippet(source, location);
        out.push_str(&format!("\n{gutter} |"));
        out.push_str(format!("\n{} | {text}", location.line).trim_end());
        out.push_str(&format!("\n{gutter} | {carets}"));
    }
    for note in &diagnostic.notes {
        out.push_str(&format!("\n{gutter} = note: {note}"));
    }
    out
}

/// Widest part of a source line echoed under a diagnostic, in characters: a longer line is
/// cut to this window around the column, with `...` where it is cut.
const SNIPPET_WIDTH: usize = 120;

/// Characters of a cut line kept before the column.
const SNIPPET_BEFORE: usize = 40;

/// The text of the location's line and the marker line under it (the indentation before
/// the carets copies the line's tabs, so that the carets line up in a terminal). A line
/// longer than [`SNIPPET_WIDTH`] is cut to a window around the column.
fn snippet(source: &SourceFile, location: &Location) -> (String, String) {
    let line = source.line(location.line);
    let line_start = source.offset(location.line, 1);
    let line_end = line_start + line.len();
    let chars: Vec<char> = line.chars().collect();
    let column = location.column.saturating_sub(1).min(chars.len());
    let start = location.span.start.clamp(line_start, line_end);
    let end = location.span.end.clamp(start, line_end);
    let count = source
        .text()
        .get(start..end)
        .map_or(0, |s| s.chars().count());
    let (first, last) = if chars.len() <= SNIPPET_WIDTH {
        (0, chars.len())
    } else {
        let last = (column.saturating_sub(SNIPPET_BEFORE) + SNIPPET_WIDTH).min(chars.len());
        (last - SNIPPET_WIDTH, last)
    };
    let cut_before = if first > 0 { "..." } else { "" };
    let cut_after = if last < chars.len() { "..." } else { "" };
    let text: String = chars[first..last].iter().collect();
    let before: String = chars[first..column]
        .iter()
        .map(|c| if *c == '\t' { '\t' } else { ' ' })
        .collect();
    let carets = "^".repeat(count.min(last.saturating_sub(column)).max(1));
    (
        format!("{cut_before}{text}{cut_after}"),
        format!("{}{before}{carets}", " ".repeat(cut_before.len())),
    )
}

#[cfg(test)]
mod tests {
    use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind};
    use bondgraph_core::source::{SourceFile, Span};

    use super::render;

    /// Twelve lines; line 12 holds the mass.
    fn model() -> std::sync::Arc<SourceFile> {
        let mut text = String::from("Model(\n");
        for i in 2..12 {
            text.push_str(&format!("    // line {i}\n"));
        }
        text.push_str("    \"mass\": I(inertance: \"m\"),\n)\n");
        SourceFile::new("models/bad.ron", text)
    }

    fn at(file: &SourceFile, needle: &str) -> Span {
        let start = file.text().find(needle).unwrap();
        Span::new(start, start + needle.len())
    }

    #[test]
    fn snippet_with_notes_and_a_two_digit_gutter() {
        let file = model();
        let diagnostic = Diagnostic::new(
            DiagnosticKind::InvalidValue,
            "element 'mass': inertance m = 0 must be positive",
        )
        .at(&file, at(&file, "\"mass\""))
        .element("mass")
        .note("a mass of zero has no dynamics; remove the element instead");
        assert_eq!(
            render(&diagnostic, Some(file.as_ref())),
            "error: element 'mass': inertance m = 0 must be positive\n  \
             --> models/bad.ron:12:5\n   \
             |\n\
             12 |     \"mass\": I(inertance: \"m\"),\n   \
             |     ^^^^^^\n   \
             = note: a mass of zero has no dynamics; remove the element instead"
        );
    }

    #[test]
    fn one_digit_gutter() {
        let file = SourceFile::new("m.ron", "(name: x)\n");
        let diagnostic =
            Diagnostic::new(DiagnosticKind::WrongType, "field 'name' must be a string")
                .at(&file, Span::new(7, 8));
        assert_eq!(
            render(&diagnostic, Some(file.as_ref())),
            "error: field 'name' must be a string\n \
             --> m.ron:1:8\n  \
             |\n\
             1 | (name: x)\n  \
             |        ^"
        );
    }

    #[test]
    fn a_span_past_the_end_of_the_line_is_cut_there() {
        let file = SourceFile::new("m.ron", "(\n  \"a\": I(\n    inertance: 1),\n)");
        let span = Span::new(file.text().find("I(").unwrap(), file.text().len());
        let diagnostic = Diagnostic::new(DiagnosticKind::Syntax, "whole value").at(&file, span);
        assert_eq!(
            render(&diagnostic, Some(file.as_ref())),
            "error: whole value\n \
             --> m.ron:2:8\n  \
             |\n\
             2 |   \"a\": I(\n  \
             |        ^^"
        );
    }

    #[test]
    fn an_empty_span_gets_one_caret_even_at_the_end_of_the_file() {
        let file = SourceFile::new("m.ron", "(name: \"x\"\n");
        let end = file.text().len();
        let diagnostic = Diagnostic::new(DiagnosticKind::Syntax, "unexpected end of file")
            .at(&file, Span::new(end, end))
            .note("the '(' at line 1, column 1 is never closed");
        assert_eq!(
            render(&diagnostic, Some(file.as_ref())),
            "error: unexpected end of file\n \
             --> m.ron:2:1\n  \
             |\n\
             2 |\n  \
             | ^\n  \
             = note: the '(' at line 1, column 1 is never closed"
        );
    }

    #[test]
    fn carets_line_up_after_tabs_and_multi_byte_characters() {
        let file = SourceFile::new("m.ron", "\t\"µ€\": Q,\n");
        let diagnostic = Diagnostic::new(DiagnosticKind::UnknownElementKind, "unknown kind 'Q'")
            .at(&file, at(&file, "Q"));
        assert_eq!(
            render(&diagnostic, Some(file.as_ref())),
            "error: unknown kind 'Q'\n \
             --> m.ron:1:8\n  \
             |\n\
             1 | \t\"µ€\": Q,\n  \
             | \t      ^"
        );
    }

    /// A 20,000-character line is not echoed whole: a window around the column, with an
    /// ellipsis on each side that is cut, and the carets still under the marked text.
    #[test]
    fn a_long_line_is_cut_to_a_window_around_the_column() {
        let mut line = "x".repeat(10_000);
        line.push_str("\"mass\"");
        line.push_str(&"y".repeat(20_000 - line.len()));
        let file = SourceFile::new("m.ron", format!("{line}\n"));
        let diagnostic = Diagnostic::new(DiagnosticKind::UnknownElementKind, "bad")
            .at(&file, at(&file, "\"mass\""));
        // 40 characters before the marked text, then 120 - 40 from it on.
        let expected = format!(
            "error: bad\n \
             --> m.ron:1:10001\n  \
             |\n\
             1 | ...{}\"mass\"{}...\n  \
             | {}^^^^^^",
            "x".repeat(40),
            "y".repeat(120 - 40 - 6),
            " ".repeat(3 + 40)
        );
        assert_eq!(render(&diagnostic, Some(file.as_ref())), expected);
    }

    /// A line of exactly the window's width is shown whole; one character more is cut at
    /// the end only when the marked text is at its start.
    #[test]
    fn a_line_at_the_window_width_is_whole_and_one_past_it_is_cut() {
        let file = SourceFile::new("m.ron", format!("{}\n", "a".repeat(120)));
        let diagnostic = Diagnostic::new(DiagnosticKind::Syntax, "bad").at(&file, Span::new(0, 1));
        let rendered = render(&diagnostic, Some(file.as_ref()));
        assert!(
            rendered.contains(&format!("1 | {}\n", "a".repeat(120))),
            "{rendered}"
        );
        let file = SourceFile::new("m.ron", format!("{}\n", "a".repeat(121)));
        let diagnostic = Diagnostic::new(DiagnosticKind::Syntax, "bad").at(&file, Span::new(0, 1));
        let rendered = render(&diagnostic, Some(file.as_ref()));
        assert!(
            rendered.contains(&format!("1 | {}...\n  | ^", "a".repeat(120))),
            "{rendered}"
        );
    }

    #[test]
    fn no_snippet_without_location_or_source() {
        let bare = Diagnostic::new(DiagnosticKind::Io, "could not read models/x.ron: not found")
            .note("check the path");
        assert_eq!(
            render(&bare, None),
            "error: could not read models/x.ron: not found\n  = note: check the path"
        );
        let file = model();
        let located = Diagnostic::new(DiagnosticKind::CausalConflict, "two sources fight")
            .at(&file, at(&file, "I("))
            .note("remove one");
        let expected =
            "error: two sources fight\n  --> models/bad.ron:12:13\n   = note: remove one";
        assert_eq!(render(&located, None), expected);
        // A source for another file is not used for the snippet.
        let other = SourceFile::new("other.ron", file.text());
        assert_eq!(render(&located, Some(&other)), expected);
    }
}
