//! State equations `dx/dt = A x + B u + c` of one mode, with symbolic entries, and the
//! term `E du/dt` where storage driven by an input makes the states follow the input's rate
//! (Rowell & Wormley's dependent spring, in co-energy variables).
//!
//! The derivation runs in four steps, each in its own module:
//! 1. [`causality`](crate::causality::assign) assigns causal strokes (SCAP);
//! 2. `elimination` expresses every bond variable through states, inputs and the unknown
//!    efforts of dependent storage, solving algebraic loops symbolically;
//! 3. `merging` folds dependent storage into the states it follows;
//! 4. optionally, the states change from energy variables (momenta `p`, displacements `q`)
//!    to co-energy variables (velocities `v`, efforts `f`), as textbooks and papers write them;
//! 5. `finite` refuses a coefficient that overflows at the parameter values.
//!
//! Everything stays sparse ([`LinearForm`]) until a caller asks for dense matrices, so a
//! 2000-state chain derives in linear time.

mod coenergy;
pub(crate) mod elimination;
mod finite;
pub(crate) mod matrix;
pub(crate) mod merging;
pub mod nonlinear;
mod outputs;
mod print;

use serde::Serialize;

use crate::causality::{self, Causality};
use crate::diagnostics::Result;
use crate::laws::Law;
use crate::linear::{LinearForm, Var};
use crate::model::{BondId, ElementId, ElementKind, Model, NonlinearLaw};
use crate::symbolic::{RatFunc, SymbolTable};

pub use elimination::AlgebraicLoop;
pub use outputs::{OutputEquation, OutputQuantity, OutputSpec};
pub use print::{EquationsJson, Layout, Matrix, OutputJson, StateJson, Triplets};

use elimination::Numbering;
use merging::Domain;

/// Which variables the states are written in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Variables {
    /// Momenta `p` of inertias and displacements `q` of compliances (the default).
    #[default]
    Energy,
    /// Velocities `v` of inertias and efforts (forces) `f` of compliances.
    #[serde(rename = "coenergy")]
    CoEnergy,
}

impl Variables {
    /// The variables a model is best read in: co-energy for a linear graph (Rowell &
    /// Wormley's states are across variables of A-types and through variables of T-types),
    /// energy for a bond graph, and for a linear graph with a nonlinear A- or T-type, whose
    /// co-energy variable would need its law's inverse.
    pub fn preferred(model: &Model) -> Self {
        let nonlinear_storage = model.elements.iter().any(|e| {
            matches!(
                &e.kind,
                ElementKind::Nonlinear(n)
                    if matches!(n.law, NonlinearLaw::Inertia(_) | NonlinearLaw::Compliance(_))
            )
        });
        if model.linear_graph.is_some() && !nonlinear_storage {
            Variables::CoEnergy
        } else {
            Variables::Energy
        }
    }
}

/// The physical quantity a state measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Quantity {
    /// Momentum (generalised momentum) of an inertia.
    #[serde(rename = "p")]
    Momentum,
    /// Displacement (generalised) of a compliance, or slack length of a slack element.
    #[serde(rename = "q")]
    Displacement,
    /// Velocity (flow) of an inertia.
    #[serde(rename = "v")]
    Velocity,
    /// Force (effort) of a compliance.
    #[serde(rename = "f")]
    Force,
}

