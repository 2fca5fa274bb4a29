//! Causality assignment: the sequential causality assignment procedure (SCAP).
//!
//! Causality decides, for every bond, which end imposes the effort and which the flow, and
//! so which equation computes which variable. It is what turns a bond graph into explicit
//! state equations, and what reveals the graph's trouble spots: storage that cannot be
//! independent (derivative causality), and resistor networks that must be solved
//! simultaneously (algebraic loops).
//!
//! # Arguments
//! A [`Model`] and the [`Law`] of each element in the mode being derived.
//!
//! # Returns
//! A [`Causality`]: the causal stroke of every bond, the storage elements left in
//! derivative causality (to be merged by the equation builder), and the elements whose
//! causality had to be chosen arbitrarily (the seeds of algebraic loops).
//!
//! # Errors
//! [`DiagnosticKind::CausalConflict`] when two sources or constraints impose the same
//! variable (two velocity sources on one 1-junction), naming the junction and the elements.
//!
//! # Complexity
//! Each bond is assigned once and each assignment re-examines the two elements at its ends,
//! so the procedure is `O(Σ deg²)` over junctions: linear in the model size for bounded
//! junction degrees.
//!
//! # Example
//! ```
//! use bondgraph_core::{causality, laws, model};
//! let model = bondgraph_ron::model::load_str("m.ron", r#"Model(name: "m",
//!     parameters: {"m": (value: 1.0), "k": (value: 4.0)},
//!     elements: {"j": One, "mass": I(inertance: "m"), "spring": C(stiffness: "k")},
//!     bonds: [("j", "mass"), ("j", "spring")])"#).unwrap();
//! let laws = laws::plain_laws(&model);
//! let causal = causality::assign(&model, &laws).unwrap();
//! assert!(causal.dependent.is_empty());
//! ```

pub(crate) mod trace;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::laws::Law;
use crate::model::AtElement;
use crate::model::{BondId, ElementId, ElementKind, Model, NonlinearLaw};

pub use trace::{CausalityTrace, Decision, Propagation, Rule, Step};

/// Which end of a bond receives the effort: the end where the causal stroke is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stroke {
    /// The stroke is at the bond's tail (`from`): `from` receives the effort.
    AtFrom,
    /// The stroke is at the bond's head (`to`): `to` receives the effort.
    AtTo,
}

/// The causality of one storage element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StorageCausality {
    /// Independent: integrates its input, contributes a state.
    Integral,
    /// Dependent: its state is fixed by others; merged away by the equation builder.
    Derivative,
}

/// A complete causal assignment of one mode.
#[derive(Clone, Debug, PartialEq)]
pub struct Causality {
    /// The causal stroke of every bond, indexed by [`BondId`].
    pub strokes: Vec<Stroke>,
    /// Storage elements in derivative causality, in element order.
    pub dependent: Vec<ElementId>,
    /// Elements (resistors, or junctions for junction-to-junction bonds) whose causality was
    /// chosen arbitrarily because nothing forced it: where algebraic loops start.
    pub arbitrary: Vec<ElementId>,
}

impl Causality {
    /// The element that receives the effort of `bond`.
    pub fn effort_receiver(&self, model: &Model, bond: BondId) -> ElementId {
        let b = model.bond(bond);
        match self.strokes[bond.index()] {
            Stroke::AtFrom => b.from,
            Stroke::AtTo => b.to,
        }
    }

    /// The element that imposes the effort of `bond` (and receives its flow).
    pub fn effort_giver(&self, model: &Model, bond: BondId) -> ElementId {
        let receiver = self.effort_receiver(model, bond);
        model.bond(bond).other(receiver)
    }

    /// Whether `element` receives the effort of `bond`.
    pub fn receives_effort(&self, model: &Model, bond: BondId, element: ElementId) -> bool {
        self.effort_receiver(model, bond) == element
    }

    /// The causality of storage `element` (`None` if it is not storage in `laws`).
    pub fn storage(&self, element: ElementId, laws: &[Law]) -> Option<StorageCausality> {
        laws[element.index()].is_storage().then(|| {
            if self.dependent.contains(&element) {
                StorageCausality::Derivative
            } else {
                StorageCausality::Integral
            }
        })
    }
}

