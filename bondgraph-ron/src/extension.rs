//! Model extensions: bond-graph or linear-graph fragments merged into a model file.
//!
//! When a model disagrees with measurements, the cause is often a piece of physics it leaves
//! out: a force nobody modelled, a friction that depends on the load. An extension writes that
//! piece down as a small bond-graph fragment with a physical cause, its own parameters (with
//! bounds, for calibration) and, where it changes an element rather than adding one, the
//! replacement of that element:
//!
//! ```ron
//! Extension(
//!     id: "supply-line-resistance",
//!     cause: "the pump pushes through a long supply line, so the pressure at the cylinder sags in proportion to its speed",
//!     evidence: "measure the pressure at the cylinder while it moves",
//!     parameters: { "R_s": (value: 0.0, unit: "Pa*s/m^3", bounds: (0.0, 1e10)) },
//!     elements: { "supply_line": R(resistance: "A^2*R_s") },
//!     bonds: [("piston", "supply_line")],
//! )
//! ```
//!
//! Fields: `id`, `cause` (one sentence), `evidence` (optional: the measurement that would
//! show the effect directly), `parameters` and `inputs` (new ones), `elements` (new ones,
//! and the new version of each element named in `replace`), `replace` (names of the base
//! model's elements that `elements` gives anew) and `bonds` (new bonds, which may join new
//! elements to the base model's).
//!
//! A linear graph takes a linear-graph fragment: `branches` in place of `elements` and
//! `bonds`, written as the graph writes them, each naming its nodes (a node the base graph
//! does not have is a new node), `replace` naming the base graph's branches it gives anew:
//!
//! ```ron
//! Extension(
//!     id: "contact-resistance",
//!     cause: "a dry joint adds a contact resistance in series with the bar",
//!     parameters: { "R_c": (value: 0.0, unit: "K/W", bounds: (0.0, 10.0)) },
//!     branches: {
//!         "bar": D(resistance: "R_12", from: "T1", to: "contact"),
//!         "joint": D(resistance: "R_c", from: "contact", to: "T2"),
//!     },
//!     replace: ["bar"],
//! )
//! ```
//!
//! [`merge`] writes the fragments into the base model's *text*: entries are appended to the
//! model's sections and replaced elements are rewritten in place, comments and layout kept,
//! and the model is renamed `base+id`. The result is an ordinary model file that
//! [`load_source`](crate::model::load_source) checks like any other, that `bondgraph equations`
//! and `simulate` accept, and that a person can read. A problem the merged model has (a bond
//! to an element neither file defines) is reported at the line of the file it came from:
//! [`Extended::load`] points diagnostics about copied text back into the extension file.
//!
//! # Example
//! ```
//! use bondgraph_ron::extension::{self, Extension};
//! use bondgraph_core::source::SourceFile;
//!
//! let base = SourceFile::new("msd.ron", r#"Model(name: "msd",
//!     parameters: {"m": (value: 2.0), "b": (value: 4.0)},
//!     inputs: {"F": ()},
//!     elements: {"push": Se(effort: "F"), "v": One, "mass": I(inertance: "m"), "damper": R(resistance: "b")},
//!     bonds: [("push", "v"), ("v", "mass"), ("v", "damper")])"#);
//! let fragment = SourceFile::new("air.ron", r#"Extension(
//!     id: "air-drag",
//!     cause: "the air resists the mass in proportion to its speed",
//!     parameters: {"b_air": (value: 1.0, bounds: (0.0, 10.0))},
//!     elements: {"air": R(resistance: "b_air")},
//!     bonds: [("v", "air")],
//! )"#);
//! let extension = Extension::load(&fragment).unwrap();
//! let extended = extension::merge(&base, &[extension]).unwrap();
//! let model = extended.load().unwrap();
//! assert_eq!(model.name(), "msd+air-drag");
//! assert_eq!(model.elements().len(), 5);
//! assert_eq!(model.parameters()[2].bounds, Some((0.0, 10.0)));
//! ```

use std::collections::HashSet;
use std::sync::Arc;

use serde::Deserialize;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use bondgraph_core::source::{SourceFile, Span};

