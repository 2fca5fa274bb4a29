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
//! linear-graph file's line and branch, worded in the graph's terms ([`reword`]).
//!
//! What the bond graph does not show, the graph keeps: the checked [`LinearGraph`] (nodes,
//! branches, where each branch's across and through variables are in the bond graph) rides
//! on the [`Model`], for `across:BRANCH` and `through:BRANCH` outputs, for the normal tree of
//! each mode ([`crate::normal_tree`]), which also decides which storage causality treats as
//! independent so that the states are the normal tree's, and for drawing the graph.
//!
//! The modules: [`format`](mod@format) (the file as serde reads it), `check` (the graph's own rules:
//! nodes, pieces, source loops and cut-sets), [`translate`] (to the bond graph), and
//! [`graph`] (the checked graph).
//!
//! # Example
//! ```
//! use bondgraph_core::model;
//! let model = model::load_str("msd.lg.ron", r#"LinearGraph(
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
//! assert_eq!(model.elements.len(), 5);
//! assert_eq!(model.linear_graph.as_ref().unwrap().branches.len(), 4);
//!
//! let typo = model::load_str("msd.lg.ron", r#"LinearGraph(name: "msd", ground: "g",
//!     parameters: {"m": (value: 2.0), "k": (value: 1.0)},
//!     branches: {"mass": A(capacitance: "m", from: "v1", to: "g"),
//!                "spring": T(stiffness: "k", from: "v1", to: "g"),
//!                "push": ThroughSource(value: "1", from: "g", to: "v2")})"#).unwrap_err();
//! assert_eq!(typo.first().message, "branch 'push' names node 'v2', which no other branch touches");
//! assert_eq!(typo.first().location.as_ref().unwrap().line, 5);
//! ```

mod check;
pub mod format;
pub mod graph;
pub mod translate;

use std::sync::Arc;

pub use graph::{Branch, BranchKind, Edge, JunctionOf, LinearGraph, Node, NodeId};

use crate::diagnostics::{Diagnostic, Diagnostics, Result};
use crate::model::Model;
use crate::model::parse::{FileKind, parse_file};
use crate::source::SourceFile;

use format::RawLinearGraph;

/// Parses, checks and translates the linear graph in `source`, and validates the bond graph
/// it becomes.
///
/// # Errors
/// The file's syntax error; the graph's problems (see `check`); or the validator's, each
/// pointing at its branch in `source`.
pub fn load(source: &Arc<SourceFile>) -> Result<Model> {
    let (raw, map) = parse_file::<RawLinearGraph>(source, FileKind::LinearGraph)?;
    let topology = check::check(source, &raw, &map)?;
    let translated = translate::translate(&raw, &map, &topology);
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
    let mut model = crate::model::validate::validate_as(
        source,
        translated.raw,
        &translated.map,
        crate::model::validate::units::Convention::LinearGraph,
    )
    .map_err(|d| words.apply(d))?;
    model.linear_graph = Some(Arc::new(translated.graph));
    Ok(model)
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
    crate::model::spec::ModelSpec,
    crate::model::source_map::SourceMap,
)> {
    let (raw, map) = parse_file::<RawLinearGraph>(source, FileKind::LinearGraph)?;
    let model = crate::model::spec::ModelSpec {
        name: raw.name,
        description: raw.description,
        parameters: raw.parameters,
        inputs: raw.inputs,
        elements: raw
            .branches
            .into_iter()
            .map(|(name, _)| (name, crate::model::spec::ElementSpec::One))
            .collect(),
        bonds: Vec::new(),
    };
    let map = crate::model::source_map::SourceMap {
        elements: map.branches.clone(),
        ..map
    };
    Ok((model, map))
}

