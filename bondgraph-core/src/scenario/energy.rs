//! Energy records: `energy:ELEMENT`, `power:ELEMENT` and the books `energy:supplied`,
//! `energy:stored`, `energy:dissipated`, as a scenario's `record` list writes them.
//!
//! They are not bond variables: the energy a storage element holds is a function of its
//! energy variable (`q²/2C`, `p²/2I`, or `∫ e dq` for a nonlinear law), a one-port's power
//! is the product of its effort and the flow into it, and the books are integrals of the
//! sources' and resistors' powers over the run. Parsing them here, apart from
//! [`OutputSpec`], keeps `--output` (a linear row of the state equations) what it is; the
//! solver computes these from the state it carries.
//!
//! Sign conventions, in words: `power:ELEMENT` is the power flowing *into* the element
//! along its bond (a resistor's is never negative; a source that delivers power has a
//! negative one); `energy:supplied` is the energy the sources delivered since time 0
//! (minus the integral of their `power:`), `energy:dissipated` what resistors, friction
//! contacts and flow limits turned into heat plus what was lost when bodies merged at
//! events, and `energy:stored` the sum of every storage element's `energy:`. So
//! `energy:stored(t) - energy:stored(0) = energy:supplied(t) - energy:dissipated(t)`.

use crate::diagnostics::{Diagnostic, DiagnosticKind, Result};
use crate::equations::{OutputQuantity, OutputSpec};
use crate::model::{ElementId, ElementKind, Model, NonlinearLaw};

/// One of the run's energy books.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Book {
    /// Delivered by the sources since time 0, in joules.
    Supplied,
    /// Held by every storage element now, in joules.
    Stored,
    /// Dissipated since time 0 (resistors, friction, flow limits, and merges at events), in
    /// joules.
    Dissipated,
}

impl Book {
    /// The book's name after `energy:`.
    pub fn keyword(self) -> &'static str {
        match self {
            Book::Supplied => "supplied",
            Book::Stored => "stored",
            Book::Dissipated => "dissipated",
        }
    }
}

/// An energy record, parsed and resolved against the model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EnergyRecord {
    /// The energy held by one storage element, in joules.
    Stored(ElementId),
    /// The power into a one-port element along its bond, in watts: its effort times its
    /// flow, the flow counted into the element.
    Power {
        /// The element.
        element: ElementId,
        /// The effort on its bond.
        effort: OutputSpec,
        /// The flow on its bond, counted into the element.
        flow: OutputSpec,
    },
    /// One of the books.
    Book(Book),
}

/// Whether an element stores energy (and so has an `energy:`).
pub fn stores_energy(kind: &ElementKind) -> bool {
    match kind {
        ElementKind::Inertia(_) | ElementKind::Compliance(_) | ElementKind::TensionOnly(_) => true,
        ElementKind::Nonlinear(n) => {
            matches!(
                n.law,
                NonlinearLaw::Inertia(_) | NonlinearLaw::Compliance(_)
            )
        }
        _ => false,
    }
}

impl EnergyRecord {
    /// Parses `energy:ELEMENT`, `energy:supplied|stored|dissipated` or `power:ELEMENT`;
    /// `None` when `text` is none of these (a bond output, say). An element named like a
    /// book is reached as the element: a model may call an element `stored`.
    ///
    /// # Errors
    /// A [`DiagnosticKind::BadOutput`] naming the element when it has no such quantity:
    /// energy of an element that stores none, power of an element with several bonds.
    pub fn parse(model: &Model, text: &str) -> Option<Result<Self>> {
        let (quantity, target) = text.split_once(':')?;
        let target = target.trim();
        let power = match quantity.trim() {
            "energy" => false,
            "power" => true,
            _ => return None,
        };
        Some(Self::resolve(model, text.trim(), power, target))
    }

    fn resolve(model: &Model, text: &str, power: bool, target: &str) -> Result<Self> {
        let bad = |message: String| Diagnostic::new(DiagnosticKind::BadOutput, message);
        let Some(id) = model.element_named(target) else {
            if !power {
                for book in [Book::Supplied, Book::Stored, Book::Dissipated] {
                    if target == book.keyword() {
                        return Ok(EnergyRecord::Book(book));
                    }
                }
            }
            let mut d = bad(format!(
                "record '{text}': the model has no element '{target}'"
            ))
            .element(target);
            if !power {
                d = d.note("or a book: energy:supplied, energy:stored, energy:dissipated");
            }
            return Err(d.into());
        };
        let element = model.element(id);
        if !power {
            if stores_energy(&element.kind) {
                return Ok(EnergyRecord::Stored(id));
            }
            return Err(bad(format!(
                "record '{text}': '{target}' is a {} and stores no energy",
                element.kind.description()
            ))
            .element(target)
            .note(format!(
                "energy: is for storage elements (I, C, TensionOnly); power:{target} is the power it takes in"
            ))
            .into());
        }
        let [bond] = element.bonds[..] else {
            return Err(bad(format!(
                "record '{text}': '{target}' is a {} with {} bonds; power: is for one-port elements",
                element.kind.description(),
                element.bonds.len()
            ))
            .element(target)
            .note("junctions, transformers and gyrators pass power on without taking any")
            .into());
        };
        let spec = |quantity, negated| OutputSpec {
            name: text.to_string(),
            quantity,
            bond,
            negated,
        };
        Ok(EnergyRecord::Power {
            element: id,
            effort: spec(OutputQuantity::Effort, false),
            flow: spec(OutputQuantity::Flow, model.bond(bond).sign_into(id) < 0),
        })
    }
}
