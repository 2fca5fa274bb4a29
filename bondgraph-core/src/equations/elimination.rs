//! From causal bond graph to every bond variable as an affine function of the states.
//!
//! Causality gives every bond effort and flow exactly one defining equation: the element
//! that imposes it computes it from what the element receives. Sorting those equations by
//! dependency (strongly connected components of the "uses" graph) evaluates them in one
//! pass; a component with more than one variable is an algebraic loop, a small linear system
//! solved symbolically by Gaussian elimination.
//!
//! # Arguments
//! The model, the laws of the mode, its causality and the numbering of its states and
//! dependent storage.
//!
//! # Returns
//! The effort and flow of every bond as [`LinearForm`]s over [`Var::State`],
//! [`Var::Input`], [`Var::Dependent`] and [`Var::Constant`], and the algebraic loops solved.
//!
//! # Errors
//! [`DiagnosticKind::SingularLoop`] when a loop's system is singular,
//! [`DiagnosticKind::InvalidValue`] when a resistor must set a flow but has zero resistance.
//!
//! # Complexity
//! Linear in the number of bonds for loop-free graphs (each definition is substituted once);
//! `O(k³)` symbolic operations for a loop of `k` variables.

use petgraph::algo::tarjan_scc;
use petgraph::graph::DiGraph;

use crate::causality::Causality;
use crate::diagnostics::{Diagnostic, DiagnosticKind, Result};
use crate::laws::Law;
use crate::linear::{LinearForm, Var};
use crate::model::AtElement;
use crate::model::{BondId, ElementId, Model, NonlinearLaw};
use crate::symbolic::RatFunc;

/// The effort variable of `bond`.
pub(crate) fn effort(bond: BondId) -> Var {
    Var::Bond(2 * bond.0)
}

/// The flow variable of `bond`.
pub(crate) fn flow(bond: BondId) -> Var {
    Var::Bond(2 * bond.0 + 1)
}

/// Picks one variable of a bond: [`effort`] or [`flow`].
type BondVariable = fn(BondId) -> Var;

/// The numbering of the mode's states and dependent storage, by element.
pub(crate) struct Numbering {
    /// `Some(i)` if the element contributes state `i` before merging.
    pub state: Vec<Option<u32>>,
    /// `Some(i)` if the element is the `i`-th dependent storage element.
    pub dependent: Vec<Option<u32>>,
    /// `Some(i)` if the element has a nonlinear law whose outputs are the auxiliary
    /// variables from `i` on ([`crate::equations::nonlinear`]).
    pub auxiliary: Vec<Option<u32>>,
}

/// An algebraic loop that was solved, by the elements whose equations formed it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AlgebraicLoop {
    /// The elements whose equations form the loop, in element order.
    pub elements: Vec<ElementId>,
}

/// Every bond variable solved, and the loops met on the way.
pub(crate) struct Solved {
    /// Effort (index `2b`) and flow (`2b + 1`) of every bond.
    pub bond_vars: Vec<LinearForm>,
    pub loops: Vec<AlgebraicLoop>,
}

fn ratio(n: i64) -> RatFunc {
    RatFunc::integer(n)
}

/// Builds the defining equation of every bond variable and solves them all.
pub(crate) fn solve(
    model: &Model,
    laws: &[Law],
    causal: &Causality,
    numbering: &Numbering,
) -> Result<Solved> {
    let definitions = define(model, laws, causal, numbering)?;
    let variable_count = definitions.len();

    // Edges from each variable to the variables its definition uses.
    let mut graph = DiGraph::<(), ()>::with_capacity(variable_count, 2 * variable_count);
    for _ in 0..variable_count {
        graph.add_node(());
    }
    for (index, (_, definition)) in definitions.iter().enumerate() {
        for (var, _) in definition.terms() {
            if let Var::Bond(used) = var {
                graph.add_edge((index as u32).into(), (*used).into(), ());
            }
        }
    }

    let mut solved: Vec<Option<LinearForm>> = vec![None; variable_count];
    let mut loops = Vec::new();
    // Tarjan yields components in reverse topological order of the "uses" edges: every
    // component comes after the components it uses.
    for component in tarjan_scc(&graph) {
        let members: Vec<u32> = component.iter().map(|n| n.index() as u32).collect();
        let is_loop = members.len() > 1
            || definitions[members[0] as usize]
                .1
                .get(Var::Bond(members[0]))
                .is_some();
        if !is_loop {
            let index = members[0] as usize;
            solved[index] = Some(substitute_solved(&definitions[index].1, &solved));
            continue;
        }
        if let Some(error) = loop_through_feedback(model, laws, numbering, &definitions, &members) {
            return Err(error);
        }
        let solution = solve_loop(model, &definitions, &members, &solved)?;
        for (member, form) in members.iter().zip(solution) {
            solved[*member as usize] = Some(form);
        }
        let mut elements: Vec<ElementId> =
            members.iter().map(|m| definitions[*m as usize].0).collect();
        elements.sort();
        elements.dedup();
        loops.push(AlgebraicLoop { elements });
    }

    Ok(Solved {
        bond_vars: solved
            .into_iter()
            .map(|s| s.expect("every variable lies in some component"))
            .collect(),
        loops,
    })
}