use crate::model::Format;
use crate::model::linear_graph::format::{RawBranch, RawLinearGraph};
use crate::model::parse::{FileKind, parse_file, parse_model};
use crate::source_map::{TokenKind, lex};
use bondgraph_core::diagnostics::suggest;
use bondgraph_core::model::Model;
use bondgraph_core::model::source_map::{EntrySpans, SourceMap};
use bondgraph_core::model::spec::{BondSpec, ElementSpec, InputSpec, ParameterSpec, entries};

/// An extension file, exactly as serde reads it.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Extension", deny_unknown_fields)]
pub struct RawExtension {
    /// A short name, lower case with dashes (`ac-fluid-displacement`).
    pub id: String,
    /// The physical cause, in one sentence.
    pub cause: String,
    /// The measurement that would show the effect directly, for people.
    pub evidence: Option<String>,
    /// New parameters.
    #[serde(default, deserialize_with = "entries")]
    pub parameters: Vec<(String, ParameterSpec)>,
    /// New inputs.
    #[serde(default, deserialize_with = "entries")]
    pub inputs: Vec<(String, InputSpec)>,
    /// New elements, and the new version of each element named in `replace`.
    #[serde(default, deserialize_with = "entries")]
    pub elements: Vec<(String, ElementSpec)>,
    /// New branches of a linear graph (new nodes allowed), and the new version of each
    /// branch named in `replace`.
    #[serde(default, deserialize_with = "entries")]
    pub branches: Vec<(String, RawBranch)>,
    /// The base model's elements (or branches) that `elements` (or `branches`) gives anew.
    #[serde(default)]
    pub replace: Vec<String>,
    /// New bonds.
    #[serde(default)]
    pub bonds: Vec<BondSpec>,
}

/// A parsed extension file, with the spans of its parts.
#[derive(Clone, Debug)]
pub struct Extension {
    /// What the file says.
    pub raw: RawExtension,
    source: Arc<SourceFile>,
    map: SourceMap,
}

impl Extension {
    /// Parses the extension in `source`.
    ///
    /// # Errors
    /// Syntax errors, unknown fields and element kinds, an id that is not lower case with
    /// dashes, and an element named in `replace` that `elements` does not give.
    pub fn load(source: &Arc<SourceFile>) -> Result<Self> {
        let (raw, map) = parse_file::<RawExtension>(source, FileKind::Extension)?;
        let mut problems = Vec::new();
        let field_span = |name: &str| map.field(name).map_or(map.root, |f| f.value_span);
        let id_ok = !raw.id.is_empty()
            && raw
                .id
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
        if !id_ok {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "extension id \"{}\" must be lower-case letters, digits and dashes",
                        raw.id
                    ),
                )
                .at(source, field_span("id")),
            );
        }
        let linear = !raw.branches.is_empty();
        if linear && (!raw.elements.is_empty() || !raw.bonds.is_empty()) {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "extension '{}' gives both branches (a linear-graph fragment) and elements or bonds (a bond-graph fragment)",
                        raw.id
                    ),
                )
                .at(source, field_span("branches"))
                .note("an extension is written in the formalism of the model it extends: branches for a linear graph, elements and bonds for a bond graph"),
            );
        }
        let (part, section) = if linear {
            ("branch", "branches")
        } else {
            ("element", "elements")
        };
        for name in &raw.replace {
            let given = raw.elements.iter().any(|(n, _)| n == name)
                || raw.branches.iter().any(|(n, _)| n == name);
            if !given {
                problems.push(
                    Diagnostic::new(
                        DiagnosticKind::UnknownName,
                        format!(
                            "extension '{}' replaces {part} '{name}' but gives no new '{name}' under {section}",
                            raw.id
                        ),
                    )
                    .at(source, field_span("replace"))
                    .element(name.clone()),
                );
            }
        }
        if map.elements.len() != raw.elements.len()
            || map.branches.len() != raw.branches.len()
            || map.parameters.len() != raw.parameters.len()
            || map.inputs.len() != raw.inputs.len()
            || map.bonds.len() != raw.bonds.len()
        {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::Syntax,
                    "this extension is written in a way that cannot be merged; write its \
                     elements (or branches), parameters, inputs and bonds as plain maps and lists",
                )
                .at(source, map.root),
            );
        }
        if !problems.is_empty() {
            return Err(Diagnostics(problems));
        }
        Ok(Self {
            raw,
            source: Arc::clone(source),
            map,
        })
    }

    /// Reads and parses the extension file at `path`.
    ///
    /// # Errors
    /// An unreadable file, and everything [`Extension::load`] reports.
    pub fn read(path: &std::path::Path) -> Result<Self> {
        let text = crate::read::read_text(path, "extension")
            .map_err(|message| Diagnostic::new(DiagnosticKind::Io, message))?;
        Self::load(&SourceFile::new(path.display().to_string(), text))
    }

    /// The extension's id.
    pub fn id(&self) -> &str {
        &self.raw.id
    }

    /// The file it was read from.
    pub fn source(&self) -> &Arc<SourceFile> {
        &self.source
    }

    /// Whether it is a linear-graph fragment (it gives branches).
    pub fn is_linear_graph(&self) -> bool {
        !self.raw.branches.is_empty()
    }

    /// Its new and replacing parts (elements, or branches of a linear graph), with their
    /// spans.
    fn parts(&self) -> impl Iterator<Item = (&str, &EntrySpans)> {
        let names = self
            .raw
            .elements
            .iter()
            .map(|(n, _)| n.as_str())
            .chain(self.raw.branches.iter().map(|(n, _)| n.as_str()));
        names.zip(self.map.elements.iter().chain(&self.map.branches))
    }
}

