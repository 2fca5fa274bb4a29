//! Optional model reduction: taking out parasitic storage.
//!
//! A mass or compliance whose time constant is many orders of magnitude below every other
//! (a 5e-15 kg tip against a 1250 N·s/m damper: 4e-18 s) makes the state
//! equations stiff without changing anything at the time scales of interest. Removing it is
//! the singular-perturbation limit: its junction then balances its efforts (or flows)
//! algebraically, and causality gives the velocity it carried to a neighbouring resistor.
//! Finding such elements takes numbers (eigenvalues), which is the solver's business
//! (`bondgraph_solver::parasitic`); this module performs the reduction as an ordinary model
//! edit, so the reduced model is a model file like any other, and reports what it removed.
//! It is never applied silently.

use std::sync::Arc;

use crate::model::edit::{self, Edit};
use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Result};
use bondgraph_core::model::{ElementKind, Model};
use bondgraph_core::source::SourceFile;

/// A model with storage elements removed.
#[derive(Clone, Debug)]
pub struct Reduced {
    /// The reduced model.
    pub model: Model,
    /// Its text.
    pub source: Arc<SourceFile>,
    /// The storage elements removed.
    pub removed: Vec<String>,
}

/// `model` (read from `source`) without the storage elements `elements`.
///
/// # Errors
/// [`DiagnosticKind::UndefinedElement`] for a name that is not an element,
/// [`DiagnosticKind::InvalidValue`] for an element that stores no energy (only inertias and
/// compliances can be parasitic), and whatever the reduced model breaks (a junction left
/// with one bond).
pub fn without_storage(model: &Model, source: &SourceFile, elements: &[String]) -> Result<Reduced> {
    for name in elements {
        let Some(id) = model.element_named(name) else {
            return Err(Diagnostic::new(
                DiagnosticKind::UndefinedElement,
                format!(
                    "cannot reduce '{name}': model '{}' has no such element",
                    model.name()
                ),
            )
            .element(name.clone())
            .into());
        };
        let element = model.element(id);
        if !matches!(
            element.kind,
            ElementKind::Inertia(_) | ElementKind::Compliance(_)
        ) {
            return Err(Diagnostic::new(
                DiagnosticKind::InvalidValue,
                format!(
                    "cannot reduce '{name}': it is a {}, and only inertias and compliances can be parasitic storage",
                    element.kind.description()
                ),
            )
            .at_location(model.locate_element(id))
            .element(name.clone())
            .into());
        }
    }
    let edit = Edit {
        remove: elements.to_vec(),
        parameters: Vec::new(),
    };
    let edited = edit::apply(source, &edit)?;
    let reduced_source = SourceFile::new(
        format!("{} (without {})", source.name(), elements.join(", ")),
        edited.text(),
    );
    let model = crate::model::load_source(&reduced_source)?;
    Ok(Reduced {
        model,
        source: reduced_source,
        removed: elements.to_vec(),
    })
}