fn substitute_solved(form: &LinearForm, solved: &[Option<LinearForm>]) -> LinearForm {
    form.substitute(|var| match var {
        Var::Bond(i) => solved[i as usize].clone(),
        _ => None,
    })
}

/// Solves the linear system of one algebraic loop by Gaussian elimination.
fn solve_loop(
    model: &Model,
    definitions: &[(ElementId, LinearForm)],
    members: &[u32],
    solved: &[Option<LinearForm>],
) -> Result<Vec<LinearForm>> {
    // Each equation as `form = 0` with the loop's variables still symbolic:
    // var - definition(var) = 0.
    let mut equations: Vec<LinearForm> = members
        .iter()
        .map(|&m| {
            let mut equation = LinearForm::var(Var::Bond(m));
            let definition = substitute_solved(&definitions[m as usize].1, solved);
            equation.add_scaled(&definition, &RatFunc::integer(-1));
            equation
        })
        .collect();

    // Forward elimination: variable k is expressed from equation k.
    let count = members.len();
    for k in 0..count {
        let unknown = Var::Bond(members[k]);
        let Some(pivot_row) = (k..count).find(|&r| equations[r].get(unknown).is_some()) else {
            return Err(singular_loop(model, definitions, members));
        };
        equations.swap(k, pivot_row);
        let pivot = equations[k].coefficient(unknown);
        let normalised = equations[k].scaled(&pivot.inv().expect("pivot is non-zero"));
        equations[k] = normalised;
        for r in 0..count {
            if r == k {
                continue;
            }
            let factor = equations[r].coefficient(unknown);
            if !factor.is_zero() {
                let pivot_equation = equations[k].clone();
                equations[r].add_scaled(&pivot_equation, &-factor);
            }
        }
    }
    // Equation k now reads: member_k + rest_k = 0, with rest free of loop variables.
    Ok((0..count)
        .map(|k| {
            let mut rest = equations[k].clone();
            rest.take(Var::Bond(members[k]));
            rest.scaled(&RatFunc::integer(-1))
        })
        .collect())
}

fn singular_loop(
    model: &Model,
    definitions: &[(ElementId, LinearForm)],
    members: &[u32],
) -> crate::diagnostics::Diagnostics {
    let mut elements: Vec<ElementId> = members.iter().map(|m| definitions[*m as usize].0).collect();
    elements.sort();
    elements.dedup();
    let names: Vec<String> = elements
        .iter()
        .map(|e| format!("'{}'", model.element(*e).name))
        .collect();
    Diagnostic::new(
        DiagnosticKind::SingularLoop,
        format!(
            "the algebraic loop through {} has no unique solution (its equations are singular)",
            names.join(", ")
        ),
    )
    .at_element(model, elements[0])
    .element(model.element(elements[0]).name.clone())
    .note("the loop's resistors, transformers or gyrators cancel each other; check their values and bond directions")
    .into()
}

