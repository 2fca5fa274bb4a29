//! Variants of a model, made by editing the model file's text.
//!
//! A scenario drives a model with some elements taken out (a rig without its load) or
//! some parameters changed (another dead band), and fitting will try candidate
//! variants of a model. Such a variant is made by editing the RON text of the model file
//! rather than the checked [`Model`](super::Model): the result is an ordinary model file,
//! comments and layout kept, that [`load_source`](super::load_source) reads and checks like
//! any other, so every rule of the model format (a junction needs two bonds, the graph
//! must be connected) applies to the variant with the same diagnostics, and the variant can
//! be printed and read by a person.
//!
//! A linear-graph file is edited the same way: a branch removed is its entry in `branches`
//! (a linear graph has no bonds to cut).
//!
//! The source map of the file gives the span of every element entry, bond and parameter value, so an
//! [`Edit`] is a list of text replacements: an element's entry and every bond that touches
//! it are cut out (whole lines when they stand on their own lines), and a parameter's
//! `value` is replaced by the shortest text that reads back as exactly the same `f64`.
//! Values set are in SI units, like every value once a file is read; one is written in the
//! parameter's own unit (250 N/m as `0.25` beside `N/mm`), so that reading the edited file
//! gives it back exactly ([`bondgraph_core::units::Unit::from_si`]).
//!
//! # Example
//! ```
//! use bondgraph_ron::model::{self, edit::{self, Edit}};
//! use bondgraph_core::source::SourceFile;
//!
//! let source = SourceFile::new("msd.ron", r#"Model(name: "msd",
//!     parameters: {"m": (value: 2.0), "b": (value: 4.0)},
//!     elements: {
//!         "v": One,
//!         "mass": I(inertance: "m"),
//!         "damper": R(resistance: "b"),
//!         "extra": R(resistance: "b"),
//!     },
//!     bonds: [("v", "mass"), ("v", "damper"), ("v", "extra")])"#);
//! let edit = Edit { remove: vec!["extra".into()], parameters: vec![("m".into(), 0.5)] };
//! let edited = edit::apply(&source, &edit).unwrap();
//! assert_eq!(edited.name(), "msd.ron (edited)");
//! let model = bondgraph_ron::model::load_source(&edited).unwrap();
//! assert_eq!(model.elements().len(), 3);
//! assert_eq!(model.parameters()[0].value, 0.5);
//! ```

use std::collections::HashSet;
use std::sync::Arc;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use bondgraph_core::source::{Location, SourceFile, Span};

mod part_values;

use super::parse::parse_model;
use crate::source_map::{TokenKind, lex};
use bondgraph_core::diagnostics::suggest;
use bondgraph_core::model::ModelSpec;
use bondgraph_core::model::source_map::SourceMap;

/// Changes to make to a model: elements to take out and parameter values to set.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Edit {
    /// Element names: each element, and every bond that touches it, is removed.
    pub remove: Vec<String>,
    /// New values of existing parameters, by name, in SI units.
    pub parameters: Vec<(String, f64)>,
}

impl Edit {
    /// Whether the edit changes nothing.
    pub fn is_empty(&self) -> bool {
        self.remove.is_empty() && self.parameters.is_empty()
    }
}

/// Applies `edit` to the model file `source`: a new [`SourceFile`] named after the original
/// with ` (edited)` added (`models/examples/two_tank/two_tank.ron (edited)`), holding the edited text.
///
/// The edited text is not validated here: load it with
/// [`load_source`](super::load_source), which reports what the edit broke (a junction left
/// with one bond, a graph in pieces) like any problem of a model file.
///
/// # Errors
/// The model file's syntax error, if it does not parse; otherwise every problem with the
/// edit, located at the model's `elements` or `parameters` field: an element to remove or a
/// parameter to set that the model does not have (with a suggestion for a typo), a name
/// given twice, or a value that is not finite.
pub fn apply(source: &SourceFile, edit: &Edit) -> Result<Arc<SourceFile>> {
    apply_traced(source, edit).map(|edited| edited.file)
}

