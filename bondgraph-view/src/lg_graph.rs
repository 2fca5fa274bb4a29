//! `bondgraph graph` on a linear graph: its nodes, its branches and the normal tree of the
//! mode, as text, Graphviz DOT or SVG ([`crate::lg_svg`]). A bond graph is drawn by
//! [`crate::graph`].

use std::sync::Arc;

use bondgraph_core::laws;
use bondgraph_core::model::Model;
use bondgraph_core::model::linear_graph::LinearGraph;
use bondgraph_core::modes::Mode;
use bondgraph_core::normal_tree::{self, NormalTree};
use bondgraph_core::source::SourceFile;

use crate::Failure;
use crate::formats::GraphFormat;

/// The linear graph of `model` in `mode`, in `format`.
///
/// # Errors
/// A failure when the mode is one the model cannot be in (its causality conflicts), in the
/// graph's words.
pub fn render(
    model: &Model,
    graph: &LinearGraph,
    mode: &Mode,
    format: GraphFormat,
    source: &Arc<SourceFile>,
) -> Result<String, Failure> {
    let laws = laws::for_mode(model, mode);
    // The mode must be one the model can be in: causality says so, in the graph's words.
    bondgraph_core::causality::assign(model, &laws).map_err(|d| {
        crate::with_source(
            bondgraph_core::model::linear_graph::reword(model, d),
            source,
        )
    })?;
    let tree = normal_tree::of_mode(model, &laws).ok_or_else(|| {
        Failure::message(
            bondgraph_core::DiagnosticKind::CausalConflict,
            "the mode has no normal tree",
        )
    })?;
    let spec = mode.spec(model);
    Ok(match format {
        GraphFormat::Text => describe(model, graph, &tree, &spec),
        GraphFormat::Dot => to_dot(model, graph, &tree),
        GraphFormat::Svg => crate::lg_svg::draw(model, graph, &tree, &spec),
    })
}

/// The graph and its normal tree as text.
pub fn describe(model: &Model, graph: &LinearGraph, tree: &NormalTree, spec: &str) -> String {
    let mut out = format!(
        "linear graph '{}': {} nodes (ground '{}'), {} branches\n\nnodes:\n",
        model.name(),
        graph.nodes.len(),
        graph.node(graph.ground).name,
        graph.branches.len()
    );
    let label = |n: usize| {
        let name = &graph.nodes[n].name;
        if n == graph.ground.index() {
            format!("{name} (ground)")
        } else {
            name.clone()
        }
    };
    let width = (0..graph.nodes.len())
        .map(|n| label(n).len())
        .max()
        .unwrap_or(0);
    for n in 0..graph.nodes.len() {
        let touching: Vec<String> = graph
            .edges()
            .filter(|(_, _, e)| e.from.index() == n || e.to.index() == n)
            .map(|(b, p, _)| graph.edge_name(b, p))
            .collect();
        out.push_str(&format!("  {:width$}  {}\n", label(n), touching.join(", ")));
    }
    out.push_str("\nbranches (from -> to):\n");
    let name_width = graph
        .edges()
        .map(|(b, p, _)| graph.edge_name(b, p).len())
        .max()
        .unwrap_or(0);
    for (b, p, edge) in graph.edges() {
        let branch = &graph.branches[b];
        let role = tree.roles[b][p];
        let kind = branch.kind.description();
        let role_text = if role.description() == kind
            || (branch.kind.is_two_port() && role.description().starts_with(kind))
        {
            String::new()
        } else {
            format!(" (here: {})", role.description())
        };
        out.push_str(&format!(
            "  {:name_width$}  {:<19} {} -> {}  {}{role_text}\n",
            graph.edge_name(b, p),
            kind,
            graph.node(edge.from).name,
            graph.node(edge.to).name,
            branch.value
        ));
    }
    let names = |edges: Vec<(usize, usize)>| -> String {
        let names: Vec<String> = edges
            .into_iter()
            .map(|(b, p)| graph.edge_name(b, p))
            .collect();
        if names.is_empty() {
            "(none)".to_string()
        } else {
            names.join(", ")
        }
    };
    let mode = if spec.is_empty() {
        String::new()
    } else {
        format!(" in mode {spec}")
    };
    out.push_str(&format!("\nnormal tree{mode}:\n"));
    out.push_str(&format!(
        "  tree:   {}\n",
        names(tree.tree_edges().collect())
    ));
    out.push_str(&format!("  links:  {}\n", names(tree.links().collect())));
    let states = tree.states(graph);
    out.push_str(&format!(
        "  states: {}\n",
        if states.is_empty() {
            "(none)".to_string()
        } else {
            states.join(", ")
        }
    ));
    let dependent = tree.dependent_storage();
    if !dependent.is_empty() {
        out.push_str(&format!(
            "  dependent storage: {}\n",
            names(dependent.into_iter().map(|b| (b, 0)).collect())
        ));
    }
    out
}

/// The graph as Graphviz DOT: tree branches solid and bold, links dashed.
pub fn to_dot(model: &Model, graph: &LinearGraph, tree: &NormalTree) -> String {
    let quote = |s: &str| format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""));
    let mut out = format!(
        "digraph {} {{\n  // linear graph: tree branches bold, links dashed\n  node [shape=circle];\n",
        quote(model.name())
    );
    for (n, node) in graph.nodes.iter().enumerate() {
        let shape = if n == graph.ground.index() {
            ", shape=doublecircle"
        } else {
            ""
        };
        out.push_str(&format!("  n{n} [label={}{shape}];\n", quote(&node.name)));
    }
    for (b, p, edge) in graph.edges() {
        let style = if tree.in_tree[b][p] {
            "style=bold, penwidth=2.5"
        } else {
            "style=dashed"
        };
        let label = format!(
            "{}\n{}",
            graph.edge_name(b, p),
            tree.roles[b][p].description()
        );
        out.push_str(&format!(
            "  n{} -> n{} [label={}, {style}];\n",
            edge.from.index(),
            edge.to.index(),
            quote(&label)
        ));
    }
    out.push_str("}\n");
    out
}
