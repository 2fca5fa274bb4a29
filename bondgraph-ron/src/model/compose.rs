//! Sub-models: a model file used as an element of another, flattened into its elements
//! before validation.
//!
//! A model file may declare `ports` (junctions the outside's bonds join) and be used by
//! another as an element, as often as need be, with its own parameter values in each use:
//!
//! ```ron
//! "front": Submodel(file: "../parts/suspension.ron", parameters: {"k_s": 20000.0, "b_s": "b_front"}),
//! ```
//!
//! and bonds to `"front.hub"`. Composition happens here, on the model as written, so that
//! everything after it (the validator, causality, equations, simulation, fits) sees one flat
//! model whose names say where each part came from: element `spring` of the use `front` is
//! `front.spring`, its state `front.q_spring`, its parameter `front.k_s`. A parameter given a
//! number keeps its name with the new value (in the part's own unit); one given an
//! expression of the using model's parameters is replaced by it; an input not given stays an
//! input of the whole model (`front.V`).
//!
//! Each sub-model file is read, composed (it may use sub-models of its own) and validated on
//! its own first, ports open, so that a mistake inside it is reported at its own line in its
//! own file; a file is read once however often it is used. What only the composition can get
//! wrong is reported in the file that composes: a cycle of files, a port the part does not
//! have, a port left unconnected, a value for a parameter it does not have. A problem found
//! later in the flattened model (a causal conflict across a port) points at the use, with a
//! note naming where the element is written in its part.
//!
//! Composition is bounded: [`MAX_DEPTH`] nested uses and [`MAX_ELEMENTS`] elements once
//! flattened (twenty uses of twenty uses of twenty parts would otherwise be 8000 copies of
//! each element, read in no time and derived for ever).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result, suggest};
use bondgraph_core::expr::rename_symbols;
use bondgraph_core::model::source_map::{EntrySpans, ItemSpans, SourceMap};
use bondgraph_core::model::{
    BondSpec, ElementSpec, InputSpec, ModelSpec, ParameterSpec, ParameterValue, PartSpec,
    state_element, validate,
};
use bondgraph_core::source::{Location, SourceFile, Span};

use super::Format;
use super::parse::parse_model;

/// The deepest nesting of sub-models (a use inside a use inside ...).
pub const MAX_DEPTH: usize = 16;

/// The most elements a composed model may have once flattened.
pub const MAX_ELEMENTS: usize = 20_000;

/// A model as written, with its sub-models flattened into it.
pub(crate) struct Composed {
    /// The flat model.
    pub spec: ModelSpec,
    /// Spans in the composing file: a sub-model's elements, parameters and bonds point at
    /// its use.
    pub map: SourceMap,
    /// Where each element of a sub-model is written in its own file, by flattened name.
    pub origins: HashMap<String, Location>,
}

/// Flattens the sub-models of `spec` (read from `source`, spans in `map`).
///
/// # Errors
/// A name written with a `.`, a sub-model file that cannot be read or is not a valid part,
/// and every composition problem, each located in the file that caused it.
pub(crate) fn compose(source: &SourceFile, spec: ModelSpec, map: SourceMap) -> Result<Composed> {
    Composer::default().flatten(source, spec, map)
}

/// Adds to each diagnostic about an element of a sub-model a note naming where the element
/// is written in its own file.
pub(crate) fn with_origins(
    diagnostics: Diagnostics,
    origins: &HashMap<String, Location>,
) -> Diagnostics {
    Diagnostics(
        diagnostics
            .0
            .into_iter()
            .map(|d| {
                // Only a sub-model's elements (qualified names) are written elsewhere.
                let origin = d
                    .element
                    .as_ref()
                    .filter(|e| e.contains('.'))
                    .and_then(|e| origins.get(e))
                    .cloned();
                match origin {
                    Some(at) if !at.is_in_code() => {
                        let name = d.element.clone().unwrap_or_default();
                        let leaf = name.rsplit('.').next().unwrap_or(&name).to_string();
                        d.note(format!("'{name}' is element '{leaf}' of {at}"))
                    }
                    _ => d,
                }
            })
            .collect(),
    )
}

/// A sub-model file, read, composed and validated.
struct Part {
    /// The file as the user's path reaches it.
    file: Arc<SourceFile>,
    /// Its flat model (ports resolved to flattened junctions).
    spec: ModelSpec,
    /// Where its elements are written, by its own flattened names.
    origins: HashMap<String, Location>,
}