/// [`apply`], keeping track of where the edited text came from, so that diagnostics about
/// the edited model (a junction the edit left with one bond) can point at the original
/// file that a user can open ([`Edited::relocate`]).
///
/// # Errors
/// As [`apply`].
pub fn apply_traced(source: &SourceFile, edit: &Edit) -> Result<Edited> {
    apply_located(source, edit, &|_| None)
}

/// Which part of an [`Edit`] a problem is about, for callers that know where the edit
/// was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EditItem {
    /// `edit.remove[i]`.
    Remove(usize),
    /// `edit.parameters[i]`.
    Parameter(usize),
}

/// An edited model file and where its text came from.
#[derive(Clone, Debug)]
pub struct Edited {
    /// The edited text, named after the original with ` (edited)` added.
    pub file: Arc<SourceFile>,
    /// The replacements made, in text order: the original span and the span of what
    /// replaced it in the edited text.
    replacements: Vec<(Span, Span)>,
}

impl Edited {
    /// The offset in the original text that edited offset `offset` came from; an offset in
    /// replaced text maps into (or to the start of) what it replaced.
    pub fn original_offset(&self, offset: usize) -> usize {
        let mut shift: isize = 0;
        for &(original, edited) in &self.replacements {
            if offset < edited.start {
                break;
            }
            if offset < edited.end {
                return (original.start + (offset - edited.start)).min(original.end);
            }
            shift = original.end as isize - edited.end as isize;
        }
        offset.saturating_add_signed(shift)
    }

    /// `diagnostic`, if it points into the edited text, pointed at the same text of
    /// `original` instead (so that a renderer can show the line from the real file).
    pub fn relocate(&self, mut diagnostic: Diagnostic, original: &SourceFile) -> Diagnostic {
        if let Some(location) = &diagnostic.location
            && location.file == self.file.name()
        {
            let start = self.original_offset(location.span.start);
            let end = self.original_offset(location.span.end).max(start);
            diagnostic.location = Some(original.locate(Span::new(start, end)));
        }
        diagnostic
    }
}

/// The replacements that set parameter values: the text of each value in the file's unit,
/// at every entry of the parameter (a parameter set twice, unknown or to a value that is not
/// finite is a problem instead).
fn parameter_values<'m>(
    edit: &Edit,
    (raw, map): (&'m ModelSpec, &SourceMap),
    source: &SourceFile,
    locate: &dyn Fn(EditItem) -> Option<Location>,
    place: &dyn Fn(EditItem, &str) -> Location,
    problems: &mut Vec<Diagnostic>,
) -> Vec<(Span, String)> {
    let mut replacements: Vec<(Span, String)> = Vec::new();
    let mut set: HashSet<&str> = HashSet::new();
    let mut qualified: Vec<(usize, &str, f64)> = Vec::new();
    for (index, (name, value)) in edit.parameters.iter().enumerate() {
        let item = EditItem::Parameter(index);
        let entries: Vec<usize> = (0..raw.parameters.len())
            .filter(|&i| raw.parameters[i].0 == *name)
            .collect();
        if !set.insert(name) {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::DuplicateName,
                    format!("parameter '{name}' is set twice"),
                )
                .at_location(place(item, "parameters"))
                .element(name.clone()),
            );
            continue;
        }
        if entries.is_empty() {
            // A sub-model's parameter (`front.k_s`) is given in its use, below.
            if name.contains('.') && value.is_finite() {
                qualified.push((index, name.as_str(), *value));
            } else {
                problems.push(unknown_parameter(raw, name, place(item, "parameters")));
            }
            continue;
        }
        if !value.is_finite() {
            let location =
                locate(item).unwrap_or_else(|| source.locate(map.parameters[entries[0]].key_span));
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!("cannot set parameter '{name}' to {value}: the value must be a finite number"),
                )
                .at_location(location)
                .element(name.clone()),
            );
            continue;
        }
        for i in entries {
            let entry = &map.parameters[i];
            let span = entry
                .field("value")
                .map_or(entry.value_span, |f| f.value_span);
            replacements.push((
                span,
                in_file_unit(*value, raw.parameters[i].1.unit.as_deref()),
            ));
        }
    }
    if !qualified.is_empty() {
        let (given, unknown) = part_values::part_values(source, (raw, map), &qualified);
        replacements.extend(given);
        for index in unknown {
            let (name, _) = &edit.parameters[index];
            let at = place(EditItem::Parameter(index), "parameters");
            problems.push(unknown_parameter(raw, name, at));
        }
    }
    replacements
}

