//! Linear-graph model files (`LinearGraph(...)`): the second formalism, read into the same
//! checked [`Model`] as a bond graph.
//!
//! A linear graph (Rowell & Wormley, *System Dynamics: An Introduction*) draws a system as
//! nodes, each with an across variable (a velocity, a voltage, a pressure), and branches
//! between them, each carrying a through variable (a force, a current, a flow). It is the
//! same physics as a bond graph, drawn with the topology in plain sight.
//!
//! # Why through the bond graph
//! Everything past the model file (causality, the elimination of algebraic loops, the
//! merging of dependent storage, modes and guards of switching elements, the solver, the
//! data analysis) works on a bond graph. Deriving a linear graph's equations directly from
//! its normal tree would duplicate all of it; instead, [`translate`] turns the linear graph
//! into the raw bond-graph model a bond-graph file would have given (nodes are 1-junctions,
//! branches 0-junctions with their element, the ground left out; see its documentation for
//! the analogy and the signs), with a source map whose every span points into the
//! linear-graph file. The bond-graph validator then checks it, so every later diagnostic
//! (a zero mass, an unknown symbol, a causal conflict in some mode) points at the
//! linear-graph file's line and branch, worded in the graph's terms ([`reword`](bondgraph_core::model::linear_graph::reword)).
//!
//! What the bond graph does not show, the graph keeps: the checked [`LinearGraph`](bondgraph_core::model::linear_graph::LinearGraph) (nodes,
//! branches, where each branch's across and through variables are in the bond graph) rides
//! on the [`Model`], for `across:BRANCH` and `through:BRANCH` outputs, for the normal tree of
//! each mode ([`bondgraph_core::normal_tree`]), which also decides which storage causality treats as
//! independent so that the states are the normal tree's, and for drawing the graph.
//!
//! The modules: [`format`](mod@format) (the file as serde reads it), `check` (the graph's own rules:
//! nodes, pieces, source loops and cut-sets), [`translate`] (to the bond graph), and
//! [`graph`] (the checked graph).
//!
//! # Example
//! ```
//! use bondgraph_core::model;
//! let model = bondgraph_ron::model::load_str("msd.lg.ron", r#"LinearGraph(
//!     name: "msd",
//!     parameters: {"m": (value: 2.0), "k": (value: 200.0), "b": (value: 4.0)},
//!     inputs: {"F": ()},
//!     ground: "g",
//!     branches: {
//!         "force": ThroughSource(value: "F", from: "g", to: "v1"),
//!         "mass": A(capacitance: "m", from: "v1", to: "g"),
//!         "spring": T(stiffness: "k", from: "v1", to: "g"),
//!         "damper": D(conductance: "b", from: "v1", to: "g"),
//!     },
//! )"#).unwrap();
//! // A force source, one 1-junction and three elements: the textbook bond graph.
//! assert_eq!(model.elements().len(), 5);
//! assert_eq!(model.linear_graph().unwrap().branches.len(), 4);
//!
//! let typo = bondgraph_ron::model::load_str("msd.lg.ron", r#"LinearGraph(name: "msd", ground: "g",
//!     parameters: {"m": (value: 2.0), "k": (value: 1.0)},
//!     branches: {"mass": A(capacitance: "m", from: "v1", to: "g"),
//!                "spring": T(stiffness: "k", from: "v1", to: "g"),
//!                "push": ThroughSource(value: "1", from: "g", to: "v2")})"#).unwrap_err();
//! assert_eq!(typo.first().message, "branch 'push' names node 'v2', which no other branch touches");
//! assert_eq!(typo.first().location.as_ref().unwrap().line, 5);
//! ```

mod check;
mod compose;
pub mod format;
pub mod translate;

use std::sync::Arc;

use bondgraph_core::model::linear_graph::{self as graph, Words};

use crate::model::parse::{FileKind, parse_file};
use bondgraph_core::diagnostics::Result;
use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;

use format::RawLinearGraph;

