//! Setting a sub-model's parameter (`front.k_s`) in a model file: the value is given where
//! the sub-model is used, in the use's `parameters`, in the unit the part writes it in.
//!
//! The parameter is not written in the using file, so its value cannot be replaced there;
//! giving it in the use (`"front": Submodel(file: ..., parameters: {"k_s": 20000.0})`) is
//! what a person would write, and composition reads it back as exactly the value set.

use std::collections::BTreeMap;

use bondgraph_core::model::ElementSpec;
use bondgraph_core::model::ModelSpec;
use bondgraph_core::model::source_map::{EntrySpans, SourceMap};
use bondgraph_core::source::{SourceFile, Span};

use super::in_file_unit;
use crate::source_map::{TokenKind, lex};

/// The text replacements that set the sub-model parameters among `values` (each
/// `(index in the edit, qualified name, SI value)`), and the indices of those that are not
/// a sub-model's parameter (for the caller to report).
pub(super) fn part_values(
    source: &SourceFile,
    (raw, map): (&ModelSpec, &SourceMap),
    values: &[(usize, &str, f64)],
) -> (Vec<(Span, String)>, Vec<usize>) {
    let has_parts = raw
        .elements
        .iter()
        .any(|(_, e)| matches!(e, ElementSpec::Submodel { .. }));
    let linear = crate::model::Format::of(source.text()) == crate::model::Format::LinearGraph;
    let composed = has_parts
        .then(|| match linear {
            true => crate::model::linear_graph::composed_parameters(source),
            false => crate::model::compose::compose(source, raw.clone(), map.clone())
                .ok()
                .map(|c| c.spec.parameters),
        })
        .flatten();
    let Some(parameters) = composed else {
        return (Vec::new(), values.iter().map(|(i, _, _)| *i).collect());
    };
    // Each use's values, in the part's own names and the part's units.
    let mut by_use: BTreeMap<usize, Vec<(String, String)>> = BTreeMap::new();
    let mut unknown = Vec::new();
    for &(index, name, value) in values {
        let found = name.split_once('.').and_then(|(use_name, rest)| {
            let element = raw
                .elements
                .iter()
                .position(|(n, e)| n == use_name && matches!(e, ElementSpec::Submodel { .. }))?;
            let (_, parameter) = parameters.iter().find(|(n, _)| n == name)?;
            let text = in_file_unit(value, parameter.unit.as_deref());
            Some((element, rest.to_string(), text))
        });
        match found {
            Some((element, rest, text)) => by_use.entry(element).or_default().push((rest, text)),
            None => unknown.push(index),
        }
    }
    let mut replacements = Vec::new();
    for (element, given) in by_use {
        if let Some(entry) = map.elements.get(element) {
            replacements.extend(in_use(source.text(), entry, given));
        }
    }
    (replacements, unknown)
}

/// The replacements that give `given` (part's name, value text) in the use at `entry`: a
/// value already given replaced, the others added to its `parameters` (made if missing).
fn in_use(text: &str, entry: &EntrySpans, given: Vec<(String, String)>) -> Vec<(Span, String)> {
    let mut replacements = Vec::new();
    let mut added = Vec::new();
    let written = entry
        .field("parameters")
        .map(|field| given_values(text, field.value_span));
    for (name, value) in given {
        match written
            .as_ref()
            .and_then(|w| w.iter().find(|(key, _)| *key == name))
        {
            Some((_, span)) => replacements.push((*span, value)),
            None => added.push(format!("\"{name}\": {value}")),
        }
    }
    if added.is_empty() {
        return replacements;
    }
    let list = added.join(", ");
    match entry.field("parameters") {
        // After the map's `{`.
        Some(field) => {
            let at = field.value_span.start + 1;
            replacements.push((Span::new(at, at), format!("{list}, ")));
        }
        // Before the use's closing `)`.
        None => {
            let close = entry.value_span.end.saturating_sub(1);
            let before = text.get(..close).unwrap_or("").trim_end();
            let comma = if before.ends_with(',') || before.ends_with('(') {
                ""
            } else {
                ", "
            };
            replacements.push((
                Span::new(close, close),
                format!("{comma}parameters: {{{list}}}"),
            ));
        }
    }
    replacements
}

/// The keys of the map at `span` (`{"k_s": 2.0, "b_s": "b"}`) with the span of each value.
fn given_values(text: &str, span: Span) -> Vec<(String, Span)> {
    let mut out = Vec::new();
    let mut pos = span.start + 1;
    let mut key: Option<String> = None;
    while pos < span.end {
        let Ok(Some(token)) = lex(text, pos) else {
            break;
        };
        if token.span.end > span.end {
            break;
        }
        match (token.kind, key.take()) {
            (TokenKind::Str, None) => {
                key = text
                    .get(token.content.start..token.content.end)
                    .map(str::to_string);
                // Skip the ':' after the key.
                if let Ok(Some(colon)) = lex(text, token.span.end)
                    && colon.is_punct(b':')
                {
                    pos = colon.span.end;
                    continue;
                }
            }
            (TokenKind::Number | TokenKind::Str, Some(name)) => out.push((name, token.span)),
            _ => {}
        }
        pos = token.span.end;
    }
    out
}