#[derive(Default)]
struct Composer {
    /// Parts read so far, by path, so that a file used often is read once; `None` for one
    /// whose problems were reported at its first use.
    parts: HashMap<PathBuf, Option<Arc<Part>>>,
    /// The files being composed, outermost first: a file met again is a cycle.
    stack: Vec<PathBuf>,
}

/// Problems found so far, all reported together.
type Problems = Vec<Diagnostic>;

impl Composer {
    fn flatten(
        &mut self,
        source: &SourceFile,
        spec: ModelSpec,
        map: SourceMap,
    ) -> Result<Composed> {
        let mut problems = written_names(source, &spec, &map);
        let has_parts = spec
            .elements
            .iter()
            .any(|(_, e)| matches!(e, ElementSpec::Submodel { .. }));
        if !has_parts {
            if !problems.is_empty() {
                return Err(Diagnostics(problems));
            }
            let origins = own_origins(source, &spec, &map);
            return Ok(Composed { spec, map, origins });
        }
        let mut out = Flat::new(&spec, &map);
        let mut uses: HashMap<String, Use> = HashMap::new();
        for (index, (name, element)) in spec.elements.iter().enumerate() {
            let entry = map
                .elements
                .get(index)
                .cloned()
                .unwrap_or_else(|| root_entry(&map, name));
            let ElementSpec::Submodel {
                file,
                parameters,
                inputs,
            } = element
            else {
                out.element(name.clone(), element.clone(), entry.clone());
                out.origins
                    .insert(name.clone(), source.locate(entry.key_span));
                continue;
            };
            let part = match self.part(source, &entry, name, file) {
                Ok(part) => part,
                Err(diagnostics) => {
                    problems.extend(diagnostics.0);
                    continue;
                }
            };
            let given = Given { parameters, inputs };
            let found = given.check(
                source,
                &entry,
                ("sub-model", name),
                (
                    part.file.name(),
                    [names_of(&part.spec.parameters), names_of(&part.spec.inputs)],
                ),
            );
            if !found.is_empty() {
                problems.extend(found);
                continue;
            }
            let ports = out.instantiate(name, &part, &given, &entry);
            if out.elements.len() > MAX_ELEMENTS {
                problems.push(
                    Diagnostic::new(
                        DiagnosticKind::TooLarge,
                        format!(
                            "sub-model '{name}': the composed model has {} elements, over the \
                             limit of {MAX_ELEMENTS}",
                            out.elements.len()
                        ),
                    )
                    .at(source, entry.key_span)
                    .element(name.clone()),
                );
                return Err(Diagnostics(problems));
            }
            uses.insert(
                name.clone(),
                Use {
                    file: part.file.name().to_string(),
                    ports,
                    connected: Vec::new(),
                    entry,
                },
            );
        }
        out.own_bonds(source, &spec, &map, &mut uses, &mut problems);
        out.ports(&spec, &mut uses);
        for (name, used) in sorted(&uses) {
            for (port, _) in &used.ports {
                if !used.connected.contains(port) {
                    problems.push(
                        Diagnostic::new(
                            DiagnosticKind::Submodel,
                            format!("sub-model '{name}': port '{port}' is not connected"),
                        )
                        .at(source, used.entry.key_span)
                        .element(name.to_string())
                        .note(format!(
                            "bond it to this model, as (\"{name}.{port}\", \"...\") or \
                             (\"...\", \"{name}.{port}\")"
                        )),
                    );
                }
            }
        }
        if !problems.is_empty() {
            return Err(Diagnostics(problems));
        }
        Ok(out.finish(&spec))
    }