/// [`apply`], with problems located by `locate` where it knows the place of the edit's
/// item, and in the model file otherwise.
pub(crate) fn apply_located(
    source: &SourceFile,
    edit: &Edit,
    locate: &dyn Fn(EditItem) -> Option<Location>,
) -> Result<Edited> {
    let linear = super::Format::of(source.text()) == super::Format::LinearGraph;
    let (raw, map) = if linear {
        super::linear_graph::editable(source)?
    } else {
        parse_model(source)?
    };
    let (noun, section) = if linear {
        ("branch", "branches")
    } else {
        ("element", "elements")
    };
    let text = source.text();
    if map.elements.len() != raw.elements.len()
        || map.parameters.len() != raw.parameters.len()
        || map.bonds.len() != raw.bonds.len()
    {
        // ron read a text the scanner cannot: there are no spans to edit.
        return Err(Diagnostic::new(
            DiagnosticKind::Syntax,
            format!(
                "model '{}' is written in a way that cannot be edited; write its elements, \
                 parameters and bonds as plain maps and lists",
                raw.name
            ),
        )
        .at(source, map.root)
        .into());
    }
    let mut problems = Vec::new();
    let place = |item: EditItem, section: &str| {
        locate(item).unwrap_or_else(|| {
            let span = map.field(section).map_or(map.root, |f| f.name_span);
            source.locate(span)
        })
    };

    // Elements, and the bonds that touch them.
    let mut removed: HashSet<&str> = HashSet::new();
    for (index, name) in edit.remove.iter().enumerate() {
        let item = EditItem::Remove(index);
        if !removed.insert(name) {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::DuplicateName,
                    format!("{noun} '{name}' is removed twice"),
                )
                .at_location(place(item, section))
                .element(name.clone()),
            );
        } else if !raw.elements.iter().any(|(n, _)| n == name) {
            let mut diagnostic = Diagnostic::new(
                DiagnosticKind::UnknownName,
                format!(
                    "cannot remove {noun} '{name}': model '{}' has no {noun} '{name}'",
                    raw.name
                ),
            )
            .at_location(place(item, section))
            .element(name.clone());
            let part = name.split_once('.').and_then(|(use_name, _)| {
                raw.elements.iter().find_map(|(n, e)| match e {
                    bondgraph_core::model::ElementSpec::Submodel { file, .. } if n == use_name => {
                        Some((use_name, file))
                    }
                    _ => None,
                })
            });
            if let Some((use_name, file)) = part {
                diagnostic = diagnostic.note(format!(
                    "'{name}' is inside sub-model '{use_name}' ('{file}'), which is used whole: \
                     remove '{use_name}', or use a part without it"
                ));
            } else if let Some(suggestion) =
                suggest(name, raw.elements.iter().map(|(n, _)| n.as_str()))
            {
                diagnostic = diagnostic.note(format!("did you mean '{suggestion}'?"));
            }
            problems.push(diagnostic);
        }
    }
    let mut cuts: Vec<Span> = Vec::new();
    for (entry, (name, _)) in map.elements.iter().zip(&raw.elements) {
        if removed.contains(name.as_str()) {
            cuts.push(removal(text, entry.span()));
        }
    }
    for (item, bond) in map.bonds.iter().zip(&raw.bonds) {
        if removed.contains(bond.0.as_str()) || removed.contains(bond.1.as_str()) {
            cuts.push(removal(text, item.span));
        }
    }

    // Parameter values.
    let mut replacements =
        parameter_values(edit, (&raw, &map), source, locate, &place, &mut problems);
    if !problems.is_empty() {
        return Err(Diagnostics(problems));
    }

    // Cuts and value replacements are in different sections and never overlap.
    cuts.sort();
    replacements.extend(
        tidy(text, cuts)
            .into_iter()
            .map(|span| (span, String::new())),
    );
    replacements.sort_by_key(|(span, _)| *span);

    let mut edited = String::with_capacity(text.len());
    let mut spans = Vec::with_capacity(replacements.len());
    let mut position = 0;
    for (span, with) in replacements {
        edited.push_str(&text[position..span.start]);
        let start = edited.len();
        edited.push_str(&with);
        spans.push((span, Span::new(start, edited.len())));
        position = span.end;
    }
    edited.push_str(&text[position..]);
    let name = if source.name().ends_with(" (edited)") {
        source.name().to_string()
    } else {
        format!("{} (edited)", source.name())
    };
    Ok(Edited {
        file: SourceFile::new(name, edited),
        replacements: spans,
    })
}

