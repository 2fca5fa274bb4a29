//! The checked [`Model`], read from RON text or built in code ([`Builder`]).
//!
//! Parsing is split so that each part answers one question (the parts are the crate's
//! own): `raw` is the file format as serde reads it, `source_map` records where each entry
//! and bond is (serde keeps no positions), `parse` runs both and turns ron's errors into
//! diagnostics that name the element and point at the offending token, and `validate`
//! checks names, expressions, values and the graph and builds the [`Model`] that every
//! later stage works on.
//! [`edit`] makes variants of a model file (elements removed, parameter values set) by
//! editing its text, so that a variant is loaded and checked like any model file.
//!
//! # Example
//! ```
//! use bondgraph_core::model;
//! let error = model::load_str("bad.ron", r#"Model(name: "bad",
//!     parameters: {"m": (value: 0.0, unit: "kg")},
//!     elements: {"j": One, "mass": I(inertance: "m"), "push": Se(effort: "1")},
//!     bonds: [("push", "j"), ("j", "mass")])"#).unwrap_err();
//! assert_eq!(error.first().location.as_ref().unwrap().line, 3);
//! assert_eq!(error.first().element.as_deref(), Some("mass"));
//! ```
mod builder;
mod checked;
pub mod edit;
pub mod linear_graph;
pub(crate) mod parse;
pub mod reduction;
pub(crate) mod source_map;
pub mod spec;
pub(crate) mod validate;

use std::sync::Arc;

pub use builder::Builder;
pub use checked::{
    Bond, BondId, Coefficient, Element, ElementId, ElementKind, ElementMode, FlowLimit, Friction,
    Input, InputId, Model, NonlinearElement, NonlinearLaw, Parameter, ResistorLaw, SourceValue,
    TensionOnly,
};

pub use spec::{BondSpec, ElementSpec, InputSpec, ModelSpec, ParameterSpec};

use crate::diagnostics::Result;
use crate::source::SourceFile;

/// Parses and validates the model in `source`: a bond graph (`Model(...)`) or a linear
/// graph (`LinearGraph(...)`, see [`linear_graph`]), told apart by the top-level value. This
/// is the one loader every command uses.
///
/// # Errors
/// Every problem found, each naming its file, line, column and element.
pub fn load_source(source: &Arc<SourceFile>) -> Result<Model> {
    match Format::of(source.text()) {
        Format::LinearGraph => linear_graph::load(source),
        Format::BondGraph => {
            let (raw, map) = parse::parse_model(source)?;
            validate::validate(source, raw, &map)
        }
    }
}

/// The two kinds of model file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// `Model(...)`: elements and bonds.
    BondGraph,
    /// `LinearGraph(...)`: a ground, nodes and branches.
    LinearGraph,
}

impl Format {
    /// The kind of model file `text` is: a linear graph if its top-level value is named
    /// `LinearGraph`, or is unnamed and has a `branches` or `ground` field; a bond graph
    /// otherwise (whose parser reports what is wrong with a file that is neither).
    pub fn of(text: &str) -> Self {
        let map = source_map::SourceMap::scan_partial(text);
        let named = text
            .get(map.root.start.min(text.len())..)
            .unwrap_or("")
            .trim_start();
        let linear = named.starts_with("LinearGraph")
            || (named.starts_with('(')
                && (map.field("branches").is_some() || map.field("ground").is_some()));
        if linear {
            Format::LinearGraph
        } else {
            Format::BondGraph
        }
    }
}

/// Parses and validates `text`, read from a file called `name`.
///
/// # Errors
/// As [`load_source`].
pub fn load_str(name: &str, text: &str) -> Result<Model> {
    load_source(&SourceFile::new(name, text))
}