/// Writes the defining equation of every bond variable, per the causality.
fn define(
    model: &Model,
    laws: &[Law],
    causal: &Causality,
    numbering: &Numbering,
) -> Result<Vec<(ElementId, LinearForm)>> {
    let mut definitions: Vec<Option<(ElementId, LinearForm)>> = vec![None; 2 * model.bonds.len()];
    let mut define = |var: Var, element: ElementId, form: LinearForm| {
        let Var::Bond(index) = var else {
            unreachable!("only bond variables are defined")
        };
        debug_assert!(
            definitions[index as usize].is_none(),
            "bond variable {var} defined twice"
        );
        definitions[index as usize] = Some((element, form));
    };

    for element in model.element_ids() {
        let bonds = &model.element(element).bonds;
        let receives = |bond: BondId| causal.receives_effort(model, bond, element);
        let sign = |bond: BondId| ratio(model.bond(bond).sign_into(element));
        match &laws[element.index()] {
            Law::EffortSource(value) => {
                let value = with_feedback(model, laws, numbering, value)?;
                define(effort(bonds[0]), element, value);
            }
            Law::FlowSource(value) => {
                // The source's value is its flow out of the element.
                let value = with_feedback(model, laws, numbering, value)?;
                define(flow(bonds[0]), element, value.scaled(&-sign(bonds[0])));
            }
            Law::SlackStorage => define(effort(bonds[0]), element, LinearForm::zero()),
            Law::Inertia(inertance) => {
                let bond = bonds[0];
                match (
                    numbering.state[element.index()],
                    numbering.dependent[element.index()],
                ) {
                    (Some(state), _) => {
                        let coefficient = sign(bond)
                            .checked_div(inertance)
                            .expect("inertance validated non-zero");
                        define(
                            flow(bond),
                            element,
                            LinearForm::term(Var::State(state), coefficient),
                        );
                    }
                    (None, Some(dependent)) => {
                        define(
                            effort(bond),
                            element,
                            LinearForm::var(Var::Dependent(dependent)),
                        );
                    }
                    (None, None) => unreachable!("storage is either a state or dependent"),
                }
            }
            Law::Compliance(compliance) => {
                let bond = bonds[0];
                match (
                    numbering.state[element.index()],
                    numbering.dependent[element.index()],
                ) {
                    (Some(state), _) => {
                        let coefficient = compliance.inv().expect("compliance validated non-zero");
                        define(
                            effort(bond),
                            element,
                            LinearForm::term(Var::State(state), coefficient),
                        );
                    }
                    (None, Some(dependent)) => {
                        define(
                            flow(bond),
                            element,
                            LinearForm::term(Var::Dependent(dependent), sign(bond)),
                        );
                    }
                    (None, None) => unreachable!("storage is either a state or dependent"),
                }
            }
            Law::Resistor { resistance, offset } => {
                let bond = bonds[0];
                if receives(bond) {
                    // Conductance causality: f = (e - offset) / R.
                    let Some(conductance) = resistance.inv() else {
                        return Err(zero_resistance(model, element));
                    };
                    if model.evaluate(resistance) == 0.0 {
                        return Err(zero_resistance(model, element));
                    }
                    let mut form = LinearForm::var(effort(bond));
                    form.add_scaled(offset, &RatFunc::integer(-1));
                    define(
                        flow(bond),
                        element,
                        form.scaled(&(&conductance * &sign(bond))),
                    );
                } else {
                    // Resistance causality: e = R f + offset.
                    let mut form = LinearForm::term(flow(bond), resistance * &sign(bond));
                    form.add(offset);
                    define(effort(bond), element, form);
                }
            }
            Law::Transformer(ratio) => {
                define_two_port(model, element, ratio, true, &receives, &mut define);
            }
            Law::Gyrator(ratio) => {
                define_two_port(model, element, ratio, false, &receives, &mut define);
            }
            Law::Nonlinear(law) => {
                let first = numbering.auxiliary[element.index()]
                    .expect("every nonlinear law has its auxiliary variables");
                let ports = Ports {
                    receives: &receives,
                    sign: &sign,
                };
                define_nonlinear(model, element, law, first, ports, &mut define);
            }
            Law::ZeroJunction | Law::OneJunction => {
                let zero = matches!(laws[element.index()], Law::ZeroJunction);
                let ports = Ports {
                    receives: &receives,
                    sign: &sign,
                };
                define_junction(bonds, element, zero, ports, &mut define);
            }
        }
    }
    Ok(definitions
        .into_iter()
        .map(|d| d.expect("causality defines every bond variable exactly once"))
        .collect())
}

