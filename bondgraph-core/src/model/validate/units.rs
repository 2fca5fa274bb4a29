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
//! # Which law is wrong
//! Where laws disagree around a loop (a front and a rear lever arm on one pitching body),
//! the law applied last is the one that finds the disagreement, which says nothing about
//! which law is wrong. So when the check finds problems, it checks the model again without
//! each field's laws in turn: if exactly one field leaves every other law agreeing, that
//! field is blamed, its laws checked against what the rest of the model makes of its bonds.
//! Otherwise (no single field explains every problem, or several do equally well) the
//! problems are reported as found, in the order above: sources, then the laws in file
//! order, as a reader would check them. A field is reported at most once (a transformer's
//! ratio relates both the efforts and the flows of its bonds).
//!
//! # Words
//! A linear graph is checked through the bond graph it translates to, but reported in its
//! own words ([`Convention::LinearGraph`]): branches of A-, T- and D-type with their
//! capacitance, inductance, stiffness, resistance or conductance, and through and across
//! variables where the bond graph has efforts and flows.

use std::collections::HashMap;

use crate::diagnostics::{Diagnostic, DiagnosticKind};
use crate::expr::{self, Expr, ExprKind};
use crate::model::source_map::SourceMap;
use crate::model::spec::{ElementSpec, ModelSpec};
use crate::model::{ElementId, ElementKind, Model};
use crate::source::Span;