    /// The sub-model `file` used as `name` by `parent` (at `entry`): read, composed and
    /// validated once.
    fn part(
        &mut self,
        parent: &SourceFile,
        entry: &EntrySpans,
        name: &str,
        file: &str,
    ) -> Result<Arc<Part>> {
        let fail =
            |kind, message: String| use_error(parent, entry, ("sub-model", name), kind, message);
        let (path, key) = part_path(parent, entry, ("sub-model", name), file, &self.stack)?;
        match self.parts.get(&key) {
            Some(Some(part)) => return Ok(Arc::clone(part)),
            Some(None) => return Err(Diagnostics(Vec::new())),
            None => {}
        }
        let text = crate::read::read_text(&path, "sub-model file")
            .map_err(|message| fail(DiagnosticKind::Io, message))?;
        let part_source = SourceFile::new(path.display().to_string(), text);
        if Format::of(part_source.text()) == Format::LinearGraph {
            return Err(fail(
                DiagnosticKind::Submodel,
                format!(
                    "'{file}' is a linear graph; a bond graph's sub-model is a bond-graph \
                     model file"
                ),
            ));
        }
        let (spec, map) = parse_model(&part_source)?;
        if spec.ports.is_empty() {
            return Err(fail(
                DiagnosticKind::Submodel,
                format!(
                    "'{file}' declares no ports, so nothing can bond to it; add ports: \
                     {{\"name\": (element: \"a junction\")}}"
                ),
            ));
        }
        self.stack.push(key.clone());
        let composed = self.flatten(&part_source, spec, map);
        self.stack.pop();
        let part = composed.and_then(|composed| {
            validate::validate(&part_source, composed.spec.clone(), &composed.map)
                .map_err(|d| with_origins(d, &composed.origins))?;
            Ok(Arc::new(Part {
                file: Arc::clone(&part_source),
                spec: composed.spec,
                origins: composed.origins,
            }))
        });
        self.parts.insert(key, part.as_ref().ok().cloned());
        part
    }
}

/// A problem with the use `name` (a `noun`: "sub-model", "sub-graph") written at `entry`,
/// pointed at its `file` field.
pub(crate) fn use_error(
    parent: &SourceFile,
    entry: &EntrySpans,
    (noun, name): (&str, &str),
    kind: DiagnosticKind,
    message: String,
) -> Diagnostics {
    let at = entry
        .field("file")
        .map_or(entry.key_span, |f| f.text_span());
    Diagnostic::new(kind, format!("{noun} '{name}': {message}"))
        .at(parent, at)
        .element(name.to_string())
        .into()
}

/// The path of the file a use names, relative to the using file, and the key it is known
/// by (its canonical path); a cycle through the files being composed (`stack`, outermost
/// first) or nesting deeper than [`MAX_DEPTH`] is an error at the use.
pub(crate) fn part_path(
    parent: &SourceFile,
    entry: &EntrySpans,
    (noun, name): (&str, &str),
    file: &str,
    stack: &[PathBuf],
) -> Result<(PathBuf, PathBuf)> {
    let fail = |kind, message: String| use_error(parent, entry, (noun, name), kind, message);
    let directory = Path::new(parent.name()).parent().unwrap_or(Path::new(""));
    let path = tidy_path(&directory.join(file));
    let key = path.canonicalize().unwrap_or_else(|_| path.clone());
    if stack.contains(&key) {
        let chain: Vec<String> = stack
            .iter()
            .skip_while(|p| **p != key)
            .chain([&key])
            .map(|p| {
                p.file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into())
            })
            .collect();
        return Err(fail(
            DiagnosticKind::Submodel,
            format!(
                "'{file}' uses itself ({}); a model cannot contain itself",
                chain.join(" -> ")
            ),
        ));
    }
    if stack.len() >= MAX_DEPTH {
        return Err(fail(
            DiagnosticKind::TooLarge,
            format!("{noun}s are nested deeper than the limit of {MAX_DEPTH}"),
        ));
    }
    Ok((path, key))
}

/// `path` with each `dir/..` taken out, as a person would write it
/// (`models/examples/composed/../../parts/motor.ron` is `models/parts/motor.ron`); a `..`
/// with nothing before it to take out stays.
pub(crate) fn tidy_path(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component<'_>> = Vec::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out.iter().collect()
}

/// Names written in a file may not contain `.`, which joins a use's name to its part's.
fn written_names(source: &SourceFile, spec: &ModelSpec, map: &SourceMap) -> Problems {
    let symbols: Vec<(&str, Vec<&str>, &[EntrySpans])> = spec
        .elements
        .iter()
        .zip(&map.elements)
        .filter_map(|((_, element), entry)| {
            let symbol = element.symbol()?;
            Some(("state symbol", vec![symbol], std::slice::from_ref(entry)))
        })
        .collect();
    let mut problems = dotted_names(source, map, symbols);
    problems.extend(dotted_names(
        source,
        map,
        [
            ("parameter", names_of(&spec.parameters), &map.parameters[..]),
            ("input", names_of(&spec.inputs), &map.inputs[..]),
            ("element", names_of(&spec.elements), &map.elements[..]),
            ("port", names_of(&spec.ports), &map.ports[..]),
        ],
    ));
    problems
}

