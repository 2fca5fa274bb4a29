//! The units check of a model: every element's law against the units of its parameters.
//!
//! # How
//! 1. The junction structure relates bonds: at a junction every bond has the same effort
//!    dimension and the same flow dimension.
//! 2. Sources and the other laws that fix a variable (friction forces are efforts, dead
//!    bands and flow limits are flows) and two-ports with known ratios (`e_in = n e_out`,
//!    `e_in = r f_out`) go first; a source whose value is plainly the other variable (a
//!    velocity as an effort) is reported at once, and not propagated.
//! 3. Where a bond's effort is known and its flow not (or the other way), effort times flow
//!    is a power, which gives the other (not in a thermal pseudo bond graph, whose
//!    temperature times heat flow is not a power).
//! 4. Then the storage and dissipative laws, one at a time: `I`: inertance =
//!    effort·time/flow; `C` and tension-only: stiffness = effort/(flow·time) (compliance the
//!    inverse); `R`: resistance = effort/flow; friction's viscous coefficient likewise; a
//!    nonlinear law's expression is its effort or flow, with its state `q_X` a flow times
//!    time and `p_X` an effort times time. A law that disagrees with what the graph already
//!    makes of its bond is reported at its field, naming both units; laws whose parameters
//!    have no unit are skipped.
//! 5. Last, every bond whose effort and flow are both known must carry a power.
//!
//! The order decides which of two disagreeing laws is blamed: sources, then the laws in
//! file order, as a reader would check them.

use std::collections::HashMap;

use crate::diagnostics::{Diagnostic, DiagnosticKind};
use crate::expr::{self, Expr, ExprKind};
use crate::model::raw::{RawElement, RawModel};
use crate::model::source_map::SourceMap;
use crate::model::{ElementId, ElementKind, Model};
use crate::source::Span;

use super::dimension::Dim;
use super::domain::{self, Domain};
use super::format::{readable, readable_with};
use super::infer::{Symbols, infer};
use super::parse::parse_unit;
use super::solve::{Conflict, Solver, Var, effort, flow};

/// How a file's variables map onto efforts and flows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Convention {
    /// A bond graph: efforts are forces, voltages, pressures, temperatures.
    BondGraph,
    /// A linear graph translated into a bond graph: its through variables (forces,
    /// currents, volume flows, heat flows) are the efforts.
    LinearGraph,
}

/// What a law relates.
#[derive(Clone, Copy, Debug)]
enum Law {
    /// `dim(var) = X`; `effort` says which kind of variable it is, for the message.
    Value { var: Var, is_effort: bool },
    /// `dim(a) = dim(b)·X^power·k`.
    Ratio { a: Var, b: Var, power: i32, k: Dim },
}

/// One law of one element, with its expression.
struct Constraint {
    element: ElementId,
    field: &'static str,
    text: String,
    expr: Expr,
    /// The span of the expression text in the file.
    span: Span,
    law: Law,
    /// Sources, fixed variables and two-ports go first.
    early: bool,
    /// The element's own bond, for `effort`, `flow` in resistor laws.
    port: usize,
}

/// What the check found of one bond: the dimensions of its effort and flow, where known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BondDimensions {
    /// The effort's dimension.
    pub effort: Option<Dim>,
    /// The flow's dimension.
    pub flow: Option<Dim>,
}

/// Every unit problem of `model` (built from `raw`, positions in `map`): mismatches inside
/// expressions, laws whose parameters disagree with their bonds, and bonds whose effort
/// times flow is not a power (empty if the units agree, or are not given); and the
/// dimensions found for each bond.
pub(crate) fn check(
    model: &Model,
    raw: &RawModel,
    map: &SourceMap,
    convention: Convention,
) -> (Vec<Diagnostic>, Vec<BondDimensions>) {
    let mut units: HashMap<&str, (Dim, &str)> = HashMap::new();
    for (name, unit) in raw
        .parameters
        .iter()
        .map(|(n, p)| (n, &p.unit))
        .chain(raw.inputs.iter().map(|(n, i)| (n, &i.unit)))
    {
        if let Some(unit) = unit
            && let Ok(dim) = parse_unit(unit)
        {
            units.insert(name.as_str(), (dim, unit.as_str()));
        }
    }
    let mut checker = Checker {
        model,
        units,
        solver: Solver::new(2 * model.bonds.len()),
        problems: Vec::new(),
        convention,
    };
    checker.junctions();
    let mut constraints = checker.constraints(raw, map);
    checker.solve(&mut constraints);
    checker.powers();
    let dimensions = (0..model.bonds.len())
        .map(|b| BondDimensions {
            effort: checker.solver.get(effort(b)),
            flow: checker.solver.get(flow(b)),
        })
        .collect();
    (checker.problems, dimensions)
}

