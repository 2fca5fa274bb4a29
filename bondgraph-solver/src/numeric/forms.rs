//! A linear mode's symbolic pieces with no numbers in, gathered once per mode.
//!
//! A calibration evaluates the same modes at thousands of parameter values. Putting numbers
//! into a mode needs its matrices, guard functions, outputs, ports and storage maps as
//! symbolic forms; gathering them (a guard's `quantity - threshold`, a port's flow turned
//! into the element, the dense matrices) is symbolic arithmetic that does not depend on the
//! values. [`ModeForms`] holds the result, so that new values only cost evaluating rational
//! functions ([`super::NumericMode::from_forms`]).

use bondgraph_core::guards::{Regime, Watched};
use bondgraph_core::linear::LinearForm;
use bondgraph_core::model::{ElementId, ElementKind, ElementMode, Friction, Model};
use bondgraph_core::modes::{Mode, ModeEquations};
use bondgraph_core::symbolic::RatFunc;

/// A nonzero entry `(row, column, value)` of a symbolic matrix.
pub(super) type Entry = (usize, usize, RatFunc);

/// A guard's function and what it switches.
pub(super) struct GuardForm {
    pub element: ElementId,
    pub leaves_to: ElementMode,
    pub requires_hold: bool,
    pub watched: Watched,
    /// `g(x, u)`, firing when it reaches zero from below.
    pub function: LinearForm,
    /// For a guard of one regime of a Stribeck contact, the regime and the contact, whose
    /// Stribeck velocity at the values bound says whether the guard applies.
    pub only_in: Option<(Regime, Friction)>,
}

impl GuardForm {
    /// Whether the guard applies with the parameter `values`.
    pub fn applies(&self, values: &[f64]) -> bool {
        self.only_in
            .as_ref()
            .is_none_or(|(regime, contact)| regime.applies(contact.creeps_at(values)))
    }
}

/// A one-port's effort and the flow into it.
pub(super) struct PortForm {
    pub element: ElementId,
    pub source: bool,
    pub effort: LinearForm,
    pub flow: LinearForm,
}

/// The symbolic pieces of a derived linear mode, ready to be evaluated at any parameter
/// values.
pub struct ModeForms {
    pub(super) mode: Mode,
    pub(super) spec: String,
    pub(super) state_names: Vec<String>,
    pub(super) inputs: usize,
    /// The nonzero entries of `A`, `B` and `E`, and of `c` (column 0).
    pub(super) a: Vec<Entry>,
    pub(super) b: Vec<Entry>,
    pub(super) e: Vec<Entry>,
    pub(super) c: Vec<Entry>,
    pub(super) guards: Vec<GuardForm>,
    pub(super) outputs: Vec<LinearForm>,
    pub(super) ports: Vec<PortForm>,
    pub(super) storage_energy: Vec<(ElementId, LinearForm)>,
}

impl ModeForms {
    /// Gathers the forms of `derived`, a mode of `model`; `outputs` are the requested
    /// outputs' forms in that mode.
    pub fn new(model: &Model, derived: &ModeEquations, outputs: &[LinearForm]) -> Self {
        let eq = &derived.equations;
        let nonzero = |rows: Vec<Vec<RatFunc>>| -> Vec<Entry> {
            rows.into_iter()
                .enumerate()
                .flat_map(|(i, row)| {
                    row.into_iter()
                        .enumerate()
                        .filter(|(_, value)| !value.is_zero())
                        .map(move |(j, value)| (i, j, value))
                })
                .collect()
        };
        let guards = derived
            .guards
            .iter()
            .map(|g| GuardForm {
                element: g.element,
                leaves_to: g.leaves_to,
                requires_hold: g.requires_hold,
                watched: g.watched,
                function: g.function(),
                only_in: match (&model.element(g.element).kind, g.regime) {
                    (_, Regime::Always) => None,
                    (ElementKind::Friction(contact), regime) => Some((regime, (**contact).clone())),
                    _ => None,
                },
            })
            .collect();
        let ports = model
            .element_ids()
            .filter_map(|id| {
                let source = match model.element(id).kind {
                    ElementKind::EffortSource(_) | ElementKind::FlowSource(_) => true,
                    ElementKind::Resistor(_)
                    | ElementKind::Friction(_)
                    | ElementKind::FlowLimit(_) => false,
                    _ => return None,
                };
                let bond = model.element(id).bonds[0];
                let sign = RatFunc::integer(model.bond(bond).sign_into(id));
                Some(PortForm {
                    element: id,
                    source,
                    effort: eq.bond_effort(bond).clone(),
                    flow: eq.bond_flow(bond).scaled(&sign),
                })
            })
            .collect();
        ModeForms {
            mode: derived.mode.clone(),
            spec: derived.mode.spec(model),
            state_names: eq.states.iter().map(|s| s.name.clone()).collect(),
            inputs: eq.inputs.len(),
            a: nonzero(eq.a()),
            b: nonzero(eq.b()),
            e: nonzero(eq.e()),
            c: nonzero(eq.c().into_iter().map(|v| vec![v]).collect()),
            guards,
            outputs: outputs.to_vec(),
            ports,
            storage_energy: eq.storage_energy().to_vec(),
        }
    }

    /// The mode's specification (`fr_1=stuck,...`).
    pub fn spec(&self) -> &str {
        &self.spec
    }
}