/// Why a model with ports has no causality of its own: the outside its ports join is
/// missing.
fn open_ports(model: &Model, first: &crate::model::Port) -> Diagnostic {
    let names: Vec<String> = model
        .ports()
        .iter()
        .map(|p| format!("'{}'", p.name))
        .collect();
    Diagnostic::new(
        DiagnosticKind::Submodel,
        format!(
            "model '{}' is a part with open ports ({}): it has equations only where a model \
             uses it and bonds its ports",
            model.name(),
            names.join(", ")
        ),
    )
    .at_location(model.source().locate(first.span))
    .note("use it as an element of another model: \"name\": Submodel(file: \"...\"), bonded to \"name.port\"")
}

/// Assigns causality to every bond by SCAP: sources first, then storage preferring integral
/// causality, then resistors, then whatever is left, propagating through junctions,
/// transformers and gyrators after each choice. See the module documentation.
pub fn assign(model: &Model, laws: &[Law]) -> Result<Causality> {
    assign_traced(model, laws).map(|(causality, _)| causality)
}

/// Assigns causality as [`assign`] does, and returns the record of every decision it made
/// on the way ([`CausalityTrace`]): the same run, so the trace's strokes are the causality's.
///
/// # Errors
/// As [`assign`].
pub fn assign_traced(model: &Model, laws: &[Law]) -> Result<(Causality, CausalityTrace)> {
    if let Some(port) = model.ports().first() {
        return Err(open_ports(model, port).into());
    }
    let mut scap = Scap::new(model, laws);

    for element in model.element_ids() {
        let law = &laws[element.index()];
        if law.is_source() {
            let bond = single_bond(model, element);
            // Effort sources (and slack storage, which imposes zero effort) give effort.
            let receiver = if law.gives_effort() {
                model.bond(bond).other(element)
            } else {
                element
            };
            scap.impose(bond, receiver, element, Decision::Source)?;
        }
    }

    // A resistor whose law is known one way only (`flow: g(effort)` that cannot be solved
    // for the effort) has its causality fixed by that law, like a source.
    for element in model.element_ids() {
        let Some(fixed) = fixed_resistor_causality(&laws[element.index()]) else {
            continue;
        };
        let bond = single_bond(model, element);
        let receiver = match fixed {
            Fixed::Resistance => model.bond(bond).other(element),
            Fixed::Conductance => element,
        };
        if let Err(error) = scap.impose(bond, receiver, element, Decision::OneWayResistor) {
            return Err(explain_fixed(model, laws, error));
        }
    }

    let mut dependent = Vec::new();
    for element in storage_order(model, laws) {
        let law = &laws[element.index()];
        let bond = single_bond(model, element);
        let integral_receiver = if law.gives_effort() {
            model.bond(bond).other(element)
        } else {
            element
        };
        match scap.strokes[bond.index()] {
            None => scap
                .impose(bond, integral_receiver, element, Decision::Integral)
                .map_err(|e| explain_fixed(model, laws, e))?,
            Some(_) if scap.receiver(bond) == integral_receiver => {
                scap.record(bond, element, Decision::Integral);
            }
            Some(_) => {
                scap.record(bond, element, Decision::Derivative);
                dependent.push(element);
            }
        }
    }

    // Resistors whose causality sources and storage have already forced.
    for element in model.element_ids() {
        let law = &laws[element.index()];
        if is_resistor(law) && fixed_resistor_causality(law).is_none() {
            let bond = single_bond(model, element);
            if scap.strokes[bond.index()].is_some() {
                scap.record(bond, element, Decision::ResistorForced);
            }
        }
    }

    // What nothing forced is chosen: resistors (resistance causality first), then free
    // bonds. A choice can make a later junction impossible to satisfy, so the choices are
    // searched depth-first and undone when they lead to a conflict.
    let mut arbitrary = Vec::new();
    let mut budget = SEARCH_BUDGET;
    scap.complete(&mut arbitrary, &mut budget)
        .map_err(|e| explain_fixed(model, laws, e))?;
    dependent.sort();

    let trace = CausalityTrace {
        steps: std::mem::take(&mut scap.steps),
    };
    let causality = Causality {
        strokes: scap
            .strokes
            .into_iter()
            .map(|s| s.expect("every bond was assigned"))
            .collect(),
        dependent,
        arbitrary,
    };
    Ok((causality, trace))
}

