//! Reading an answer file: a student's states and `A`, `B` (and optionally `E`) as
//! expressions in the model's parameters.
//!
//! ```ron
//! Answer(
//!     states: ["x_spring", "v_mass"],      // optional: named as the model names its states
//!     A: [["0", "1"], ["-k/m", "-b/m"]],
//!     B: [["0"], ["1/m"]],
//!     // E: [["0"], ["0"]],                // optional: the inputs' rates, dx/dt = ... + E du/dt
//! )
//! ```
//!
//! Entries are rational expressions (`+ - * /`, integer powers, numbers, parameter names);
//! every error names the file, the line and the entry (`A[2][1]`, rows and columns from 1).

use serde::Deserialize;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use bondgraph_core::source::{SourceFile, Span};
use bondgraph_core::symbolic::{RatFunc, SymbolTable};

use bondgraph_core::analysis::Matrix;
use bondgraph_core::analysis::answer::{Answer, rational};

#[derive(Deserialize)]
#[serde(rename = "Answer", deny_unknown_fields)]
struct RawAnswer {
    #[serde(default)]
    states: Option<Vec<String>>,
    #[serde(rename = "A")]
    a: Vec<Vec<String>>,
    #[serde(rename = "B")]
    b: Vec<Vec<String>>,
    #[serde(rename = "E", default)]
    e: Option<Vec<Vec<String>>>,
}

/// Reads `file` as an answer over `symbols` (the model's parameters).
///
/// # Errors
/// [`DiagnosticKind::Syntax`] for text that is not an answer, [`DiagnosticKind::BadExpression`]
/// for an entry that does not parse or is not rational, [`DiagnosticKind::UnknownSymbol`] for
/// a name that is not a parameter, [`DiagnosticKind::InvalidValue`] for rows of unequal length
/// or a non-square `A`; each at its line.
pub fn load(file: &SourceFile, symbols: &SymbolTable) -> Result<Answer> {
    let raw: RawAnswer = crate::model::parse::ron_options()
        .from_str(file.text())
        .map_err(|error| {
            let offset = file.offset(error.span.start.line, error.span.start.col);
            Diagnostics::from(
                Diagnostic::new(
                    DiagnosticKind::Syntax,
                    format!("not an answer file: {}", error.code),
                )
                .at(file, Span::new(offset, offset + 1))
                .note(
                    "an answer is Answer(states: [...], A: [[...], ...], B: [[...], ...]) with entries as strings",
                ),
            )
        })?;
    let mut problems = Vec::new();
    let a = matrix(file, symbols, "A", &raw.a, &mut problems);
    let b = matrix(file, symbols, "B", &raw.b, &mut problems);
    let e = raw
        .e
        .as_ref()
        .map(|e| matrix(file, symbols, "E", e, &mut problems));
    let key_span = |key: &str| key_spans(file.text(), key).0;
    if a.iter().any(|row| row.len() != a.len()) {
        problems.push(
            Diagnostic::new(
                DiagnosticKind::InvalidValue,
                format!(
                    "A must be square: it has {} rows of lengths {:?}",
                    a.len(),
                    a.iter().map(Vec::len).collect::<Vec<_>>()
                ),
            )
            .at(file, key_span("A")),
        );
    }
    for (name, m) in [("B", Some(&b)), ("E", e.as_ref())] {
        let Some(m) = m else { continue };
        if m.len() != a.len() {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "{name} must have one row per state: it has {}, A has {}",
                        m.len(),
                        a.len()
                    ),
                )
                .at(file, key_span(name)),
            );
        }
    }
    if let Some(states) = &raw.states
        && states.len() != a.len()
    {
        problems.push(
            Diagnostic::new(
                DiagnosticKind::InvalidValue,
                format!("states names {} states, A has {}", states.len(), a.len()),
            )
            .at(file, key_span("states")),
        );
    }
    if !problems.is_empty() {
        return Err(Diagnostics(problems));
    }
    Ok(Answer {
        states: raw.states,
        a,
        b,
        e,
    })
}