struct Checker<'a> {
    model: &'a Model,
    units: HashMap<&'a str, (Dim, &'a str)>,
    solver: Solver,
    problems: Vec<Diagnostic>,
    convention: Convention,
}

/// The symbols of one law: parameters and inputs by unit, states and port variables by
/// what is known of their bonds.
struct Scope<'c, 'a> {
    checker: &'c Checker<'a>,
    port: usize,
}

impl Symbols for Scope<'_, '_> {
    fn dim(&self, name: &str) -> Option<Dim> {
        if let Some((dim, _)) = self.checker.units.get(name) {
            return Some(*dim);
        }
        let solver = &self.checker.solver;
        match name {
            "effort" => return solver.get(effort(self.port)),
            "flow" => return solver.get(flow(self.port)),
            _ => {}
        }
        let model = self.checker.model;
        let (letter, element) = name.split_once('_')?;
        let id = model.element_named(element)?;
        let bond = model.element(id).bonds.first()?.index();
        match (letter, model.storage_name(id)) {
            ("q", Some(state)) if state == name => {
                solver.get(flow(bond)).map(|d| d.times(Dim::TIME))
            }
            ("p", Some(state)) if state == name => {
                solver.get(effort(bond)).map(|d| d.times(Dim::TIME))
            }
            _ => None,
        }
    }

    fn written(&self, name: &str) -> Option<String> {
        self.checker.units.get(name).map(|(_, u)| (*u).to_string())
    }
}