/// What a merge needs of the base model file: its names and the spans of its sections.
struct Base {
    name: String,
    parameters: Vec<String>,
    inputs: Vec<String>,
    /// Its elements, or a linear graph's branches.
    parts: Vec<String>,
    map: SourceMap,
    linear: bool,
}

impl Base {
    fn parse(file: &SourceFile) -> Result<Self> {
        fn names<T>(entries: &[(String, T)]) -> Vec<String> {
            entries.iter().map(|(n, _)| n.clone()).collect()
        }
        Ok(match Format::of(file.text()) {
            Format::BondGraph => {
                let (raw, map) = parse_model(file)?;
                Base {
                    parameters: names(&raw.parameters),
                    inputs: names(&raw.inputs),
                    parts: names(&raw.elements),
                    name: raw.name,
                    map,
                    linear: false,
                }
            }
            Format::LinearGraph => {
                let (raw, map) = parse_file::<RawLinearGraph>(file, FileKind::LinearGraph)?;
                Base {
                    parameters: names(&raw.parameters),
                    inputs: names(&raw.inputs),
                    parts: names(&raw.branches),
                    name: raw.name,
                    map,
                    linear: true,
                }
            }
        })
    }

    /// The word for a part, and the section that holds them.
    fn part(&self) -> (&'static str, &'static str) {
        if self.linear {
            ("branch", "branches")
        } else {
            ("element", "elements")
        }
    }

    fn part_spans(&self) -> &[EntrySpans] {
        if self.linear {
            &self.map.branches
        } else {
            &self.map.elements
        }
    }
}

/// A model file with extensions merged in, and where each part of its text came from.
#[derive(Clone, Debug)]
pub struct Extended {
    /// The merged model file, named `base + id + ...`.
    pub file: Arc<SourceFile>,
    base: Arc<SourceFile>,
    extensions: Vec<Arc<SourceFile>>,
    /// The merged text, piece by piece, in order.
    pieces: Vec<Piece>,
}

/// A stretch of the merged text and where it came from.
#[derive(Clone, Copy, Debug)]
struct Piece {
    merged: Span,
    origin: Origin,
}

#[derive(Clone, Copy, Debug)]
enum Origin {
    /// Copied from the base model, starting at this offset.
    Base(usize),
    /// Copied from extension `.0`, starting at offset `.1`.
    Extension(usize, usize),
    /// Written by the merge (separators, comments), at this offset of the base model.
    Generated(usize),
}

/// Text that replaces a span of the base model: written text and copies from extensions.
struct Splice {
    at: Span,
    parts: Vec<Part>,
}

enum Part {
    Text(String),
    Copy(usize, Span),
}