/// The matrix `key`, each entry parsed; problems are collected.
fn matrix(
    file: &SourceFile,
    symbols: &SymbolTable,
    key: &str,
    rows: &[Vec<String>],
    problems: &mut Vec<Diagnostic>,
) -> Matrix {
    let (key_span, spans) = key_spans(file.text(), key);
    let mut k = 0;
    let mut out = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        if i > 0 && row.len() != rows[0].len() {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "{key} row {} has {} entries, row 1 has {}",
                        i + 1,
                        row.len(),
                        rows[0].len()
                    ),
                )
                .at(file, spans.get(k).copied().unwrap_or(key_span)),
            );
        }
        let mut parsed = Vec::new();
        for (j, text) in row.iter().enumerate() {
            // The span of the string's contents, when the scan found it.
            let span = spans
                .get(k)
                .copied()
                .filter(|s| &file.text()[s.start..s.end] == text);
            k += 1;
            match rational(text, symbols) {
                Ok(value) => parsed.push(value),
                Err((message, at)) => {
                    let diagnostic = Diagnostic::new(
                        DiagnosticKind::BadExpression,
                        format!("{key}[{}][{}] = \"{text}\": {message}", i + 1, j + 1),
                    );
                    problems.push(match span {
                        Some(s) => diagnostic.at(
                            file,
                            Span::new(s.start + at.start, (s.start + at.end).max(s.start + 1)),
                        ),
                        None => diagnostic.at(file, key_span),
                    });
                    parsed.push(RatFunc::zero());
                }
            }
        }
        out.push(parsed);
    }
    out
}

/// The span of the key `key:` and of the contents of each string literal in the bracketed
/// value after it, in order (comments skipped). Empty when the key is not found.
fn key_spans(text: &str, key: &str) -> (Span, Vec<Span>) {
    let bytes = text.as_bytes();
    let mut i = 0;
    let mut found: Option<Span> = None;
    let mut depth = 0usize;
    let mut spans = Vec::new();
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c == b'/' && bytes.get(i + 1) == Some(&b'*') {
            i += 2;
            while i + 1 < bytes.len() && !(bytes[i] == b'*' && bytes[i + 1] == b'/') {
                i += 1;
            }
            i += 2;
            continue;
        }
        if c == b'"' {
            let start = i + 1;
            i += 1;
            while i < bytes.len() && bytes[i] != b'"' {
                if bytes[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            if found.is_some() && depth > 0 {
                spans.push(Span::new(start, i.min(bytes.len())));
            }
            i += 1;
            continue;
        }
        if let Some(_key) = found {
            match c {
                b'[' | b'(' => depth += 1,
                b']' | b')' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
            i += 1;
            continue;
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            let word = &text[start..i];
            let rest = text[i..].trim_start();
            if word == key && rest.starts_with(':') {
                found = Some(Span::new(start, i));
            }
            continue;
        }
        i += 1;
    }
    (found.unwrap_or_default(), spans)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_are_located_by_their_strings() {
        let text = "Answer(\n  // A: [\"no\"]\n  A: [[\"0\", \"1\"],\n     [\"-k\", \"-b\"]],\n  B: [[\"0\"], [\"1\"]],\n)";
        let (key, spans) = key_spans(text, "A");
        assert_eq!(&text[key.start..key.end], "A");
        let entries: Vec<&str> = spans.iter().map(|s| &text[s.start..s.end]).collect();
        assert_eq!(entries, ["0", "1", "-k", "-b"]);
    }

    #[test]
    fn a_bad_entry_is_reported_at_its_line() {
        let symbols = SymbolTable::new(["k", "b"]);
        let file = SourceFile::new(
            "answer.ron",
            "Answer(\n  A: [[\"0\", \"1\"],\n     [\"-k\", \"-c\"]],\n  B: [[\"0\"], [\"1\"]],\n)",
        );
        let error = load(&file, &symbols).unwrap_err();
        let d = error.first();
        assert_eq!(d.kind, DiagnosticKind::BadExpression);
        assert!(d.message.contains("A[2][2]"), "{}", d.message);
        assert_eq!(d.location.as_ref().unwrap().line, 3);
    }
}