impl Checker<'_> {
    fn junctions(&mut self) {
        for id in self.model.element_ids() {
            let element = self.model.element(id);
            if !matches!(
                element.kind,
                ElementKind::ZeroJunction | ElementKind::OneJunction
            ) {
                continue;
            }
            let bonds: Vec<usize> = element.bonds.iter().map(|b| b.index()).collect();
            for pair in bonds.windows(2) {
                // Fresh classes with no values: these cannot disagree.
                let _ = self
                    .solver
                    .relate(effort(pair[1]), effort(pair[0]), Dim::NONE);
                let _ = self.solver.relate(flow(pair[1]), flow(pair[0]), Dim::NONE);
            }
        }
    }

    fn constraints(&self, raw: &RawModel, map: &SourceMap) -> Vec<Constraint> {
        let mut out = Vec::new();
        for (index, (name, raw_element)) in raw.elements.iter().enumerate() {
            let Some(id) = self.model.element_named(name) else {
                continue;
            };
            let element = self.model.element(id);
            let Some(first) = element.bonds.first().map(|b| b.index()) else {
                continue;
            };
            let (e, f) = (effort(first), flow(first));
            // Two-ports: the bond into the element and the bond out of it.
            let (port_in, port_out) = {
                let into = element
                    .bonds
                    .iter()
                    .find(|b| self.model.bond(**b).to == id)
                    .map(|b| b.index());
                let out_of = element
                    .bonds
                    .iter()
                    .find(|b| self.model.bond(**b).from == id)
                    .map(|b| b.index());
                (into.unwrap_or(first), out_of.unwrap_or(first))
            };
            let value = |var, is_effort| Law::Value { var, is_effort };
            let ratio = |power, k| Law::Ratio {
                a: e,
                b: f,
                power,
                k,
            };
            let per_s = Dim::TIME.recip();
            let mut laws: Vec<(&'static str, &Option<String>, Law, bool)> = Vec::new();
            let some = |s: &String| Some(s.clone());
            let owned: Vec<Option<String>>;
            match raw_element {
                RawElement::Se { effort: text } => {
                    owned = vec![some(text)];
                    laws.push(("effort", &owned[0], value(e, true), true));
                }
                RawElement::Sf { flow: text } => {
                    owned = vec![some(text)];
                    laws.push(("flow", &owned[0], value(f, false), true));
                }
                RawElement::I {
                    inertance,
                    flow: law,
                } => {
                    laws.push(("inertance", inertance, ratio(1, per_s), false));
                    laws.push(("flow", law, value(f, false), false));
                }
                RawElement::C {
                    compliance,
                    stiffness,
                    effort: law,
                } => {
                    laws.push(("compliance", compliance, ratio(-1, Dim::TIME), false));
                    laws.push(("stiffness", stiffness, ratio(1, Dim::TIME), false));
                    laws.push(("effort", law, value(e, true), false));
                }
                RawElement::TensionOnly {
                    compliance,
                    stiffness,
                    ..
                } => {
                    laws.push(("compliance", compliance, ratio(-1, Dim::TIME), false));
                    laws.push(("stiffness", stiffness, ratio(1, Dim::TIME), false));
                }
                RawElement::R {
                    resistance,
                    effort: effort_law,
                    flow: flow_law,
                } => {
                    laws.push(("resistance", resistance, ratio(1, Dim::NONE), false));
                    laws.push(("effort", effort_law, value(e, true), false));
                    laws.push(("flow", flow_law, value(f, false), false));
                }
                RawElement::Conductance { conductance } => {
                    owned = vec![some(conductance)];
                    laws.push(("conductance", &owned[0], ratio(-1, Dim::NONE), false));
                }
                RawElement::TF { ratio: text } => {
                    owned = vec![some(text)];
                    let (i, o) = (port_in, port_out);
                    let two = |a, b| Law::Ratio {
                        a,
                        b,
                        power: 1,
                        k: Dim::NONE,
                    };
                    laws.push(("ratio", &owned[0], two(effort(i), effort(o)), true));
                    laws.push(("ratio", &owned[0], two(flow(o), flow(i)), true));
                }
                RawElement::GY { ratio: text } | RawElement::ReciprocalGY { ratio: text } => {
                    owned = vec![some(text)];
                    let power = if matches!(raw_element, RawElement::GY { .. }) {
                        1
                    } else {
                        -1
                    };
                    let (i, o) = (port_in, port_out);
                    let two = |a, b| Law::Ratio {
                        a,
                        b,
                        power,
                        k: Dim::NONE,
                    };
                    laws.push(("ratio", &owned[0], two(effort(i), flow(o)), true));
                    laws.push(("ratio", &owned[0], two(effort(o), flow(i)), true));
                }
                RawElement::Friction {
                    breakaway,
                    coulomb,
                    viscous,
                    dead_band,
                    stribeck,
                    ..
                } => {
                    owned = vec![some(breakaway), some(coulomb)];
                    laws.push(("breakaway", &owned[0], value(e, true), true));
                    laws.push(("coulomb", &owned[1], value(e, true), true));
                    laws.push(("dead_band", dead_band, value(f, false), true));
                    laws.push(("stribeck", stribeck, value(f, false), true));
                    laws.push(("viscous", viscous, ratio(1, Dim::NONE), false));
                }
                RawElement::FlowLimit { max_flow, .. } => {
                    owned = vec![some(max_flow)];
                    laws.push(("max_flow", &owned[0], value(f, false), true));
                }
                RawElement::Zero | RawElement::One => {}
            }
            for (field, text, law, early) in laws {
                let Some(text) = text else { continue };
                let Ok(expr) = expr::parse(text) else {
                    continue;
                };
                let span = map
                    .elements
                    .get(index)
                    .and_then(|entry| entry.fields.iter().find(|f| f.name == field))
                    .map(|f| f.string_content.unwrap_or(f.value_span))
                    .unwrap_or(element.span);
                out.push(Constraint {
                    element: id,
                    field,
                    text: text.clone(),
                    expr,
                    span,
                    law,
                    early,
                    port: first,
                });
            }
        }
        out
    }

    fn solve(&mut self, constraints: &mut Vec<Constraint>) {
        loop {
            if self.apply(constraints, true, usize::MAX) || self.power_step() {
                continue;
            }
            if !self.apply(constraints, false, 1) {
                return;
            }
        }
    }

    /// Applies up to `limit` pending constraints of the given class whose expression's
    /// dimension is known; reports and drops those that disagree. Whether any applied.
    fn apply(&mut self, constraints: &mut Vec<Constraint>, early: bool, limit: usize) -> bool {
        let mut applied = 0;
        let mut index = 0;
        while index < constraints.len() && applied < limit {
            let c = &constraints[index];
            if c.early != early {
                index += 1;
                continue;
            }
            let scope = Scope {
                checker: self,
                port: c.port,
            };
            let dim = match infer(&c.text, &c.expr, &scope) {
                Ok(Some(dim)) => dim,
                Ok(None) => {
                    index += 1;
                    continue;
                }
                Err(mismatch) => {
                    let span = Span::new(
                        c.span.start + mismatch.span.start,
                        c.span.start + mismatch.span.end,
                    );
                    let d = self.diagnostic(c, span, mismatch.message);
                    self.problems.push(d);
                    constraints.remove(index);
                    continue;
                }
            };
            let c = constraints.remove(index);
            applied += 1;
            if let Some(problem) = self.enforce(&c, dim) {
                self.problems.push(problem);
            }
        }
        applied > 0
    }

    /// Applies one constraint whose expression is in `dim`; the diagnostic if it disagrees.
    fn enforce(&mut self, c: &Constraint, dim: Dim) -> Option<Diagnostic> {
        let who = format!(
            "{} '{}'",
            self.model.element(c.element).kind.description(),
            self.model.element(c.element).name
        );
        match c.law {
            Law::Value { var, is_effort } => {
                if c.early
                    && let Some(message) = self.implausible(c, dim, is_effort)
                {
                    return Some(self.diagnostic(c, c.span, message));
                }
                match self
                    .solver
                    .set(var, dim, format!("the {} of the {who}", c.field))
                {
                    Ok(_) => None,
                    Err(Conflict::Value(known)) => {
                        let what = if is_effort { "effort" } else { "flow" };
                        let message = format!(
                            "{} '{}' is in {} but the bond's {what} is in {} (from {})",
                            c.field,
                            c.text,
                            self.unit_of(c, dim),
                            self.display(known.dim, None),
                            known.by
                        );
                        Some(self.diagnostic(c, c.span, message))
                    }
                    Err(Conflict::Factor { .. }) => None,
                }
            }
            Law::Ratio { a, b, power, k } => {
                let r = dim.powi(power).times(k);
                match self.solver.relate(a, b, r) {
                    Ok(_) => None,
                    Err(Conflict::Factor { needed }) => {
                        // X^power·k = needed, so X = (needed/k)^power (power is ±1).
                        let needed_dim = needed.per(k).powi(power);
                        let bond = c.port;
                        let here = self.context(c, bond);
                        let hints = self.domain(bond).map_or(&[][..], |d| d.hints);
                        let message = format!(
                            "{} '{}' is in {} but {here} needs {}",
                            c.field,
                            c.text,
                            self.unit_of(c, dim),
                            readable_with(needed_dim, hints)
                        );
                        Some(self.diagnostic(c, c.span, message))
                    }
                    Err(Conflict::Value(_)) => None,
                }
            }
        }
    }

    /// A source's value that is plainly the other kind of variable (a velocity given as an
    /// effort): the message, if so.
    fn implausible(&self, c: &Constraint, dim: Dim, is_effort: bool) -> Option<String> {
        let lg = self.convention == Convention::LinearGraph;
        let unit = |(u, _): (&str, &str)| parse_unit(u).unwrap_or(Dim::NONE);
        let as_effort = domain::DOMAINS
            .iter()
            .find(|d| unit(d.file_effort(lg)) == dim);
        let as_flow = domain::DOMAINS
            .iter()
            .find(|d| unit(d.file_flow(lg)) == dim);
        let kw = self.model.element(c.element).kind.keyword();
        let article = if kw.starts_with(['I', 'R', 'S', 'A', 'E', 'O']) {
            "an"
        } else {
            "a"
        };
        match (is_effort, as_effort, as_flow) {
            (true, None, Some(d)) => Some(format!(
                "{} '{}' is in {}, a {}, where {article} {kw} needs an effort: {}",
                c.field,
                c.text,
                self.unit_of(c, dim),
                d.file_flow(lg).1,
                domain::effort_list(lg)
            )),
            (false, Some(d), None) => Some(format!(
                "{} '{}' is in {}, a {}, where {article} {kw} needs a flow: {}",
                c.field,
                c.text,
                self.unit_of(c, dim),
                d.file_effort(lg).1,
                domain::flow_list(lg)
            )),
            _ => None,
        }
    }

    /// `a C on a mechanical translational bond`, or what is known of the bond.
    fn context(&self, c: &Constraint, bond: usize) -> String {
        let kind = &self.model.element(c.element).kind;
        let kw = kind.keyword();
        let article = if kw.starts_with(['I', 'R', 'S', 'A', 'E', 'O']) {
            "an"
        } else {
            "a"
        };
        if matches!(
            kind,
            ElementKind::Transformer(_) | ElementKind::Gyrator(_) | ElementKind::Nonlinear(_)
        ) && self.model.element(c.element).bonds.len() == 2
        {
            return format!("{article} {kw} between these bonds");
        }
        match self.domain(bond) {
            Some(d) => format!("{article} {kw} on a {} bond", d.name),
            None => match (self.solver.get(effort(bond)), self.solver.get(flow(bond))) {
                (Some(e), Some(f)) => format!(
                    "{article} {kw} on a bond with effort in {} and flow in {}",
                    readable(e),
                    readable(f)
                ),
                _ => format!("{article} {kw} here (as the laws around it make its bond)"),
            },
        }
    }

    fn domain(&self, bond: usize) -> Option<&'static Domain> {
        let e = self.solver.get(effort(bond))?;
        let f = self.solver.get(flow(bond))?;
        Domain::of(e, f)
    }

    /// The unit of a constraint's expression: as written, for a lone parameter.
    fn unit_of(&self, c: &Constraint, dim: Dim) -> String {
        let written = match &c.expr.kind {
            ExprKind::Symbol(name) => self.units.get(name.as_str()).map(|(_, u)| *u),
            _ => None,
        };
        self.display(dim, written)
    }

    fn display(&self, dim: Dim, written: Option<&str>) -> String {
        written.map_or_else(|| readable(dim), str::to_string)
    }

    fn diagnostic(&self, c: &Constraint, span: Span, message: String) -> Diagnostic {
        let element = self.model.element(c.element);
        Diagnostic::new(
            DiagnosticKind::UnitMismatch,
            format!(
                "{} '{}': {message}",
                element.kind.description(),
                element.name
            ),
        )
        .at(&self.model.source, span)
        .element(element.name.clone())
    }

    /// Effort times flow is a power: where one is known and the other not, the other.
    fn power_step(&mut self) -> bool {
        let power = domain::power();
        let lg = self.convention == Convention::LinearGraph;
        let mut learnt = false;
        for bond in 0..self.model.bonds.len() {
            let (e, f) = (self.solver.get(effort(bond)), self.solver.get(flow(bond)));
            // In a pseudo bond graph (temperature and heat flow) the product is no power.
            let temperature = Dim::TEMPERATURE;
            let (effort_is_t, flow_is_t) = if lg { (false, true) } else { (true, false) };
            let result = match (e, f) {
                (Some(e), None) if !(effort_is_t && e == temperature || lg && e == power) => self
                    .solver
                    .set(flow(bond), power.per(e), "effort times flow being a power"),
                (None, Some(f)) if !(flow_is_t && f == temperature || !lg && f == power) => {
                    self.solver.set(
                        effort(bond),
                        power.per(f),
                        "effort times flow being a power",
                    )
                }
                _ => Ok(false),
            };
            learnt |= result.unwrap_or(false);
        }
        learnt
    }

    /// Every bond whose effort and flow are known carries a power (or is a thermal pseudo
    /// bond).
    fn powers(&mut self) {
        if !self.problems.is_empty() {
            return;
        }
        let power = domain::power();
        for id in self.model.bond_ids() {
            let bond = id.index();
            let (Some(e), Some(f)) = (self.solver.get(effort(bond)), self.solver.get(flow(bond)))
            else {
                continue;
            };
            if e.times(f) == power || Domain::of(e, f).is_some_and(Domain::is_pseudo) {
                continue;
            }
            let (from, to) = {
                let b = self.model.bond(id);
                (
                    self.model.element(b.from).name.clone(),
                    self.model.element(b.to).name.clone(),
                )
            };
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::UnitMismatch,
                    format!(
                        "bond {from} -> {to} carries an effort in {} and a flow in {}, whose product {} is not a power (W)",
                        readable(e),
                        readable(f),
                        readable(e.times(f))
                    ),
                )
                .at(&self.model.source, self.model.bond(id).span)
                .element(from),
            );
        }
    }
}