use crate::units::BondDimensions;
use crate::units::dimension::Dim;
use crate::units::domain::{self, Domain};
use crate::units::format::{readable, readable_with};
use crate::units::infer::{Mismatch, Symbols, infer};
use crate::units::parse::parse_unit;
use crate::units::solve::{Conflict, Solver, Var, effort, flow};

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
#[derive(Clone)]
struct Constraint {
    element: ElementId,
    field: &'static str,
    /// The element as the file calls it: `inertia 'mass'`, `A-type 'tank'`.
    who: String,
    /// The field as the file calls it: `inertance`, `capacitance`.
    field_word: &'static str,
    /// The element's kind as the file writes it, for "an I on ...": `I`, `A-type`.
    keyword: &'static str,
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

/// Every unit problem of `model` (built from `raw`, positions in `map`): mismatches inside
/// expressions, laws whose parameters disagree with their bonds, and bonds whose effort
/// times flow is not a power (empty if the units agree, or are not given); and the
/// dimensions found for each bond.
pub(crate) fn check(
    model: &Model,
    raw: &ModelSpec,
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
    let names: HashMap<&str, ElementId> = model
        .element_ids()
        .map(|id| (model.element(id).name.as_str(), id))
        .collect();
    let constraints = constraints(model, raw, map, &names, convention);
    let states: HashMap<String, ElementId> = model
        .element_ids()
        .filter_map(|id| Some((model.storage_name(id)?, id)))
        .collect();
    let run_with = |without: Option<Field>, schedule: Schedule| {
        let mut checker = Checker {
            model,
            units: &units,
            states: &states,
            solver: Solver::new(2 * model.bonds.len()),
            problems: Vec::new(),
            blamed: Vec::new(),
            convention,
        };
        checker.junctions();
        let mut laws: Vec<Constraint> = constraints
            .iter()
            .filter(|c| Some((c.element, c.field)) != without)
            .cloned()
            .collect();
        match schedule {
            Schedule::Closure => checker.close(&mut laws),
            Schedule::Ordered => checker.solve(&mut laws),
        }
        checker.powers();
        checker
    };
    // Laws that agree reach the same dimensions in any order, so the closure, linear in the
    // model's size, is the answer wherever it finds no problem; where it finds one, the
    // laws are applied again in the order the messages follow (see the module docs).
    let run = |without: Option<Field>| {
        if !ordered_only() {
            let closed = run_with(without, Schedule::Closure);
            if closed.problems.is_empty() {
                return closed;
            }
        }
        run_with(without, Schedule::Ordered)
    };
    let found = run(None);
    let checker = if found.problems.is_empty() {
        found
    } else {
        match blame(&constraints, &found.blamed, &run) {
            Some(blamed) => blamed,
            None => found,
        }
    };
    let dimensions = (0..model.bonds.len())
        .map(|b| BondDimensions {
            effort: checker.solver.get(effort(b)),
            flow: checker.solver.get(flow(b)),
        })
        .collect();
    (checker.problems, dimensions)
}

thread_local! {
    /// Whether to check every model in [`Schedule::Ordered`] alone, the reference the
    /// closure must agree with ([`ordered_reference`]).
    static ORDERED_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Checks units, on this thread, with the ordered reference schedule alone (`true`) or the
/// usual closure (`false`): for the test that the two agree on every model file.
#[doc(hidden)]
pub fn ordered_reference(on: bool) {
    ORDERED_ONLY.with(|o| o.set(on));
}

fn ordered_only() -> bool {
    ORDERED_ONLY.with(std::cell::Cell::get)
}

/// The laws of every element of `model`, in file order, worded as `convention` says.
fn constraints(
    model: &Model,
    raw: &ModelSpec,
    map: &SourceMap,
    names: &HashMap<&str, ElementId>,
    convention: Convention,
) -> Vec<Constraint> {
    let mut out = Vec::new();
    for (index, (name, raw_element)) in raw.elements.iter().enumerate() {
        let Some(&id) = names.get(name.as_str()) else {
            continue;
        };
        let element = model.element(id);
        let Some(first) = element.bonds.first().map(|b| b.index()) else {
            continue;
        };
        let (e, f) = (effort(first), flow(first));
        // Two-ports: the bond into the element and the bond out of it.
        let (port_in, port_out) = {
            let into = element
                .bonds
                .iter()
                .find(|b| model.bond(**b).to == id)
                .map(|b| b.index());
            let out_of = element
                .bonds
                .iter()
                .find(|b| model.bond(**b).from == id)
                .map(|b| b.index());
            (into.unwrap_or(first), out_of.unwrap_or(first))
        };
        let laws = element_laws(raw_element, (e, f), (port_in, port_out));
        for (field, text, law, early) in laws {
            let Some(text) = text else { continue };
            let Ok(expr) = expr::parse(&text) else {
                continue;
            };
            let span = map
                .elements
                .get(index)
                .and_then(|entry| entry.fields.iter().find(|f| f.name == field))
                .map(|f| f.string_content.unwrap_or(f.value_span))
                .unwrap_or(element.span);
            let (kind, keyword, field_word) = words(raw_element, field, convention, &element.kind);
            out.push(Constraint {
                element: id,
                field,
                who: format!("{kind} '{name}'"),
                field_word,
                keyword,
                text,
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

/// The laws an element's fields state about its bond's effort `e` and flow `f` (for a
/// two-port, about its ports' variables): `(field, its text, the law, checked early)`.
fn element_laws(
    raw_element: &ElementSpec,
    (e, f): (Var, Var),
    (port_in, port_out): (usize, usize),
) -> Vec<(&'static str, Option<String>, Law, bool)> {
    let value = |var, is_effort| Law::Value { var, is_effort };
    let ratio = |power, k| Law::Ratio {
        a: e,
        b: f,
        power,
        k,
    };
    let per_s = Dim::TIME.recip();
    let mut laws: Vec<(&'static str, Option<String>, Law, bool)> = Vec::new();
    match raw_element {
        ElementSpec::Se { effort: text } => {
            laws.push(("effort", Some(text.clone()), value(e, true), true));
        }
        ElementSpec::Sf { flow: text } => {
            laws.push(("flow", Some(text.clone()), value(f, false), true));
        }
        ElementSpec::I {
            inertance,
            flow: law,
            ..
        } => {
            laws.push(("inertance", inertance.clone(), ratio(1, per_s), false));
            laws.push(("flow", law.clone(), value(f, false), false));
        }
        ElementSpec::C {
            compliance,
            stiffness,
            effort: law,
            ..
        } => {
            laws.push((
                "compliance",
                compliance.clone(),
                ratio(-1, Dim::TIME),
                false,
            ));
            laws.push(("stiffness", stiffness.clone(), ratio(1, Dim::TIME), false));
            laws.push(("effort", law.clone(), value(e, true), false));
        }
        ElementSpec::TensionOnly {
            compliance,
            stiffness,
            ..
        } => {
            laws.push((
                "compliance",
                compliance.clone(),
                ratio(-1, Dim::TIME),
                false,
            ));
            laws.push(("stiffness", stiffness.clone(), ratio(1, Dim::TIME), false));
        }
        ElementSpec::R {
            resistance,
            effort: effort_law,
            flow: flow_law,
        } => {
            laws.push(("resistance", resistance.clone(), ratio(1, Dim::NONE), false));
            laws.push(("effort", effort_law.clone(), value(e, true), false));
            laws.push(("flow", flow_law.clone(), value(f, false), false));
        }
        ElementSpec::Conductance { conductance } => {
            laws.push((
                "conductance",
                Some(conductance.clone()),
                ratio(-1, Dim::NONE),
                false,
            ));
        }
        ElementSpec::TF { ratio: text } => {
            let (i, o) = (port_in, port_out);
            let two = |a, b| Law::Ratio {
                a,
                b,
                power: 1,
                k: Dim::NONE,
            };
            laws.push(("ratio", Some(text.clone()), two(effort(i), effort(o)), true));
            laws.push(("ratio", Some(text.clone()), two(flow(o), flow(i)), true));
        }
        ElementSpec::GY { ratio: text } | ElementSpec::ReciprocalGY { ratio: text } => {
            let power = if matches!(raw_element, ElementSpec::GY { .. }) {
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
            laws.push(("ratio", Some(text.clone()), two(effort(i), flow(o)), true));
            laws.push(("ratio", Some(text.clone()), two(effort(o), flow(i)), true));
        }
        ElementSpec::Friction {
            breakaway,
            coulomb,
            viscous,
            dead_band,
            stribeck,
            ..
        } => {
            laws.push(("breakaway", Some(breakaway.clone()), value(e, true), true));
            laws.push(("coulomb", Some(coulomb.clone()), value(e, true), true));
            laws.push(("dead_band", dead_band.clone(), value(f, false), true));
            laws.push(("stribeck", stribeck.clone(), value(f, false), true));
            laws.push(("viscous", viscous.clone(), ratio(1, Dim::NONE), false));
        }
        ElementSpec::FlowLimit { max_flow, .. } => {
            laws.push(("max_flow", Some(max_flow.clone()), value(f, false), true));
        }
        ElementSpec::Submodel { .. } | ElementSpec::Zero | ElementSpec::One => {}
    }
    laws
}

/// How the file names an element, its kind and one of its fields: `(inertia, I,
/// inertance)` in a bond graph, `(A-type, A-type, capacitance)` for the same law in a
/// linear graph (see [`crate::model::linear_graph::translate`] for which branch becomes
/// which element).
fn words(
    raw: &ElementSpec,
    field: &'static str,
    convention: Convention,
    kind: &ElementKind,
) -> (&'static str, &'static str, &'static str) {
    if convention == Convention::BondGraph {
        return (kind.description(), kind.keyword(), field);
    }
    let (branch, field_word) = match raw {
        // A linear graph's across variable is the bond graph's flow, its through the effort.
        ElementSpec::I { .. } if field == "flow" => ("A-type", "across law"),
        ElementSpec::I { .. } => ("A-type", "capacitance"),
        ElementSpec::C { .. } => (
            "T-type",
            match field {
                "compliance" => "inductance",
                "effort" => "through law",
                other => other,
            },
        ),
        ElementSpec::Conductance { .. } => ("D-type", "resistance"),
        ElementSpec::R { .. } if field == "effort" => ("D-type", "through law"),
        ElementSpec::R { .. } if field == "flow" => ("D-type", "across law"),
        ElementSpec::R { .. } => ("D-type", "conductance"),
        ElementSpec::Sf { .. } => ("across source", "value"),
        ElementSpec::Se { .. } => ("through source", "value"),
        ElementSpec::TF { .. } => ("transformer", field),
        ElementSpec::GY { .. } | ElementSpec::ReciprocalGY { .. } => ("gyrator", field),
        ElementSpec::Friction { .. } => ("friction contact", field),
        ElementSpec::TensionOnly { .. } => (
            "tension-only T-type",
            if field == "compliance" {
                "inductance"
            } else {
                field
            },
        ),
        ElementSpec::FlowLimit { .. }
        | ElementSpec::Submodel { .. }
        | ElementSpec::Zero
        | ElementSpec::One => (kind.description(), field),
    };
    (branch, branch, field_word)
}

/// A field of an element: the laws it gives are blamed together.
type Field = (ElementId, &'static str);

/// The one field whose laws, left out, leave every other law agreeing, where the problems
/// found blamed other fields (`blamed`): a checker with that field's laws checked last,
/// against the rest of the model (see the module documentation). `None` if there is no
/// such field, or more than one.
fn blame<'a>(
    constraints: &[Constraint],
    blamed: &[Field],
    run: &dyn Fn(Option<Field>) -> Checker<'a>,
) -> Option<Checker<'a>> {
    let mut fields: Vec<Field> = Vec::new();
    for c in constraints {
        if !fields.contains(&(c.element, c.field)) {
            fields.push((c.element, c.field));
        }
    }
    let mut alone = fields
        .iter()
        .filter(|field| run(Some(**field)).problems.is_empty());
    let field = *alone.next()?;
    if alone.next().is_some() || blamed == [field] {
        return None;
    }
    let mut checker = run(Some(field));
    let mut laws: Vec<Constraint> = constraints
        .iter()
        .filter(|c| (c.element, c.field) == field)
        .cloned()
        .collect();
    for early in [true, false] {
        checker.apply(&mut laws, early, usize::MAX);
    }
    (!checker.problems.is_empty()).then_some(checker)
}

/// In which order the laws are applied.
#[derive(Clone, Copy)]
enum Schedule {
    /// Every law as soon as its dimension is known, pass after pass: the same dimensions
    /// as [`Schedule::Ordered`] where the laws agree, at a cost linear in the model's size.
    Closure,
    /// Sources and two-ports first, then one law at a time in file order, each followed by
    /// all it lets the graph propagate: the order a reader checks in, which decides which
    /// law a disagreement is reported at.
    Ordered,
}

struct Checker<'a> {
    model: &'a Model,
    units: &'a HashMap<&'a str, (Dim, &'a str)>,
    /// Each storage element by its state's name (`q_spring`, or its `symbol:`).
    states: &'a HashMap<String, ElementId>,
    solver: Solver,
    problems: Vec<Diagnostic>,
    /// The field each problem of a law blames, in order: at most one problem per field.
    blamed: Vec<Field>,
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
        let id = *self.checker.states.get(name)?;
        let letter = match model.element(id).kind {
            ElementKind::Inertia(_) => "p",
            ElementKind::Nonlinear(ref n)
                if matches!(n.law, crate::model::NonlinearLaw::Inertia(_)) =>
            {
                "p"
            }
            _ => "q",
        };
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

    /// [`Schedule::Closure`]: passes over the pending laws, each applying every law whose
    /// dimension is known, and the power rule after each, until a pass learns nothing. Laws
    /// whose dimensions come from their parameters' units alone (most of them) apply in the
    /// first pass; later passes see only the laws that read a bond (`effort`, `q_X`).
    fn close(&mut self, constraints: &mut Vec<Constraint>) {
        loop {
            let pending = constraints.len();
            constraints.retain(|c| {
                let scope = Scope {
                    checker: self,
                    port: c.port,
                };
                match infer(&c.text, &c.expr, &scope) {
                    Ok(None) => true,
                    Ok(Some(dim)) => {
                        if let Some(problem) = self.enforce(c, dim) {
                            self.report(c, problem);
                        }
                        false
                    }
                    Err(mismatch) => {
                        self.report_mismatch(c, mismatch);
                        false
                    }
                }
            });
            if !self.problems.is_empty() {
                return;
            }
            let learnt = self.power_step();
            if constraints.len() == pending && !learnt {
                return;
            }
        }
    }

    /// [`Schedule::Ordered`].
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
                    let c = constraints.remove(index);
                    self.report_mismatch(&c, mismatch);
                    continue;
                }
            };
            let c = constraints.remove(index);
            applied += 1;
            if let Some(problem) = self.enforce(&c, dim) {
                self.report(&c, problem);
            }
        }
        applied > 0
    }

    /// Records a mismatch inside `c`'s expression, at its place in the expression.
    fn report_mismatch(&mut self, c: &Constraint, mismatch: Mismatch) {
        let span = Span::new(
            c.span.start + mismatch.span.start,
            c.span.start + mismatch.span.end,
        );
        let d = self.diagnostic(c, span, mismatch.message);
        self.report(c, d);
    }

    /// Records `problem` with `c`'s law, unless its field has a problem already.
    fn report(&mut self, c: &Constraint, problem: Diagnostic) {
        let field = (c.element, c.field);
        if !self.blamed.contains(&field) {
            self.blamed.push(field);
            self.problems.push(problem);
        }
    }

    /// Whether the file is a linear graph, whose words differ.
    fn linear_graph(&self) -> bool {
        self.convention == Convention::LinearGraph
    }

    /// What the file calls a bond's effort (or flow): a linear graph's through (across)
    /// variable.
    fn variable(&self, is_effort: bool) -> &'static str {
        match (self.linear_graph(), is_effort) {
            (false, true) => "effort",
            (false, false) => "flow",
            (true, true) => "through variable",
            (true, false) => "across variable",
        }
    }

    /// What the file calls a bond.
    fn bond_word(&self) -> &'static str {
        if self.linear_graph() {
            "branch"
        } else {
            "bond"
        }
    }

    /// Applies one constraint whose expression is in `dim`; the diagnostic if it disagrees.
    fn enforce(&mut self, c: &Constraint, dim: Dim) -> Option<Diagnostic> {
        match c.law {
            Law::Value { var, is_effort } => {
                if c.early
                    && let Some(message) = self.implausible(c, dim, is_effort)
                {
                    return Some(self.diagnostic(c, c.span, message));
                }
                match self
                    .solver
                    .set(var, dim, format!("the {} of the {}", c.field_word, c.who))
                {
                    Ok(_) => None,
                    Err(Conflict::Value(known)) => {
                        let message = format!(
                            "{} '{}' is in {} but the {}'s {} is in {} (from {})",
                            c.field_word,
                            c.text,
                            self.unit_of(c, dim),
                            self.bond_word(),
                            self.variable(is_effort),
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
                            c.field_word,
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
        let lg = self.linear_graph();
        let unit = |(u, _): (&str, &str)| parse_unit(u).unwrap_or(Dim::NONE);
        let as_effort = domain::DOMAINS
            .iter()
            .find(|d| unit(d.file_effort(lg)) == dim);
        let as_flow = domain::DOMAINS
            .iter()
            .find(|d| unit(d.file_flow(lg)) == dim);
        let kw = c.keyword;
        let article = article(kw);
        let needs = |is_effort: bool| with_article(self.variable(is_effort));
        match (is_effort, as_effort, as_flow) {
            (true, None, Some(d)) => Some(format!(
                "{} '{}' is in {}, a {}, where {article} {kw} needs {}: {}",
                c.field_word,
                c.text,
                self.unit_of(c, dim),
                d.file_flow(lg).1,
                needs(true),
                domain::effort_list(lg)
            )),
            (false, Some(d), None) => Some(format!(
                "{} '{}' is in {}, a {}, where {article} {kw} needs {}: {}",
                c.field_word,
                c.text,
                self.unit_of(c, dim),
                d.file_effort(lg).1,
                needs(false),
                domain::flow_list(lg)
            )),
            _ => None,
        }
    }

    /// `a C on a mechanical translational bond`, or what is known of the bond.
    fn context(&self, c: &Constraint, bond: usize) -> String {
        let kind = &self.model.element(c.element).kind;
        let kw = c.keyword;
        let article = article(kw);
        if matches!(
            kind,
            ElementKind::Transformer(_) | ElementKind::Gyrator(_) | ElementKind::Nonlinear(_)
        ) && self.model.element(c.element).bonds.len() == 2
        {
            return if self.linear_graph() {
                format!("{article} {kw} between its primary and secondary")
            } else {
                format!("{article} {kw} between these bonds")
            };
        }
        let on = self.bond_word();
        match self.domain(bond) {
            Some(d) => format!("{article} {kw} on a {} {on}", d.name),
            None => match (self.solver.get(effort(bond)), self.solver.get(flow(bond))) {
                (Some(e), Some(f)) => format!(
                    "{article} {kw} on a {on} with {} in {} and {} in {}",
                    self.variable(true),
                    readable(e),
                    self.variable(false),
                    readable(f)
                ),
                _ => format!("{article} {kw} here (as the laws around it make its {on})"),
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
            format!("{}: {message}", c.who),
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
            let why = if lg {
                "through times across variable being a power"
            } else {
                "effort times flow being a power"
            };
            let result = match (e, f) {
                (Some(e), None) if !(effort_is_t && e == temperature || lg && e == power) => {
                    self.solver.set(flow(bond), power.per(e), why)
                }
                (None, Some(f)) if !(flow_is_t && f == temperature || !lg && f == power) => {
                    self.solver.set(effort(bond), power.per(f), why)
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
                        "bond {from} -> {to} carries {} in {} and {} in {}, whose product {} is not a power (W)",
                        with_article(self.variable(true)),
                        readable(e),
                        with_article(self.variable(false)),
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

/// The article before an element's keyword: `an I`, `an Se`, `a C`, `an A-type`.
fn article(keyword: &str) -> &'static str {
    if keyword.starts_with(['I', 'R', 'S', 'A', 'E', 'O', 'a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

/// `an effort`, `a flow`, `a through variable`, `an across variable`.
fn with_article(variable: &str) -> String {
    format!("{} {variable}", article(variable))
}
