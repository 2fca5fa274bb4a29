//! State equations of a nonlinear mode: `dx/dt = f(x, u)`, with symbolic Jacobians.
//!
//! A nonlinear model is still mostly linear: junctions, constant ratios and linear storage
//! and resistors relate its bond variables linearly. So the derivation keeps the exact
//! linear machinery and only adds unknowns: the output of every nonlinear law (the effort
//! of a nonlinear spring, the flow of an orifice, the two outputs of a modulated lever) is
//! an *auxiliary variable* `w`. Causality, elimination and merging then run exactly as for a
//! linear mode, with the `w` as free variables, and give every bond variable and state
//! derivative as an affine form of states, inputs and `w`. Each law's definition, `w` in
//! terms of what the law receives, is written in those same forms, and substituting the
//! definitions into one another (in dependency order) gives `f(x, u)` symbolically.
//!
//! What this cannot do is said, naming the elements:
//! - storage with a nonlinear law in derivative causality, or storage that follows a state
//!   through a nonlinear law (a mass driven through a modulated lever has a mass matrix
//!   that depends on the state);
//! - algebraic loops through nonlinear laws that are not affine in the loop's unknowns
//!   (a loop through a modulated transformer and resistors is solved symbolically, a loop
//!   through two orifices is not);
//! - co-energy states for nonlinear storage (they would need the law's inverse).
//!
//! The Jacobians `df/dx`, `df/du` are symbolic derivatives of `f`; [`NonlinearEquations::linearise`]
//! evaluates them at an operating point as a linear mode's equations, so that everything
//! built for linear modes (analysis, transfer functions) applies to the linearisation.

mod linearise;
mod print;

use petgraph::algo::tarjan_scc;
use petgraph::graph::DiGraph;

use crate::causality::{self, Causality};
use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::equations::elimination::{effort, flow, two_port_bonds};
use crate::equations::{Note, Options, OutputSpec, StateVariable, Variables};
use crate::laws::Law;
use crate::linear::{LinearForm, Var};
use crate::model::AtElement;
use crate::model::{BondId, ElementId, Model, NonlinearLaw};
use crate::symbolic::expr::{Atom, Sym};
use crate::symbolic::{RatFunc, SymbolTable};

pub use linearise::{OperatingPoint, PointError};
pub use print::{NonlinearEquationsJson, NonlinearOutputJson};

/// The state equations of one nonlinear mode: `dx/dt = f(x, u)`.
#[derive(Clone, Debug)]
pub struct NonlinearEquations {
    /// The model's name.
    pub model: String,
    /// The variables the states are written in.
    pub variables: Variables,
    /// The states, in element order.
    pub states: Vec<StateVariable>,
    /// For each state whose storage law is nonlinear, the law in terms of the state: the
    /// flow of a nonlinear inertia as a function of its momentum, the effort of a nonlinear
    /// compliance as a function of its displacement.
    pub storage_laws: Vec<Option<Sym>>,
    /// The model's inputs, in file order.
    pub inputs: Vec<String>,
    /// `f`: `dx_i/dt` in [`Atom::State`] and [`Atom::Input`].
    pub derivatives: Vec<Sym>,
    /// What the derivation merged, held and solved.
    pub notes: Vec<Note>,
    /// The causality the equations were derived from.
    pub causality: Causality,
    /// The parameter symbols (for printing).
    pub symbols: SymbolTable,
    /// The parameter values, indexed by symbol.
    pub values: Vec<f64>,
    /// Whether the model is a linear graph's, whose through variable is the bond graph's
    /// effort (states are described in its words).
    pub linear_graph: bool,
    /// Effort (`2b`) and flow (`2b + 1`) of every bond.
    bond_vars: Vec<Sym>,
    /// Energy variable of each storage element of the mode, affine in the states and inputs.
    storage_energy: Vec<(ElementId, LinearForm)>,
}

/// An output equation of a nonlinear mode: `y = h(x, u)`.
#[derive(Clone, Debug, PartialEq)]
pub struct NonlinearOutput {
    /// The output's name.
    pub name: String,
    /// `h`.
    pub value: Sym,
    /// Whether what is output is the time integral of `h` (`integral:flow:mass`).
    pub integral: bool,
}