/// `diagnostics` about `model` reworded in its linear graph's terms, if it has one: a
/// branch's element is called a branch (`A-type 'mass'` rather than `inertia 'mass'`), a
/// node's 1-junction the node.
pub fn reword(model: &Model, diagnostics: Diagnostics) -> Diagnostics {
    match &model.linear_graph {
        Some(graph) => {
            let names: Vec<String> = model.elements.iter().map(|e| e.name.clone()).collect();
            let bonds: Vec<(usize, usize)> = model
                .bonds
                .iter()
                .map(|b| (b.from.index(), b.to.index()))
                .collect();
            Words::new(graph, &names, &bonds, &[]).apply(diagnostics)
        }
        None => diagnostics,
    }
}

/// Replacements from the bond graph's words to the linear graph's.
struct Words {
    pairs: Vec<(String, String)>,
}

impl Words {
    /// The words for `graph`, translated into a bond graph whose elements are called
    /// `element_names` and whose bonds join `bonds` (element indices).
    fn new(
        graph: &LinearGraph,
        element_names: &[String],
        bonds: &[(usize, usize)],
        fields: &[Vec<(&'static str, &'static str)>],
    ) -> Self {
        let mut pairs = Vec::new();
        // Which branch each element belongs to (its element, or a 0-junction of a port).
        let branch_of = |index: usize| -> Option<&str> {
            let id = crate::model::ElementId(index as u32);
            match graph.junction(id) {
                Some(JunctionOf::Branch(b, _)) => Some(graph.branches[b].name.as_str()),
                Some(JunctionOf::Node(_)) => None,
                None => graph
                    .branch_of_element(id)
                    .map(|b| graph.branches[b].name.as_str()),
            }
        };
        for &(from, to) in bonds {
            let (Some(a), Some(b)) = (element_names.get(from), element_names.get(to)) else {
                continue;
            };
            if let Some(branch) = branch_of(from).or_else(|| branch_of(to)) {
                pairs.push((
                    format!("on bond {a} -> {b}"),
                    format!("at branch '{branch}'"),
                ));
                pairs.push((format!("bond {a} -> {b}"), format!("branch '{branch}'")));
            }
        }
        for (b, branch) in graph.branches.iter().enumerate() {
            let n = &branch.name;
            pairs.push((format!("element name '{n}'"), format!("branch name '{n}'")));
            for (bg, lg) in fields.get(b).map_or(&[][..], |f| &f[..]) {
                if bg != lg {
                    pairs.push((
                        format!("element '{n}': {bg} "),
                        format!("branch '{n}': {lg} "),
                    ));
                }
            }
            pairs.push((format!("element '{n}'"), format!("branch '{n}'")));
            for described in [
                "inertia",
                "compliance",
                "resistor",
                "effort source",
                "flow source",
                "transformer",
                "gyrator",
                "tension-only element",
            ] {
                pairs.push((
                    format!("{described} '{n}'"),
                    format!("{} '{n}'", branch.kind.description()),
                ));
            }
        }
        for (element, of) in &graph.junctions {
            let Some(name) = element_names.get(element.index()) else {
                continue;
            };
            match of {
                JunctionOf::Node(node) => {
                    let node = &graph.node(*node).name;
                    pairs.push((
                        format!("1-junction '{name}': its flow"),
                        format!("node '{node}': its across variable"),
                    ));
                    pairs.push((format!("1-junction '{name}'"), format!("node '{node}'")));
                }
                JunctionOf::Branch(b, _) => {
                    let branch = &graph.branches[*b].name;
                    pairs.push((
                        format!("0-junction '{name}': its effort"),
                        format!("branch '{branch}': its through variable"),
                    ));
                    pairs.push((format!("0-junction '{name}'"), format!("branch '{branch}'")));
                }
            }
        }
        Self { pairs }
    }

    fn apply(&self, diagnostics: Diagnostics) -> Diagnostics {
        Diagnostics(
            diagnostics
                .0
                .into_iter()
                .map(|d| Diagnostic {
                    message: self.text(&d.message),
                    notes: d.notes.iter().map(|n| self.text(n)).collect(),
                    ..d
                })
                .collect(),
        )
    }

    fn text(&self, text: &str) -> String {
        let mut out = text.to_string();
        for (from, to) in &self.pairs {
            if out.contains(from.as_str()) {
                out = out.replace(from.as_str(), to);
            }
        }
        out
    }
}
