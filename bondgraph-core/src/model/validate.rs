//! From a model as written ([`ModelSpec`]) to a checked [`Model`]: the one constructor of
//! models, for files and for code.
//!
//! Every independent problem is collected, so a user sees all of them at once: duplicate
//! names, invalid names, unparsable expressions, unknown symbols, expressions that depend on
//! inputs where they may not, non-positive masses and compliances, bonds to undefined
//! elements, wrong bond counts, and graphs in pieces. Each diagnostic points at the exact
//! place in the file: the symbol inside the expression, the end of the bond.

use std::collections::HashMap;
use std::sync::Arc;

use petgraph::unionfind::UnionFind;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result, suggest};
use crate::model::checked::{
    Bond, BondId, Element, ElementId, ElementKind, Input, Model, Parameter, Port,
};
use crate::model::source_map::{EntrySpans, FieldSpan, SourceMap};
use crate::model::spec::{ElementSpec, ModelSpec};
use crate::source::{SourceFile, Span};
use crate::symbolic::SymbolTable;
use crate::units::Unit;

use coefficients::to_affine;

mod coefficients;
mod elements;
mod friction;
mod laws;
mod units;

use units::Convention;
#[doc(hidden)]
pub use units::ordered_reference;

/// Checks `raw` (parsed from `file`, with positions in `map`) and builds the [`Model`].
///
/// # Errors
/// Every problem found, each naming its element and line.
pub fn validate(file: &Arc<SourceFile>, raw: ModelSpec, map: &SourceMap) -> Result<Model> {
    validate_as(file, raw, map, Convention::BondGraph)
}

/// [`validate`] for the bond graph a linear graph became (`spec`, with its through variables
/// as efforts, spans in the linear-graph file), which the model keeps as its
/// [`linear_graph`](Model::linear_graph).
///
/// # Errors
/// As [`validate`], worded for the bond graph (see
/// [`Words`](crate::model::linear_graph::Words) for the graph's terms).
pub fn validate_linear_graph(
    file: &Arc<SourceFile>,
    spec: ModelSpec,
    map: &SourceMap,
    graph: crate::model::linear_graph::LinearGraph,
) -> Result<Model> {
    let mut model = validate_as(file, spec, map, Convention::LinearGraph)?;
    model.linear_graph = Some(Arc::new(graph));
    Ok(model)
}