/// The expression of an affine form.
pub(crate) fn form_to_sym(form: &LinearForm) -> Sym {
    Sym::sum(form.terms().iter().map(|(var, c)| {
        let term = match var {
            Var::Constant => Sym::one(),
            Var::State(i) => Sym::atom(Atom::State(*i)),
            Var::Input(i) => Sym::atom(Atom::Input(*i)),
            Var::InputRate(i) => Sym::atom(Atom::InputRate(*i)),
            Var::Auxiliary(i) => Sym::atom(Atom::Auxiliary(*i)),
            Var::Bond(i) => Sym::atom(Atom::Bond(*i)),
            Var::Dependent(i) => Sym::atom(Atom::Storage(u32::MAX - *i)),
            Var::Storage(e) => Sym::atom(Atom::Storage(*e)),
        };
        (term, c.clone())
    }))
}

/// One nonlinear law's auxiliary variable and its definition.
struct Auxiliary {
    element: ElementId,
    definition: Sym,
}

/// Derives the equations of the mode given by `laws`, which may hold nonlinear laws.
///
/// # Errors
/// As [`crate::equations::derive`], and what the module documentation lists.
pub fn derive(model: &Model, laws: &[Law], options: &Options) -> Result<NonlinearEquations> {
    derive_checking(model, laws, options, true)
}

/// As [`derive`]; with `check_finite` false the coefficients are not checked at the model's
/// values, for a mode the model has only at other values ([`crate::modes::derive`]).
pub(crate) fn derive_checking(
    model: &Model,
    laws: &[Law],
    options: &Options,
    check_finite: bool,
) -> Result<NonlinearEquations> {
    let causal = causality::assign(model, laws)?;
    derive_with_checking(model, laws, causal, options, check_finite)
}

/// Derives the equations from an already assigned causality.
///
/// # Errors
/// As [`derive()`].
pub fn derive_with(
    model: &Model,
    laws: &[Law],
    causal: Causality,
    options: &Options,
) -> Result<NonlinearEquations> {
    derive_with_checking(model, laws, causal, options, true)
}

fn derive_with_checking(
    model: &Model,
    laws: &[Law],
    causal: Causality,
    options: &Options,
    check_finite: bool,
) -> Result<NonlinearEquations> {
    for &element in &causal.dependent {
        if laws[element.index()].nonlinear().is_some() {
            return Err(nonlinear_dependent(model, element));
        }
    }
    let nonlinear_storage: Vec<ElementId> = model
        .element_ids()
        .filter(|e| laws[e.index()].nonlinear().is_some() && laws[e.index()].is_storage())
        .collect();
    if options.variables == Variables::CoEnergy
        && let Some(&element) = nonlinear_storage.first()
    {
        let name = &model.element(element).name;
        return Err(Diagnostic::new(
            DiagnosticKind::NotLinear,
            format!(
                "co-energy states are not available: '{name}' has a nonlinear law, and its co-energy variable would need the law's inverse"
            ),
        )
        .at_element(model, element)
        .element(name.clone())
        .note("derive in energy variables instead (`--states energy`)")
        .into());
    }

    // Number the auxiliary variables and write each law's definition in bond variables.
    let mut first_auxiliary = vec![None; model.elements.len()];
    let mut auxiliaries: Vec<Auxiliary> = Vec::new();
    for element in model.element_ids() {
        let Some(law) = laws[element.index()].nonlinear() else {
            continue;
        };
        first_auxiliary[element.index()] = Some(auxiliaries.len() as u32);
        for definition in definitions(model, &causal, element, law)? {
            auxiliaries.push(Auxiliary {
                element,
                definition,
            });
        }
    }

    let linear = crate::equations::derive_parts(
        model,
        laws,
        causal,
        options,
        first_auxiliary,
        check_finite,
    )?;

    // Definitions in the mode's states, inputs and other auxiliaries.
    let storage_energy: Vec<(ElementId, LinearForm)> = linear.storage_energy().to_vec();
    let bond_forms: Vec<Sym> = linear.bond_vars.iter().map(form_to_sym).collect();
    let energy_of = |element: u32| {
        storage_energy
            .iter()
            .find(|(e, _)| e.0 == element)
            .map(|(_, form)| form_to_sym(form))
    };
    let in_mode = |expr: &Sym| {
        expr.substitute(&|a| match a {
            Atom::Bond(i) => Some(bond_forms[i as usize].clone()),
            Atom::Storage(e) => energy_of(e),
            _ => None,
        })
    };
    let written: Vec<Sym> = auxiliaries.iter().map(|a| in_mode(&a.definition)).collect();
    let (resolved, loops) = resolve(model, laws, &auxiliaries, &written)?;
    let expand = |expr: &Sym| {
        expr.substitute(&|a| match a {
            Atom::Auxiliary(i) => Some(resolved[i as usize].clone()),
            _ => None,
        })
    };

    let derivatives: Vec<Sym> = linear
        .derivatives
        .iter()
        .map(|form| expand(&form_to_sym(form)))
        .collect();
    if let Some(k) = derivatives
        .iter()
        .position(|f| f.mentions_any(&|a| matches!(a, Atom::InputRate(_))))
    {
        let element = model
            .element_named(&linear.states[k].element)
            .expect("a state's element exists");
        let name = &model.element(element).name;
        return Err(Diagnostic::new(
            DiagnosticKind::DependentStorage,
            format!(
                "the equation of '{name}' would need the time derivative of an input: storage driven directly by an input reaches it through a nonlinear law"
            ),
        )
        .at_element(model, element)
        .element(name.clone())
        .note("put a compliance or resistor between the source and the storage element")
        .into());
    }
    let bond_vars: Vec<Sym> = bond_forms.iter().map(&expand).collect();

    let storage_laws = linear
        .states
        .iter()
        .map(|state| {
            let element = model.element_named(&state.element)?;
            let law = match laws[element.index()].nonlinear()? {
                NonlinearLaw::Inertia(law) | NonlinearLaw::Compliance(law) => law,
                _ => return None,
            };
            Some(in_mode(law))
        })
        .collect();

    let mut notes = linear.notes.clone();
    notes.extend(
        loops
            .iter()
            .map(|elements| loop_note(model, laws, elements)),
    );

    Ok(NonlinearEquations {
        model: linear.model.clone(),
        variables: linear.variables,
        states: linear.states.clone(),
        storage_laws,
        inputs: linear.inputs.clone(),
        derivatives,
        notes,
        causality: linear.causality.clone(),
        symbols: linear.symbols.clone(),
        values: linear.values.clone(),
        linear_graph: linear.linear_graph,
        bond_vars,
        storage_energy,
    })
}