/// The names of a section's entries.
pub(crate) fn names_of<T>(entries: &[(String, T)]) -> Vec<&str> {
    entries.iter().map(|(n, _)| n.as_str()).collect()
}

/// A diagnostic for each name with a `.` in it, of each section given as (what an entry is
/// called, its names, their spans): such a name would read as a sub-model's.
pub(crate) fn dotted_names<'a>(
    source: &SourceFile,
    map: &SourceMap,
    sections: impl IntoIterator<Item = (&'static str, Vec<&'a str>, &'a [EntrySpans])>,
) -> Problems {
    let mut problems = Vec::new();
    for (what, names, entries) in sections {
        for (index, name) in names.into_iter().enumerate() {
            if name.contains('.') {
                let span = entries.get(index).map_or(map.root, |e| e.key_span);
                problems.push(
                    Diagnostic::new(
                        DiagnosticKind::InvalidName,
                        format!(
                            "{what} name '{name}' is not a valid name: a '.' joins a \
                             sub-model's name to its parts' ('front.spring')"
                        ),
                    )
                    .at(source, span)
                    .element(name.to_string())
                    .note("use letters, digits and '_', starting with a letter"),
                );
            }
        }
    }
    problems
}

/// Where each element of a flat model is written.
fn own_origins(
    source: &SourceFile,
    spec: &ModelSpec,
    map: &SourceMap,
) -> HashMap<String, Location> {
    spec.elements
        .iter()
        .zip(&map.elements)
        .map(|((name, _), entry)| (name.clone(), source.locate(entry.key_span)))
        .collect()
}

/// An entry standing for a name the scanner did not place: the whole model.
fn root_entry(map: &SourceMap, name: &str) -> EntrySpans {
    EntrySpans {
        key: name.to_string(),
        key_span: map.root,
        value_span: map.root,
        kind: None,
        fields: Vec::new(),
    }
}

/// The uses in name order, for reports that do not depend on hashing.
fn sorted(uses: &HashMap<String, Use>) -> Vec<(&str, &Use)> {
    let mut all: Vec<(&str, &Use)> = uses.iter().map(|(n, u)| (n.as_str(), u)).collect();
    all.sort_by_key(|(n, _)| *n);
    all
}

/// One use of a sub-model in the file being composed.
struct Use {
    /// Its file, as read.
    file: String,
    /// Its ports and the flattened junction each is.
    ports: Vec<(String, String)>,
    /// The ports a bond of the composing file names.
    connected: Vec<String>,
    /// Its entry in the composing file.
    entry: EntrySpans,
}

/// The values a use gives its sub-model (or sub-graph): parameters and inputs by the
/// part's names.
pub(crate) struct Given<'a> {
    pub(crate) parameters: &'a [(String, ParameterValue)],
    pub(crate) inputs: &'a [(String, String)],
}

/// A part's parameters and inputs as one use gives them.
pub(crate) struct Values {
    /// What each of the part's parameters and inputs is written as in the flat model: its
    /// qualified name, or the expression given for it.
    pub(crate) renames: HashMap<String, String>,
    /// The parameters the use keeps (qualified), with the values given.
    pub(crate) parameters: Vec<(String, ParameterSpec)>,
    /// The inputs the use leaves to the whole model (qualified).
    pub(crate) inputs: Vec<(String, InputSpec)>,
}

