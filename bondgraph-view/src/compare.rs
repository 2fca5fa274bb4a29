//! `bondgraph compare MODEL ANSWER.ron`: checks a student's `A`, `B` against the model's
//! equations of one mode (see `bondgraph_core::analysis::compare` for how), and says equal,
//! equal up to a change of state variables, or different at which entry.
//!
//! Exit codes: 0 equal or similar, 1 different, 2 an error (unreadable files, bad entries).

use std::path::Path;
use std::sync::Arc;

use bondgraph_core::analysis::compare::{Comparison, Verdict, compare};
use bondgraph_core::equations::{self, Variables};
use bondgraph_core::model::{ElementKind, Model};
use bondgraph_core::modes;
use bondgraph_core::source::SourceFile;
use bondgraph_core::symbolic::SymbolTable;
use bondgraph_core::{Diagnostic, DiagnosticKind};
use serde_json::json;

use crate::{Failure, json as to_json, load, parse_mode, print, read_source, with_source};

/// Runs the comparison and prints the verdict; `Ok(true)` unless the answer is different.
pub fn run(
    model_path: &Path,
    answer_path: &Path,
    mode: Option<&str>,
    as_json: bool,
) -> Result<bool, Failure> {
    let (model, source) = load(model_path)?;
    let answer = read_source(answer_path)?;
    let compared = check(&model, &source, &answer, mode)?;
    print(if as_json {
        &compared.json
    } else {
        &compared.text
    });
    Ok(compared.agrees)
}

/// A verdict, as the command prints it.
pub struct Compared {
    /// The verdict and its notes, as text.
    pub text: String,
    /// The same, as the JSON document of `--format json`.
    pub json: String,
    /// Whether the answer is equal or similar (the command's exit code 0).
    pub agrees: bool,
}

/// Compares `answer` (an answer file's text) with `model` (read from `source`) in `mode`.
///
/// # Errors
/// A failure when the model is nonlinear, the mode or its equations cannot be had, or the
/// answer does not read (each at its line and entry).
pub fn check(
    model: &Model,
    source: &Arc<SourceFile>,
    answer: &Arc<SourceFile>,
    mode: Option<&str>,
) -> Result<Compared, Failure> {
    if let Some(element) = model
        .elements()
        .iter()
        .find(|e| matches!(e.kind, ElementKind::Nonlinear(_)))
    {
        let ElementKind::Nonlinear(law) = &element.kind else {
            unreachable!("found as nonlinear")
        };
        let diagnostic = Diagnostic::new(
            DiagnosticKind::NotLinear,
            format!(
                "'{}' is nonlinear: an answer's A and B are compared with a linear mode's, and {} '{}' has the nonlinear law {}: \"{}\"",
                source.name(),
                element.kind.description(),
                element.name,
                law.field,
                law.text
            ),
        )
        .at_location(model.source().locate(law.span))
        .element(element.name.clone());
        return Err(with_source(diagnostic.into(), source));
    }
    let mode = parse_mode(model, mode, source)?;
    let derive = |variables| {
        modes::derive(model, &mode, &equations::Options { variables })
            .map(|d| d.equations)
            .map_err(|d| with_source(d, source))
    };
    let energy = derive(Variables::Energy)?;
    let coenergy = derive(Variables::CoEnergy)?;
    let parsed = bondgraph_ron::answer::load(answer, model.symbols()).map_err(|d| Failure {
        diagnostics: d,
        sources: vec![answer.clone()],
    })?;
    let comparison = compare(&energy, &coenergy, Variables::preferred(model), &parsed);
    let agrees = !matches!(comparison.verdict, Verdict::Different { .. });
    Ok(Compared {
        text: to_text(&comparison, &energy.model, &mode.spec(model)),
        json: to_json(&to_value(&comparison, &mode.spec(model), &energy.symbols))?,
        agrees,
    })
}

fn to_text(comparison: &Comparison, model: &str, mode: &str) -> String {
    let mut text = String::new();
    let mode = if mode.is_empty() {
        String::new()
    } else {
        format!(", mode {mode}")
    };
    match &comparison.verdict {
        Verdict::Equal => text.push_str(&format!("equal: the answer is '{model}'{mode}\n")),
        Verdict::Similar {
            changes,
            entries_checked,
        } => {
            text.push_str(&format!(
                "similar: the answer is '{model}'{mode} up to a change of state variables{}\n",
                if *entries_checked {
                    ""
                } else {
                    " (only the characteristic polynomial could be checked)"
                }
            ));
            for change in changes {
                text.push_str(&format!("  {change}\n"));
            }
        }
        Verdict::Different { first } => {
            text.push_str(&format!("different from '{model}'{mode}: {first}\n"));
        }
    }
    for note in &comparison.notes {
        text.push_str(&format!("note: {note}\n"));
    }
    text
}

fn to_value(comparison: &Comparison, mode: &str, symbols: &SymbolTable) -> serde_json::Value {
    let (verdict, changes, first, entries_checked) = match &comparison.verdict {
        Verdict::Equal => ("equal", Vec::new(), None, true),
        Verdict::Similar {
            changes,
            entries_checked,
        } => ("similar", changes.clone(), None, *entries_checked),
        Verdict::Different { first } => ("different", Vec::new(), Some(first.clone()), true),
    };
    json!({
        "mode": mode,
        "verdict": verdict,
        "changes": changes,
        "first_difference": first,
        "entries_checked": entries_checked,
        "notes": comparison.notes,
        "characteristic_polynomial": {
            "model": comparison.polynomials[0],
            "answer": comparison.polynomials[1],
        },
        "transformation": comparison.transformation.as_ref().map(|t| json!({
            "T": t.entries_text(symbols),
            "rows": t.rows_text(symbols),
            "from": t.from,
            "to": t.to,
            "given": t.given,
            "unique": t.unique,
            "symbolic": t.symbolic,
        })),
    })
}