/// The note on an algebraic loop through nonlinear laws: its elements, junctions apart.
fn loop_note(model: &Model, laws: &[Law], elements: &[ElementId]) -> Note {
    let (junctions, others): (Vec<ElementId>, Vec<ElementId>) = elements
        .iter()
        .partition(|e| matches!(laws[e.index()], Law::ZeroJunction | Law::OneJunction));
    let names = |ids: Vec<ElementId>| -> Vec<String> {
        ids.iter().map(|e| model.element(*e).name.clone()).collect()
    };
    Note::AlgebraicLoop {
        elements: names(others),
        junctions: names(junctions),
    }
}

/// The definitions of a nonlinear law's auxiliary variables, in bond variables, the
/// inputs and the storage elements' energy variables.
fn definitions(
    model: &Model,
    causal: &Causality,
    element: ElementId,
    law: &NonlinearLaw,
) -> Result<Vec<Sym>> {
    let bonds = &model.element(element).bonds;
    let bond_var = |var: Var| match var {
        Var::Bond(i) => Sym::atom(Atom::Bond(i)),
        _ => unreachable!("bond variables only"),
    };
    let receives = |bond: BondId| causal.receives_effort(model, bond, element);
    let sign = |bond: BondId| RatFunc::integer(model.bond(bond).sign_into(element));
    let with_port =
        |law: &Sym, port: Sym| law.substitute(&|a| (a == Atom::Port).then(|| port.clone()));
    Ok(match law {
        NonlinearLaw::EffortSource(value)
        | NonlinearLaw::FlowSource(value)
        | NonlinearLaw::Inertia(value)
        | NonlinearLaw::Compliance(value) => vec![value.clone()],
        NonlinearLaw::Resistor(r) => {
            let bond = bonds[0];
            if receives(bond) {
                let Some(flow_law) = &r.flow else {
                    return Err(one_way(model, element, "effort"));
                };
                vec![with_port(flow_law, bond_var(effort(bond)))]
            } else {
                let Some(effort_law) = &r.effort else {
                    return Err(one_way(model, element, "flow"));
                };
                vec![with_port(
                    effort_law,
                    bond_var(flow(bond)).scaled(&sign(bond)),
                )]
            }
        }
        NonlinearLaw::Transformer(ratio) | NonlinearLaw::Gyrator(ratio) => {
            let transformer = matches!(law, NonlinearLaw::Transformer(_));
            let (input, output) = two_port_bonds(model, element);
            let over = |var: Var| Sym::div(&bond_var(var), ratio).expect("ratio checked non-zero");
            let times = |var: Var| Sym::mul(ratio, &bond_var(var));
            match (transformer, receives(input)) {
                // e_out = e_in / r, f_in = f_out / r
                (true, true) => vec![over(effort(input)), over(flow(output))],
                // e_in = r e_out, f_out = r f_in
                (true, false) => vec![times(effort(output)), times(flow(input))],
                // f_out = e_in / r, f_in = e_out / r
                (false, true) => vec![over(effort(input)), over(effort(output))],
                // e_in = r f_out, e_out = r f_in
                (false, false) => vec![times(flow(output)), times(flow(input))],
            }
        }
    })
}

