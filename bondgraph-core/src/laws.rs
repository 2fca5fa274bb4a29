//! The constitutive law of every element in one mode.
//!
//! Causality and elimination never look at element kinds directly: they look at a [`Law`].
//! A plain element has one law in every mode; a switching element (a friction contact, a
//! string that goes slack) has one law per mode. Separating the two is what lets every mode
//! of a switching model be derived by the same code as a plain model.

use crate::linear::LinearForm;
use crate::model::{ElementKind, Model};
use crate::symbolic::RatFunc;

/// What an element does to its bonds in one mode.
#[derive(Clone, Debug, PartialEq)]
pub enum Law {
    /// Imposes the effort `value` (affine in the inputs).
    EffortSource(LinearForm),
    /// Imposes the flow `value` (affine in the inputs); positive out of the element.
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
}

impl Law {
    /// Whether the law imposes its causality regardless of the rest of the graph.
    pub fn is_source(&self) -> bool {
        matches!(
            self,
            Law::EffortSource(_) | Law::FlowSource(_) | Law::SlackStorage
        )
    }

    /// Whether the element stores energy with a preferred (integral) causality.
    pub fn is_storage(&self) -> bool {
        matches!(self, Law::Inertia(_) | Law::Compliance(_))
    }

    /// Whether the law carries a state of its own (storage, or slack storage).
    pub fn has_state(&self) -> bool {
        matches!(
            self,
            Law::Inertia(_) | Law::Compliance(_) | Law::SlackStorage
        )
    }
}

/// The laws of a model without switching elements (its only mode).
pub fn plain_laws(model: &Model) -> Vec<Law> {
    model
        .elements
        .iter()
        .map(|element| match &element.kind {
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
            ElementKind::ZeroJunction => Law::ZeroJunction,
            ElementKind::OneJunction => Law::OneJunction,
        })
        .collect()
}