impl Extended {
    /// Checks the merged model, with every diagnostic pointed at the file and line its
    /// text came from (the base model or an extension).
    ///
    /// # Errors
    /// Every problem of the merged model, as [`load_source`](crate::model::load_source) reports it.
    pub fn load(&self) -> Result<Model> {
        crate::model::load_source(&self.file)
            .map_err(|d| Diagnostics(d.0.into_iter().map(|d| self.relocate(d)).collect()))
    }

    /// Checks the merged model as `bondgraph check` does: [`Extended::load`], then the
    /// equations of every reachable mode. A fragment can make a consistent model
    /// inconsistent (a second flow source on a 1-junction is a causal conflict); such a
    /// problem is reported at the line of the extension that brought in the element or bond
    /// it names, with a note giving the place in the base model.
    ///
    /// # Errors
    /// Every problem [`Extended::load`] reports, else the first problem deriving a mode's
    /// equations.
    pub fn check(&self) -> Result<Model> {
        let model = self.load()?;
        let options = bondgraph_core::equations::Options::default();
        let derived = if model.is_nonlinear() {
            bondgraph_core::modes::reachable_nonlinear(&model, &options).map(|_| ())
        } else {
            bondgraph_core::modes::reachable(&model, &options).map(|_| ())
        };
        match derived {
            Ok(()) => Ok(model),
            Err(problems) => Err(Diagnostics(
                problems
                    .0
                    .into_iter()
                    .map(|d| self.blame_extension(&model, self.relocate(d)))
                    .collect(),
            )),
        }
    }

    /// `diagnostic`, if it points into the base model but names an element an extension
    /// brought in (or one at the end of a bond an extension brought in), pointed at that
    /// place of the extension instead, with the base model's place kept in a note.
    fn blame_extension(&self, model: &Model, mut diagnostic: Diagnostic) -> Diagnostic {
        let Some(location) = diagnostic.location.clone() else {
            return diagnostic;
        };
        if location.file != self.base.name() {
            return diagnostic;
        }
        let in_extension = |span: Span| {
            let located = self.relocate(Diagnostic::new(diagnostic.kind, "").at(&self.file, span));
            located
                .location
                .filter(|l| self.extensions.iter().any(|e| e.name() == l.file))
        };
        let named = |name: &str| diagnostic.message.contains(&format!("'{name}'"));
        let from_extension = model
            .element_ids()
            .map(|id| model.element(id))
            .filter(|e| named(&e.name))
            .find_map(|e| in_extension(e.span).map(|l| (format!("'{}'", e.name), l)))
            .or_else(|| {
                model.bond_ids().map(|id| model.bond(id)).find_map(|bond| {
                    let (from, to) = (&model.element(bond.from).name, &model.element(bond.to).name);
                    if !named(from) && !named(to) {
                        return None;
                    }
                    in_extension(bond.span).map(|l| (format!("the bond {from} -> {to}"), l))
                })
            });
        if let Some((what, place)) = from_extension {
            diagnostic.location = Some(place.clone());
            diagnostic.notes.push(format!(
                "{what} comes from the extension {}; the problem shows at {location}",
                place.file
            ));
        }
        diagnostic
    }

    /// `diagnostic`, if it points into the merged text, pointed at the file its text came
    /// from.
    pub fn relocate(&self, mut diagnostic: Diagnostic) -> Diagnostic {
        let Some(location) = &diagnostic.location else {
            return diagnostic;
        };
        if location.file != self.file.name() {
            return diagnostic;
        }
        let span = location.span;
        let Some(piece) = self
            .pieces
            .iter()
            .find(|p| p.merged.contains(span.start) || p.merged.start == span.start)
        else {
            return diagnostic;
        };
        let shift = span.start - piece.merged.start;
        let length = span.len().min(piece.merged.end - span.start);
        let (file, start, length) = match piece.origin {
            Origin::Base(start) => (&self.base, start + shift, length),
            Origin::Extension(i, start) => (&self.extensions[i], start + shift, length),
            Origin::Generated(at) => (&self.base, at, 0),
        };
        diagnostic.location = Some(file.locate(Span::new(start, start + length)));
        diagnostic
    }
}