/// [`validate`], for a model whose efforts and flows follow `convention` (a linear graph
/// translated into a bond graph has its through variables as efforts): the units check
/// ([`crate::units`]) needs to know which is which.
///
/// # Errors
/// As [`validate`].
fn validate_as(
    file: &Arc<SourceFile>,
    raw: ModelSpec,
    map: &SourceMap,
    convention: Convention,
) -> Result<Model> {
    let mut v = Validator {
        file: file.clone(),
        map,
        problems: Vec::new(),
    };

    if raw.elements.is_empty() {
        let span = v.field_span("elements").unwrap_or(map.root);
        v.problems.push(
            Diagnostic::new(
                DiagnosticKind::EmptyModel,
                format!("model '{}' has no elements", raw.name),
            )
            .at(file, span)
            .note("add elements such as \"mass\": I(inertance: \"m\") and bonds between them"),
        );
        return Err(Diagnostics(v.problems));
    }

    // Parameters and inputs share the namespace of expressions.
    let mut seen: HashMap<String, (Span, &'static str)> = HashMap::new();
    let mut parameters = Vec::new();
    for (index, (name, raw_parameter)) in raw.parameters.iter().enumerate() {
        let span = v.entry_span(&map.parameters, index);
        if !v.check_name(name, "parameter", span)
            || !v.check_unique(&mut seen, name, "parameter", span)
        {
            continue;
        }
        v.check_finite(name, raw_parameter.value, index, span);
        if let Some(bounds) = raw_parameter.bounds {
            v.check_bounds(name, raw_parameter.value, bounds, index);
        }
        let unit = v.check_unit(
            "parameter",
            name,
            raw_parameter.unit.as_deref(),
            &map.parameters,
            index,
        );
        let in_si = v.in_si(name, raw_parameter, unit.as_ref(), index);
        parameters.push((name.clone(), raw_parameter.clone(), in_si, span));
    }
    let mut inputs = Vec::new();
    for (index, (name, raw_input)) in raw.inputs.iter().enumerate() {
        let span = v.entry_span(&map.inputs, index);
        if !v.check_name(name, "input", span) || !v.check_unique(&mut seen, name, "input", span) {
            continue;
        }
        let unit = v.check_unit("input", name, raw_input.unit.as_deref(), &map.inputs, index);
        if let (Some(unit), Some(written)) = (unit, raw_input.unit.as_deref()) {
            v.check_input_unit(name, &unit, written, index);
        }
        inputs.push(Input {
            name: name.clone(),
            unit: raw_input.unit.clone(),
            description: raw_input.description.clone(),
            span,
        });
    }

    let symbols = SymbolTable::new(parameters.iter().map(|(n, _, _, _)| n.clone()));
    let mut values = vec![f64::NAN; symbols.len()];
    let parameters: Vec<Parameter> = parameters
        .into_iter()
        .map(|(name, raw_parameter, in_si, span)| {
            let symbol = symbols.get(&name).expect("every parameter has a symbol");
            values[symbol.index()] = in_si.value;
            Parameter {
                name,
                value: in_si.value,
                unit: raw_parameter.unit,
                description: raw_parameter.description,
                bounds: in_si.bounds,
                symbol,
                span,
                as_written: in_si.as_written,
                si_unit: in_si.si_unit,
            }
        })
        .collect();
    let input_ids: HashMap<&str, u32> = inputs
        .iter()
        .enumerate()
        .map(|(i, input)| (input.name.as_str(), i as u32))
        .collect();
    v.check_symbols(&raw, &seen);
    let states = energy_variables(&raw);
    let scope = Scope {
        symbols: &symbols,
        inputs: &input_ids,
        values: &values,
        states: &states,
    };

    let (mut elements, element_index) = v.elements(&raw, &scope);

    let (bonds, dropped) = v.bonds(&raw, &element_index, &mut elements);

    let mut model = Model {
        name: raw.name.clone(),
        description: raw.description.clone(),
        source: file.clone(),
        symbols,
        parameters,
        inputs,
        elements,
        bonds,
        values,
        linear_graph: None,
        bond_dimensions: Vec::new(),
        ports: Vec::new(),
        parts: raw.parts.clone(),
    };
    model.ports = v.ports(&raw, &element_index, &model);
    for element in model.element_ids() {
        if dropped[element.index()] == 0 {
            v.check_ports(&model, element);
        }
    }
    if v.problems.is_empty() {
        v.check_connected(&model);
    }
    if v.problems.is_empty() {
        let (problems, dimensions) = units::check(&model, &raw, map, convention);
        v.problems = problems;
        model.bond_dimensions = dimensions;
    }
    if v.problems.is_empty() {
        Ok(model)
    } else {
        Err(Diagnostics(v.problems))
    }
}

/// Storage elements' energy variables, by their printed names (`p_mass`, `q_spring`), for
/// nonlinear laws.
/// "a" or "an", for a kind's description.
fn article(word: &str) -> &'static str {
    match word.chars().next() {
        Some('a' | 'e' | 'i' | 'o' | 'u') => "an",
        _ => "a",
    }
}

fn energy_variables(raw: &ModelSpec) -> HashMap<String, u32> {
    raw.elements
        .iter()
        .enumerate()
        .filter_map(|(index, (name, element))| {
            let letter = match element {
                ElementSpec::I { .. } => "p",
                ElementSpec::C { .. } | ElementSpec::TensionOnly { .. } => "q",
                _ => return None,
            };
            let state = match element.symbol() {
                Some(symbol) => symbol.to_string(),
                None => super::state_symbol(letter, name),
            };
            Some((state, index as u32))
        })
        .collect()
}

/// A parameter's numbers in SI units.
struct InSi {
    value: f64,
    bounds: Option<(f64, f64)>,
    /// The value as written, where the unit is not SI.
    as_written: Option<f64>,
    /// The SI unit of `value`.
    si_unit: Option<String>,
}

/// The two numbers of a `bounds: (low, high)` as written.
fn bound_texts(text: &str) -> Option<(&str, &str)> {
    let inner = text.trim().strip_prefix('(')?.strip_suffix(')')?;
    let mut parts = inner.split(',').map(str::trim).filter(|p| !p.is_empty());
    let low = parts.next()?;
    let high = parts.next()?;
    parts.next().is_none().then_some((low, high))
}