/// Substitutes the auxiliaries' definitions into one another in dependency order; a cycle
/// (an algebraic loop through nonlinear laws) is solved where it is affine in its unknowns.
/// Returns every auxiliary in states and inputs, and the loops solved (by element).
fn resolve(
    model: &Model,
    laws: &[Law],
    auxiliaries: &[Auxiliary],
    written: &[Sym],
) -> Result<(Vec<Sym>, Vec<Vec<ElementId>>)> {
    let count = written.len();
    let mut graph = DiGraph::<(), ()>::with_capacity(count, count);
    for _ in 0..count {
        graph.add_node(());
    }
    for (i, definition) in written.iter().enumerate() {
        for atom in definition.atoms() {
            if let Atom::Auxiliary(j) = atom {
                graph.add_edge((i as u32).into(), j.into(), ());
            }
        }
    }
    let mut resolved: Vec<Option<Sym>> = vec![None; count];
    let mut loops = Vec::new();
    for component in tarjan_scc(&graph) {
        let members: Vec<u32> = component.iter().map(|n| n.index() as u32).collect();
        let substitute = |expr: &Sym, resolved: &[Option<Sym>]| {
            expr.substitute(&|a| match a {
                Atom::Auxiliary(j) => resolved[j as usize].clone(),
                _ => None,
            })
        };
        let self_loop = members.len() == 1
            && written[members[0] as usize].mentions(Atom::Auxiliary(members[0]));
        if members.len() == 1 && !self_loop {
            let i = members[0] as usize;
            resolved[i] = Some(substitute(&written[i], &resolved));
            continue;
        }
        // w = A w + r with A and r free of the loop's unknowns: solve (I - A) w = r.
        let equations: Vec<Sym> = members
            .iter()
            .map(|&m| substitute(&written[m as usize], &resolved))
            .collect();
        let mut elements: Vec<ElementId> = members
            .iter()
            .map(|&m| auxiliaries[m as usize].element)
            .collect();
        elements.sort();
        elements.dedup();
        let solution = solve_affine(&members, &equations)
            .ok_or_else(|| nonlinear_loop(model, laws, &elements))?;
        for (&m, value) in members.iter().zip(solution) {
            resolved[m as usize] = Some(value);
        }
        loops.push(elements);
    }
    Ok((
        resolved
            .into_iter()
            .map(|r| r.expect("every auxiliary lies in a component"))
            .collect(),
        loops,
    ))
}