/// A parameter the model does not have, with a suggestion, or a note if it is an input.
fn unknown_parameter(raw: &ModelSpec, name: &str, location: Location) -> Diagnostic {
    let mut diagnostic = Diagnostic::new(
        DiagnosticKind::UnknownName,
        format!(
            "cannot set parameter '{name}': model '{}' has no parameter '{name}'",
            raw.name
        ),
    )
    .at_location(location)
    .element(name);
    if raw.inputs.iter().any(|(n, _)| n == name) {
        diagnostic = diagnostic.note(format!(
            "'{name}' is an input of the model; give it a signal under inputs"
        ));
    } else if let Some(suggestion) = suggest(name, raw.parameters.iter().map(|(n, _)| n.as_str())) {
        diagnostic = diagnostic.note(format!("did you mean '{suggestion}'?"));
    }
    diagnostic
}

/// The text to write for SI value `value` of a parameter whose unit is `unit`: in that
/// unit, as reading the file converts it back to exactly `value` (`0.25` for 250 N/m in
/// `N/mm`); [`number`] where the unit is SI, absent or not a unit (which loading reports).
fn in_file_unit(value: f64, unit: Option<&str>) -> String {
    match unit.map(bondgraph_core::units::parse_scaled) {
        Some(Ok(unit)) => unit.from_si(value),
        _ => number(value),
    }
}

/// The text that reads back as exactly `value`: Rust's shortest round-trip form (`5.0`,
/// `1e-6`, `0.1`), which RON reads as the same `f64`.
pub(crate) fn number(value: f64) -> String {
    format!("{value:?}")
}

/// What to cut to remove the entry or list item at `span`: the item, the comma after it
/// and the spaces after that, so that `[a, b, c]` becomes `[a, c]`.
fn removal(text: &str, span: Span) -> Span {
    let mut end = span.end;
    if let Ok(Some(token)) = lex(text, end)
        && token.kind == TokenKind::Punct(b',')
    {
        end = token.span.end;
    }
    let rest = &text[end..];
    let spaces = rest.len() - rest.trim_start_matches([' ', '\t']).len();
    Span::new(span.start, end + spaces)
}