impl Given<'_> {
    /// Every name given must be one of the part's (`known`: its parameters and its
    /// inputs), given once; each problem located at the name in the use's entry.
    pub(crate) fn check(
        &self,
        source: &SourceFile,
        entry: &EntrySpans,
        (noun, name): (&str, &str),
        (file, known): (&str, [Vec<&str>; 2]),
    ) -> Problems {
        let mut problems = Vec::new();
        let [known_parameters, known_inputs] = known;
        let lists = [
            ("parameters", names_of(self.parameters), known_parameters),
            ("inputs", names_of(self.inputs), known_inputs),
        ];
        for (field, given, known) in lists {
            let (what, article) = match field {
                "inputs" => ("input", "an"),
                _ => ("parameter", "a"),
            };
            for (index, key) in given.iter().enumerate() {
                let at = key_span(source, entry, field, key);
                let diagnostic = if given[..index].contains(key) {
                    Diagnostic::new(
                        DiagnosticKind::DuplicateName,
                        format!("{noun} '{name}': {what} '{key}' is given twice"),
                    )
                } else if !known.contains(key) {
                    let d = Diagnostic::new(
                        DiagnosticKind::Submodel,
                        format!("{noun} '{name}': '{key}' is not {article} {what} of '{file}'"),
                    );
                    match suggest(key, known.iter().copied()) {
                        Some(near) => d.note(format!("did you mean '{near}'?")),
                        None => d.note(format!("its {field}: {}", list(&known))),
                    }
                } else {
                    continue;
                };
                problems.push(diagnostic.at(source, at).element(name.to_string()));
            }
        }
        problems
    }

    /// The part's `parameters` and `inputs` as this use, `name`, gives them: a number keeps
    /// the parameter (qualified) with that value in the part's unit, and its bounds; an
    /// expression replaces a parameter or an input; an input not given stays one, qualified.
    pub(crate) fn values(
        &self,
        name: &str,
        parameters: &[(String, ParameterSpec)],
        inputs: &[(String, InputSpec)],
    ) -> Values {
        let qualified = |n: &str| format!("{name}.{n}");
        let mut values = Values {
            renames: HashMap::new(),
            parameters: Vec::new(),
            inputs: Vec::new(),
        };
        for (parameter, spec) in parameters {
            match self.parameters.iter().find(|(n, _)| n == parameter) {
                Some((_, ParameterValue::Expression(expression))) => {
                    values
                        .renames
                        .insert(parameter.clone(), format!("({expression})"));
                }
                given => {
                    let mut spec = spec.clone();
                    // The part's bounds stay: a value outside them is refused at the use.
                    if let Some((_, ParameterValue::Value(v))) = given {
                        spec.value = *v;
                    }
                    values
                        .renames
                        .insert(parameter.clone(), qualified(parameter));
                    values.parameters.push((qualified(parameter), spec));
                }
            }
        }
        for (input, spec) in inputs {
            match self.inputs.iter().find(|(n, _)| n == input) {
                Some((_, expression)) => {
                    values
                        .renames
                        .insert(input.clone(), format!("({expression})"));
                }
                None => {
                    values.renames.insert(input.clone(), qualified(input));
                    values.inputs.push((qualified(input), spec.clone()));
                }
            }
        }
        values
    }
}