/// Solves `w_i = equations_i(w)` for the loop's unknowns `members` by Gaussian elimination,
/// if every equation is affine in them; `None` otherwise (or when singular).
fn solve_affine(members: &[u32], equations: &[Sym]) -> Option<Vec<Sym>> {
    let n = members.len();
    let unknowns: Vec<Atom> = members.iter().map(|&m| Atom::Auxiliary(m)).collect();
    let is_unknown = |a: Atom| unknowns.contains(&a);
    // Rows [M | r] with M = I - ∂eq/∂w, r = eq - (∂eq/∂w)·w.
    let mut matrix: Vec<Vec<Sym>> = Vec::with_capacity(n);
    let mut rhs: Vec<Sym> = Vec::with_capacity(n);
    for (i, equation) in equations.iter().enumerate() {
        let mut row = Vec::with_capacity(n);
        for (j, &unknown) in unknowns.iter().enumerate() {
            let coefficient = equation.diff(unknown);
            if coefficient.mentions_any(&is_unknown) {
                return None;
            }
            let identity = if i == j { Sym::one() } else { Sym::zero() };
            row.push(Sym::sub(&identity, &coefficient));
        }
        // Affine (every slope free of the unknowns): the rest is the equation at w = 0,
        // without multiplying out products such as r(u)·(p/m - w/b).
        let rest = equation.substitute(&|a| is_unknown(a).then(Sym::zero));
        matrix.push(row);
        rhs.push(rest);
    }
    for k in 0..n {
        let pivot_row = (k..n).find(|&r| !matrix[r][k].is_zero())?;
        matrix.swap(k, pivot_row);
        rhs.swap(k, pivot_row);
        let pivot = matrix[k][k].clone();
        for entry in matrix[k].iter_mut() {
            *entry = Sym::div(entry, &pivot)?;
        }
        rhs[k] = Sym::div(&rhs[k], &pivot)?;
        let pivot_row = matrix[k].clone();
        for r in 0..n {
            if r == k || matrix[r][k].is_zero() {
                continue;
            }
            let factor = matrix[r][k].clone();
            for (entry, above) in matrix[r].iter_mut().zip(&pivot_row) {
                *entry = Sym::sub(entry, &Sym::mul(&factor, above));
            }
            rhs[r] = Sym::sub(&rhs[r], &Sym::mul(&factor, &rhs[k]));
        }
    }
    Some(rhs)
}

impl NonlinearEquations {
    /// Number of states.
    pub fn state_count(&self) -> usize {
        self.states.len()
    }

    /// `∂f/∂x`, symbolically (states × states).
    pub fn jacobian_states(&self) -> Vec<Vec<Sym>> {
        self.jacobian(|j| Atom::State(j as u32), self.states.len())
    }

    /// `∂f/∂u`, symbolically (states × inputs).
    pub fn jacobian_inputs(&self) -> Vec<Vec<Sym>> {
        self.jacobian(|j| Atom::Input(j as u32), self.inputs.len())
    }

    fn jacobian(&self, atom: impl Fn(usize) -> Atom, columns: usize) -> Vec<Vec<Sym>> {
        self.derivatives
            .iter()
            .map(|f| (0..columns).map(|j| f.diff(atom(j))).collect())
            .collect()
    }

    /// The effort of `bond` in this mode's states and inputs (and inputs' rates).
    pub fn bond_effort(&self, bond: BondId) -> &Sym {
        &self.bond_vars[2 * bond.index()]
    }

    /// The flow of `bond` in this mode's states and inputs (and inputs' rates).
    pub fn bond_flow(&self, bond: BondId) -> &Sym {
        &self.bond_vars[2 * bond.index() + 1]
    }

    /// The energy variable of every storage element of the mode, affine in its states and
    /// inputs: how to rebuild the full physical state (see
    /// [`StateEquations::storage_energy`](crate::equations::StateEquations::storage_energy)).
    pub fn storage_energy(&self) -> &[(ElementId, LinearForm)] {
        &self.storage_energy
    }

    /// The index of the state called `name`.
    pub fn state_named(&self, name: &str) -> Option<usize> {
        self.states.iter().position(|s| s.name == name)
    }

    /// The output equation of `spec` in this mode (negated where the spec counts its bond
    /// the other way: a power into an element whose bond points out of it, a linear graph's
    /// branch against its bond).
    pub fn output(&self, spec: &OutputSpec) -> NonlinearOutput {
        let value = match spec.quantity {
            crate::equations::OutputQuantity::Effort => self.bond_effort(spec.bond),
            crate::equations::OutputQuantity::Flow => self.bond_flow(spec.bond),
        };
        NonlinearOutput {
            name: spec.name.clone(),
            // A linear graph's branch may count its variable against its bond's, and a
            // one-port's power is into it, against a bond that points out.
            value: if spec.negated {
                Sym::neg(value)
            } else {
                value.clone()
            },
            integral: false,
        }
    }

    /// The name of a variable in text.
    pub fn atom_name(&self, atom: Atom) -> String {
        match atom {
            Atom::State(i) => self.states[i as usize].name.clone(),
            Atom::Input(i) => self.inputs[i as usize].clone(),
            Atom::InputRate(i) => format!("der({})", self.inputs[i as usize]),
            other => format!("{other:?}"),
        }
    }

