//! The record of one causality assignment: what SCAP decided, in the order it decided it.
//!
//! A teacher assigns causality on the board one decision at a time: a source's fixed
//! causality, then what it forces through the junctions it touches, then each storage
//! element's preferred integral causality, and so on. [`assign_traced`](super::assign_traced)
//! records exactly those decisions as it makes them, so the trace cannot disagree with the
//! strokes it returns: replaying the trace ([`CausalityTrace::strokes`]) gives them back.
//!
//! Each [`Step`] is one decision about one element's bond ([`Decision`]); the strokes that
//! the decision then forced elsewhere are its [`Propagation`]s, each naming the junction,
//! transformer or gyrator whose rule ([`Rule`]) forced it. A choice that led to a conflict
//! and was undone stays in the trace as a [`Decision::Undone`] step (its strokes removed).
//!
//! The causal stroke is at the end of the bond that receives the effort ([`Stroke`]).
//!
//! # Example
//! ```
//! use bondgraph_core::causality::{self, Decision};
//! use bondgraph_core::{laws, model};
//! let model = bondgraph_ron::model::load_str("m.ron", r#"Model(name: "m",
//!     parameters: {"m": (value: 1.0), "k": (value: 4.0)}, inputs: {"F": ()},
//!     elements: {"push": Se(effort: "F"), "j": One, "mass": I(inertance: "m"),
//!                "spring": C(stiffness: "k")},
//!     bonds: [("push", "j"), ("j", "mass"), ("j", "spring")])"#).unwrap();
//! let laws = laws::plain_laws(&model);
//! let (causal, trace) = causality::assign_traced(&model, &laws).unwrap();
//! let decisions: Vec<Decision> = trace.steps.iter().map(|s| s.decision.clone()).collect();
//! assert_eq!(decisions, [Decision::Source, Decision::Integral, Decision::Integral]);
//! // The mass's integral causality gave the junction its flow; the junction imposed it on
//! // the spring's bond.
//! assert_eq!(trace.steps[1].propagated.len(), 1);
//! let replayed: Vec<_> = trace.strokes(model.bonds().len()).into_iter().flatten().collect();
//! assert_eq!(replayed, causal.strokes);
//! ```

use super::Stroke;
use crate::model::{BondId, ElementId};

/// Every decision of one run of SCAP, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CausalityTrace {
    /// The decisions, in the order they were made.
    pub steps: Vec<Step>,
}

/// One decision about one element's bond, and what it forced.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The element whose causality was decided.
    pub element: ElementId,
    /// What was decided, and why.
    pub decision: Decision,
    /// The element's bond the decision is about.
    pub bond: BondId,
    /// The stroke of that bond: the one the step gave it, or found on it, or (for an undone
    /// choice) the one it tried.
    pub stroke: Stroke,
    /// Whether this step stroked the bond; `false` when an earlier step had stroked it
    /// already (the step then records what that meant for the element).
    pub new: bool,
    /// The step that had already stroked the bond, when `new` is false.
    pub earlier: Option<usize>,
    /// The strokes this step forced on other bonds, in the order they were made.
    pub propagated: Vec<Propagation>,
}

/// What a [`Step`] decided.
#[derive(Clone, Debug, PartialEq)]
pub enum Decision {
    /// A source (or a switching element acting as one in this mode, or a slack
    /// tension-only element imposing zero effort) takes its fixed causality.
    Source,
    /// A resistor whose law is known one way only takes the causality that law allows.
    OneWayResistor,
    /// A storage element in its preferred integral causality: it integrates what it
    /// receives (an inertia its effort, a compliance its flow) into a state.
    Integral,
    /// A storage element whose bond an earlier step had stroked against its preference:
    /// derivative causality, no independent state.
    Derivative,
    /// A resistor whose causality an earlier step had forced.
    ResistorForced,
    /// A resistor whose causality nothing forced, chosen (resistance causality first).
    ResistorChosen,
    /// A bond between junctions or two-ports whose causality nothing forced, chosen.
    BondChosen,
    /// A choice (the step's element, bond and stroke) that led to a conflict and was
    /// undone; the search then tried the alternative.
    Undone {
        /// The conflict it led to.
        conflict: String,
    },
}

/// A stroke one decision forced on another bond through a junction or two-port's rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Propagation {
    /// The bond stroked.
    pub bond: BondId,
    /// Its stroke.
    pub stroke: Stroke,
    /// The junction, transformer or gyrator whose rule forced it.
    pub through: ElementId,
    /// That rule.
    pub rule: Rule,
}

/// The causal rule that forced a [`Propagation`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// A 0-junction's effort comes in on `from`; it gives that effort to its other bonds.
    CommonEffort {
        /// The bond that brings the effort in.
        from: BondId,
    },
    /// Every other bond of a 0-junction takes its effort, so the last one must bring it in.
    LastSetsEffort,
    /// A 1-junction's flow comes in on `from`; it gives that flow to its other bonds.
    CommonFlow {
        /// The bond that brings the flow in.
        from: BondId,
    },
    /// Every other bond of a 1-junction takes its flow, so the last one must bring it in.
    LastSetsFlow,
    /// A transformer passes causality through: the effort that comes in on `from` goes out
    /// on its other port (or the flow).
    Transformer {
        /// The port whose causality was known.
        from: BondId,
    },
    /// A gyrator turns causality over: the effort on `from` sets the flow on its other port.
    Gyrator {
        /// The port whose causality was known.
        from: BondId,
    },
}

impl CausalityTrace {
    /// The stroke of every bond (indexed by [`BondId`]) as the trace's steps make them,
    /// undone choices left out; `None` for a bond no step stroked.
    pub fn strokes(&self, bond_count: usize) -> Vec<Option<Stroke>> {
        let mut strokes = vec![None; bond_count];
        for (bond, stroke, _) in self.assignments() {
            strokes[bond.index()].get_or_insert(stroke);
        }
        strokes
    }

    /// Every stroke the trace makes: `(bond, stroke, step index)`, in order, undone
    /// choices left out. A consistent trace strokes every bond once.
    pub fn assignments(&self) -> impl Iterator<Item = (BondId, Stroke, usize)> + '_ {
        self.steps
            .iter()
            .enumerate()
            .filter(|(_, step)| !matches!(step.decision, Decision::Undone { .. }))
            .flat_map(|(i, step)| {
                let own = step.new.then_some((step.bond, step.stroke, i));
                own.into_iter()
                    .chain(step.propagated.iter().map(move |p| (p.bond, p.stroke, i)))
            })
    }

    /// The step that stroked `bond` (its own bond or by propagation).
    pub fn step_of(&self, bond: BondId) -> Option<usize> {
        self.assignments()
            .find(|(b, _, _)| *b == bond)
            .map(|(_, _, i)| i)
    }
}