/// Whether `law` is a resistor's (linear, or nonlinear).
fn is_resistor(law: &Law) -> bool {
    matches!(law, Law::Resistor { .. })
        || matches!(law.nonlinear(), Some(NonlinearLaw::Resistor(_)))
}

/// The causality a one-way resistor law forces.
enum Fixed {
    /// Only `effort: f(flow)` is known: the resistor must receive its flow.
    Resistance,
    /// Only `flow: g(effort)` is known: the resistor must receive its effort.
    Conductance,
}

fn fixed_resistor_causality(law: &Law) -> Option<Fixed> {
    match law.nonlinear()? {
        NonlinearLaw::Resistor(r) => match (&r.effort, &r.flow) {
            (Some(_), None) => Some(Fixed::Resistance),
            (None, Some(_)) => Some(Fixed::Conductance),
            _ => None,
        },
        _ => None,
    }
}

/// A conflict that involves a resistor with a one-way law says why its causality is fixed.
fn explain_fixed(model: &Model, laws: &[Law], mut error: Diagnostics) -> Diagnostics {
    for element in model.element_ids() {
        let Some(fixed) = fixed_resistor_causality(&laws[element.index()]) else {
            continue;
        };
        let name = &model.element(element).name;
        let quoted = format!("'{name}'");
        for diagnostic in &mut error.0 {
            if diagnostic.message.contains(&quoted) {
                diagnostic.notes.push(match fixed {
                    Fixed::Conductance => format!(
                        "'{name}' has its law as flow: f(effort), which could not be solved for the effort, so it needs its effort given (conductance causality); write it as effort: f(flow) too, or let the graph give it an effort"
                    ),
                    Fixed::Resistance => format!(
                        "'{name}' has its law as effort: f(flow), which could not be solved for the flow, so it needs its flow given (resistance causality); write it as flow: f(effort) too, or let the graph give it a flow"
                    ),
                });
            }
        }
    }
    error
}

/// The storage elements in the order integral causality is offered to them: element order
/// for a bond graph; for a linear graph, the normal tree's independent storage first
/// ([`crate::normal_tree`]), so that the states are the tree's where dependent storage
/// leaves a choice (which of two springs in series keeps its state).
fn storage_order(model: &Model, laws: &[Law]) -> Vec<ElementId> {
    let mut order: Vec<ElementId> = match (
        &model.linear_graph,
        crate::normal_tree::of_mode(model, laws),
    ) {
        (Some(graph), Some(tree)) => tree.storage_priority(graph),
        _ => Vec::new(),
    };
    let mut listed = vec![false; model.elements.len()];
    for element in &order {
        listed[element.index()] = true;
    }
    order.extend(model.element_ids().filter(|e| !listed[e.index()]));
    order.retain(|e| laws[e.index()].is_storage());
    order
}

/// How many arbitrary choices the search may try before it reports the first conflict it
/// met; real models need a handful.
const SEARCH_BUDGET: usize = 10_000;

/// The only bond of a one-port element (validated to exist).
fn single_bond(model: &Model, element: ElementId) -> BondId {
    model.element(element).bonds[0]
}

/// The propagation engine.
struct Scap<'a> {
    model: &'a Model,
    laws: &'a [Law],
    strokes: Vec<Option<Stroke>>,
    /// The element whose choice led to each bond's assignment, for naming conflicts.
    origin: Vec<Option<ElementId>>,
    queue: Vec<ElementId>,
    /// The decisions so far ([`trace`]).
    steps: Vec<Step>,
    /// The step that stroked each bond.
    bond_step: Vec<Option<usize>>,
}

