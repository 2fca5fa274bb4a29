//! Reading a scenario file: its text through serde, every name resolved against the edited
//! model and every number checked, each problem a [`Diagnostic`] pointing into the file.
//!
//! # Example
//! ```
//! use bondgraph_ron::scenario;
//! use bondgraph_core::source::SourceFile;
//!
//! let model = SourceFile::new("msd.ron", r#"Model(name: "msd",
//!     parameters: {"m": (value: 2.0), "k": (value: 200.0), "b": (value: 4.0)},
//!     inputs: {"F": (unit: "N")},
//!     elements: {"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
//!                "spring": C(stiffness: "k"), "damper": R(resistance: "b")},
//!     bonds: [("force", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")])"#);
//! let text = r#"Scenario(name: "push", parameters: {"b": 8.0},
//!     inputs: {"F": Step(at: 0.1, before: 0.0, after: 10.0)},
//!     initial_state: {"spring": 0.01}, duration: 2.0, record: ["flow:mass"])"#;
//! let scenario = scenario::load(&SourceFile::new("push.ron", text), &model).unwrap();
//! assert_eq!(scenario.model.parameters()[2].value, 8.0);
//! assert_eq!(scenario.inputs[0].value(0.5), 10.0);
//! assert_eq!(scenario.inputs[0].to_string(), "step from 0 to 10 at t = 0.1 s");
//!
//! let typo = text.replace(r#""F": Step"#, r#""f": Step"#);
//! let error = scenario::load(&SourceFile::new("push.ron", typo), &model).unwrap_err();
//! assert_eq!(error.first().to_string(),
//!     "push.ron:2:14: error: input 'f': model 'msd' has no input 'f'\n  note: did you mean 'F'?");
//! ```

use std::collections::HashMap;
use std::sync::Arc;

use serde::Deserialize;

use crate::model::edit::{self, Edit, EditItem};
use crate::model::parse::{FileKind, parse_file};
use crate::source_map::{Token, TokenKind, lex, list_items};
use bondgraph_core::diagnostics::suggest;
use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use bondgraph_core::equations::OutputSpec;
use bondgraph_core::mode::Mode;
use bondgraph_core::model::source_map::{EntrySpans, SourceMap};
use bondgraph_core::model::spec::entries;
use bondgraph_core::model::{ElementId, ElementKind, Model};
use bondgraph_core::source::{SourceFile, Span};

use bondgraph_core::number::readable as num;
use bondgraph_core::scenario::{EnergyRecord, Record, Scenario, Signal};

/// A scenario file, as serde reads it.
#[derive(Debug, Deserialize)]
#[serde(rename = "Scenario", deny_unknown_fields)]
struct RawScenario {
    name: String,
    description: Option<String>,
    #[serde(default)]
    remove: Vec<String>,
    #[serde(default, deserialize_with = "entries")]
    parameters: Vec<(String, f64)>,
    #[serde(default, deserialize_with = "entries")]
    inputs: Vec<(String, RawSignal)>,
    initial_mode: Option<String>,
    #[serde(default, deserialize_with = "entries")]
    initial_state: Vec<(String, f64)>,
    duration: f64,
    #[serde(default)]
    record: Vec<String>,
    sample: Option<f64>,
}

/// A signal as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "Signal", deny_unknown_fields)]
enum RawSignal {
    Constant(f64),
    Step {
        at: f64,
        before: f64,
        after: f64,
    },
    Ramp {
        slope: f64,
        start: Option<f64>,
        initial: Option<f64>,
        ceiling: Option<f64>,
    },
    Table(Vec<(f64, f64)>),
}

/// Reads the scenario in `scenario` and applies it to the model in `model`: parses the
/// scenario, edits the model's text (`remove`, `parameters`), loads the edited model, and
/// checks the rest of the scenario against it.
///
/// # Errors
/// The scenario file's syntax error; or every problem found, each pointing into the
/// scenario file (naming the input, parameter, element or output concerned): numbers that
/// are not finite, a duration or sample interval that is not positive, a ramp that never
/// reaches its ceiling, a table that is empty or whose times do not increase, names the
/// model does not have (with a suggestion for a typo), a used input without a signal,
/// initial states of elements that store no energy, a bad initial mode or output, names
/// given twice. The model file's own problems point into the model file, and problems the
/// edits cause (a junction left with one bond) point at the model file's text with a note
/// naming the scenario's edits.
pub fn load(scenario: &Arc<SourceFile>, model: &Arc<SourceFile>) -> Result<Scenario> {
    load_measured(scenario, model, &[])
}

/// [`load`] for a scenario driven partly by measured signals (a time series fitted to
/// data): the inputs named in `measured` need no signal in the file, and are held at
/// `Constant(0.0)` where it gives none, for the caller to replace.
///
/// # Errors
/// As [`load`].
pub fn load_measured(
    scenario: &Arc<SourceFile>,
    model: &Arc<SourceFile>,
    measured: &[&str],
) -> Result<Scenario> {
    let (raw, map) = parse_file::<RawScenario>(scenario, FileKind::Scenario)?;
    let mut checker = Checker {
        file: scenario.clone(),
        map: &map,
        problems: Vec::new(),
        measured,
    };

    // What needs no model.
    let mut edit = Edit::default();
    let mut edit_parameters = Vec::new();
    for (index, (name, value)) in raw.parameters.iter().enumerate() {
        let span = checker.value_span(checker.map.parameters.get(index));
        if checker.finite(
            *value,
            span,
            &format!("parameter '{name}':"),
            Some(name.as_str()),
        ) {
            edit.parameters.push((name.clone(), *value));
            edit_parameters.push(index);
        }
    }
    edit.remove.clone_from(&raw.remove);
    let duration_span = checker.field_value_span("duration");
    if checker.finite(raw.duration, duration_span, "duration", None) && raw.duration <= 0.0 {
        checker.problem(
            DiagnosticKind::InvalidValue,
            format!(
                "duration must be positive, found {}",
                checker.written(duration_span, raw.duration)
            ),
            duration_span,
            None,
        );
    }
    if let Some(sample) = raw.sample {
        let span = checker.field_value_span("sample");
        let span = checker.number_in(span);
        if checker.finite(sample, span, "sample interval", None) && sample <= 0.0 {
            checker.problem(
                DiagnosticKind::InvalidValue,
                format!(
                    "sample interval must be positive, found {}",
                    checker.written(span, sample)
                ),
                span,
                None,
            );
        }
    }
    let interval = raw.sample.unwrap_or(raw.duration / 1000.0);
    if raw.duration > 0.0 && raw.duration.is_finite() && interval > 0.0 && interval.is_finite() {
        let count = bondgraph_core::limits::sample_count(raw.duration, interval);
        if count > bondgraph_core::limits::MAX_SAMPLES as f64 {
            let span = checker.number_in(checker.field_value_span("sample"));
            checker.problem(
                DiagnosticKind::TooLarge,
                format!(
                    "{} s sampled every {} s is {} samples, over the limit of {}; give a longer sample interval",
                    checker.written(duration_span, raw.duration),
                    checker.written(span, interval),
                    bondgraph_core::limits::count_in_words(count),
                    bondgraph_core::limits::MAX_SAMPLES,
                ),
                span,
                None,
            );
        }
    }
    let signals: Vec<Option<Signal>> = raw
        .inputs
        .iter()
        .enumerate()
        .map(|(index, (name, signal))| checker.signal(index, name, signal))
        .collect();
    let initial_values: Vec<bool> = raw
        .initial_state
        .iter()
        .enumerate()
        .map(|(index, (name, value))| {
            let span = checker.value_span(checker.map.initial_state.get(index));
            checker.finite(
                *value,
                span,
                &format!("initial state of '{name}':"),
                Some(name.as_str()),
            )
        })
        .collect();

    // The model, edited.
    let model = match checker.model(model, &raw, &edit, &edit_parameters) {
        Ok(model) => model,
        Err(diagnostics) => {
            checker.problems.extend(diagnostics.0);
            return Err(Diagnostics(checker.problems));
        }
    };

    // What needs the model.
    let inputs = checker.inputs(&model, &raw, signals);
    let initial_mode = match &raw.initial_mode {
        Some(text) => checker.mode(&model, &raw, text),
        None => Some(Mode::initial(&model)),
    };
    let initial_state = checker.initial_state(&model, &raw, &initial_values);
    let record = checker.record(&model, &raw);

    match (inputs, initial_mode) {
        (Some(inputs), Some(initial_mode)) if checker.problems.is_empty() => Ok(Scenario {
            name: raw.name,
            description: raw.description,
            model,
            inputs,
            initial_mode,
            initial_state,
            duration: raw.duration,
            record,
            sample: raw.sample,
            source: scenario.clone(),
        }),
        _ => Err(Diagnostics(checker.problems)),
    }
}