/// Defines a transformer's (`transformer`) or gyrator's bond variables: the two it imposes,
/// by the ratio `n` (`r` for a gyrator), the way the causality has it.
fn define_two_port(
    model: &Model,
    element: ElementId,
    ratio: &RatFunc,
    transformer: bool,
    receives: &dyn Fn(BondId) -> bool,
    define: &mut dyn FnMut(Var, ElementId, LinearForm),
) {
    if transformer {
        let n = ratio;
        let (input, output) = two_port_bonds(model, element);
        let inverse = n.inv().expect("ratio validated non-zero");
        if receives(input) {
            define(
                effort(output),
                element,
                LinearForm::term(effort(input), inverse.clone()),
            );
            define(
                flow(input),
                element,
                LinearForm::term(flow(output), inverse),
            );
        } else {
            define(
                effort(input),
                element,
                LinearForm::term(effort(output), n.clone()),
            );
            define(
                flow(output),
                element,
                LinearForm::term(flow(input), n.clone()),
            );
        }
    } else {
        let r = ratio;
        let (input, output) = two_port_bonds(model, element);
        if receives(input) {
            let inverse = r.inv().expect("ratio validated non-zero");
            define(
                flow(output),
                element,
                LinearForm::term(effort(input), inverse.clone()),
            );
            define(
                flow(input),
                element,
                LinearForm::term(effort(output), inverse),
            );
        } else {
            define(
                effort(input),
                element,
                LinearForm::term(flow(output), r.clone()),
            );
            define(
                effort(output),
                element,
                LinearForm::term(flow(input), r.clone()),
            );
        }
    }
}

/// The bonds of an element as its causality and directions see them: whether it receives
/// each bond's effort, and each bond's sign into it.
#[derive(Clone, Copy)]
struct Ports<'a> {
    receives: &'a dyn Fn(BondId) -> bool,
    sign: &'a dyn Fn(BondId) -> RatFunc,
}

/// Defines a nonlinear law's outputs: auxiliary variables from `first` on, defined by the
/// nonlinear derivation in terms of what the law receives.
fn define_nonlinear(
    model: &Model,
    element: ElementId,
    law: &NonlinearLaw,
    first: u32,
    Ports { receives, sign }: Ports<'_>,
    define: &mut dyn FnMut(Var, ElementId, LinearForm),
) {
    let bonds = &model.element(element).bonds;
    let aux = |k: u32| LinearForm::var(Var::Auxiliary(first + k));
    match law {
        NonlinearLaw::EffortSource(_) | NonlinearLaw::Compliance(_) => {
            define(effort(bonds[0]), element, aux(0));
        }
        NonlinearLaw::FlowSource(_) => {
            define(flow(bonds[0]), element, aux(0).scaled(&-sign(bonds[0])));
        }
        NonlinearLaw::Inertia(_) => {
            define(flow(bonds[0]), element, aux(0).scaled(&sign(bonds[0])));
        }
        NonlinearLaw::Resistor(_) => {
            if receives(bonds[0]) {
                define(flow(bonds[0]), element, aux(0).scaled(&sign(bonds[0])));
            } else {
                define(effort(bonds[0]), element, aux(0));
            }
        }
        NonlinearLaw::Transformer(_) | NonlinearLaw::Gyrator(_) => {
            let transformer = matches!(law, NonlinearLaw::Transformer(_));
            let (input, output) = two_port_bonds(model, element);
            let (first, second) = match (transformer, receives(input)) {
                (true, true) => (effort(output), flow(input)),
                (true, false) => (effort(input), flow(output)),
                (false, true) => (flow(output), flow(input)),
                (false, false) => (effort(input), effort(output)),
            };
            define(first, element, aux(0));
            define(second, element, aux(1));
        }
    }
}

/// Defines a junction's bond variables: its common variable (effort at a 0-junction, flow
/// at a 1-junction) on every bond from its unique bond, and the unique bond's summed one.
fn define_junction(
    bonds: &[BondId],
    element: ElementId,
    zero: bool,
    Ports { receives, sign }: Ports<'_>,
    define: &mut dyn FnMut(Var, ElementId, LinearForm),
) {
    // The unique bond: effort in for a 0-junction, effort out for a 1-junction.
    let unique = *bonds
        .iter()
        .find(|&&b| receives(b) == zero)
        .expect("causality leaves every junction one unique bond");
    let (common, summed): (BondVariable, BondVariable) =
        if zero { (effort, flow) } else { (flow, effort) };
    // Σ σ_j x_j = 0 over the junction's bonds (σ = +1 into the junction), solved
    // for the unique bond's summed variable.
    let mut sum = LinearForm::zero();
    let unique_sign = sign(unique);
    for &bond in bonds {
        if bond == unique {
            continue;
        }
        define(common(bond), element, LinearForm::var(common(unique)));
        sum.add_scaled(
            &LinearForm::var(summed(bond)),
            &-(&sign(bond) * &unique_sign),
        );
    }
    define(summed(unique), element, sum);
}