impl Quantity {
    /// The letter that prefixes state names (`p`, `q`, `v`, `f`).
    pub fn letter(self) -> &'static str {
        match self {
            Quantity::Momentum => "p",
            Quantity::Displacement => "q",
            Quantity::Velocity => "v",
            Quantity::Force => "f",
        }
    }

    /// A readable name of the quantity in a linear graph's terms: a state of an A-type
    /// (an inertia of the bond graph) is its across variable, or its capacitance times it.
    pub fn linear_graph_description(self) -> &'static str {
        match self {
            Quantity::Momentum => "momentum (capacitance times across variable)",
            Quantity::Displacement => "displacement (inductance times through variable)",
            Quantity::Velocity => "across variable",
            Quantity::Force => "through variable",
        }
    }

    /// A readable name of the quantity in the words of `domain` (a capacitor's charge, a
    /// tank's volume, a body's heat), or the general words without one. `linear_graph`:
    /// whether the state is a linear graph's, whose through variable is the bond graph's
    /// effort (so an A-type capacitor's "momentum" is its charge).
    pub fn description_in(
        self,
        domain: Option<&crate::units::Domain>,
        linear_graph: bool,
    ) -> &'static str {
        let Some(d) = domain else {
            return if linear_graph {
                self.linear_graph_description()
            } else {
                self.description()
            };
        };
        let swapped = linear_graph && !d.effort_is_through;
        match (self, swapped) {
            (Quantity::Momentum, false) | (Quantity::Displacement, true) => d.momentum,
            (Quantity::Displacement, false) | (Quantity::Momentum, true) => d.displacement,
            (Quantity::Velocity, _) => d.file_flow(linear_graph).1,
            (Quantity::Force, _) => d.file_effort(linear_graph).1,
        }
    }

    /// A readable name of the quantity.
    pub fn description(self) -> &'static str {
        match self {
            Quantity::Momentum => "momentum",
            Quantity::Displacement => "displacement",
            Quantity::Velocity => "flow",
            Quantity::Force => "effort",
        }
    }
}

/// One state of the equations.
#[derive(Clone, Debug, PartialEq)]
pub struct StateVariable {
    /// The state's name: the quantity's letter and the element's name (`p_mass`).
    pub name: String,
    /// The storage element the state belongs to.
    pub element: String,
    /// What it measures.
    pub quantity: Quantity,
    /// Storage elements in derivative causality merged into this state.
    pub merged: Vec<String>,
    /// The state's (merged) inertance or compliance: `m1 + m2` for two merged masses.
    pub storage: RatFunc,
    /// The energy domain of the element's bond, if the model's units tell it.
    pub domain: Option<&'static crate::units::Domain>,
}

/// Something the derivation did that the reader should know.
#[derive(Clone, Debug, PartialEq)]
pub enum Note {
    /// Dependent storage merged into a state.
    Merged {
        /// The state that absorbed them.
        state: String,
        /// The independent element.
        element: String,
        /// The dependent elements.
        merged: Vec<String>,
        /// The merged inertance or compliance.
        storage: RatFunc,
    },
    /// Storage held by sources: no state in this mode.
    Held {
        /// The element.
        element: String,
    },
    /// The equations are a nonlinear mode's linearisation at an operating point.
    Linearised {
        /// The point, as text (`q = 0.5, p = 0`).
        point: String,
    },
    /// An algebraic loop solved symbolically.
    AlgebraicLoop {
        /// The elements (other than junctions) whose equations formed it.
        elements: Vec<String>,
        /// The junctions it passes through.
        junctions: Vec<String>,
    },
}

impl Note {
    /// The note as a sentence, with symbolic values in plain text.
    pub fn text(&self, symbols: &SymbolTable) -> String {
        match self {
            Note::Merged {
                state,
                element,
                merged,
                storage,
            } => format!(
                "derivative causality: {} merged into '{element}'; state {state} has storage {}",
                quote_list(merged),
                storage.text(symbols)
            ),
            Note::Held { element } => format!(
                "'{element}' has its motion imposed by sources and constraints: no state of its own in this mode"
            ),
            Note::Linearised { point } => {
                format!("linearisation of the nonlinear equations at {point}")
            }
            Note::AlgebraicLoop {
                elements,
                junctions,
            } => format!(
                "algebraic loop through {} (at {}) solved symbolically",
                quote_list(elements),
                quote_list(junctions)
            ),
        }
    }
}