    /// An expression of this mode as text.
    pub fn sym_text(&self, expr: &Sym) -> String {
        expr.text(&self.symbols, &|a| self.atom_name(a))
    }
}

/// The diagnostic for a mode with nonlinear laws derived as a linear one.
pub(crate) fn not_linear(model: &Model, element: ElementId) -> Diagnostics {
    let e = model.element(element);
    let law = match &e.kind {
        crate::model::ElementKind::Nonlinear(n) => format!(" ({}: \"{}\")", n.field, n.text),
        _ => String::new(),
    };
    Diagnostic::new(
        DiagnosticKind::NotLinear,
        format!(
            "model '{}' is nonlinear: {} '{}' has a nonlinear law{law}, so its equations are dx/dt = f(x, u), not A x + B u + c",
            model.name,
            e.kind.description(),
            e.name
        ),
    )
    .at_element(model, element)
    .element(e.name.clone())
    .note("derive it with equations::nonlinear::derive; for matrices, linearise at an operating point (--at)")
    .into()
}

fn nonlinear_dependent(model: &Model, element: ElementId) -> Diagnostics {
    let name = &model.element(element).name;
    Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!(
            "'{name}' has a nonlinear law and is in derivative causality: its state is fixed by others, and merging it would need its law's inverse"
        ),
    )
    .at_element(model, element)
    .element(name.clone())
    .note("add a compliance or resistor next to it so that it can keep its own state")
    .into()
}

/// Storage in derivative causality that follows a state through a nonlinear law.
pub(crate) fn dependent_through_law(
    model: &Model,
    laws: &[Law],
    element: ElementId,
) -> Diagnostics {
    let name = &model.element(element).name;
    let through: Vec<String> = model
        .element_ids()
        .filter(|e| laws[e.index()].nonlinear().is_some())
        .map(|e| format!("'{}'", model.element(e).name))
        .collect();
    let diagnostic = Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!(
            "'{name}' is in derivative causality and follows the rest of the model through a nonlinear law ({}); it cannot be merged into one state",
            through.join(", ")
        ),
    )
    .at_element(model, element)
    .element(name.clone());
    // A resistor whose law could not be turned round is the usual cause: it must be given
    // its flow, so the storage next to it cannot give it an effort from its own state.
    let one_way = model
        .element_ids()
        .find_map(|e| match laws[e.index()].nonlinear() {
            Some(NonlinearLaw::Resistor(r)) if r.flow.is_none() => Some((e, "effort", "flow")),
            Some(NonlinearLaw::Resistor(r)) if r.effort.is_none() => Some((e, "flow", "effort")),
            _ => None,
        });
    match one_way {
        Some((resistor, given, unknown)) => diagnostic.note(format!(
            "'{}' has its law as {given}: f({unknown}), which could not be solved for the {unknown}, so it must be given its {unknown}, and '{name}' cannot give it its {given} from a state of its own; write the law as {unknown}: f({given}) too",
            model.element(resistor).name
        )),
        None => diagnostic.note("a mass driven through a modulated ratio has a state-dependent mass matrix; add a compliance or resistor next to it so that it keeps its own state"),
    }
    .into()
}

fn nonlinear_loop(model: &Model, laws: &[Law], elements: &[ElementId]) -> Diagnostics {
    let names: Vec<String> = elements
        .iter()
        .filter(|e| laws[e.index()].nonlinear().is_some())
        .map(|e| format!("'{}'", model.element(*e).name))
        .collect();
    let first = elements[0];
    Diagnostic::new(
        DiagnosticKind::SingularLoop,
        format!(
            "the algebraic loop through the nonlinear laws of {} cannot be solved symbolically",
            names.join(", ")
        ),
    )
    .at_element(model, first)
    .element(model.element(first).name.clone())
    .note("the loop's equations are not affine in its unknowns; break it with a storage element (a small mass or compliance) or combine the laws into one")
    .into()
}

fn one_way(model: &Model, element: ElementId, given: &str) -> Diagnostics {
    let name = &model.element(element).name;
    Diagnostic::new(
        DiagnosticKind::CausalConflict,
        format!("resistor '{name}' is given its {given}, but its law cannot be solved for the other port variable"),
    )
    .at_element(model, element)
    .element(name.clone())
    .into()
}