/// Names quoted and joined, or "none".
pub(crate) fn list(names: &[&str]) -> String {
    if names.is_empty() {
        return "none".into();
    }
    names
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The span of `"key"` inside field `field` of `entry`, or the field, or the entry's key.
pub(crate) fn key_span(source: &SourceFile, entry: &EntrySpans, field: &str, key: &str) -> Span {
    let Some(field) = entry.field(field) else {
        return entry.key_span;
    };
    let value = field.value_span;
    let quoted = format!("\"{key}\"");
    source
        .text()
        .get(value.start..value.end)
        .and_then(|text| text.find(&quoted))
        .map_or(field.name_span, |at| {
            Span::new(value.start + at, value.start + at + quoted.len())
        })
}

/// The flat model being built, with its source map in step.
struct Flat {
    parameters: Vec<(String, ParameterSpec)>,
    parameter_spans: Vec<EntrySpans>,
    inputs: Vec<(String, InputSpec)>,
    input_spans: Vec<EntrySpans>,
    elements: Vec<(String, ElementSpec)>,
    element_spans: Vec<EntrySpans>,
    /// The composing file's own bonds, then each part's.
    bonds: Vec<BondSpec>,
    bond_spans: Vec<ItemSpans>,
    part_bonds: Vec<(BondSpec, ItemSpans)>,
    ports: Vec<(String, bondgraph_core::model::PortSpec)>,
    parts: Vec<PartSpec>,
    origins: HashMap<String, Location>,
    map: SourceMap,
}

impl Flat {
    fn new(spec: &ModelSpec, map: &SourceMap) -> Self {
        Self {
            parameters: spec.parameters.clone(),
            parameter_spans: map.parameters.clone(),
            inputs: spec.inputs.clone(),
            input_spans: map.inputs.clone(),
            elements: Vec::new(),
            element_spans: Vec::new(),
            bonds: Vec::new(),
            bond_spans: Vec::new(),
            part_bonds: Vec::new(),
            ports: Vec::new(),
            parts: Vec::new(),
            origins: HashMap::new(),
            map: map.clone(),
        }
    }

    fn element(&mut self, name: String, element: ElementSpec, entry: EntrySpans) {
        self.elements.push((name, element));
        self.element_spans.push(entry);
    }

    /// Adds the elements, parameters, inputs and bonds of `part` used as `name` (at
    /// `entry`), renamed; returns its ports with the flattened junction of each.
    fn instantiate(
        &mut self,
        name: &str,
        part: &Part,
        given: &Given<'_>,
        entry: &EntrySpans,
    ) -> Vec<(String, String)> {
        let qualified = |n: &str| format!("{name}.{n}");
        let at_use = |key: String| EntrySpans {
            key,
            ..entry.clone()
        };
        let values = given.values(name, &part.spec.parameters, &part.spec.inputs);
        for (parameter, spec) in values.parameters {
            self.parameter_spans.push(at_use(parameter.clone()));
            self.parameters.push((parameter, spec));
        }
        for (input, spec) in values.inputs {
            self.input_spans.push(at_use(input.clone()));
            self.inputs.push((input, spec));
        }
        let renames = values.renames;
        let elements: HashMap<&str, ()> = part
            .spec
            .elements
            .iter()
            .map(|(n, _)| (n.as_str(), ()))
            .collect();
        // States named with `symbol:` keep their names, qualified.
        let symbols: Vec<&str> = part
            .spec
            .elements
            .iter()
            .filter_map(|(_, e)| e.symbol())
            .collect();
        let rename = |symbol: &str| -> Option<String> {
            if let Some(new) = renames.get(symbol) {
                return Some(new.clone());
            }
            if symbols.contains(&symbol) {
                return Some(qualified(symbol));
            }
            // A state of the part (`q_spring`, `rear.q_spring`) keeps its form, qualified.
            let (_, element) = state_element(symbol)?;
            elements
                .contains_key(element.as_str())
                .then(|| qualified(symbol))
        };
        let mut origins = Vec::new();
        for (element_name, element) in &part.spec.elements {
            let mut element = element.clone();
            for (_, expression) in element.expressions_mut() {
                *expression = rename_symbols(expression, rename);
            }
            if let Some(symbol) = element.symbol_mut() {
                *symbol = qualified(symbol);
            }
            let flat_name = qualified(element_name);
            if let Some(origin) = part.origins.get(element_name) {
                self.origins.insert(flat_name.clone(), origin.clone());
                origins.push((flat_name.clone(), origin.clone()));
            }
            self.element(flat_name.clone(), element, at_use(flat_name));
        }
        for BondSpec(from, to) in &part.spec.bonds {
            let item = ItemSpans {
                span: entry.key_span,
                strings: vec![
                    (qualified(from), entry.key_span),
                    (qualified(to), entry.key_span),
                ],
            };
            self.part_bonds
                .push((BondSpec(qualified(from), qualified(to)), item));
        }
        let ports: Vec<(String, String)> = part
            .spec
            .ports
            .iter()
            .map(|(port, spec)| (port.clone(), qualified(&spec.element)))
            .collect();
        // A nested use's elements are its own part's, listed under it.
        let nested_elements: Vec<String> = part
            .spec
            .parts
            .iter()
            .flat_map(|nested| nested.origins.iter().map(|(e, _)| qualified(e)))
            .collect();
        origins.retain(|(e, _)| !nested_elements.contains(e));
        self.parts.push(PartSpec {
            name: name.to_string(),
            file: part.file.name().to_string(),
            model: part.spec.name.clone(),
            ports: ports.clone(),
            origins,
        });
        for nested in &part.spec.parts {
            self.parts.push(PartSpec {
                name: qualified(&nested.name),
                file: nested.file.clone(),
                model: nested.model.clone(),
                ports: nested
                    .ports
                    .iter()
                    .map(|(p, e)| (p.clone(), qualified(e)))
                    .collect(),
                origins: nested
                    .origins
                    .iter()
                    .map(|(e, at)| (qualified(e), at.clone()))
                    .collect(),
            });
        }
        ports
    }

    /// The composing file's bonds, each end that names a use's port (`"front.hub"`) turned
    /// into the port's junction.
    fn own_bonds(
        &mut self,
        source: &SourceFile,
        spec: &ModelSpec,
        map: &SourceMap,
        uses: &mut HashMap<String, Use>,
        problems: &mut Problems,
    ) {
        for (index, BondSpec(from, to)) in spec.bonds.iter().enumerate() {
            let item = map.bonds.get(index);
            let mut ends = [from.clone(), to.clone()];
            for (side, end) in ends.iter_mut().enumerate() {
                let at = item
                    .and_then(|i| i.strings.get(side))
                    .map_or(map.root, |(_, span)| *span);
                let (use_name, port) = match end.split_once('.') {
                    Some((u, p)) if uses.contains_key(u) => (u.to_string(), Some(p.to_string())),
                    _ if uses.contains_key(end.as_str()) => (end.clone(), None),
                    _ => continue,
                };
                let used = uses.get_mut(&use_name).expect("a use");
                let names: Vec<&str> = used.ports.iter().map(|(p, _)| p.as_str()).collect();
                let found = port
                    .as_ref()
                    .and_then(|p| used.ports.iter().find(|(q, _)| q == p));
                match found {
                    Some((port, junction)) => {
                        used.connected.push(port.clone());
                        *end = junction.clone();
                    }
                    None => {
                        let message = match &port {
                            Some(port) => format!(
                                "bond {}: '{port}' is not a port of sub-model '{use_name}' ('{}')",
                                index + 1,
                                used.file
                            ),
                            None => format!(
                                "bond {}: a bond joins a port of sub-model '{use_name}', not \
                                 the sub-model itself",
                                index + 1
                            ),
                        };
                        let mut diagnostic = Diagnostic::new(DiagnosticKind::Submodel, message)
                            .at(source, at)
                            .element(use_name.clone());
                        let near = port
                            .as_deref()
                            .and_then(|p| suggest(p, names.iter().copied()));
                        diagnostic = match near {
                            Some(near) => {
                                diagnostic.note(format!("did you mean '{use_name}.{near}'?"))
                            }
                            None => diagnostic.note(format!(
                                "its ports: {}",
                                list(
                                    &names
                                        .iter()
                                        .map(|p| format!("{use_name}.{p}"))
                                        .collect::<Vec<_>>()
                                        .iter()
                                        .map(String::as_str)
                                        .collect::<Vec<_>>()
                                )
                            )),
                        };
                        problems.push(diagnostic);
                    }
                }
            }
            let [from, to] = ends;
            self.bonds.push(BondSpec(from, to));
            self.bond_spans.push(item.cloned().unwrap_or(ItemSpans {
                span: map.root,
                strings: Vec::new(),
            }));
        }
    }

    /// The composing file's own ports, a use's port (`"wheel.axle"`) turned into its
    /// junction; a use's port passed on as the file's own is connected (to the outside).
    fn ports(&mut self, spec: &ModelSpec, uses: &mut HashMap<String, Use>) {
        self.ports = spec
            .ports
            .iter()
            .map(|(name, port)| {
                let mut port = port.clone();
                let written = port.element.clone();
                if let Some((use_name, port_name)) = written.split_once('.')
                    && let Some(used) = uses.get_mut(use_name)
                    && let Some((_, junction)) = used.ports.iter().find(|(p, _)| p == port_name)
                {
                    port.element = junction.clone();
                    used.connected.push(port_name.to_string());
                }
                (name.clone(), port)
            })
            .collect();
    }

    fn finish(mut self, spec: &ModelSpec) -> Composed {
        for (bond, item) in std::mem::take(&mut self.part_bonds) {
            self.bonds.push(bond);
            self.bond_spans.push(item);
        }
        let map = SourceMap {
            parameters: self.parameter_spans,
            inputs: self.input_spans,
            elements: self.element_spans,
            bonds: self.bond_spans,
            ..self.map
        };
        Composed {
            spec: ModelSpec {
                name: spec.name.clone(),
                description: spec.description.clone(),
                parameters: self.parameters,
                inputs: self.inputs,
                elements: self.elements,
                bonds: self.bonds,
                ports: self.ports,
                parts: self.parts,
            },
            map,
            origins: self.origins,
        }
    }
}