/// Merges the cuts of single items (sorted) that overlap or touch, and widens each so that
/// no empty line or trailing space is left behind: a cut with nothing else on its lines
/// (but a trailing `//` comment, which is about what was cut) takes the whole lines, and a
/// cut that ends its line takes the spaces before it.
fn tidy(text: &str, cuts: Vec<Span>) -> Vec<Span> {
    let mut merged: Vec<Span> = Vec::new();
    for cut in cuts {
        match merged.last_mut() {
            Some(last) if cut.start <= last.end => last.end = last.end.max(cut.end),
            _ => merged.push(cut),
        }
    }
    for cut in &mut merged {
        let line_start = text[..cut.start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[cut.end..]
            .find('\n')
            .map_or(text.len(), |i| cut.end + i + 1);
        let before = &text[line_start..cut.start];
        let after = text[cut.end..line_end].trim();
        if before.trim().is_empty() && (after.is_empty() || after.starts_with("//")) {
            *cut = Span::new(line_start, line_end);
        } else if after.is_empty() {
            cut.start -= before.len() - before.trim_end_matches([' ', '\t']).len();
        }
    }
    merged
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::load_source;

    const MODEL: &str = r#"// Two masses on springs.
Model(
    name: "chain",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "k": (value: 50.0, unit: "N/m"), // the springs
        "dv": Parameter(value: 1e-3),
    },
    inputs: { "F": (unit: "N") },
    elements: {
        "push": Se(effort: "F"),
        "v1": One,
        "mass1": I(inertance: "m"),
        // The coupling.
        "coupling": Zero, "spring1": C(stiffness: "k"),
        "v2": One, "mass2": I(inertance: "m"), "spring2": C(stiffness: "k"),
        "wall": Zero, // a junction left with one bond if spring2 goes
    },
    bonds: [
        ("push", "v1"),
        ("v1", "mass1"),
        ("v1", "coupling"), ("coupling", "v2"),
        ("coupling", "spring1"),
        ("v2", "mass2"),
        ("v2", "wall"), ("wall", "spring2"),
    ],
)
"#;

    fn source() -> Arc<SourceFile> {
        SourceFile::new("models/chain.ron", MODEL)
    }

    fn edit(remove: &[&str], parameters: &[(&str, f64)]) -> Edit {
        Edit {
            remove: remove.iter().map(|s| s.to_string()).collect(),
            parameters: parameters
                .iter()
                .map(|(n, v)| (n.to_string(), *v))
                .collect(),
        }
    }

    #[test]
    fn removing_cuts_entries_and_bonds_and_keeps_comments() {
        let edited = apply(&source(), &edit(&["mass2", "wall"], &[])).unwrap();
        assert_eq!(edited.name(), "models/chain.ron (edited)");
        let expected = MODEL
            .replace("\"mass2\": I(inertance: \"m\"), ", "")
            .replace(
                "        \"wall\": Zero, // a junction left with one bond if spring2 goes\n",
                "",
            )
            .replace("        (\"v2\", \"mass2\"),\n", "")
            .replace("        (\"v2\", \"wall\"), (\"wall\", \"spring2\"),\n", "");
        assert_eq!(edited.text(), expected);
        assert!(edited.text().contains("// The coupling."));
    }

    #[test]
    fn removing_a_line_of_several_items_keeps_the_others() {
        let edited = apply(&source(), &edit(&["spring2"], &[])).unwrap();
        assert!(
            edited
                .text()
                .contains("        \"v2\": One, \"mass2\": I(inertance: \"m\"),\n")
        );
        assert!(
            edited
                .text()
                .contains("        (\"v2\", \"wall\"),\n    ],")
        );
        assert!(!edited.text().contains("\"spring2\""));
        // 'wall' is left with one bond: the loader says so, in the edited text.
        let error = load_source(&edited).unwrap_err();
        let first = error.first();
        assert_eq!(first.element.as_deref(), Some("wall"));
        let location = first.location.as_ref().unwrap();
        assert_eq!(location.file, "models/chain.ron (edited)");
        assert_eq!(
            &edited.text()[location.span.start..location.span.end],
            "\"wall\""
        );
    }

    #[test]
    fn setting_parameters_writes_round_trip_numbers() {
        for value in [
            1e-6,
            5.0,
            0.1,
            -0.0,
            1.0 / 3.0,
            6.02214076e23,
            5e-324,
            f64::MAX,
            -1234.5,
        ] {
            let edited = apply(&source(), &edit(&[], &[("k", value), ("dv", value)])).unwrap();
            let (raw, _) = parse_model(&edited).unwrap();
            assert_eq!(
                raw.parameters[1].1.value.to_bits(),
                value.to_bits(),
                "{value}"
            );
            assert_eq!(
                raw.parameters[2].1.value.to_bits(),
                value.to_bits(),
                "{value}"
            );
        }
        let edited = apply(&source(), &edit(&[], &[("dv", 1e-6)])).unwrap();
        assert!(edited.text().contains("\"dv\": Parameter(value: 1e-6),"));
        let edited = apply(&source(), &edit(&[], &[("m", 5.0)])).unwrap();
        assert!(
            edited
                .text()
                .contains("\"m\": (value: 5.0, unit: \"kg\"),\n        \"k\"")
        );
        let model = load_source(&edited).unwrap();
        assert_eq!(model.parameters()[0].value, 5.0);
    }

    #[test]
    fn an_empty_edit_copies_the_text() {
        let edited = apply(&source(), &Edit::default()).unwrap();
        assert_eq!(edited.text(), MODEL);
        assert!(Edit::default().is_empty());
    }

    #[test]
    fn problems_with_the_edit_point_at_the_model_sections() {
        let error = apply(
            &source(),
            &edit(
                &["mas1", "v1", "v1"],
                &[
                    ("kk", 1.0),
                    ("F", 2.0),
                    ("m", f64::INFINITY),
                    ("dv", 1.0),
                    ("dv", 2.0),
                ],
            ),
        )
        .unwrap_err();
        let got: Vec<(DiagnosticKind, String, usize, usize, Vec<String>)> = error
            .iter()
            .map(|d| {
                let l = d.location.as_ref().unwrap();
                (d.kind, d.message.clone(), l.line, l.column, d.notes.clone())
            })
            .collect();
        assert_eq!(
            got,
            [
                (
                    DiagnosticKind::UnknownName,
                    "cannot remove element 'mas1': model 'chain' has no element 'mas1'".into(),
                    10,
                    5,
                    vec!["did you mean 'mass1'?".to_string()]
                ),
                (
                    DiagnosticKind::DuplicateName,
                    "element 'v1' is removed twice".into(),
                    10,
                    5,
                    vec![]
                ),
                (
                    DiagnosticKind::UnknownName,
                    "cannot set parameter 'kk': model 'chain' has no parameter 'kk'".into(),
                    4,
                    5,
                    vec!["did you mean 'k'?".to_string()]
                ),
                (
                    DiagnosticKind::UnknownName,
                    "cannot set parameter 'F': model 'chain' has no parameter 'F'".into(),
                    4,
                    5,
                    vec!["'F' is an input of the model; give it a signal under inputs".into()]
                ),
                (
                    DiagnosticKind::InvalidValue,
                    "cannot set parameter 'm' to inf: the value must be a finite number".into(),
                    5,
                    9,
                    vec![]
                ),
                (
                    DiagnosticKind::DuplicateName,
                    "parameter 'dv' is set twice".into(),
                    4,
                    5,
                    vec![]
                ),
            ]
        );
        assert_eq!(error.0[0].element.as_deref(), Some("mas1"));
    }

    #[test]
    fn a_model_that_does_not_parse_gives_its_syntax_error() {
        let broken = SourceFile::new("m.ron", "Model(name: \"x\", elements: {\"a\": Q})");
        let error = apply(&broken, &edit(&["a"], &[])).unwrap_err();
        assert_eq!(error.first().kind, DiagnosticKind::UnknownElementKind);
        assert_eq!(error.first().location.as_ref().unwrap().file, "m.ron");
    }

    #[test]
    fn edited_offsets_map_back_to_the_original() {
        let original = source();
        let edited = apply_traced(&original, &edit(&["mass2"], &[("m", 0.5)])).unwrap();
        let text = edited.file.text();
        for needle in ["\"wall\"", "\"k\"", "(\"wall\", \"spring2\")", "Model("] {
            let at = text.find(needle).unwrap();
            assert_eq!(
                edited.original_offset(at),
                MODEL.find(needle).unwrap(),
                "{needle}"
            );
        }
        // Inside a replaced value: into what it replaced.
        let value = text.find("0.5").unwrap();
        assert_eq!(edited.original_offset(value), MODEL.find("2.0").unwrap());
        let error = load_source(&apply(&original, &edit(&["spring2"], &[])).unwrap()).unwrap_err();
        let edited = apply_traced(&original, &edit(&["spring2"], &[])).unwrap();
        let relocated = edited.relocate(error.first().clone(), &original);
        let location = relocated.location.unwrap();
        assert_eq!(
            (location.file.as_str(), location.line, location.column),
            ("models/chain.ron", 17, 9)
        );
    }
}