/// The names extension `e` adds or replaces, checked against the base model's: a clash, a
/// replacement of what the model does not have or of what another extension replaced is a
/// problem; a replacement that checks is a splice of its new value.
fn check_names<'a>(
    base: &Base,
    (e, extension): (usize, &'a Extension),
    replaced: &mut HashSet<&'a str>,
    splices: &mut Vec<Splice>,
    problems: &mut Vec<Diagnostic>,
) {
    let part = base.part().0;
    let ext = &extension.raw;
    let ext_map = &extension.map;
    let here = |span: Span| extension.source.locate(span);
    if let Some(problem) = other_formalism(base, extension) {
        problems.push(problem);
        return;
    }
    // Clashes of new names with the base model's.
    let clash = |kind: &str, name: &str, span: Span, note: &str| {
        let mut d = Diagnostic::new(
            DiagnosticKind::DuplicateName,
            format!(
                "extension '{}' adds {kind} '{name}', which model '{}' already has",
                ext.id, base.name
            ),
        )
        .at_location(here(span))
        .element(name);
        if !note.is_empty() {
            d = d.note(note);
        }
        d
    };
    let symbol_taken = |name: &String| base.parameters.contains(name) || base.inputs.contains(name);
    for ((name, _), spans) in ext.parameters.iter().zip(&ext_map.parameters) {
        if symbol_taken(name) {
            problems.push(clash("parameter", name, spans.key_span, ""));
        }
    }
    for ((name, _), spans) in ext.inputs.iter().zip(&ext_map.inputs) {
        if symbol_taken(name) {
            problems.push(clash("input", name, spans.key_span, ""));
        }
    }
    for (name, spans) in extension.parts() {
        let replaces = ext.replace.iter().any(|r| r == name);
        let index = base.parts.iter().position(|n| n == name);
        match (replaces, index) {
            (true, None) => {
                let mut d = Diagnostic::new(
                    DiagnosticKind::UnknownName,
                    format!(
                        "extension '{}' replaces {part} '{name}', which model '{}' does not have",
                        ext.id, base.name
                    ),
                )
                .at_location(here(spans.key_span))
                .element(name);
                if let Some(suggestion) = suggest(name, base.parts.iter().map(String::as_str)) {
                    d = d.note(format!("did you mean '{suggestion}'?"));
                }
                problems.push(d);
            }
            (false, Some(_)) => problems.push(clash(
                part,
                name,
                spans.key_span,
                &format!("to change the model's '{name}', list it under replace"),
            )),
            (true, Some(_)) if !replaced.insert(name) => problems.push(
                Diagnostic::new(
                    DiagnosticKind::DuplicateName,
                    format!("{part} '{name}' is replaced by two extensions"),
                )
                .at_location(here(spans.key_span))
                .element(name),
            ),
            (true, Some(index)) => splices.push(Splice {
                at: base.part_spans()[index].value_span,
                parts: vec![Part::Copy(e, spans.value_span)],
            }),
            (false, None) => {}
        }
    }
}

