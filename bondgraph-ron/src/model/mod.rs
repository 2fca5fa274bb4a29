//! Model files to a checked [`Model`]: bond graphs (`Model(...)`) and linear graphs
//! (`LinearGraph(...)`, [`linear_graph`]).
//!
//! Reading is split so that each part answers one question: serde reads the file into a
//! [`ModelSpec`](bondgraph_core::model::ModelSpec) (the model as written, a `bondgraph-core` type), the scanner
//! ([`crate::source_map`]) records where each entry and bond is (serde keeps no
//! positions), [`parse`] runs both and turns ron's errors into diagnostics that name the
//! element and point at the offending token, and core's validator checks names,
//! expressions, values and the graph and builds the [`Model`] every later stage works on.
//! [`edit`] makes variants of a model file (elements removed, parameter values set) by
//! editing its text, so that a variant is loaded and checked like any model file.
//!
//! # Example
//! ```
//! use bondgraph_ron::model;
//! let error = bondgraph_ron::model::load_str("bad.ron", r#"Model(name: "bad",
//!     parameters: {"m": (value: 0.0, unit: "kg")},
//!     elements: {"j": One, "mass": I(inertance: "m"), "push": Se(effort: "1")},
//!     bonds: [("push", "j"), ("j", "mass")])"#).unwrap_err();
//! assert_eq!(error.first().location.as_ref().unwrap().line, 3);
//! assert_eq!(error.first().element.as_deref(), Some("mass"));
//! ```
pub mod compose;
pub mod edit;
pub mod linear_graph;
pub mod parse;
pub mod reduction;
#[cfg(test)]
mod spec_tests;
#[cfg(test)]
mod units_tests;

use std::sync::Arc;

use bondgraph_core::diagnostics::Result;
use bondgraph_core::model::{Model, validate};
use bondgraph_core::source::SourceFile;

use crate::source_map;

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
            let composed = compose::compose(source, raw, map)?;
            validate::validate(source, composed.spec, &composed.map)
                .map_err(|d| compose::with_origins(d, &composed.origins))
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
        let map = source_map::scan_partial(text);
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