fn quote_list(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Options of a derivation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// Energy (default) or co-energy states.
    pub variables: Variables,
}

/// The state equations of one mode: `dx/dt = A x + B u + c`, kept sparse.
#[derive(Clone, Debug)]
pub struct StateEquations {
    /// The model's name.
    pub model: String,
    /// The variables the states are written in.
    pub variables: Variables,
    /// The states, in element order.
    pub states: Vec<StateVariable>,
    /// The model's inputs, in file order.
    pub inputs: Vec<String>,
    /// `dx_i/dt` as an affine form of [`Var::State`], [`Var::Input`], [`Var::Constant`] and,
    /// where storage driven by an input feeds a state, [`Var::InputRate`] (the `E du/dt`
    /// term).
    pub derivatives: Vec<LinearForm>,
    /// What the derivation merged, held and solved.
    pub notes: Vec<Note>,
    /// The causality the equations were derived from.
    pub causality: Causality,
    /// The parameter symbols (for printing).
    pub symbols: SymbolTable,
    /// The parameter values, indexed by symbol.
    pub values: Vec<f64>,
    /// Whether the model is a linear graph, whose states text names in its terms (the across
    /// variable of an A-type, the through variable of a T-type).
    pub linear_graph: bool,
    /// Effort (`2b`) and flow (`2b + 1`) of every bond.
    bond_vars: Vec<LinearForm>,
    /// Energy variable of each storage element of the mode, as a form over the states.
    storage_energy: Vec<(ElementId, LinearForm)>,
}

/// Derives the state equations of the mode given by `laws`.
///
/// # Errors
/// Causal conflicts, unresolvable dependent storage, singular algebraic loops, zero
/// resistances that must set a flow, and coefficients that overflow at the parameter
/// values; each names the elements concerned.
pub fn derive(model: &Model, laws: &[Law], options: &Options) -> Result<StateEquations> {
    derive_checking(model, laws, options, true)
}

/// As [`derive`]; with `check_finite` false the coefficients are not checked at the model's
/// values, for a mode the model has only at other values ([`crate::modes::derive`]).
pub(crate) fn derive_checking(
    model: &Model,
    laws: &[Law],
    options: &Options,
    check_finite: bool,
) -> Result<StateEquations> {
    if let Some(element) = model
        .element_ids()
        .find(|e| laws[e.index()].nonlinear().is_some())
    {
        return Err(nonlinear::not_linear(model, element));
    }
    let causal = causality::assign(model, laws)?;
    derive_parts(
        model,
        laws,
        causal,
        options,
        vec![None; model.elements.len()],
        check_finite,
    )
}

/// Derives the state equations from an already assigned causality.
///
/// # Errors
/// As [`derive()`]; a mode with a nonlinear law is [`DiagnosticKind::NotLinear`]: derive it
/// with [`nonlinear::derive`].
///
/// [`DiagnosticKind::NotLinear`]: crate::diagnostics::DiagnosticKind::NotLinear
pub fn derive_with(
    model: &Model,
    laws: &[Law],
    causal: Causality,
    options: &Options,
) -> Result<StateEquations> {
    if let Some(element) = model
        .element_ids()
        .find(|e| laws[e.index()].nonlinear().is_some())
    {
        return Err(nonlinear::not_linear(model, element));
    }
    derive_parts(
        model,
        laws,
        causal,
        options,
        vec![None; model.elements.len()],
        true,
    )
}