/// Merges `extensions` into the model file `base`, in order: bond-graph fragments into a
/// bond graph, linear-graph fragments (branches) into a linear graph.
///
/// # Errors
/// The base model's syntax error, and every conflict between the base and the extensions,
/// located in the extension: a fragment of the other formalism, a replaced element (or
/// branch) the base does not have, a new element, branch, parameter or input the base
/// already has, two extensions replacing the same element. Problems of the merged model (a
/// bond to an unknown element, a branch to a node nothing else touches) are found by
/// [`Extended::load`].
pub fn merge(base: &Arc<SourceFile>, extensions: &[Extension]) -> Result<Extended> {
    let model = Base::parse(base)?;
    let map = &model.map;
    let text = base.text();
    let section = model.part().1;
    let mut problems = Vec::new();
    let mut splices: Vec<Splice> = Vec::new();
    let mut replaced: HashSet<&str> = HashSet::new();

    for (e, extension) in extensions.iter().enumerate() {
        check_names(
            &model,
            (e, extension),
            &mut replaced,
            &mut splices,
            &mut problems,
        );
    }
    if !problems.is_empty() {
        return Err(Diagnostics(problems));
    }

    // New entries and bonds, appended to the base model's sections.
    let ids: Vec<&str> = extensions.iter().map(Extension::id).collect();
    let marker = format!("// added by extension {}", quoted_list(&ids));
    let sections: [(&str, &[EntrySpans]); 3] = [
        ("parameters", &map.parameters),
        ("inputs", &map.inputs),
        (section, model.part_spans()),
    ];
    for (name, base_entries) in sections {
        let items: Vec<(usize, Span)> = extensions
            .iter()
            .enumerate()
            .flat_map(|(e, x)| {
                let entries: Box<dyn Iterator<Item = &EntrySpans>> = match name {
                    "parameters" => Box::new(x.map.parameters.iter()),
                    "inputs" => Box::new(x.map.inputs.iter()),
                    _ => Box::new(x.parts().map(|(_, s)| s)),
                };
                entries
                    .filter(move |s| name != section || !x.raw.replace.contains(&s.key))
                    .map(move |s| (e, s.span()))
            })
            .collect();
        let last = base_entries.last().map(|s| s.span().end);
        if let Some(splice) = append(text, map, name, '{', last, items, &marker) {
            splices.push(splice);
        }
    }
    let bonds: Vec<(usize, Span)> = extensions
        .iter()
        .enumerate()
        .flat_map(|(e, x)| x.map.bonds.iter().map(move |b| (e, b.span)))
        .collect();
    let last_bond = map.bonds.last().map(|b| b.span.end);
    if let Some(splice) = append(text, map, "bonds", '[', last_bond, bonds, &marker) {
        splices.push(splice);
    }

    // The name, and a header saying what was merged.
    let name = std::iter::once(model.name.as_str())
        .chain(ids.iter().copied())
        .collect::<Vec<_>>()
        .join("+");
    if let Some(field) = map.field("name") {
        splices.push(Splice {
            at: field.value_span,
            parts: vec![Part::Text(ron_string(&name))],
        });
    }
    let mut header = format!(
        "// Model '{}' ({}) extended by `bondgraph extend`.\n",
        model.name,
        base.name()
    );
    for extension in extensions {
        header.push_str(&format!(
            "// Extension '{}' ({}): {}\n",
            extension.raw.id,
            extension.source.name(),
            extension.raw.cause
        ));
    }
    header.push_str("//\n");
    splices.push(Splice {
        at: Span::new(0, 0),
        parts: vec![Part::Text(header)],
    });

    splices.sort_by_key(|s| (s.at.start, s.at.end));
    let mut merged = String::with_capacity(text.len() + 1024);
    let mut pieces = Vec::new();
    let mut position = 0;
    let mut push = |merged: &mut String, content: &str, origin: Origin| {
        if content.is_empty() {
            return;
        }
        let start = merged.len();
        merged.push_str(content);
        pieces.push(Piece {
            merged: Span::new(start, merged.len()),
            origin,
        });
    };
    for splice in &splices {
        push(
            &mut merged,
            &text[position..splice.at.start],
            Origin::Base(position),
        );
        for part in &splice.parts {
            match part {
                Part::Text(t) => push(&mut merged, t, Origin::Generated(splice.at.start)),
                Part::Copy(e, span) => push(
                    &mut merged,
                    &extensions[*e].source.text()[span.start..span.end],
                    Origin::Extension(*e, span.start),
                ),
            }
        }
        position = splice.at.end;
    }
    push(&mut merged, &text[position..], Origin::Base(position));
    let file_name = format!("{}+{}", base.name(), ids.join("+"));
    Ok(Extended {
        file: SourceFile::new(file_name, merged),
        base: Arc::clone(base),
        extensions: extensions.iter().map(|x| Arc::clone(&x.source)).collect(),
        pieces,
    })
}

