//! A linear graph kept beside the bond graph it became: the checked [`LinearGraph`] (nodes,
//! branches, the element and junctions of each branch), from which its normal tree, its
//! drawings and its words come, and [`Words`], which say a diagnostic about the bond graph
//! in the linear graph's terms (`A-type 'mass'` rather than `inertia 'mass'`).
//!
//! Linear-graph files are read, checked and translated into a bond graph by
//! `bondgraph-ron`; the model then goes through the one validator.

pub(crate) mod graph;

pub use graph::{Branch, BranchKind, Edge, JunctionOf, LinearGraph, Node, NodeId};

use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::model::Model;

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

/// Replacements from the bond graph's words to the linear graph's, for the diagnostics of
/// a linear graph's model.
pub struct Words {
    pairs: Vec<(String, String)>,
}

impl Words {
    /// The words for `graph`, translated into a bond graph whose elements are called
    /// `element_names` and whose bonds join `bonds` (element indices).
    pub fn new(
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

    /// `diagnostics` with the bond graph's words replaced by the linear graph's.
    pub fn apply(&self, diagnostics: Diagnostics) -> Diagnostics {
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