/// Parses, checks and translates the linear graph in `source`, and validates the bond graph
/// it becomes.
///
/// # Errors
/// The file's syntax error; the graph's problems (see `check`); or the validator's, each
/// pointing at its branch in `source`.
pub fn load(source: &Arc<SourceFile>) -> Result<Model> {
    let (raw, map) = parse_file::<RawLinearGraph>(source, FileKind::LinearGraph)?;
    use crate::model::compose::names_of as names;
    let dotted = crate::model::compose::dotted_names(
        source,
        &map,
        [
            ("parameter", names(&raw.parameters), &map.parameters[..]),
            ("input", names(&raw.inputs), &map.inputs[..]),
            ("branch", names(&raw.branches), &map.branches[..]),
            ("terminal", names(&raw.terminals), &map.terminals[..]),
        ],
    );
    if !dotted.is_empty() {
        return Err(bondgraph_core::diagnostics::Diagnostics(dotted));
    }
    let (raw, map, parts) = compose::compose(source, raw, map)?;
    check_and_validate(source, raw, &map, parts)
}

/// Checks the (flat) graph `raw`, translates it and validates the bond graph it becomes.
///
/// # Errors
/// The graph's problems (see `check`), or the validator's, each pointing at its branch.
pub(crate) fn check_and_validate(
    source: &Arc<SourceFile>,
    raw: RawLinearGraph,
    map: &bondgraph_core::model::source_map::SourceMap,
    parts: Vec<bondgraph_core::model::PartSpec>,
) -> Result<Model> {
    let topology = check::check(source, &raw, map)?;
    let mut translated = translate::translate(&raw, map, &topology);
    translated.raw.parts = parts;
    let names: Vec<String> = translated
        .raw
        .elements
        .iter()
        .map(|(n, _)| n.clone())
        .collect();
    let bonds: Vec<(usize, usize)> = translated
        .raw
        .bonds
        .iter()
        .filter_map(|b| {
            let at = |name: &str| names.iter().position(|n| n == name);
            Some((at(&b.0)?, at(&b.1)?))
        })
        .collect();
    let words = Words::new(&translated.graph, &names, &bonds, &translated.fields);
    bondgraph_core::model::validate::validate_linear_graph(
        source,
        translated.raw,
        &translated.map,
        translated.graph,
    )
    .map_err(|d| words.apply(d))
}

/// The parameters of the linear graph in `source` with its sub-graphs flattened (a
/// sub-graph's named `wall.R_w`), or `None` if it does not compose.
pub(crate) fn composed_parameters(
    source: &SourceFile,
) -> Option<Vec<(String, bondgraph_core::model::ParameterSpec)>> {
    let (raw, map) = parse_file::<RawLinearGraph>(source, FileKind::LinearGraph).ok()?;
    let (raw, _, _) = compose::compose(source, raw, map).ok()?;
    Some(raw.parameters)
}

/// The linear graph in `source` in the shape [`edit`](crate::model::edit) edits: a raw
/// model whose elements are the branches (their kinds left out) and has no bonds, with the
/// source map of the branches as its elements.
///
/// # Errors
/// The file's syntax error.
pub(crate) fn editable(
    source: &SourceFile,
) -> Result<(
    bondgraph_core::model::spec::ModelSpec,
    bondgraph_core::model::source_map::SourceMap,
)> {
    let (raw, map) = parse_file::<RawLinearGraph>(source, FileKind::LinearGraph)?;
    let model = bondgraph_core::model::spec::ModelSpec {
        name: raw.name,
        description: raw.description,
        parameters: raw.parameters,
        inputs: raw.inputs,
        elements: raw
            .branches
            .into_iter()
            .map(|(name, branch)| {
                // A sub-graph's use is edited like a sub-model's (its parameters set in it).
                let element = match branch {
                    format::RawBranch::Subgraph {
                        file,
                        parameters,
                        inputs,
                        ..
                    } => bondgraph_core::model::spec::ElementSpec::Submodel {
                        file,
                        parameters,
                        inputs,
                    },
                    _ => bondgraph_core::model::spec::ElementSpec::One,
                };
                (name, element)
            })
            .collect(),
        bonds: Vec::new(),
        ports: Vec::new(),
        parts: Vec::new(),
    };
    let map = bondgraph_core::model::source_map::SourceMap {
        elements: map.branches.clone(),
        ..map
    };
    Ok((model, map))
}
