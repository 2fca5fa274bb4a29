//! The constitutive law of every element in one mode.
//!
//! Causality and elimination never look at element kinds directly: they look at a [`Law`].
//! A plain element has one law in every mode; a switching element (a friction contact, a
//! string that goes slack) has one law per mode. Separating the two is what lets every mode
//! of a switching model be derived by the same code as a plain model.

use crate::linear::LinearForm;
use crate::mode::Mode;
use crate::model::{ElementKind, ElementMode, Model, NonlinearLaw};
use crate::symbolic::RatFunc;

/// What an element does to its bonds in one mode.
#[derive(Clone, Debug, PartialEq)]
pub enum Law {
    /// Imposes the effort `value` (affine in the inputs and storage energy variables).
    EffortSource(LinearForm),
    /// Imposes the flow `value` (affine in the inputs and storage energy variables);
    /// positive out of the element.
    FlowSource(LinearForm),
    /// Integrates its effort into momentum `p`; flow `p / inertance`.
    Inertia(RatFunc),
    /// Integrates its flow into displacement `q`; effort `q / compliance`.
    Compliance(RatFunc),
    /// `e = resistance · f + offset`; the offset (a Coulomb force, say) is affine in the inputs.
    Resistor {
        /// The linear coefficient.
        resistance: RatFunc,
        /// The constant part of the effort.
        offset: LinearForm,
    },
    /// `e_in = ratio · e_out`, `f_out = ratio · f_in`.
    Transformer(RatFunc),
    /// `e_in = ratio · f_out`, `e_out = ratio · f_in`.
    Gyrator(RatFunc),
    /// Common effort, flows sum to zero.
    ZeroJunction,
    /// Common flow, efforts sum to zero.
    OneJunction,
    /// Imposes zero effort but still integrates its flow into a displacement state: a
    /// tension-only compliance gone slack, tracking its slack length.
    SlackStorage,
    /// A nonlinear or modulated law: the mode is derived as `dx/dt = f(x, u)`
    /// ([`crate::equations::nonlinear`]).
    Nonlinear(Box<NonlinearLaw>),
}

impl Law {
    /// Whether the law imposes its causality regardless of the rest of the graph.
    pub fn is_source(&self) -> bool {
        matches!(
            self,
            Law::EffortSource(_) | Law::FlowSource(_) | Law::SlackStorage
        ) || matches!(
            self.nonlinear(),
            Some(NonlinearLaw::EffortSource(_) | NonlinearLaw::FlowSource(_))
        )
    }

    /// Whether the element stores energy with a preferred (integral) causality.
    pub fn is_storage(&self) -> bool {
        matches!(self, Law::Inertia(_) | Law::Compliance(_))
            || matches!(
                self.nonlinear(),
                Some(NonlinearLaw::Inertia(_) | NonlinearLaw::Compliance(_))
            )
    }

    /// Whether the law carries a state of its own (storage, or slack storage).
    pub fn has_state(&self) -> bool {
        self.is_storage() || matches!(self, Law::SlackStorage)
    }

    /// The nonlinear law, if it is one.
    pub fn nonlinear(&self) -> Option<&NonlinearLaw> {
        match self {
            Law::Nonlinear(law) => Some(law),
            _ => None,
        }
    }

    /// Whether it imposes an effort (rather than a flow) on its bond when it is a source or
    /// storage in integral causality: effort sources and compliances (and slack storage).
    pub fn gives_effort(&self) -> bool {
        matches!(
            self,
            Law::EffortSource(_) | Law::Compliance(_) | Law::SlackStorage
        ) || matches!(
            self.nonlinear(),
            Some(NonlinearLaw::EffortSource(_) | NonlinearLaw::Compliance(_))
        )
    }
}

/// The laws of the model's initial mode: for a model without switching elements, its only
/// mode.
pub fn plain_laws(model: &Model) -> Vec<Law> {
    for_mode(model, &Mode::initial(model))
}

/// The laws of every element in `mode`.
///
/// A stuck friction contact holds its velocity at zero (a zero flow source); a slipping one
/// resists with `viscous·v ± coulomb` (a resistor with an offset, or an effort source when it
/// has no viscous part), a creeping one with `(viscous - (breakaway - coulomb)/v_s)·v ±
/// breakaway`; a taut tension-only element is a compliance, a slack one imposes
/// zero effort while tracking its slack length; an open flow limit imposes zero effort, a
/// limiting one its maximum flow.
pub fn for_mode(model: &Model, mode: &Mode) -> Vec<Law> {
    model
        .element_ids()
        .map(|id| {
            let element = model.element(id);
            match &element.kind {
                ElementKind::EffortSource(v) => Law::EffortSource(v.value.clone()),
                ElementKind::FlowSource(v) => Law::FlowSource(v.value.clone()),
                ElementKind::Inertia(c) => Law::Inertia(c.value.clone()),
                ElementKind::Compliance(c) => Law::Compliance(c.value.clone()),
                ElementKind::Resistor(c) => Law::Resistor {
                    resistance: c.value.clone(),
                    offset: LinearForm::zero(),
                },
                ElementKind::Transformer(c) => Law::Transformer(c.value.clone()),
                ElementKind::Gyrator(c) => Law::Gyrator(c.value.clone()),
                ElementKind::Nonlinear(n) => Law::Nonlinear(Box::new(n.law.clone())),
                ElementKind::ZeroJunction => Law::ZeroJunction,
                ElementKind::OneJunction => Law::OneJunction,
                ElementKind::Friction(friction) => {
                    let slip = |sign: i64| {
                        let offset = friction.coulomb.value.scaled(&RatFunc::integer(sign));
                        if friction.viscous.value.is_zero() {
                            Law::EffortSource(offset)
                        } else {
                            Law::Resistor {
                                resistance: friction.viscous.value.clone(),
                                offset,
                            }
                        }
                    };
                    // Slower than the Stribeck velocity: the breakaway force, weakening with speed.
                    let creep = |sign: i64| Law::Resistor {
                        resistance: friction
                            .creep_resistance()
                            .expect("validated: a creeping contact has a constant slope"),
                        offset: friction.breakaway.value.scaled(&RatFunc::integer(sign)),
                    };
                    match mode.of(id).unwrap_or(friction.initial) {
                        ElementMode::SlipPositive => slip(1),
                        ElementMode::SlipNegative => slip(-1),
                        ElementMode::CreepPositive => creep(1),
                        ElementMode::CreepNegative => creep(-1),
                        _ => Law::FlowSource(LinearForm::zero()),
                    }
                }
                ElementKind::TensionOnly(string) => match mode.of(id).unwrap_or(string.initial) {
                    ElementMode::Slack => Law::SlackStorage,
                    _ => Law::Compliance(string.compliance.value.clone()),
                },
                ElementKind::FlowLimit(limit) => match mode.of(id).unwrap_or(limit.initial) {
                    // A flow source's value is its flow out of the element.
                    ElementMode::Limiting => {
                        Law::FlowSource(limit.max_flow.value.scaled(&RatFunc::integer(-1)))
                    }
                    _ => Law::EffortSource(LinearForm::zero()),
                },
            }
        })
        .collect()
}