/// Collects the problems of one scenario file.
struct Checker<'a> {
    file: Arc<SourceFile>,
    map: &'a SourceMap,
    problems: Vec<Diagnostic>,
    /// Inputs the caller drives with measured signals: they need none in the file.
    measured: &'a [&'a str],
}

impl Checker<'_> {
    fn problem(
        &mut self,
        kind: DiagnosticKind,
        message: String,
        span: Span,
        element: Option<&str>,
    ) -> &mut Diagnostic {
        let mut diagnostic = Diagnostic::new(kind, message).at(&self.file, span);
        if let Some(element) = element {
            diagnostic = diagnostic.element(element);
        }
        self.problems.push(diagnostic);
        let last = self.problems.len() - 1;
        &mut self.problems[last]
    }

    /// The value of a top-level field, or the whole scenario.
    fn field_value_span(&self, name: &str) -> Span {
        self.map.field(name).map_or(self.map.root, |f| f.value_span)
    }

    /// The span of an entry's value, or the whole scenario.
    fn value_span(&self, entry: Option<&EntrySpans>) -> Span {
        entry.map_or(self.map.root, |e| e.value_span)
    }

    /// The span of an entry's key, or the whole scenario.
    fn key_span(&self, entry: Option<&EntrySpans>) -> Span {
        entry.map_or(self.map.root, |e| e.key_span)
    }

    /// Whether `token` is a number (`1e-4`, `-inf`, or the identifiers `inf` and `NaN`).
    fn is_number(&self, token: &Token) -> bool {
        token.kind == TokenKind::Number
            || (token.kind == TokenKind::Ident
                && matches!(
                    &self.file.text()[token.span.start..token.span.end],
                    "inf" | "NaN"
                ))
    }

    /// The first number written inside `span` (`1e-4` in `Some(1e-4)` or
    /// `Constant(1e-4)`), or `span`.
    fn number_in(&self, span: Span) -> Span {
        let text = self.file.text();
        let mut pos = span.start;
        while let Ok(Some(token)) = lex(text, pos) {
            if token.span.end > span.end {
                break;
            }
            if self.is_number(&token) {
                return token.span;
            }
            pos = token.span.end;
        }
        span
    }

    /// The number as written at `span`, if that is a number; else as `value` prints.
    fn written(&self, span: Span, value: f64) -> String {
        let text = self.file.text();
        match lex(text, span.start) {
            Ok(Some(token)) if self.is_number(&token) && token.span == span => {
                text[span.start..span.end].to_string()
            }
            _ => num(value),
        }
    }

    /// Whether `value` is finite; if not, a problem `{what} 1e400 is too large ...`.
    fn finite(&mut self, value: f64, span: Span, what: &str, element: Option<&str>) -> bool {
        if value.is_finite() {
            return true;
        }
        let written = self.written(span, value);
        let message = if value.is_infinite()
            && written.bytes().any(|b| b.is_ascii_digit())
            && !written.contains("inf")
        {
            format!("{what} {written} is too large for a 64-bit floating-point number")
        } else {
            format!("{what} {written} is not a finite number")
        };
        self.problem(DiagnosticKind::InvalidValue, message, span, element);
        false
    }

    /// Checks input `index`'s signal; `None` if it has a problem.
    fn signal(&mut self, index: usize, name: &str, signal: &RawSignal) -> Option<Signal> {
        let map = self.map;
        let entry = map.inputs.get(index);
        let whole = self.value_span(entry);
        let field = |field: &str| {
            entry
                .and_then(|e| e.field(field))
                .map_or(whole, |f| f.value_span)
        };
        let prefix = format!("input '{name}':");
        let mut ok = true;
        let mut check = |checker: &mut Self, value: f64, span: Span, what: &str| {
            ok &= checker.finite(value, span, &format!("{prefix} {what}"), Some(name));
        };
        match signal {
            RawSignal::Constant(value) => {
                let span = self.number_in(whole);
                check(self, *value, span, "constant");
                ok.then_some(Signal::Constant(*value))
            }
            RawSignal::Step { at, before, after } => {
                check(self, *at, field("at"), "step time");
                check(self, *before, field("before"), "value before the step");
                check(self, *after, field("after"), "value after the step");
                ok.then_some(Signal::Step {
                    at: *at,
                    before: *before,
                    after: *after,
                })
            }
            RawSignal::Ramp {
                slope,
                start,
                initial,
                ceiling,
            } => {
                let (start, initial) = (start.unwrap_or(0.0), initial.unwrap_or(0.0));
                let start_span = self.number_in(field("start"));
                let initial_span = self.number_in(field("initial"));
                let ceiling_span = self.number_in(field("ceiling"));
                check(self, *slope, field("slope"), "slope");
                check(self, start, start_span, "start");
                check(self, initial, initial_span, "initial value");
                if let Some(c) = ceiling {
                    check(self, *c, ceiling_span, "ceiling");
                }
                if !ok {
                    return None;
                }
                if let Some(c) = *ceiling {
                    let reached = if *slope == 0.0 {
                        c == initial
                    } else {
                        (c - initial) / slope >= 0.0
                    };
                    if !reached {
                        let how = if *slope > 0.0 {
                            format!("rises (slope {})", num(*slope))
                        } else if *slope < 0.0 {
                            format!("falls (slope {})", num(*slope))
                        } else {
                            "stays there (slope 0)".to_string()
                        };
                        self.problem(
                            DiagnosticKind::InvalidValue,
                            format!(
                                "input '{name}': the ramp starts at {} and {how}, so it never reaches its ceiling {}",
                                num(initial),
                                num(c)
                            ),
                            ceiling_span,
                            Some(name),
                        )
                        .notes
                        .push(
                            "a ramp stops at its ceiling: above where it starts if it rises, below if it falls"
                                .to_string(),
                        );
                        return None;
                    }
                }
                Some(Signal::Ramp {
                    start,
                    initial,
                    slope: *slope,
                    ceiling: *ceiling,
                })
            }
            RawSignal::Table(points) => {
                let items =
                    list_items(self.file.text(), whole).filter(|items| items.len() == points.len());
                let item = |i: usize| items.as_ref().map_or(whole, |items| items[i]);
                if points.is_empty() {
                    self.problem(
                        DiagnosticKind::InvalidValue,
                        format!(
                            "input '{name}': the table has no points; give at least one (time, value)"
                        ),
                        whole,
                        Some(name),
                    );
                    return None;
                }
                for (i, (t, v)) in points.iter().enumerate() {
                    if !(t.is_finite() && v.is_finite()) {
                        let span = item(i);
                        let written = &self.file.text()[span.start..span.end];
                        let message = format!(
                            "input '{name}': table point {} {written} is not a pair of finite numbers",
                            i + 1
                        );
                        self.problem(DiagnosticKind::InvalidValue, message, span, Some(name));
                        return None;
                    }
                }
                for (i, pair) in points.windows(2).enumerate() {
                    if pair[1].0 <= pair[0].0 {
                        self.problem(
                            DiagnosticKind::InvalidValue,
                            format!(
                                "input '{name}': table times must increase, but point {} at t = {} follows point {} at t = {}",
                                i + 2,
                                num(pair[1].0),
                                i + 1,
                                num(pair[0].0)
                            ),
                            item(i + 1),
                            Some(name),
                        );
                        return None;
                    }
                }
                Some(Signal::Table(points.clone()))
            }
        }
    }

    /// Loads the model and applies the scenario's edits to it.
    fn model(
        &self,
        model_file: &Arc<SourceFile>,
        raw: &RawScenario,
        edit: &Edit,
        edit_parameters: &[usize],
    ) -> Result<Model> {
        let original = crate::model::load_source(model_file)?;
        if edit.is_empty() {
            return Ok(original);
        }
        let map = self.map;
        let file = &self.file;
        let locate = |item: EditItem| {
            let span = match item {
                EditItem::Remove(i) => map.remove.get(i).map(|item| item.text_span()),
                EditItem::Parameter(i) => edit_parameters
                    .get(i)
                    .and_then(|&i| map.parameters.get(i))
                    .map(|entry| entry.key_span),
            };
            Some(file.locate(span.unwrap_or(map.root)))
        };
        let edited = edit::apply_located(model_file, edit, &locate)?;
        crate::model::load_source(&edited.file).map_err(|diagnostics| {
            let field = if edit.remove.is_empty() {
                "parameters"
            } else {
                "remove"
            };
            let at = self
                .file
                .locate(self.map.field(field).map_or(self.map.root, |f| f.name_span));
            let note = format!(
                "in the model as scenario '{}' edits it ({}:{}:{})",
                raw.name, at.file, at.line, at.column
            );
            Diagnostics(
                diagnostics
                    .0
                    .into_iter()
                    .map(|d| edited.relocate(d, model_file).note(note.clone()))
                    .collect(),
            )
        })
    }

    /// A note for a name the edited model lacks: that the scenario removed it, or a
    /// suggestion.
    fn missing_element_note(
        raw: &RawScenario,
        name: &str,
        candidates: impl Iterator<Item = String>,
    ) -> Option<String> {
        if raw.remove.iter().any(|r| r == name) {
            return Some(format!("the scenario removes '{name}'"));
        }
        let candidates: Vec<String> = candidates.collect();
        suggest(name, candidates.iter().map(String::as_str)).map(|s| format!("did you mean '{s}'?"))
    }

    /// The signal of each model input.
    fn inputs(
        &mut self,
        model: &Model,
        raw: &RawScenario,
        signals: Vec<Option<Signal>>,
    ) -> Option<Vec<Signal>> {
        let mut given: Vec<Option<Signal>> = vec![None; model.inputs().len()];
        let mut seen: HashMap<&str, Span> = HashMap::new();
        let mut ok = true;
        for (index, ((name, _), signal)) in raw.inputs.iter().zip(signals).enumerate() {
            let span = self.key_span(self.map.inputs.get(index));
            if let Some(first) = seen.insert(name, span) {
                let (line, _) = self.file.line_col(first.start);
                self.problem(
                    DiagnosticKind::DuplicateName,
                    format!("input '{name}' is given twice"),
                    span,
                    Some(name),
                )
                .notes
                .push(format!("it is first given on line {line}"));
                ok = false;
                continue;
            }
            let Some(id) = model.input_named(name) else {
                let mut notes = Vec::new();
                if model.parameters().iter().any(|p| p.name == *name) {
                    notes.push(format!(
                        "'{name}' is a parameter of the model; set it under parameters"
                    ));
                } else if let Some(s) =
                    suggest(name, model.inputs().iter().map(|i| i.name.as_str()))
                {
                    notes.push(format!("did you mean '{s}'?"));
                }
                self.problem(
                    DiagnosticKind::UnknownName,
                    format!(
                        "input '{name}': model '{}' has no input '{name}'",
                        model.name()
                    ),
                    span,
                    Some(name),
                )
                .notes
                .extend(notes);
                ok = false;
                continue;
            };
            match signal {
                Some(signal) => given[id.index()] = Some(signal),
                None => ok = false,
            }
        }
        let used = used_inputs(model);
        let inputs_span = self
            .map
            .field("inputs")
            .map_or(self.map.root, |f| f.name_span);
        let mut inputs = Vec::with_capacity(model.inputs().len());
        for (index, input) in model.inputs().iter().enumerate() {
            match given[index].take() {
                Some(signal) => inputs.push(signal),
                None if !used[index] || self.measured.contains(&input.name.as_str()) => {
                    inputs.push(Signal::Constant(0.0));
                }
                None if seen.contains_key(input.name.as_str()) => {}
                None => {
                    let unit = input
                        .unit
                        .as_deref()
                        .map_or(String::new(), |u| format!(" ({u})"));
                    self.problem(
                        DiagnosticKind::MissingInput,
                        format!(
                            "input '{}'{unit} of model '{}' has no signal",
                            input.name,
                            model.name()
                        ),
                        inputs_span,
                        Some(&input.name),
                    )
                    .notes
                    .push(format!(
                        "give it one under inputs, e.g. \"{}\": Constant(0.0)",
                        input.name
                    ));
                    ok = false;
                }
            }
        }
        ok.then_some(inputs)
    }

    /// The initial mode, with problems located at the part of the text they concern.
    fn mode(&mut self, model: &Model, raw: &RawScenario, text: &str) -> Option<Mode> {
        let field = self.map.field("initial_mode");
        let content = field.map_or(self.map.root, |f| f.text_span());
        match Mode::parse(model, text) {
            Ok(mode) => Some(mode),
            Err(diagnostics) => {
                // The first part that is wrong on its own, if the text is as written.
                let exact = self.file.text().get(content.start..content.end) == Some(text);
                let mut offset = 0;
                let mut span = content;
                let mut element = None;
                for part in text.split(',') {
                    let trimmed = part.trim();
                    if !trimmed.is_empty() && Mode::parse(model, trimmed).is_err() {
                        let lead = part.len() - part.trim_start().len();
                        if exact {
                            let start = content.start + offset + lead;
                            span = Span::new(start, start + trimmed.len());
                        }
                        let name = trimmed.split('=').next().unwrap_or("").trim();
                        element = Some(name.to_string());
                        break;
                    }
                    offset += part.len() + 1;
                }
                for mut diagnostic in diagnostics.0 {
                    diagnostic = diagnostic.at(&self.file, span);
                    if let Some(name) = &element
                        && model.element_named(name).is_none()
                    {
                        diagnostic = diagnostic.element(name.clone());
                        let names = model.elements().iter().map(|e| e.name.clone());
                        if let Some(note) = Self::missing_element_note(raw, name, names) {
                            diagnostic = diagnostic.note(note);
                        }
                    }
                    self.problems.push(diagnostic);
                }
                None
            }
        }
    }

    /// The initial states given, each resolved to a storage element.
    fn initial_state(
        &mut self,
        model: &Model,
        raw: &RawScenario,
        finite: &[bool],
    ) -> Vec<(ElementId, f64)> {
        let mut states = Vec::new();
        let mut seen: HashMap<&str, Span> = HashMap::new();
        for (index, (name, value)) in raw.initial_state.iter().enumerate() {
            let span = self.key_span(self.map.initial_state.get(index));
            if let Some(first) = seen.insert(name, span) {
                let (line, _) = self.file.line_col(first.start);
                self.problem(
                    DiagnosticKind::DuplicateName,
                    format!("initial state of '{name}' is given twice"),
                    span,
                    Some(name),
                )
                .notes
                .push(format!("it is first given on line {line}"));
                continue;
            }
            let Some(id) = model.element_named(name) else {
                let names = model.elements().iter().map(|e| e.name.clone());
                let note = Self::missing_element_note(raw, name, names);
                self.problem(
                    DiagnosticKind::UnknownName,
                    format!(
                        "initial state of '{name}': model '{}' has no element '{name}'",
                        model.name()
                    ),
                    span,
                    Some(name),
                )
                .notes
                .extend(note);
                continue;
            };
            let kind = &model.element(id).kind;
            if model.storage_name(id).is_none() {
                let what = kind.description();
                let article = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                };
                self.problem(
                    DiagnosticKind::NotStorage,
                    format!(
                        "initial state of '{name}': '{name}' is {article} {what}, which stores no energy"
                    ),
                    span,
                    Some(name),
                )
                .notes
                .push(
                    "initial states are the momentum of an inertia or the displacement of a compliance or tension-only element"
                        .to_string(),
                );
                continue;
            }
            if finite.get(index).copied().unwrap_or(false) {
                states.push((id, *value));
            }
        }
        states
    }

    /// The outputs to record.
    fn record(&mut self, model: &Model, raw: &RawScenario) -> Vec<Record> {
        let mut records: Vec<(Record, usize)> = Vec::new();
        for (index, text) in raw.record.iter().enumerate() {
            let item = self.map.record.get(index);
            let content = item.map_or(self.map.root, |i| i.text_span());
            let exact = self.file.text().get(content.start..content.end) == Some(text.as_str());
            let trimmed = text.trim();
            if let Some(energy) = EnergyRecord::parse(model, trimmed) {
                match energy {
                    Ok(energy) => {
                        let record = Record::Energy(trimmed.to_string(), energy);
                        if self.duplicate_record(&records, &record, index, content) {
                            continue;
                        }
                        records.push((record, index));
                    }
                    Err(diagnostics) => self
                        .problems
                        .extend(diagnostics.0.into_iter().map(|d| d.at(&self.file, content))),
                }
                continue;
            }
            let (integral, spec_text) = match trimmed.strip_prefix("integral:") {
                Some(rest) => (true, rest.trim()),
                None => (false, trimmed),
            };
            let spec = match OutputSpec::parse(model, spec_text) {
                Ok(spec) => spec,
                Err(diagnostics) => {
                    let span = match text.find(spec_text) {
                        Some(at) if exact && !spec_text.is_empty() => {
                            Span::new(content.start + at, content.start + at + spec_text.len())
                        }
                        _ => content,
                    };
                    for mut diagnostic in diagnostics.0 {
                        diagnostic = diagnostic.at(&self.file, span);
                        if let Some(name) = diagnostic.element.clone()
                            && model.element_named(&name).is_none()
                        {
                            let names = model.elements().iter().map(|e| e.name.clone());
                            if let Some(note) = Self::missing_element_note(raw, &name, names) {
                                diagnostic = diagnostic.note(note);
                            }
                        }
                        if !spec_text.contains(':') {
                            diagnostic = diagnostic.note(
                                "or integral:OUTPUT for its time integral, e.g. integral:flow:mass",
                            );
                        }
                        self.problems.push(diagnostic);
                    }
                    continue;
                }
            };
            let record = if integral {
                Record::Integral(spec)
            } else {
                Record::Output(spec)
            };
            if self.duplicate_record(&records, &record, index, content) {
                continue;
            }
            records.push((record, index));
        }
        records.into_iter().map(|(r, _)| r).collect()
    }

    /// Reports `record` (item `index`) if an earlier item records the same; true if so.
    fn duplicate_record(
        &mut self,
        records: &[(Record, usize)],
        record: &Record,
        index: usize,
        content: Span,
    ) -> bool {
        let Some((first, first_index)) = records.iter().find(|(r, _)| r.same_as(record)) else {
            return false;
        };
        let message = format!(
            "record item {} '{}' records the same as item {} '{}'",
            index + 1,
            record.name(),
            first_index + 1,
            first.name()
        );
        self.problem(DiagnosticKind::DuplicateName, message, content, None);
        true
    }
}