/// What expressions may name.
struct Scope<'a> {
    symbols: &'a SymbolTable,
    inputs: &'a HashMap<&'a str, u32>,
    values: &'a [f64],
    /// Storage states by printed name (`q_spring`), to their element's index.
    states: &'a HashMap<String, u32>,
}

struct Validator<'a> {
    file: Arc<SourceFile>,
    map: &'a SourceMap,
    problems: Vec<Diagnostic>,
}

/// What an element's coefficient must satisfy, numerically.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Sign {
    Positive,
    NonNegative,
    NonZero,
}

impl Validator<'_> {
    /// The expression in `field` of element `element` (entry `index`), parsed, and the span
    /// of its string in the file (symbols' spans are relative to it); a text that does not
    /// parse is a problem at its place in the string.
    fn parse_field(
        &mut self,
        element: &str,
        index: usize,
        field: &str,
        text: &str,
    ) -> Option<(crate::expr::Expr, Span)> {
        let base = self
            .string_span(index, field)
            .unwrap_or_else(|| self.entry_span(&self.map.elements, index));
        match crate::expr::parse(text) {
            Ok(expr) => Some((expr, base)),
            Err(error) => {
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::BadExpression,
                        format!(
                            "element '{element}': cannot parse {field} \"{text}\": {}",
                            error.message
                        ),
                    )
                    .at(&self.file, error.span.shifted(base.start))
                    .element(element),
                );
                None
            }
        }
    }

    /// A parameter's value that is not a finite number, worded as the user wrote it (`1e400`
    /// reads as infinity).
    fn check_finite(&mut self, name: &str, value: f64, index: usize, span: Span) {
        if value.is_finite() {
            return;
        }
        let value_span = self
            .field_value_span(&self.map.parameters, index, "value")
            .unwrap_or(span);
        let written = self.file.text().get(value_span.start..value_span.end);
        // `1e400` reads as infinity; say why in the terms the user wrote.
        let message = match written {
            Some(written)
                if written.bytes().any(|b| b.is_ascii_digit()) && !written.contains("inf") =>
            {
                format!(
                    "parameter '{name}' has value {written}, which is too large for a 64-bit floating-point number"
                )
            }
            _ => format!(
                "parameter '{name}' has value {}, which is not a finite number",
                value
            ),
        };
        self.problems.push(
            Diagnostic::new(DiagnosticKind::InvalidValue, message)
                .at(&self.file, value_span)
                .element(name),
        );
    }

    /// A state's name given with `symbol:` is a valid name that names nothing else: no
    /// parameter, input or other state.
    fn check_symbols(&mut self, raw: &ModelSpec, seen: &HashMap<String, (Span, &'static str)>) {
        let mut states: HashMap<String, &str> = HashMap::new();
        for (name, element) in &raw.elements {
            let letter = match element {
                ElementSpec::I { .. } => "p",
                ElementSpec::C { .. } | ElementSpec::TensionOnly { .. } => "q",
                _ => continue,
            };
            if element.symbol().is_none() {
                states.insert(super::state_symbol(letter, name), name);
            }
        }
        for (index, (name, element)) in raw.elements.iter().enumerate() {
            let Some(symbol) = element.symbol() else {
                continue;
            };
            let span = self
                .field_value_span(&self.map.elements, index, "symbol")
                .unwrap_or_else(|| self.entry_span(&self.map.elements, index));
            if !self.check_name(symbol, "state symbol", span) {
                continue;
            }
            let clash = match (seen.get(symbol), states.get(symbol)) {
                (Some((_, what)), _) => Some(format!("the {what} '{symbol}'")),
                (None, Some(other)) => Some(format!("the state of '{other}'")),
                (None, None) => None,
            };
            match clash {
                Some(clash) => self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::DuplicateName,
                        format!("element '{name}': symbol '{symbol}' is already {clash}"),
                    )
                    .at(&self.file, span)
                    .element(name.clone()),
                ),
                None => {
                    states.insert(symbol.to_string(), name);
                }
            }
        }
    }

    /// The elements that check, and every element name that does (an element rejected for
    /// its fields keeps its name, at an id of `u32::MAX`, so bonds to it are not reported
    /// as undefined).
    fn elements(
        &mut self,
        raw: &ModelSpec,
        scope: &Scope<'_>,
    ) -> (Vec<Element>, HashMap<String, ElementId>) {
        let mut element_names: HashMap<String, (Span, &'static str)> = HashMap::new();
        let mut elements: Vec<Element> = Vec::new();
        let mut element_index: HashMap<String, ElementId> = HashMap::new();
        for (index, (name, raw_element)) in raw.elements.iter().enumerate() {
            let span = self.entry_span(&self.map.elements, index);
            let named_ok = self.check_name(name, "element", span)
                && self.check_unique(&mut element_names, name, "element", span);
            let kind = self.element_kind(name, raw_element, index, scope);
            if let (true, Some(kind)) = (named_ok, kind) {
                element_index.insert(name.clone(), ElementId(elements.len() as u32));
                elements.push(Element {
                    name: name.clone(),
                    kind,
                    span,
                    bonds: Vec::new(),
                    symbol: raw_element.symbol().map(str::to_string),
                });
            } else if named_ok {
                // Keep the name known so bonds to it are not reported as undefined.
                element_index.insert(name.clone(), ElementId(u32::MAX));
            }
        }
        (elements, element_index)
    }

    /// The bonds between elements that check, each added to its ends' lists; and for each
    /// element, the bonds dropped at it (their other end was reported, or they join it to
    /// itself), so that its bond count is not blamed next.
    fn bonds(
        &mut self,
        raw: &ModelSpec,
        element_index: &HashMap<String, ElementId>,
        elements: &mut [Element],
    ) -> (Vec<Bond>, Vec<usize>) {
        // Bonds. A bond dropped because one of its ends was already reported (a rejected or
        // undefined element, a self bond) is counted at its other end, so that end is not
        // blamed next for the bond count the file does give it.
        let mut bonds = Vec::new();
        let mut dropped = vec![0usize; elements.len()];
        for (index, raw_bond) in raw.bonds.iter().enumerate() {
            let bond_spans = self.map.bonds.get(index);
            let span = bond_spans.map_or(self.map.root, |b| b.span);
            let mut ends = [ElementId(u32::MAX); 2];
            let mut ok = true;
            for (side, name) in [&raw_bond.0, &raw_bond.1].into_iter().enumerate() {
                let end_span = bond_spans
                    .and_then(|b| b.strings.get(side))
                    .map_or(span, |(_, s)| *s);
                match element_index.get(name) {
                    Some(id) if id.0 != u32::MAX => ends[side] = *id,
                    Some(_) => ok = false, // the element itself was already reported
                    None => {
                        ok = false;
                        let mut diagnostic = Diagnostic::new(
                            DiagnosticKind::UndefinedElement,
                            format!(
                                "bond {} -> {} names '{name}', which is not an element of the model",
                                raw_bond.0, raw_bond.1
                            ),
                        )
                        .at(&self.file, end_span)
                        .element(name.clone());
                        if let Some(suggestion) =
                            suggest(name, element_index.keys().map(String::as_str))
                        {
                            diagnostic = diagnostic.note(format!("did you mean '{suggestion}'?"));
                        }
                        self.problems.push(diagnostic);
                    }
                }
            }
            if !ok {
                for end in ends.iter().filter(|id| id.0 != u32::MAX) {
                    dropped[end.index()] += 1;
                }
                continue;
            }
            if ends[0] == ends[1] {
                dropped[ends[0].index()] += 1;
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::SelfBond,
                        format!(
                            "bond {0} -> {0} connects element '{0}' to itself",
                            raw_bond.0
                        ),
                    )
                    .at(&self.file, span)
                    .element(raw_bond.0.clone()),
                );
                continue;
            }
            let id = BondId(bonds.len() as u32);
            elements[ends[0].index()].bonds.push(id);
            elements[ends[1].index()].bonds.push(id);
            bonds.push(Bond {
                from: ends[0],
                to: ends[1],
                span,
            });
        }
        (bonds, dropped)
    }

    fn entry_span(&self, entries: &[EntrySpans], index: usize) -> Span {
        entries.get(index).map_or(self.map.root, |e| e.key_span)
    }

    fn field_span(&self, name: &str) -> Option<Span> {
        self.map.field(name).map(|f| f.name_span)
    }

    /// Bounds must be finite, `low < high`, and hold the parameter's value.
    fn check_bounds(&mut self, name: &str, value: f64, (low, high): (f64, f64), index: usize) {
        let problem = if !low.is_finite() || !high.is_finite() {
            format!("parameter '{name}' has bounds ({low}, {high}); bounds must be finite numbers")
        } else if low >= high {
            format!(
                "parameter '{name}' has bounds ({low}, {high}); the low bound must be below the high one"
            )
        } else if !(low..=high).contains(&value) {
            format!("parameter '{name}' has value {value}, outside its bounds ({low}, {high})")
        } else {
            return;
        };
        let span = self
            .field_value_span(&self.map.parameters, index, "bounds")
            .unwrap_or_else(|| self.entry_span(&self.map.parameters, index));
        self.problems.push(
            Diagnostic::new(DiagnosticKind::InvalidValue, problem)
                .at(&self.file, span)
                .element(name),
        );
    }

    /// A `unit` string must parse ([`crate::units::parse_scaled`]): the unit, if it does.
    fn check_unit(
        &mut self,
        what: &str,
        name: &str,
        unit: Option<&str>,
        entries: &[EntrySpans],
        index: usize,
    ) -> Option<Unit> {
        let unit = unit?;
        let error = match crate::units::parse_scaled(unit) {
            Ok(parsed) => return Some(parsed),
            Err(error) => error,
        };
        let span = self.unit_span(entries, index);
        self.problems.push(
            Diagnostic::new(
                DiagnosticKind::UnknownUnit,
                format!("{what} '{name}' has unit \"{unit}\": {error}"),
            )
            .at(&self.file, span)
            .element(name)
            .note("write units with SI symbols and prefixes, '*', '/' and '^': \"N*s/m\", \"kg*m^2\", \"kPa\""),
        );
        None
    }

    /// The span of the `unit` string of entry `index`.
    fn unit_span(&self, entries: &[EntrySpans], index: usize) -> Span {
        entries
            .get(index)
            .and_then(|e| e.fields.iter().find(|f| f.name == "unit"))
            .map(|f| f.string_content.unwrap_or(f.value_span))
            .unwrap_or_else(|| self.entry_span(entries, index))
    }

    /// An input's values come in SI units (scenarios, experiments, `--at`): its unit must
    /// be an SI one, without a factor or an offset.
    fn check_input_unit(&mut self, name: &str, unit: &Unit, written: &str, index: usize) {
        if unit.is_si() {
            return;
        }
        let span = self.unit_span(&self.map.inputs, index);
        self.problems.push(
            Diagnostic::new(
                DiagnosticKind::UnknownUnit,
                format!(
                    "input '{name}' has unit {}: inputs take SI values in scenarios, experiments and --at; declare it in \"{}\"",
                    unit.in_si_words(written),
                    unit.si_text(written)
                ),
            )
            .at(&self.file, span)
            .element(name),
        );
    }

    /// A parameter's value and bounds in SI units, converted from its unit as written in
    /// the file (the decimals themselves, so that `0.501` kN is exactly 501 N); a value
    /// that over- or underflows once converted is reported at the value.
    fn in_si(
        &mut self,
        name: &str,
        raw: &crate::model::spec::ParameterSpec,
        unit: Option<&Unit>,
        index: usize,
    ) -> InSi {
        let plain = InSi {
            value: raw.value,
            bounds: raw.bounds,
            as_written: None,
            si_unit: raw.unit.clone(),
        };
        let (Some(unit), Some(written_unit)) = (unit, raw.unit.as_deref()) else {
            return plain;
        };
        let si_unit = unit.si_text(written_unit);
        if unit.is_si() || !raw.value.is_finite() {
            return InSi {
                si_unit: Some(si_unit),
                ..plain
            };
        }
        let value_span = self.field_value_span(&self.map.parameters, index, "value");
        let text = value_span.and_then(|span| self.file.text().get(span.start..span.end));
        let value = unit.to_si(raw.value, text);
        let shown = text.map_or_else(|| raw.value.to_string(), str::to_string);
        let problem = if !value.is_finite() {
            Some("which is too large in SI units")
        } else if value == 0.0 && raw.value != 0.0 && unit.offset.is_none() {
            Some("which underflows to 0 in SI units")
        } else {
            None
        };
        if let Some(problem) = problem {
            let span = value_span.unwrap_or_else(|| self.entry_span(&self.map.parameters, index));
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "parameter '{name}' has value {shown} {written_unit}, {problem} ({si_unit}) for a 64-bit floating-point number"
                    ),
                )
                .at(&self.file, span)
                .element(name)
                .note("write the value in a unit nearer its size"),
            );
        }
        let bounds = raw.bounds.map(|(low, high)| {
            let texts = self
                .field_value_span(&self.map.parameters, index, "bounds")
                .and_then(|span| self.file.text().get(span.start..span.end))
                .and_then(bound_texts);
            let (low_text, high_text) = texts.unzip();
            (unit.to_si(low, low_text), unit.to_si(high, high_text))
        });
        InSi {
            value,
            bounds,
            as_written: Some(raw.value),
            si_unit: Some(si_unit),
        }
    }

    fn field_value_span(&self, entries: &[EntrySpans], index: usize, field: &str) -> Option<Span> {
        entries
            .get(index)?
            .fields
            .iter()
            .find(|f| f.name == field)
            .map(|f| f.value_span)
    }

    /// The span of a field's string contents, to shift expression spans onto the file.
    fn string_span(&self, index: usize, field: &str) -> Option<Span> {
        let entry = self.map.elements.get(index)?;
        let field = entry.fields.iter().find(|f| f.name == field)?;
        Some(field.string_content.unwrap_or(field.value_span))
    }

    fn check_name(&mut self, name: &str, what: &str, span: Span) -> bool {
        // Names joined by '.' are the qualified names of a sub-model's parts (`front.spring`).
        let valid = name.split('.').all(|part| {
            part.chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        });
        if !valid {
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidName,
                    format!(
                        "{what} name '{name}' is not a valid name: use letters, digits and '_', starting with a letter"
                    ),
                )
                .at(&self.file, span)
                .element(name),
            );
        }
        valid
    }

    fn check_unique(
        &mut self,
        seen: &mut HashMap<String, (Span, &'static str)>,
        name: &str,
        what: &'static str,
        span: Span,
    ) -> bool {
        if let Some((first, first_what)) = seen.get(name) {
            let (line, _) = self.file.line_col(first.start);
            let message = if *first_what == what {
                format!("{what} '{name}' is defined twice")
            } else {
                format!("'{name}' is both a {first_what} and an {what}")
            };
            self.problems.push(
                Diagnostic::new(DiagnosticKind::DuplicateName, message)
                    .at(&self.file, span)
                    .element(name)
                    .note(format!("first defined on line {line}")),
            );
            return false;
        }
        seen.insert(name.to_string(), (span, what));
        true
    }

    /// The model's ports: each named once, validly, and a junction of the model.
    fn ports(
        &mut self,
        raw: &ModelSpec,
        element_index: &HashMap<String, ElementId>,
        model: &Model,
    ) -> Vec<Port> {
        let mut seen: HashMap<String, (Span, &'static str)> = HashMap::new();
        let mut ports = Vec::new();
        for (index, (name, port)) in raw.ports.iter().enumerate() {
            let span = self.entry_span(&self.map.ports, index);
            if !self.check_name(name, "port", span)
                || !self.check_unique(&mut seen, name, "port", span)
            {
                continue;
            }
            let element_span = self
                .map
                .ports
                .get(index)
                .and_then(|e| e.field("element"))
                .map_or(span, FieldSpan::text_span);
            let Some(&element) = element_index.get(&port.element) else {
                let names = element_index.keys().map(String::as_str);
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UndefinedElement,
                    format!("port '{name}': no element '{}'", port.element),
                )
                .at(&self.file, element_span)
                .element(name.clone());
                if let Some(near) = suggest(&port.element, names) {
                    diagnostic = diagnostic.note(format!("did you mean '{near}'?"));
                }
                self.problems.push(diagnostic);
                continue;
            };
            let kind = &model.element(element).kind;
            if !matches!(kind, ElementKind::ZeroJunction | ElementKind::OneJunction) {
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::BondCount,
                        format!(
                            "port '{name}': '{}' is {} {}; a port is a 0- or 1-junction, \
                             which the outside's bonds join",
                            port.element,
                            article(kind.description()),
                            kind.description()
                        ),
                    )
                    .at(&self.file, element_span)
                    .element(name.clone())
                    .note(format!(
                        "bond '{}' to a junction and name the junction as the port",
                        port.element
                    )),
                );
                continue;
            }
            ports.push(Port {
                name: name.clone(),
                element,
                description: port.description.clone(),
                span,
            });
        }
        ports
    }

    fn check_ports(&mut self, model: &Model, element: ElementId) {
        let e = model.element(element);
        // A port counts as a bond: the outside's, when the model is used as a sub-model.
        let outside = model.ports.iter().filter(|p| p.element == element).count();
        let count = e.bonds.len() + outside;
        // Where the bonds are: their lines in a file, their ends in a model built in code.
        let lines = || {
            let in_code = model.source.is_in_code();
            let places: Vec<String> = e
                .bonds
                .iter()
                .map(|&b| match in_code {
                    true => model.bond_label(b),
                    false => model.locate_bond(b).line.to_string(),
                })
                .collect();
            match in_code {
                true => places.join(", "),
                false => format!("lines {}", places.join(", ")),
            }
        };
        let problem = match e.kind.port_count() {
            Some(1) if count != 1 => Some(if count == 0 {
                format!(
                    "{} '{}' has no bond; it needs exactly one",
                    e.kind.description(),
                    e.name
                )
            } else {
                format!(
                    "{} '{}' has {count} bonds ({}); a one-port takes exactly one",
                    e.kind.description(),
                    e.name,
                    lines()
                )
            }),
            Some(2) if count != 2 => Some(format!(
                "{} '{}' has {count} bonds{}; it takes exactly two, one in and one out",
                e.kind.description(),
                e.name,
                if count == 0 {
                    String::new()
                } else {
                    format!(" ({})", lines())
                }
            )),
            Some(2) => {
                let inward = e
                    .bonds
                    .iter()
                    .filter(|b| model.bond(**b).to == element)
                    .count();
                (inward != 1).then(|| {
                    format!(
                        "{} '{}' has {} bonds pointing {}; power must flow through it: one bond in, one out",
                        e.kind.description(),
                        e.name,
                        2,
                        if inward == 2 { "in" } else { "out" }
                    )
                })
            }
            None if count < 2 => Some(format!(
                "{} '{}' has {count} bond{}; a junction joins two or more",
                e.kind.description(),
                e.name,
                if count == 1 { "" } else { "s" }
            )),
            _ => None,
        };
        if let Some(message) = problem {
            self.problems.push(
                Diagnostic::new(DiagnosticKind::BondCount, message)
                    .at(&self.file, e.span)
                    .element(e.name.clone()),
            );
        }
    }

    fn check_connected(&mut self, model: &Model) {
        let graph = model.bond_graph();
        let mut components = UnionFind::<usize>::new(graph.node_count());
        for edge in graph.raw_edges() {
            components.union(edge.source().index(), edge.target().index());
        }
        let mut pieces: Vec<(usize, Vec<ElementId>)> = Vec::new();
        for element in model.element_ids() {
            let r = components.find(element.index());
            match pieces.iter_mut().find(|(root, _)| *root == r) {
                Some((_, members)) => members.push(element),
                None => pieces.push((r, vec![element])),
            }
        }
        if pieces.len() < 2 {
            return;
        }
        let describe = |members: &[ElementId]| {
            let names: Vec<String> = members
                .iter()
                .take(4)
                .map(|e| format!("'{}'", model.element(*e).name))
                .collect();
            let more = members.len().saturating_sub(4);
            if more > 0 {
                format!("{{{}, and {more} more}}", names.join(", "))
            } else {
                format!("{{{}}}", names.join(", "))
            }
        };
        let listed: Vec<String> = pieces.iter().map(|(_, m)| describe(m)).collect();
        let first_of_second = pieces[1].1[0];
        self.problems.push(
            Diagnostic::new(
                DiagnosticKind::Disconnected,
                format!(
                    "the model is in {} pieces that no bond joins: {}",
                    pieces.len(),
                    listed.join(" and ")
                ),
            )
            .at(&self.file, model.element(first_of_second).span)
            .element(model.element(first_of_second).name.clone())
            .note("bond the pieces together, or model them in separate files"),
        );
    }
}