impl<'a> Scap<'a> {
    fn new(model: &'a Model, laws: &'a [Law]) -> Self {
        Self {
            model,
            laws,
            strokes: vec![None; model.bonds.len()],
            origin: vec![None; model.bonds.len()],
            queue: Vec::new(),
            steps: Vec::new(),
            bond_step: vec![None; model.bonds.len()],
        }
    }

    /// The stroke that makes `receiver` receive the effort of `bond`.
    fn stroke_for(&self, bond: BondId, receiver: ElementId) -> Stroke {
        if receiver == self.model.bond(bond).from {
            Stroke::AtFrom
        } else {
            Stroke::AtTo
        }
    }

    /// Records a decision about `element`'s bond, which an earlier step already stroked.
    fn record(&mut self, bond: BondId, element: ElementId, decision: Decision) {
        self.steps.push(Step {
            element,
            decision,
            bond,
            stroke: self.strokes[bond.index()].expect("recorded bonds are stroked"),
            new: false,
            earlier: self.bond_step[bond.index()],
            propagated: Vec::new(),
        });
    }

    fn receiver(&self, bond: BondId) -> ElementId {
        let b = self.model.bond(bond);
        match self.strokes[bond.index()] {
            Some(Stroke::AtFrom) => b.from,
            _ => b.to,
        }
    }

    /// Assigns `bond` so that `receiver` receives its effort, then propagates; the decision
    /// is `origin`'s, recorded as one step of the trace.
    fn impose(
        &mut self,
        bond: BondId,
        receiver: ElementId,
        origin: ElementId,
        decision: Decision,
    ) -> Result<()> {
        self.steps.push(Step {
            element: origin,
            decision,
            bond,
            stroke: self.stroke_for(bond, receiver),
            new: self.strokes[bond.index()].is_none(),
            earlier: self.bond_step[bond.index()],
            propagated: Vec::new(),
        });
        self.set(bond, receiver, origin, None)?;
        self.propagate()
    }

    /// The next choice nothing forced: a free resistor (resistance causality first, then
    /// conductance), else a free bond (effort to its head first).
    fn next_choice(&self) -> Option<(BondId, [ElementId; 2], ElementId, Decision)> {
        let model = self.model;
        let open = |element: ElementId| {
            is_resistor(&self.laws[element.index()])
                && self.strokes[single_bond(model, element).index()].is_none()
        };
        // A resistor that only one causality allows at the model's values is chosen first,
        // in that causality: a zero resistance (a series resistor at its no-effect value)
        // can give an effort, e = 0·f, but not take one, and an infinite one (a linear
        // graph's zero resistance, across = 0·through) the other way round.
        let resistor = model
            .element_ids()
            .filter(|&e| open(e))
            .find_map(|element| {
                let bond = single_bond(model, element);
                let other = model.bond(bond).other(element);
                match &self.laws[element.index()] {
                    Law::Resistor { resistance, .. } => {
                        let value = model.evaluate(resistance);
                        if value == 0.0 {
                            Some([other, element])
                        } else if value.is_infinite() {
                            Some([element, other])
                        } else {
                            None
                        }
                    }
                    _ => None,
                }
                .map(|receivers| (bond, receivers, element, Decision::ResistorChosen))
            })
            .or_else(|| {
                model.element_ids().find(|&e| open(e)).map(|element| {
                    let bond = single_bond(model, element);
                    (
                        bond,
                        [model.bond(bond).other(element), element],
                        element,
                        Decision::ResistorChosen,
                    )
                })
            });
        resistor.or_else(|| {
            model.bond_ids().find_map(|bond| {
                let b = model.bond(bond);
                self.strokes[bond.index()].is_none().then_some((
                    bond,
                    [b.to, b.from],
                    b.from,
                    Decision::BondChosen,
                ))
            })
        })
    }