/// The problem of merging `extension` into `base` if it is written in the other formalism:
/// branches into a bond graph, elements or bonds into a linear graph.
fn other_formalism(base: &Base, extension: &Extension) -> Option<Diagnostic> {
    let ext = &extension.raw;
    let span = |field: &str| {
        extension
            .map
            .field(field)
            .map_or(extension.map.root, |f| f.value_span)
    };
    let (message, at, note) = if base.linear {
        let field = if ext.elements.is_empty() {
            "bonds"
        } else {
            "elements"
        };
        if ext.elements.is_empty() && ext.bonds.is_empty() {
            return None;
        }
        (
            format!(
                "extension '{}' is a bond-graph fragment ({field}), and model '{}' is a linear graph",
                ext.id, base.name
            ),
            span(field),
            "write the fragment as the graph writes it: `branches` with their nodes, `replace` naming the branches it gives anew",
        )
    } else {
        if !extension.is_linear_graph() {
            return None;
        }
        (
            format!(
                "extension '{}' is a linear-graph fragment (branches), and model '{}' is a bond graph",
                ext.id, base.name
            ),
            span("branches"),
            "extend the model's linear-graph file, or write the fragment as elements and bonds",
        )
    };
    Some(
        Diagnostic::new(DiagnosticKind::WrongType, message)
            .at_location(extension.source.locate(at))
            .note(note),
    )
}

/// The splice that appends `items` (copied from extensions) to the section `field` of the
/// base model, whose last item ends at `last`; a missing section is added before the
/// model's closing parenthesis.
fn append(
    text: &str,
    map: &SourceMap,
    field: &str,
    open: char,
    last: Option<usize>,
    items: Vec<(usize, Span)>,
    marker: &str,
) -> Option<Splice> {
    if items.is_empty() {
        return None;
    }
    let close = if open == '{' { '}' } else { ']' };
    let mut parts = Vec::new();
    let Some(section) = map.field(field) else {
        // `    field: { items },` before the root's `)`.
        let last_field = map.fields.last().map(|f| f.value_span.end);
        let (at, comma) = after_item(text, last_field.unwrap_or(map.root.start + 1));
        if last_field.is_some() && !comma {
            parts.push(Part::Text(",".into()));
        }
        parts.push(Part::Text(format!(
            "\n    {field}: {open}\n        {marker}"
        )));
        for (e, span) in items {
            parts.push(Part::Text("\n        ".into()));
            parts.push(Part::Copy(e, span));
            parts.push(Part::Text(",".into()));
        }
        parts.push(Part::Text(format!("\n    {close},")));
        return Some(Splice {
            at: Span::new(at, at),
            parts,
        });
    };
    let (at, indent) = match last {
        Some(end) => {
            let (at, comma) = after_item(text, end);
            if !comma {
                parts.push(Part::Text(",".into()));
            }
            (at, indentation(text, end))
        }
        None => (section.value_span.start + 1, "        ".to_string()),
    };
    parts.push(Part::Text(format!("\n{indent}{marker}")));
    for (e, span) in items {
        parts.push(Part::Text(format!("\n{indent}")));
        parts.push(Part::Copy(e, span));
        parts.push(Part::Text(",".into()));
    }
    if last.is_none() {
        parts.push(Part::Text("\n    ".into()));
    }
    Some(Splice {
        at: Span::new(at, at),
        parts,
    })
}

/// Where to insert after the item ending at `end`: after its comma if it has one, and after
/// a comment that ends its line; and whether it has a comma.
fn after_item(text: &str, end: usize) -> (usize, bool) {
    let mut at = end;
    let mut comma = false;
    if let Ok(Some(token)) = lex(text, end)
        && token.kind == TokenKind::Punct(b',')
    {
        at = token.span.end;
        comma = true;
    }
    let line_end = text[at..].find('\n').map_or(text.len(), |i| at + i);
    let rest = text[at..line_end].trim();
    if rest.is_empty() || (comma && rest.starts_with("//")) {
        at = line_end;
    }
    (at, comma)
}

/// The indentation of the line holding `offset`.
fn indentation(text: &str, offset: usize) -> String {
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    text[line_start..]
        .chars()
        .take_while(|c| *c == ' ' || *c == '\t')
        .collect()
}

/// `s` as a RON string literal.
fn ron_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

fn quoted_list(ids: &[&str]) -> String {
    ids.iter()
        .map(|id| format!("'{id}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod law_tests;

#[cfg(test)]
mod linear_graph_tests;