/// The derivation with the outputs of nonlinear laws kept as auxiliary variables
/// (`auxiliary`: the first auxiliary index of each nonlinear element); `check_finite` refuses
/// coefficients that overflow at the model's values ([`finite`]).
pub(crate) fn derive_parts(
    model: &Model,
    laws: &[Law],
    causal: Causality,
    options: &Options,
    auxiliary: Vec<Option<u32>>,
    check_finite: bool,
) -> Result<StateEquations> {
    let (numbering, state_elements) = number_storage(model, laws, &causal, auxiliary);
    let solved = elimination::solve(model, laws, &causal, &numbering)?;
    let merged = merging::merge(model, laws, &numbering, &state_elements, &solved.bond_vars)?;

    let mut notes = Vec::new();
    let domains: Vec<Domain> = state_elements
        .iter()
        .map(|e| merging::domain(&laws[e.index()]))
        .collect();
    // Where each state sits in its storage block.
    let mut place = vec![(0usize, 0usize); state_elements.len()];
    for (b, block) in merged.blocks.iter().enumerate() {
        for (position, &k) in block.states.iter().enumerate() {
            place[k as usize] = (b, position);
        }
    }
    let states: Vec<StateVariable> = state_elements
        .iter()
        .enumerate()
        .map(|(k, &element)| {
            let quantity = match (domains[k], options.variables) {
                (Domain::Kinetic, Variables::Energy) => Quantity::Momentum,
                (Domain::Kinetic, Variables::CoEnergy) => Quantity::Velocity,
                (Domain::Potential, Variables::CoEnergy) => Quantity::Force,
                _ => Quantity::Displacement,
            };
            let name = &model.element(element).name;
            let (block, position) = place[k];
            StateVariable {
                // A name given with `symbol:` names the energy variable.
                name: match (&model.element(element).symbol, quantity) {
                    (Some(symbol), Quantity::Momentum | Quantity::Displacement) => symbol.clone(),
                    _ => crate::model::state_symbol(quantity.letter(), name),
                },
                element: name.clone(),
                quantity,
                merged: merged.merged_into[k]
                    .iter()
                    .map(|e| model.element(*e).name.clone())
                    .collect(),
                storage: merged.blocks[block].matrix.entry(position, position),
                domain: model.element_domain(element),
            }
        })
        .collect();
    for state in &states {
        if !state.merged.is_empty() {
            notes.push(Note::Merged {
                state: state.name.clone(),
                element: state.element.clone(),
                merged: state.merged.clone(),
                storage: state.storage.clone(),
            });
        }
    }
    for element in &merged.held {
        notes.push(Note::Held {
            element: model.element(*element).name.clone(),
        });
    }
    for algebraic_loop in &solved.loops {
        let (junctions, elements): (Vec<ElementId>, Vec<ElementId>) = algebraic_loop
            .elements
            .iter()
            .partition(|e| matches!(laws[e.index()], Law::ZeroJunction | Law::OneJunction));
        let names = |ids: Vec<ElementId>| -> Vec<String> {
            ids.iter().map(|e| model.element(*e).name.clone()).collect()
        };
        notes.push(Note::AlgebraicLoop {
            elements: names(elements),
            junctions: names(junctions),
        });
    }

    let merging::InStates {
        derivatives,
        bond_vars,
        storage_energy,
    } = match options.variables {
        Variables::Energy => merged.in_energy_variables(),
        Variables::CoEnergy => coenergy::convert(&merged),
    };

    let equations = StateEquations {
        model: model.name.clone(),
        variables: options.variables,
        states,
        inputs: model.inputs.iter().map(|i| i.name.clone()).collect(),
        derivatives,
        notes,
        causality: causal,
        symbols: model.symbols.clone(),
        values: model.values.clone(),
        linear_graph: model.linear_graph.is_some(),
        bond_vars,
        storage_energy,
    };
    if check_finite {
        finite::check(model, &equations, &state_elements)?;
    }
    Ok(equations)
}