/// A source's value with the energy variables it feeds back ([`Var::Storage`]) written in
/// this mode's terms: a state is itself (its own momentum or displacement, which merging
/// rewrites); storage in derivative causality is its inertance (compliance) times the flow
/// (effort) the rest of the graph imposes on it, a bond variable solved with the others.
fn with_feedback(
    model: &Model,
    laws: &[Law],
    numbering: &Numbering,
    value: &LinearForm,
) -> Result<LinearForm> {
    if !value.mentions(|v| matches!(v, Var::Storage(_))) {
        return Ok(value.clone());
    }
    let mut energies = Vec::new();
    for (var, _) in value.terms() {
        let Var::Storage(index) = *var else {
            continue;
        };
        let element = ElementId(index);
        let bond = model.element(element).bonds[0];
        let energy = match (numbering.state[element.index()], &laws[element.index()]) {
            (Some(state), _) => LinearForm::var(Var::State(state)),
            (None, Law::Inertia(inertance)) => LinearForm::term(
                flow(bond),
                inertance * &ratio(model.bond(bond).sign_into(element)),
            ),
            (None, Law::Compliance(compliance)) => {
                LinearForm::term(effort(bond), compliance.clone())
            }
            (None, _) => return Err(feedback_without_state(model, element)),
        };
        energies.push((index, energy));
    }
    Ok(value.substitute(|var| match var {
        Var::Storage(index) => energies
            .iter()
            .find(|(i, _)| *i == index)
            .map(|(_, energy)| energy.clone()),
        _ => None,
    }))
}

/// A source whose feedback closes an algebraic loop: it feeds back the energy variable of
/// storage in derivative causality ([`with_feedback`] writes it in that storage's bond
/// variable), and that variable depends on what the source itself imposes. Only feedback
/// puts bond variables in a source's definition, so a loop through one always runs through
/// its feedback. Solving it would give a constraint (`f = a m f`, so `f = 0`), never a
/// controller's dynamics: refused, naming the source and the storage it feeds back.
fn loop_through_feedback(
    model: &Model,
    laws: &[Law],
    numbering: &Numbering,
    definitions: &[(ElementId, LinearForm)],
    members: &[u32],
) -> Option<crate::diagnostics::Diagnostics> {
    members.iter().find_map(|&member| {
        let source = definitions[member as usize].0;
        let (Law::EffortSource(value) | Law::FlowSource(value)) = &laws[source.index()] else {
            return None;
        };
        let storage = value.terms().iter().find_map(|(var, _)| match *var {
            Var::Storage(index) if numbering.state[index as usize].is_none() => {
                Some(ElementId(index))
            }
            _ => None,
        })?;
        let source_name = &model.element(source).name;
        let storage_name = &model.element(storage).name;
        let energy = model.storage_name(storage).unwrap_or_default();
        Some(
            Diagnostic::new(
                DiagnosticKind::DependentStorage,
                format!(
                    "source '{source_name}' feeds back {energy}, but '{storage_name}' is in derivative causality and its {energy} follows from what '{source_name}' imposes: an algebraic loop, not a controller"
                ),
            )
            .at_element(model, source)
            .element(source_name.clone())
            .note(format!(
                "give '{storage_name}' a state of its own (a compliance or resistor between it and '{source_name}'), or feed back a state the source does not set"
            ))
            .into(),
        )
    })
}

/// A source feeds back the energy variable of nonlinear storage that has no state of its
/// own in this mode (refused before derivation reaches here; said rather than assumed).
fn feedback_without_state(model: &Model, element: ElementId) -> crate::diagnostics::Diagnostics {
    let name = &model.element(element).name;
    Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!(
            "a source feeds back the state of '{name}', which is in derivative causality and has no state of its own in this mode"
        ),
    )
    .at_element(model, element)
    .element(name.clone())
    .note("add a compliance or resistor next to it so that it keeps its own state")
    .into()
}

/// The bond into and the bond out of a two-port (validated: one of each).
pub(crate) fn two_port_bonds(model: &Model, element: ElementId) -> (BondId, BondId) {
    let bonds = &model.element(element).bonds;
    if model.bond(bonds[0]).to == element {
        (bonds[0], bonds[1])
    } else {
        (bonds[1], bonds[0])
    }
}

fn zero_resistance(model: &Model, element: ElementId) -> crate::diagnostics::Diagnostics {
    let name = &model.element(element).name;
    Diagnostic::new(
        DiagnosticKind::InvalidValue,
        format!(
            "resistor '{name}' must set its flow from its effort (conductance causality), \
             but its resistance is zero"
        ),
    )
    .at_element(model, element)
    .element(name.clone())
    .note("a zero resistance is a rigid connection: replace the resistor by a bond")
    .into()
}