/// Which of the model's inputs some element uses.
fn used_inputs(model: &Model) -> Vec<bool> {
    use bondgraph_core::linear::Var;
    let mut used = vec![false; model.inputs().len()];
    let mut mark = |form: &bondgraph_core::linear::LinearForm| {
        for (var, _) in form.terms() {
            if let Var::Input(i) = var
                && let Some(u) = used.get_mut(*i as usize)
            {
                *u = true;
            }
        }
    };
    for element in model.elements() {
        match &element.kind {
            ElementKind::EffortSource(source) | ElementKind::FlowSource(source) => {
                mark(&source.value);
            }
            ElementKind::Friction(friction) => {
                mark(&friction.breakaway.value);
                mark(&friction.coulomb.value);
            }
            ElementKind::FlowLimit(limit) => mark(&limit.max_flow.value),
            _ => {}
        }
    }
    used
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cart pushed by three forces, with a friction contact and a string to a moving
    /// wall.
    const MODEL: &str = r#"// A cart on a rough floor, tied to a moving wall by a string.
Model(
    name: "cart",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "k": (value: 100.0, unit: "N/m"),
        "b": (value: 4.0, unit: "N*s/m"),
        "F_S": (value: 3.0, unit: "N"),
        "F_C": (value: 2.0, unit: "N"),
    },
    inputs: {
        "F": (unit: "N"),
        "G": (unit: "N"),
        "H": (unit: "N"),
        "v_w": (unit: "m/s", description: "wall velocity"),
    },
    elements: {
        "push": Se(effort: "F + G + H"),
        "cart": One,
        "mass": I(inertance: "m"),
        "damper": R(resistance: "b"),
        "fr": Friction(breakaway: "F_S", coulomb: "F_C"),
        "tether": Zero,
        "string": TensionOnly(stiffness: "k"),
        "wall": Sf(flow: "v_w"),
    },
    bonds: [
        ("push", "cart"),
        ("cart", "mass"),
        ("cart", "damper"),
        ("cart", "fr"),
        ("cart", "tether"),
        ("tether", "string"),
        ("wall", "tether"),
    ],
)
"#;

    const SCENARIO: &str = r#"// Every kind of signal.