/// Numbers the storage of the mode: states (independent storage, in element order) and
/// dependent storage. Returns the numbering and the state elements.
pub(crate) fn number_storage(
    model: &Model,
    laws: &[Law],
    causal: &Causality,
    auxiliary: Vec<Option<u32>>,
) -> (Numbering, Vec<ElementId>) {
    let mut numbering = Numbering {
        state: vec![None; model.elements.len()],
        dependent: vec![None; model.elements.len()],
        auxiliary,
    };
    let mut state_elements = Vec::new();
    let mut dependent_count = 0;
    for element in model.element_ids() {
        if !laws[element.index()].has_state() {
            continue;
        }
        if causal.dependent.contains(&element) {
            numbering.dependent[element.index()] = Some(dependent_count);
            dependent_count += 1;
        } else {
            numbering.state[element.index()] = Some(state_elements.len() as u32);
            state_elements.push(element);
        }
    }
    (numbering, state_elements)
}

impl StateEquations {
    /// Number of states.
    pub fn state_count(&self) -> usize {
        self.states.len()
    }

    /// The dense matrix `A` (states × states).
    pub fn a(&self) -> Vec<Vec<RatFunc>> {
        self.dense(|j| Var::State(j as u32), self.states.len())
    }

    /// The dense matrix `B` (states × inputs).
    pub fn b(&self) -> Vec<Vec<RatFunc>> {
        self.dense(|j| Var::Input(j as u32), self.inputs.len())
    }

    /// The dense matrix `E` (states × inputs) of the inputs' rates: zero unless storage
    /// driven by an input feeds a state.
    pub fn e(&self) -> Vec<Vec<RatFunc>> {
        self.dense(|j| Var::InputRate(j as u32), self.inputs.len())
    }

    /// Whether the state equations have an `E du/dt` term.
    pub fn has_input_rates(&self) -> bool {
        self.derivatives
            .iter()
            .any(|row| row.mentions(|v| matches!(v, Var::InputRate(_))))
    }

    /// The affine term `c` (one entry per state).
    pub fn c(&self) -> Vec<RatFunc> {
        self.derivatives
            .iter()
            .map(|row| row.coefficient(Var::Constant))
            .collect()
    }

    /// The non-zero entries of `A` (`column` maps a state to its column), `B` (inputs) or
    /// `E` (inputs' rates) as `(row, column, entry)`, row by row, columns ascending: a large
    /// model's matrices in memory linear in their non-zeros.
    pub fn nonzeros(&self, column: impl Fn(Var) -> Option<usize>) -> Vec<(usize, usize, &RatFunc)> {
        self.derivatives
            .iter()
            .enumerate()
            .flat_map(|(i, row)| {
                let column = &column;
                row.terms()
                    .iter()
                    .filter_map(move |(var, entry)| column(*var).map(|j| (i, j, entry)))
            })
            .collect()
    }

    fn dense(&self, var: impl Fn(usize) -> Var, columns: usize) -> Vec<Vec<RatFunc>> {
        self.derivatives
            .iter()
            .map(|row| (0..columns).map(|j| row.coefficient(var(j))).collect())
            .collect()
    }

    /// Evaluates a symbolic entry with the model's parameter values.
    pub fn evaluate(&self, value: &RatFunc) -> f64 {
        value.eval(&self.values)
    }

    /// The effort of `bond` in this mode's states and inputs (and inputs' rates, where storage
    /// is driven directly by an input).
    pub fn bond_effort(&self, bond: BondId) -> &LinearForm {
        &self.bond_vars[2 * bond.index()]
    }

    /// The flow of `bond` in this mode's states and inputs (and inputs' rates).
    pub fn bond_flow(&self, bond: BondId) -> &LinearForm {
        &self.bond_vars[2 * bond.index() + 1]
    }

    /// The energy variable (momentum or displacement) of every storage element that has
    /// one in this mode, as an affine form of the states (and inputs): how to rebuild the
    /// full physical state from this mode's states.
    pub fn storage_energy(&self) -> &[(ElementId, LinearForm)] {
        &self.storage_energy
    }

    /// The index of the state called `name`.
    pub fn state_named(&self, name: &str) -> Option<usize> {
        self.states.iter().position(|s| s.name == name)
    }
}