    /// Completes the assignment by depth-first search over the remaining choices; every
    /// junction is checked once all bonds are assigned, and a choice that leads to a conflict
    /// is undone and the alternative tried.
    fn complete(&mut self, arbitrary: &mut Vec<ElementId>, budget: &mut usize) -> Result<()> {
        let Some((bond, receivers, origin, decision)) = self.next_choice() else {
            for element in self.model.element_ids() {
                self.check_complete(element)?;
            }
            return Ok(());
        };
        let saved = (
            self.strokes.clone(),
            self.origin.clone(),
            arbitrary.len(),
            self.bond_step.clone(),
            self.steps.len(),
        );
        let mut first_error = None;
        for receiver in receivers {
            if *budget == 0 {
                break;
            }
            *budget -= 1;
            arbitrary.push(origin);
            let attempt = self
                .impose(bond, receiver, origin, decision.clone())
                .and_then(|()| self.complete(arbitrary, budget));
            match attempt {
                Ok(()) => return Ok(()),
                Err(error) => {
                    (self.strokes, self.origin) = (saved.0.clone(), saved.1.clone());
                    self.bond_step.clone_from(&saved.3);
                    self.steps.truncate(saved.4);
                    self.steps.push(Step {
                        element: origin,
                        decision: Decision::Undone {
                            conflict: error.first().message.clone(),
                        },
                        bond,
                        stroke: self.stroke_for(bond, receiver),
                        new: false,
                        earlier: None,
                        propagated: Vec::new(),
                    });
                    first_error.get_or_insert(error);
                    arbitrary.truncate(saved.2);
                    self.queue.clear();
                }
            }
        }
        Err(first_error.unwrap_or_else(|| self.search_exhausted(origin)))
    }

    fn search_exhausted(&self, element: ElementId) -> Diagnostics {
        let name = &self.model.element(element).name;
        Diagnostic::new(
            DiagnosticKind::CausalConflict,
            format!(
                "no causal assignment found after {SEARCH_BUDGET} choices; the search stopped at '{name}'"
            ),
        )
        .at_element(self.model, element)
        .element(name.clone())
        .note("the graph's resistor network leaves too many choices open; check it for redundant junctions")
        .into()
    }

    /// Strokes `bond` so that `receiver` receives its effort; `via` is the junction or
    /// two-port whose rule forced it, when it was propagated rather than decided.
    fn set(
        &mut self,
        bond: BondId,
        receiver: ElementId,
        origin: ElementId,
        via: Option<(ElementId, Rule)>,
    ) -> Result<()> {
        let b = *self.model.bond(bond);
        let stroke = self.stroke_for(bond, receiver);
        match self.strokes[bond.index()] {
            Some(existing) if existing == stroke => Ok(()),
            Some(_) => Err(self.conflict_on_bond(bond, origin)),
            None => {
                self.strokes[bond.index()] = Some(stroke);
                self.origin[bond.index()] = Some(origin);
                self.bond_step[bond.index()] = self.steps.len().checked_sub(1);
                if let (Some((through, rule)), Some(step)) = (via, self.steps.last_mut()) {
                    step.propagated.push(Propagation {
                        bond,
                        stroke,
                        through,
                        rule,
                    });
                }
                self.queue.push(b.from);
                self.queue.push(b.to);
                Ok(())
            }
        }
    }

    fn propagate(&mut self) -> Result<()> {
        while let Some(element) = self.queue.pop() {
            self.examine(element)?;
        }
        Ok(())
    }