Scenario(
    name: "push",
    description: "The cart pushed by a ramp, a step and a table.",
    parameters: { "b": 2.5, "F_S": 4 },
    inputs: {
        "F": Ramp(slope: 2.0, start: 1.0, initial: -1.0, ceiling: 3.0),
        "G": Step(at: 0.5, before: 1.0, after: -2.0),
        "H": Table([(0.0, 0.0), (1.0, 2.0), (3.0, -2.0)]),
        "v_w": Constant(0.25),
    },
    initial_mode: "fr=slip+, string=slack",
    initial_state: { "mass": 0.5, "string": -1.0e-2 },
    duration: 4.0,
    record: ["flow:mass", "effort:string", "integral:flow:mass", "e:push->cart"],
    sample: 1e-2,
)
"#;

    fn load_text(scenario: &str) -> Result<Scenario> {
        load(
            &SourceFile::new("scenarios/push.ron", scenario),
            &SourceFile::new("models/cart.ron", MODEL),
        )
    }

    /// The scenario with `from` replaced by `to` (which must occur exactly once).
    fn with(from: &str, to: &str) -> String {
        assert_eq!(SCENARIO.matches(from).count(), 1, "{from:?}");
        SCENARIO.replace(from, to)
    }

    /// Each diagnostic's kind, message, line, column and element.
    fn problems(scenario: &str) -> Vec<(DiagnosticKind, String, usize, usize, Option<String>)> {
        let error = load_text(scenario).expect_err("the scenario has a problem");
        error
            .iter()
            .map(|d| {
                let location = d.location.as_ref().expect("located");
                (
                    d.kind,
                    d.message.clone(),
                    location.line,
                    location.column,
                    d.element.clone(),
                )
            })
            .collect()
    }

    /// The only diagnostic, its notes and the text it underlines.
    fn only(scenario: &str) -> (DiagnosticKind, String, usize, usize, Vec<String>, String) {
        let error = load_text(scenario).expect_err("the scenario has a problem");
        assert_eq!(error.0.len(), 1, "{error}");
        let d = error.first();
        let location = d.location.as_ref().expect("located");
        assert_eq!(location.file, "scenarios/push.ron");
        let underlined = scenario[location.span.start..location.span.end].to_string();
        (
            d.kind,
            d.message.clone(),
            location.line,
            location.column,
            d.notes.clone(),
            underlined,
        )
    }

    #[test]
    fn a_scenario_with_every_kind_of_signal() {
        let scenario = load_text(SCENARIO).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scenario.name, "push");
        assert_eq!(
            scenario.description.as_deref(),
            Some("The cart pushed by a ramp, a step and a table.")
        );
        assert_eq!(scenario.source.name(), "scenarios/push.ron");
        let model = &scenario.model;
        assert_eq!(model.source().name(), "models/cart.ron (edited)");
        let value = |name: &str| {
            model
                .parameters()
                .iter()
                .find(|p| p.name == name)
                .unwrap()
                .value
        };
        assert_eq!((value("b"), value("F_S"), value("m")), (2.5, 4.0, 2.0));

        let [f, g, h, v] = &scenario.inputs[..] else {
            panic!("four inputs: {:?}", scenario.inputs)
        };
        assert_eq!(
            *f,
            Signal::Ramp {
                start: 1.0,
                initial: -1.0,
                slope: 2.0,
                ceiling: Some(3.0)
            }
        );
        assert_eq!(
            *g,
            Signal::Step {
                at: 0.5,
                before: 1.0,
                after: -2.0
            }
        );
        assert_eq!(*h, Signal::Table(vec![(0.0, 0.0), (1.0, 2.0), (3.0, -2.0)]));
        assert_eq!(*v, Signal::Constant(0.25));

        // F: -1 until t = 1, then -1 + 2 (t - 1) until it reaches 3 at t = 3.
        let at =
            |s: &Signal, times: &[f64]| -> Vec<f64> { times.iter().map(|&t| s.value(t)).collect() };
        let rates =
            |s: &Signal, times: &[f64]| -> Vec<f64> { times.iter().map(|&t| s.rate(t)).collect() };
        assert_eq!(
            at(f, &[-1.0, 0.0, 1.0, 1.5, 2.0, 3.0, 3.5, 100.0]),
            [-1.0, -1.0, -1.0, 0.0, 1.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(
            rates(f, &[0.0, 0.999, 1.0, 2.0, 2.999, 3.0, 10.0]),
            [0.0, 0.0, 2.0, 2.0, 2.0, 0.0, 0.0]
        );
        assert_eq!(f.breakpoints(), [1.0, 3.0]);
        assert_eq!(f.ceiling_time(), Some(3.0));
        // G: 1 before t = 0.5, -2 from then on.
        assert_eq!(
            at(g, &[-5.0, 0.0, 0.4999, 0.5, 7.0]),
            [1.0, 1.0, 1.0, -2.0, -2.0]
        );
        assert_eq!(rates(g, &[0.0, 0.5, 1.0]), [0.0, 0.0, 0.0]);
        assert_eq!(g.breakpoints(), [0.5]);
        // H: 0 -> 2 over [0, 1] (rate 2), 2 -> -2 over [1, 3] (rate -2), then held.
        assert_eq!(
            at(h, &[-1.0, 0.0, 0.25, 1.0, 2.0, 2.5, 3.0, 9.0]),
            [0.0, 0.0, 0.5, 2.0, 0.0, -1.0, -2.0, -2.0]
        );
        assert_eq!(
            rates(h, &[-1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 9.0]),
            [0.0, 2.0, 2.0, -2.0, -2.0, 0.0, 0.0]
        );
        assert_eq!(h.breakpoints(), [0.0, 1.0, 3.0]);
        assert_eq!((v.value(123.0), v.rate(0.0)), (0.25, 0.0));
        assert!(v.breakpoints().is_empty());
        assert_eq!(scenario.breakpoints(), [0.0, 0.5, 1.0, 3.0]);

        assert_eq!(
            f.to_string(),
            "ramp from -1 at t = 1 s with slope 2/s, up to 3"
        );
        assert_eq!(g.to_string(), "step from 1 to -2 at t = 0.5 s");
        assert_eq!(h.to_string(), "table through (0, 0), (1, 2), (3, -2)");
        assert_eq!(v.to_string(), "constant 0.25");

        assert_eq!(scenario.initial_mode.spec(model), "fr=slip+,string=slack");
        let states: Vec<(&str, f64)> = scenario
            .initial_state
            .iter()
            .map(|(id, x)| (model.element(*id).name.as_str(), *x))
            .collect();
        assert_eq!(states, [("mass", 0.5), ("string", -0.01)]);
        assert_eq!(scenario.duration, 4.0);
        assert_eq!(scenario.sample, Some(0.01));
        let records: Vec<String> = scenario.record.iter().map(Record::name).collect();
        assert_eq!(
            records,
            [
                "flow:mass",
                "effort:string",
                "integral:flow:mass",
                "e:push->cart"
            ]
        );
        assert!(matches!(scenario.record[2], Record::Integral(_)));
        assert_eq!(scenario.record[2].spec(), scenario.record[0].spec());
        assert_eq!(
            scenario.record[3].spec().unwrap().bond,
            model.bond_ids().next().unwrap()
        );
    }

    #[test]
    fn the_least_a_scenario_says() {
        let text = r#"(name: "rest", inputs: {"F": Constant(0), "G": Constant(0),
            "H": Constant(0), "v_w": Constant(0)}, duration: 1)"#;
        let scenario = load_text(text).unwrap();
        assert_eq!(scenario.model.source().name(), "models/cart.ron");
        assert_eq!(
            scenario.initial_mode.spec(&scenario.model),
            "fr=stuck,string=taut"
        );
        assert!(scenario.initial_state.is_empty() && scenario.record.is_empty());
        assert_eq!((scenario.sample, scenario.description), (None, None));
    }

    #[test]
    fn numbers_that_are_not_finite() {
        assert_eq!(
            only(&with("slope: 2.0", "slope: 1e400")),
            (
                DiagnosticKind::InvalidValue,
                "input 'F': slope 1e400 is too large for a 64-bit floating-point number".into(),
                7,
                26,
                vec![],
                "1e400".into()
            )
        );
        assert_eq!(
            only(&with("Constant(0.25)", "Constant(NaN)")),
            (
                DiagnosticKind::InvalidValue,
                "input 'v_w': constant NaN is not a finite number".into(),
                10,
                25,
                vec![],
                "NaN".into()
            )
        );
        assert_eq!(
            only(&with("\"b\": 2.5", "\"b\": -inf")),
            (
                DiagnosticKind::InvalidValue,
                "parameter 'b': -inf is not a finite number".into(),
                5,
                24,
                vec![],
                "-inf".into()
            )
        );
        assert_eq!(
            only(&with("\"mass\": 0.5", "\"mass\": inf")),
            (
                DiagnosticKind::InvalidValue,
                "initial state of 'mass': inf is not a finite number".into(),
                13,
                30,
                vec![],
                "inf".into()
            )
        );
        assert_eq!(
            only(&with("(1.0, 2.0)", "(1.0, inf)")),
            (
                DiagnosticKind::InvalidValue,
                "input 'H': table point 2 (1.0, inf) is not a pair of finite numbers".into(),
                9,
                33,
                vec![],
                "(1.0, inf)".into()
            )
        );
        assert_eq!(
            only(&with("at: 0.5", "at: NaN")).1,
            "input 'G': step time NaN is not a finite number"
        );
    }

    #[test]
    fn plans_over_the_sample_limit_are_refused_with_their_count() {
        assert_eq!(
            only(&with("sample: 1e-2", "sample: 1e-8")),
            (
                DiagnosticKind::TooLarge,
                "4.0 s sampled every 1e-8 s is 400000001 samples, over the limit of 1000000; \
                 give a longer sample interval"
                    .into(),
                16,
                13,
                vec![],
                "1e-8".into()
            )
        );
        assert_eq!(
            only(&with("sample: 1e-2", "sample: 5e-324")).1,
            "4.0 s sampled every 5e-324 s is inf samples, over the limit of 1000000; \
             give a longer sample interval"
        );
        // At the limit exactly: 4 s every 4e-6 s is 1 000 001 samples, one over.
        assert_eq!(
            only(&with("sample: 1e-2", "sample: 4e-6")).1,
            "4.0 s sampled every 4e-6 s is 1000001 samples, over the limit of 1000000; \
             give a longer sample interval"
        );
        if let Err(e) = load_text(&with("sample: 1e-2", "sample: 4.000001e-6")) {
            panic!("{e}");
        }
    }

    #[test]
    fn durations_and_sample_intervals_must_be_positive() {
        assert_eq!(
            only(&with("duration: 4.0", "duration: 0")),
            (
                DiagnosticKind::InvalidValue,
                "duration must be positive, found 0".into(),
                14,
                15,
                vec![],
                "0".into()
            )
        );
        assert_eq!(
            only(&with("duration: 4.0", "duration: -1.5")).1,
            "duration must be positive, found -1.5"
        );
        assert_eq!(
            only(&with("sample: 1e-2", "sample: Some(-1e-2)")),
            (
                DiagnosticKind::InvalidValue,
                "sample interval must be positive, found -1e-2".into(),
                16,
                18,
                vec![],
                "-1e-2".into()
            )
        );
        assert_eq!(
            only(&with("duration: 4.0", "duration: 1e999")).1,
            "duration 1e999 is too large for a 64-bit floating-point number"
        );
    }

    #[test]
    fn ramps_that_never_reach_their_ceiling() {
        let note =
            "a ramp stops at its ceiling: above where it starts if it rises, below if it falls";
        assert_eq!(
            only(&with("ceiling: 3.0", "ceiling: -3.0")),
            (
                DiagnosticKind::InvalidValue,
                "input 'F': the ramp starts at -1 and rises (slope 2), so it never reaches its ceiling -3".into(),
                7,
                67,
                vec![note.to_string()],
                "-3.0".into()
            )
        );
        assert_eq!(
            only(&with("slope: 2.0", "slope: -2.0")).1,
            "input 'F': the ramp starts at -1 and falls (slope -2), so it never reaches its ceiling 3"
        );
        assert_eq!(
            only(&with("slope: 2.0", "slope: 0")).1,
            "input 'F': the ramp starts at -1 and stays there (slope 0), so it never reaches its ceiling 3"
        );
        // A ceiling where the ramp starts is reached at once; negative times are fine.
        let flat = with("ceiling: 3.0", "ceiling: -1.0").replace("start: 1.0", "start: -2.0");
        let scenario = load_text(&flat).unwrap();
        assert_eq!(scenario.inputs[0].breakpoints(), [-2.0]);
        assert_eq!(scenario.inputs[0].value(0.0), -1.0);
    }

    #[test]
    fn tables_must_have_increasing_times() {
        assert_eq!(
            only(&with("(3.0, -2.0)", "(1.0, -2.0)")),
            (
                DiagnosticKind::InvalidValue,
                "input 'H': table times must increase, but point 3 at t = 1 follows point 2 at t = 1".into(),
                9,
                45,
                vec![],
                "(1.0, -2.0)".into()
            )
        );
        assert_eq!(
            only(&with(
                "Table([(0.0, 0.0), (1.0, 2.0), (3.0, -2.0)])",
                "Table([])"
            )),
            (
                DiagnosticKind::InvalidValue,
                "input 'H': the table has no points; give at least one (time, value)".into(),
                9,
                14,
                vec![],
                "Table([])".into()
            )
        );
    }

    #[test]
    fn inputs_unknown_missing_and_given_twice() {
        assert_eq!(
            problems(&with("\"G\": Step", "\"g\": Step")),
            [
                (
                    DiagnosticKind::UnknownName,
                    "input 'g': model 'cart' has no input 'g'".into(),
                    8,
                    9,
                    Some("g".into())
                ),
                (
                    DiagnosticKind::MissingInput,
                    "input 'G' (N) of model 'cart' has no signal".into(),
                    6,
                    5,
                    Some("G".into())
                ),
            ]
        );
        let error = load_text(&with("\"G\": Step", "\"g\": Step")).unwrap_err();
        assert_eq!(error.0[0].notes, ["did you mean 'G'?"]);
        assert_eq!(
            error.0[1].notes,
            ["give it one under inputs, e.g. \"G\": Constant(0.0)"]
        );
        assert_eq!(
            only(&with(
                "\"v_w\": Constant(0.25),",
                "\"v_w\": Constant(0.25), \"k\": Constant(1),"
            )),
            (
                DiagnosticKind::UnknownName,
                "input 'k': model 'cart' has no input 'k'".into(),
                10,
                32,
                vec!["'k' is a parameter of the model; set it under parameters".into()],
                "\"k\"".into()
            )
        );
        assert_eq!(
            only(&with(
                "\"v_w\": Constant(0.25),",
                "\"v_w\": Constant(0.25),\n        \"F\": Constant(1),"
            )),
            (
                DiagnosticKind::DuplicateName,
                "input 'F' is given twice".into(),
                11,
                9,
                vec!["it is first given on line 7".into()],
                "\"F\"".into()
            )
        );
    }

    #[test]
    fn initial_states_of_unknown_and_non_storage_elements() {
        assert_eq!(
            only(&with("\"mass\": 0.5", "\"mas\": 0.5")),
            (
                DiagnosticKind::UnknownName,
                "initial state of 'mas': model 'cart' has no element 'mas'".into(),
                13,
                22,
                vec!["did you mean 'mass'?".into()],
                "\"mas\"".into()
            )
        );
        assert_eq!(
            only(&with("\"mass\": 0.5", "\"fr\": 0.5")),
            (
                DiagnosticKind::NotStorage,
                "initial state of 'fr': 'fr' is a friction contact, which stores no energy".into(),
                13,
                22,
                vec!["initial states are the momentum of an inertia or the displacement of a compliance or tension-only element".into()],
                "\"fr\"".into()
            )
        );
        assert_eq!(
            only(&with("\"string\": -1.0e-2", "\"mass\": -1.0e-2")).1,
            "initial state of 'mass' is given twice"
        );
    }

    #[test]
    fn bad_modes_and_outputs_point_into_the_string() {
        assert_eq!(
            only(&with("string=slack", "string=slak")),
            (
                DiagnosticKind::BadMode,
                "mode 'string=slak': 'string' has modes taut, slack, not 'slak'".into(),
                12,
                30,
                vec![],
                "string=slak".into()
            )
        );
        assert_eq!(
            only(&with(
                "\"fr=slip+, string=slack\"",
                "\"fr=slip+, strin=slack\""
            )),
            (
                DiagnosticKind::BadMode,
                "mode 'strin=slack': the model has no element 'strin'".into(),
                12,
                30,
                vec!["did you mean 'string'?".into()],
                "strin=slack".into()
            )
        );
        assert_eq!(
            only(&with("\"integral:flow:mass\"", "\"integral:flow:mas\"")),
            (
                DiagnosticKind::BadOutput,
                "output 'flow:mas': the model has no element 'mas'".into(),
                15,
                54,
                vec!["did you mean 'mass'?".into()],
                "flow:mas".into()
            )
        );
        assert_eq!(
            only(&with("\"effort:string\"", "\"string\"")),
            (
                DiagnosticKind::BadOutput,
                "output 'string' must be written effort:ELEMENT, flow:ELEMENT or effort:FROM->TO"
                    .into(),
                15,
                28,
                vec!["or integral:OUTPUT for its time integral, e.g. integral:flow:mass".into()],
                "string".into()
            )
        );
        assert_eq!(
            only(&with(
                "\"e:push->cart\"",
                "\"e:push->cart\", \"effort:push\""
            )),
            (
                DiagnosticKind::DuplicateName,
                "record item 5 'effort:push' records the same as item 4 'e:push->cart'".into(),
                15,
                83,
                vec![],
                "effort:push".into()
            )
        );
    }

    #[test]
    fn edits_through_the_scenario() {
        // Without the damper and the wall: 'v_w' drives nothing and need not be given.
        let text = with(
            "parameters: { \"b\": 2.5, \"F_S\": 4 },",
            "remove: [\"damper\", \"wall\", \"string\", \"tether\"],\n    parameters: { \"k\": 250.0 },",
        )
        .replace("\"v_w\": Constant(0.25),", "")
        .replace(", string=slack", "")
        .replace(", \"string\": -1.0e-2", "")
        .replace("\"effort:string\", ", "");
        let scenario = load_text(&text).unwrap_or_else(|e| panic!("{e}"));
        let model = &scenario.model;
        assert_eq!(model.source().name(), "models/cart.ron (edited)");
        assert_eq!(model.elements().len(), 4);
        assert_eq!(model.bonds().len(), 3);
        assert_eq!(model.element_named("damper"), None);
        assert_eq!(model.parameters()[1].value, 250.0);
        assert_eq!(model.inputs().len(), 4);
        assert_eq!(scenario.inputs[3], Signal::Constant(0.0));
        assert!(model.source().text().contains("// A cart on a rough floor"));

        // What the scenario removed cannot be used.
        let error = load_text(&text.replace("\"mass\": 0.5", "\"wall\": 0.5")).unwrap_err();
        assert_eq!(
            error.first().message,
            "initial state of 'wall': model 'cart' has no element 'wall'"
        );
        assert_eq!(error.first().notes, ["the scenario removes 'wall'"]);
    }

    #[test]
    fn edit_problems_point_into_the_scenario() {
        let text = with(
            "parameters: { \"b\": 2.5, \"F_S\": 4 },",
            "remove: [\"dampr\"],\n    parameters: { \"b\": 2.5, \"bb\": 4 },",
        );
        assert_eq!(
            problems(&text),
            [
                (
                    DiagnosticKind::UnknownName,
                    "cannot remove element 'dampr': model 'cart' has no element 'dampr'".into(),
                    5,
                    15,
                    Some("dampr".into())
                ),
                (
                    DiagnosticKind::UnknownName,
                    "cannot set parameter 'bb': model 'cart' has no parameter 'bb'".into(),
                    6,
                    29,
                    Some("bb".into())
                ),
            ]
        );
        let error = load_text(&text).unwrap_err();
        assert_eq!(error.0[0].notes, ["did you mean 'damper'?"]);
        assert_eq!(error.0[1].notes, ["did you mean 'b'?"]);
    }

    #[test]
    fn what_an_edit_breaks_points_at_the_model_file() {
        let text = with(
            "parameters: { \"b\": 2.5, \"F_S\": 4 },",
            "remove: [\"wall\", \"string\"],",
        );
        let error = load_text(&text).unwrap_err();
        let d = error.first();
        assert_eq!(d.kind, DiagnosticKind::BondCount);
        assert_eq!(
            d.message,
            "0-junction 'tether' has 1 bond; a junction joins two or more"
        );
        let location = d.location.as_ref().unwrap();
        assert_eq!(
            (location.file.as_str(), location.line, location.column),
            ("models/cart.ron", 23, 9)
        );
        assert_eq!(
            d.notes,
            ["in the model as scenario 'push' edits it (scenarios/push.ron:5:5)"]
        );
        // The model's own problems are the model's.
        let broken = MODEL.replace("\"m\": (value: 2.0", "\"m\": (value: -2.0");
        let error = load(
            &SourceFile::new("scenarios/push.ron", SCENARIO),
            &SourceFile::new("models/cart.ron", broken),
        )
        .unwrap_err();
        assert_eq!(
            error.first().location.as_ref().unwrap().file,
            "models/cart.ron"
        );
        assert!(error.first().notes.iter().all(|n| !n.contains("scenario")));
    }

    proptest::proptest! {
        /// Whatever the damage, loading gives a scenario or diagnostics that are all
        /// located on character boundaries inside the file they name; never a panic.
        #[test]
        fn any_damaged_scenario_gives_located_diagnostics_or_a_scenario(
            cut in 0..SCENARIO.len(),
            len in 0_usize..12,
            insert in "[ (){}\\[\\]:,\"'#/*a-z0-9.\\-+é]{0,4}",
        ) {
            let mut text = SCENARIO.to_string();
            let start = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
            let end = (start + len..=text.len())
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(text.len());
            text.replace_range(start..end, &insert);
            if let Err(diagnostics) = load_text(&text) {
                for d in diagnostics.iter() {
                    let location = d.location.as_ref().expect("located");
                    let file = match location.file.as_str() {
                        "scenarios/push.ron" => text.as_str(),
                        "models/cart.ron" => MODEL,
                        other => panic!("{other}: {d}"),
                    };
                    let span = location.span;
                    proptest::prop_assert!(span.start <= span.end && span.end <= file.len());
                    proptest::prop_assert!(
                        file.is_char_boundary(span.start) && file.is_char_boundary(span.end)
                    );
                    proptest::prop_assert!(!d.message.is_empty());
                }
            }
        }
    }

    #[test]
    fn syntax_errors_are_worded_for_scenarios() {
        assert_eq!(
            only(&with("Ramp(slope", "Rmp(slope")),
            (
                DiagnosticKind::UnknownSignalKind,
                "input 'F': unknown signal kind 'Rmp'; expected one of Constant, Step, Ramp, Table"
                    .into(),
                7,
                14,
                vec![],
                "Rmp".into()
            )
        );
        assert_eq!(
            only(&with("start: 1.0", "begin: 1.0")).1,
            "input 'F': unknown field 'begin'; expected one of 'slope', 'start', 'initial', 'ceiling'"
        );
        assert_eq!(
            only(&with("Constant(0.25)", "0.25")),
            (
                DiagnosticKind::WrongType,
                "input 'v_w': expected a signal (Constant, Step, Ramp or Table), found '0.25'"
                    .into(),
                10,
                16,
                vec!["a constant input is written Constant(0.25)".into()],
                "0.25".into()
            )
        );
        assert_eq!(
            only(&with("    duration: 4.0,\n", "")),
            (
                DiagnosticKind::MissingField,
                "missing field 'duration' in the scenario".into(),
                2,
                1,
                vec![],
                SCENARIO[SCENARIO.find("Scenario(").unwrap()..]
                    .trim_end()
                    .replace("    duration: 4.0,\n", "")
            )
        );
        assert_eq!(
            only(&with("duration:", "durration:")).1,
            "unknown field 'durration' in the scenario; expected one of 'name', 'description', \
             'remove', 'parameters', 'inputs', 'initial_mode', 'initial_state', 'duration', \
             'record', 'sample'"
        );
        assert_eq!(
            only(&with("Scenario(", "Senario(")).1,
            "expected Scenario(...) or just (...) around the scenario, found 'Senario'"
        );
        assert_eq!(
            only(&with("\"flow:mass\", \"effort", "flow, \"effort")).1,
            "record item 1 must be a string in double quotes, found 'flow'"
        );
        let (kind, message, line, column, ..) = only("");
        assert_eq!(
            (kind, message.as_str(), line, column),
            (
                DiagnosticKind::Syntax,
                "the file is empty; expected a Scenario(...)",
                1,
                1
            )
        );
    }
}