    /// Applies the causal rule of `element` to its bonds.
    fn examine(&mut self, element: ElementId) -> Result<()> {
        let model = self.model;
        let bonds = &model.element(element).bonds;
        let law = &self.laws[element.index()];
        let two_port = matches!(law, Law::Transformer(_) | Law::Gyrator(_))
            || matches!(
                law.nonlinear(),
                Some(NonlinearLaw::Transformer(_) | NonlinearLaw::Gyrator(_))
            );
        if two_port {
            return self.examine_two_port(element);
        }
        match self.laws[element.index()] {
            Law::ZeroJunction | Law::OneJunction => {
                // A 0-junction has exactly one bond bringing the effort in; a 1-junction
                // has exactly one bond on which it gives the effort (bringing the flow in).
                let zero = matches!(self.laws[element.index()], Law::ZeroJunction);
                let is_unique = |s: &Self, bond: BondId| (s.receiver(bond) == element) == zero;
                let mut unique = Vec::new();
                let mut open = Vec::new();
                for &bond in bonds {
                    if self.strokes[bond.index()].is_none() {
                        open.push(bond);
                    } else if is_unique(self, bond) {
                        unique.push(bond);
                    }
                }
                if unique.len() > 1 {
                    return Err(self.junction_conflict(element, &unique));
                }
                let origin = unique
                    .first()
                    .and_then(|b| self.origin[b.index()])
                    .unwrap_or(element);
                if unique.len() == 1 {
                    let rule = if zero {
                        Rule::CommonEffort { from: unique[0] }
                    } else {
                        Rule::CommonFlow { from: unique[0] }
                    };
                    for bond in open {
                        let receiver = if zero {
                            model.bond(bond).other(element)
                        } else {
                            element
                        };
                        self.set(bond, receiver, origin, Some((element, rule)))?;
                    }
                } else if open.len() == 1 {
                    let bond = open[0];
                    let receiver = if zero {
                        element
                    } else {
                        model.bond(bond).other(element)
                    };
                    let origin = bonds
                        .iter()
                        .find_map(|b| self.origin[b.index()])
                        .unwrap_or(element);
                    let rule = if zero {
                        Rule::LastSetsEffort
                    } else {
                        Rule::LastSetsFlow
                    };
                    self.set(bond, receiver, origin, Some((element, rule)))?;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The causal rule of a transformer (effort passes through) or gyrator (effort turns
    /// into flow).
    fn examine_two_port(&mut self, element: ElementId) -> Result<()> {
        let model = self.model;
        let bonds = &model.element(element).bonds;
        let law = &self.laws[element.index()];
        let transformer = matches!(law, Law::Transformer(_))
            || matches!(law.nonlinear(), Some(NonlinearLaw::Transformer(_)));
        let (a, b) = (bonds[0], bonds[1]);
        for (known, open) in [(a, b), (b, a)] {
            if self.strokes[known.index()].is_some() && self.strokes[open.index()].is_none() {
                let known_in = self.receiver(known) == element;
                // A transformer passes effort through (one side in, the other out);
                // a gyrator turns effort into flow (both sides alike).
                let open_in = if transformer { !known_in } else { known_in };
                let receiver = if open_in {
                    element
                } else {
                    model.bond(open).other(element)
                };
                let origin = self.origin[known.index()].unwrap_or(element);
                let rule = if transformer {
                    Rule::Transformer { from: known }
                } else {
                    Rule::Gyrator { from: known }
                };
                self.set(open, receiver, origin, Some((element, rule)))?;
            }
        }
        if let (Some(_), Some(_)) = (self.strokes[a.index()], self.strokes[b.index()]) {
            let a_in = self.receiver(a) == element;
            let b_in = self.receiver(b) == element;
            if (a_in != b_in) != transformer {
                return Err(self.two_port_conflict(element, a, b));
            }
        }
        Ok(())
    }

    /// After assignment, a junction with no bond setting its common variable is a conflict.
    fn check_complete(&self, element: ElementId) -> Result<()> {
        let zero = match self.laws[element.index()] {
            Law::ZeroJunction => true,
            Law::OneJunction => false,
            _ => return Ok(()),
        };
        let bonds = &self.model.element(element).bonds;
        let unique = bonds
            .iter()
            .filter(|&&b| (self.receiver(b) == element) == zero)
            .count();
        if unique != 1 {
            let all: Vec<BondId> = bonds.clone();
            return Err(self.junction_conflict(element, &all));
        }
        Ok(())
    }

    fn describe_origin(&self, origin: Option<ElementId>) -> String {
        match origin {
            Some(e) => {
                let element = self.model.element(e);
                format!(
                    "{} '{}'",
                    law_description(&self.laws[e.index()], &element.kind),
                    element.name
                )
            }
            None => "an arbitrary choice".to_string(),
        }
    }

    fn junction_conflict(&self, junction: ElementId, bonds: &[BondId]) -> Diagnostics {
        let origins: Vec<String> = bonds
            .iter()
            .map(|b| self.describe_origin(self.origin[b.index()]))
            .collect();
        self.junction_conflict_between(junction, origins)
    }

    /// A junction whose common variable is imposed by each of `origins` (described).
    fn junction_conflict_between(
        &self,
        junction: ElementId,
        mut origins: Vec<String>,
    ) -> Diagnostics {
        let model = self.model;
        let name = &model.element(junction).name;
        let zero = matches!(self.laws[junction.index()], Law::ZeroJunction);
        let (what, variable) = if zero {
            ("0-junction", "effort")
        } else {
            ("1-junction", "flow")
        };
        origins.dedup();
        let message = if origins.len() >= 2 {
            format!(
                "causal conflict at {what} '{name}': its {variable} is imposed by both {}",
                origins.join(" and ")
            )
        } else {
            format!("causal conflict at {what} '{name}': no bond can set its common {variable}")
        };
        Diagnostic::new(DiagnosticKind::CausalConflict, message)
            .at_element(model, junction)
            .element(name.clone())
            .note(format!(
                "a {what} needs exactly one bond that sets its {variable}; two sources of \
                 {variable} on it (or constraints acting as such) contradict each other"
            ))
            .into()
    }

    fn two_port_conflict(&self, element: ElementId, a: BondId, b: BondId) -> Diagnostics {
        let name = &self.model.element(element).name;
        Diagnostic::new(
            DiagnosticKind::CausalConflict,
            format!(
                "causal conflict at '{name}': {} and {} impose incompatible causality on it",
                self.describe_origin(self.origin[a.index()]),
                self.describe_origin(self.origin[b.index()])
            ),
        )
        .at_element(self.model, element)
        .element(name.clone())
        .into()
    }

    fn conflict_on_bond(&self, bond: BondId, origin: ElementId) -> Diagnostics {
        let model = self.model;
        let b = model.bond(bond);
        let earlier = self.describe_origin(self.origin[bond.index()]);
        let later = self.describe_origin(Some(origin));
        // A source on a junction whose common variable is already imposed (two velocity
        // sources on one 1-junction): the conflict is the junction's.
        let current = self.receiver(bond);
        let wanted = b.other(current);
        if let Some(junction) = [b.from, b.to].into_iter().find(|&e| e != origin)
            && let zero @ (Law::ZeroJunction | Law::OneJunction) = &self.laws[junction.index()]
            && (wanted == junction) == matches!(zero, Law::ZeroJunction)
            && earlier != later
        {
            return self.junction_conflict_between(junction, vec![earlier, later]);
        }
        let concerned = if matches!(
            self.laws[b.from.index()],
            Law::ZeroJunction | Law::OneJunction
        ) {
            b.to
        } else {
            b.from
        };
        Diagnostic::new(
            DiagnosticKind::CausalConflict,
            format!(
                "causal conflict on bond {}: {earlier} and {later} both impose its causality",
                model.bond_label(bond)
            ),
        )
        .at_location(model.locate_bond(bond))
        .element(model.element(concerned).name.clone())
        .note("two sources (or constraints) fight over one variable; remove one or insert a compliance or resistor between them")
        .into()
    }
}

/// How an element acts in this mode, for messages: a switching element is described by
/// its mode ("stuck friction contact"), a plain one by its kind.
pub fn law_description(law: &Law, kind: &ElementKind) -> &'static str {
    match (kind, law) {
        (ElementKind::Friction(_), Law::FlowSource(_)) => "stuck friction contact",
        (ElementKind::Friction(_), _) => "slipping friction contact",
        (ElementKind::TensionOnly(_), Law::SlackStorage) => "slack tension-only element",
        (ElementKind::FlowLimit(_), Law::FlowSource(_)) => "limiting flow limit",
        (ElementKind::FlowLimit(_), _) => "open flow limit",
        (_, Law::EffortSource(_)) => "effort source",
        (_, Law::FlowSource(_)) => "flow source",
        _ => kind.description(),
    }
}
