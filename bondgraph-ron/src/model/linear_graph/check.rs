//! The checks a linear graph must pass before it is translated: the graph's own rules, in the
//! graph's own words.
//!
//! The bond-graph validator checks expressions, values and names once the graph is
//! translated; what it cannot see, because the translation would hide it or word it in
//! junctions and bonds, is checked here on the nodes and branches as written:
//!
//! - every branch joins two different nodes, and every node is the end of at least two
//!   branches (a node touched once is a dangling branch or a misspelt node name: it is
//!   reported as an undefined node when another node's name is close, with the suggestion);
//! - the ground is a node of the graph, and every node reaches it through branches (a graph
//!   in pieces, or parts that meet only at the ground, which are separate systems);
//! - across sources form no loop (their across variables would have to sum to zero) and
//!   through sources no cut-set (their through variables would have to sum to zero);
//! - branches that take one of two fields (a T-type's inductance or stiffness, a D-type's
//!   resistance or conductance) give exactly one.
//!
//! Every problem found is reported at once, each at the branch and node it concerns.

use std::collections::HashMap;

use petgraph::unionfind::UnionFind;

use crate::source_map::{TokenKind, lex};
use bondgraph_core::diagnostics::suggest;
use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use bondgraph_core::model::source_map::{EntrySpans, SourceMap};
use bondgraph_core::source::{SourceFile, Span};

use super::format::{RawBranch, RawLinearGraph};
use super::graph::{Node, NodeId};

/// One port of a branch: its nodes and where each is named.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PortEnds {
    pub from: NodeId,
    pub to: NodeId,
    pub from_span: Span,
    pub to_span: Span,
}

/// The graph's nodes and every branch's ports, checked.
#[derive(Clone, Debug)]
pub(crate) struct Topology {
    pub nodes: Vec<Node>,
    pub ground: NodeId,
    /// Per branch (file order): one port, or primary and secondary.
    pub ports: Vec<Vec<PortEnds>>,
}

/// Checks `raw` (parsed from `file`, with positions in `map`).
///
/// # Errors
/// Every problem found; see the module documentation.
pub(crate) fn check(file: &SourceFile, raw: &RawLinearGraph, map: &SourceMap) -> Result<Topology> {
    let mut problems = Vec::new();
    let root = map.root;
    let branch_span = |i: usize| map.branches.get(i).map_or(root, |e| e.key_span);
    if raw.branches.is_empty() {
        let span = map.field("branches").map_or(root, |f| f.name_span);
        return Err(Diagnostic::new(
            DiagnosticKind::EmptyModel,
            format!("linear graph '{}' has no branches", raw.name),
        )
        .at(file, span)
        .note("add branches such as \"mass\": A(capacitance: \"m\", from: \"v1\", to: \"g\")")
        .into());
    }

    // Nodes, in the order first named; the ground first if it is named by the field.
    let ground_span = map
        .field("ground")
        .map_or(root, |f| f.string_content.unwrap_or(f.value_span));
    let mut nodes: Vec<Node> = Vec::new();
    let mut index: HashMap<String, NodeId> = HashMap::new();
    let mut intern = |name: &str, span: Span, nodes: &mut Vec<Node>| -> NodeId {
        *index.entry(name.to_string()).or_insert_with(|| {
            nodes.push(Node {
                name: name.to_string(),
                span,
            });
            NodeId(nodes.len() as u32 - 1)
        })
    };
    let ground = intern(&raw.ground, ground_span, &mut nodes);
    // How many branch ends touch each node, and the first branch that does.
    let mut touches: Vec<Vec<(usize, Span)>> = vec![Vec::new()];
    let mut ports: Vec<Vec<PortEnds>> = Vec::new();
    for (b, (name, branch)) in raw.branches.iter().enumerate() {
        let spans = node_spans(file.text(), map.branches.get(b), branch);
        let mut branch_ports = Vec::new();
        for (p, (from, to)) in branch.ports().into_iter().enumerate() {
            let (from_span, to_span) = spans
                .get(p)
                .copied()
                .unwrap_or((branch_span(b), branch_span(b)));
            let from_id = intern(from, from_span, &mut nodes);
            let to_id = intern(to, to_span, &mut nodes);
            touches.resize(nodes.len(), Vec::new());
            touches[from_id.index()].push((b, from_span));
            touches[to_id.index()].push((b, to_span));
            if from_id == to_id {
                let port = if branch.ports().len() == 2 {
                    if p == 0 { " (primary)" } else { " (secondary)" }
                } else {
                    ""
                };
                problems.push(
                    Diagnostic::new(
                        DiagnosticKind::SelfBond,
                        format!(
                            "branch '{name}'{port} goes from node '{from}' to node '{from}': a branch joins two different nodes"
                        ),
                    )
                    .at(file, to_span)
                    .element(name.clone()),
                );
            }
            branch_ports.push(PortEnds {
                from: from_id,
                to: to_id,
                from_span,
                to_span,
            });
        }
        ports.push(branch_ports);
        check_fields(
            file,
            name,
            branch,
            map.branches.get(b),
            branch_span(b),
            &mut problems,
        );
    }
    touches.resize(nodes.len(), Vec::new());

    check_touches(
        file,
        raw,
        &nodes,
        (ground, ground_span),
        &touches,
        &mut problems,
    );
    if !problems.is_empty() {
        return Err(Diagnostics(problems));
    }

    let topology = Topology {
        nodes,
        ground,
        ports,
    };
    // Source loops and cut-sets first: a node reached only through through sources is a
    // cut-set of sources before it is a separate part.
    check_sources(file, raw, map, &topology, &mut problems);
    if problems.is_empty() {
        check_connected(file, raw, map, &topology, &mut problems);
    }
    if problems.is_empty() {
        Ok(topology)
    } else {
        Err(Diagnostics(problems))
    }
}

/// Nodes touched once: a typo (another node's name is close), or a dangling branch; and a
/// ground that no branch touches.
fn check_touches(
    file: &SourceFile,
    raw: &RawLinearGraph,
    nodes: &[Node],
    (ground, ground_span): (NodeId, Span),
    touches: &[Vec<(usize, Span)>],
    problems: &mut Vec<Diagnostic>,
) {
    if touches[ground.index()].is_empty() {
        let mut d = Diagnostic::new(
            DiagnosticKind::UndefinedNode,
            format!("the ground '{}' is not a node of any branch", raw.ground),
        )
        .at(file, ground_span)
        .element(raw.ground.clone());
        let others = nodes.iter().skip(1).map(|n| n.name.as_str());
        if let Some(s) = suggest(&raw.ground, others) {
            d = d.note(format!("did you mean '{s}'?"));
        } else {
            let named: Vec<String> = nodes
                .iter()
                .skip(1)
                .take(6)
                .map(|n| format!("'{}'", n.name))
                .collect();
            d = d.note(format!(
                "the branches' nodes are {}; the ground must be one of them",
                named.join(", ")
            ));
        }
        problems.push(d);
    }
    for (n, node) in nodes.iter().enumerate() {
        let [(branch, span)] = touches[n][..] else {
            continue;
        };
        // A terminal's other branch is outside, where the graph is used as a sub-graph, and
        // so may be the ground's (one ground for the whole model).
        let is_ground = n == ground.index();
        if raw.terminals.iter().any(|(_, t)| t.node == node.name)
            || (is_ground && !raw.terminals.is_empty())
        {
            continue;
        }
        let branch_name = &raw.branches[branch].0;
        let others: Vec<&str> = nodes
            .iter()
            .enumerate()
            .filter(|&(m, _)| m != n && touches[m].len() >= 2)
            .map(|(_, other)| other.name.as_str())
            .collect();
        let diagnostic = match suggest(&node.name, others.iter().copied()) {
            Some(close) => Diagnostic::new(
                DiagnosticKind::UndefinedNode,
                format!(
                    "branch '{branch_name}' names node '{}', which no other branch touches",
                    node.name
                ),
            )
            .note(format!("did you mean '{close}'?")),
            None => Diagnostic::new(
                DiagnosticKind::DanglingNode,
                format!(
                    "node '{}' has only one branch, '{branch_name}': no through variable can flow through it",
                    node.name
                ),
            )
            .note(format!(
                "connect another branch to '{}', or end '{branch_name}' at a node of the graph",
                node.name
            )),
        };
        problems.push(diagnostic.at(file, span).element(branch_name.clone()));
    }
}

/// The spans of the node names of each port of a branch: the `from` and `to` strings, or
/// the two strings of each `(from, to)` pair of a two-port.
fn node_spans(text: &str, entry: Option<&EntrySpans>, branch: &RawBranch) -> Vec<(Span, Span)> {
    let Some(entry) = entry else {
        return Vec::new();
    };
    let fields: &[&str] = if branch.ports().len() == 2 {
        &["primary", "secondary"]
    } else {
        &["from", "to"]
    };
    if fields[0] == "from" {
        let span = |name: &str| entry.field(name).map_or(entry.key_span, |f| f.text_span());
        return vec![(span("from"), span("to"))];
    }
    fields
        .iter()
        .map(|name| {
            let Some(field) = entry.field(name) else {
                return (entry.key_span, entry.key_span);
            };
            let strings = strings_in(text, field.value_span);
            match strings[..] {
                [a, b, ..] => (a, b),
                _ => (field.value_span, field.value_span),
            }
        })
        .collect()
}

/// The contents of the string literals inside `span`.
fn strings_in(text: &str, span: Span) -> Vec<Span> {
    let mut out = Vec::new();
    let mut pos = span.start;
    while let Ok(Some(token)) = lex(text, pos) {
        if token.span.end > span.end {
            break;
        }
        if token.kind == TokenKind::Str {
            out.push(token.content);
        }
        pos = token.span.end;
    }
    out
}

/// A branch that takes exactly one of two fields gives exactly one.
fn check_fields(
    file: &SourceFile,
    name: &str,
    branch: &RawBranch,
    entry: Option<&EntrySpans>,
    span: Span,
    problems: &mut Vec<Diagnostic>,
) {
    let (a, b, what) = match branch {
        RawBranch::A {
            capacitance,
            across,
            ..
        } => (
            ("capacitance", capacitance.is_some()),
            ("across", across.is_some()),
            branch.keyword(),
        ),
        RawBranch::T {
            inductance,
            stiffness,
            through: Some(_),
            ..
        } if inductance.is_some() || stiffness.is_some() => {
            let second = if inductance.is_some() {
                "inductance"
            } else {
                "stiffness"
            };
            let at = entry
                .and_then(|e| e.field(second))
                .map_or(span, |f| f.name_span);
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::ConflictingFields,
                    format!("branch '{name}' gives both through and {second}; give one"),
                )
                .at(file, at)
                .element(name)
                .note("write inductance: \"...\" or stiffness: \"...\", or a law: through: \"EXPR of q_NAME\""),
            );
            return;
        }
        RawBranch::T {
            through: Some(_), ..
        } => return,
        RawBranch::T {
            inductance,
            stiffness,
            ..
        }
        | RawBranch::TensionOnly {
            inductance,
            stiffness,
            ..
        } => (
            ("inductance", inductance.is_some()),
            ("stiffness", stiffness.is_some()),
            branch.keyword(),
        ),
        RawBranch::D {
            resistance,
            conductance,
            through,
            across,
            ..
        } => {
            let given: Vec<&str> = [
                ("resistance", resistance),
                ("conductance", conductance),
                ("through", through),
                ("across", across),
            ]
            .into_iter()
            .filter(|(_, v)| v.is_some())
            .map(|(f, _)| f)
            .collect();
            if given.len() == 1 {
                return;
            }
            let (kind, message, at) = match given.as_slice() {
                [] => (
                    DiagnosticKind::MissingField,
                    format!("D branch '{name}' needs a resistance, a conductance or a law"),
                    span,
                ),
                [_, second, ..] => (
                    DiagnosticKind::ConflictingFields,
                    format!(
                        "branch '{name}' gives both {} and {second}; give one",
                        given[0]
                    ),
                    entry
                        .and_then(|e| e.field(second))
                        .map_or(span, |f| f.name_span),
                ),
                [_] => return,
            };
            problems.push(
                Diagnostic::new(kind, message).at(file, at).element(name).note(
                    "write resistance: \"...\" or conductance: \"...\", or a law: through: \"EXPR of across\" or across: \"EXPR of through\"",
                ),
            );
            return;
        }
        _ => return,
    };
    let (kind, message, at) = match (a.1, b.1) {
        (true, true) => (
            DiagnosticKind::ConflictingFields,
            format!("branch '{name}' gives both {} and {}; give one", a.0, b.0),
            entry
                .and_then(|e| e.field(b.0))
                .map_or(span, |f| f.name_span),
        ),
        (false, false) => (
            DiagnosticKind::MissingField,
            format!(
                "{what} branch '{name}' needs a {} or {}",
                a.0,
                match b.0 {
                    "across" => "an across law".to_string(),
                    other => format!("a {other}"),
                }
            ),
            span,
        ),
        _ => return,
    };
    problems.push(
        Diagnostic::new(kind, message)
            .at(file, at)
            .element(name)
            .note(format!("write {}: \"...\" or {}: \"...\"", a.0, b.0)),
    );
}

/// Every node reaches the ground through branches other than the ground itself: parts that
/// meet only at the ground (or not at all) are separate systems.
fn check_connected(
    file: &SourceFile,
    raw: &RawLinearGraph,
    map: &SourceMap,
    topology: &Topology,
    problems: &mut Vec<Diagnostic>,
) {
    let n = topology.nodes.len();
    // Nodes joined by branches, the ground left out; a two-port joins its two sides, which
    // exchange power through it.
    let mut pieces = UnionFind::<usize>::new(n);
    let mut touches_ground = vec![false; n];
    let ground = topology.ground.index();
    for ports in &topology.ports {
        let mut ends = Vec::new();
        for port in ports {
            let (a, b) = (port.from.index(), port.to.index());
            if a != ground && b != ground {
                pieces.union(a, b);
            }
            ends.extend([a, b]);
        }
        let inner: Vec<usize> = ends.into_iter().filter(|&e| e != ground).collect();
        for pair in inner.windows(2) {
            pieces.union(pair[0], pair[1]);
        }
    }
    for ports in &topology.ports {
        for port in ports {
            for (a, b) in [(port.from, port.to), (port.to, port.from)] {
                if b.index() == ground {
                    touches_ground[a.index()] = true;
                }
            }
        }
    }
    // Pieces, in the order of their first branch.
    let mut order: Vec<usize> = Vec::new();
    let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
    for (b, ports) in topology.ports.iter().enumerate() {
        let Some(node) = ports
            .iter()
            .flat_map(|p| [p.from.index(), p.to.index()])
            .find(|&x| x != ground)
        else {
            continue;
        };
        let root = pieces.find(node);
        if !members.contains_key(&root) {
            order.push(root);
        }
        members.entry(root).or_default().push(b);
    }
    if order.len() < 2 {
        return;
    }
    let grounded =
        |root: usize| (0..n).any(|x| x != ground && pieces.find(x) == root && touches_ground[x]);
    let describe = |branches: &[usize]| {
        let names: Vec<String> = branches
            .iter()
            .take(4)
            .map(|b| format!("'{}'", raw.branches[*b].0))
            .collect();
        let more = branches.len().saturating_sub(4);
        if more > 0 {
            format!("{{{}, and {more} more}}", names.join(", "))
        } else {
            format!("{{{}}}", names.join(", "))
        }
    };
    let listed: Vec<String> = order.iter().map(|r| describe(&members[r])).collect();
    let all_grounded = order.iter().all(|&r| grounded(r));
    let first_of_second = members[&order[1]][0];
    let (message, note) = if all_grounded {
        (
            format!(
                "the linear graph is in {} parts that meet only at the ground '{}': {}",
                order.len(),
                raw.ground,
                listed.join(" and ")
            ),
            "parts joined only by their reference do not interact: model them in separate files",
        )
    } else {
        (
            format!(
                "the linear graph is in {} pieces that no branch joins: {}",
                order.len(),
                listed.join(" and ")
            ),
            "join the pieces with branches; every node must reach the ground",
        )
    };
    problems.push(
        Diagnostic::new(DiagnosticKind::Disconnected, message)
            .at(
                file,
                map.branches
                    .get(first_of_second)
                    .map_or(map.root, |e| e.key_span),
            )
            .element(raw.branches[first_of_second].0.clone())
            .note(note),
    );
}

/// No loop of across sources, no cut-set of through sources.
fn check_sources(
    file: &SourceFile,
    raw: &RawLinearGraph,
    map: &SourceMap,
    topology: &Topology,
    problems: &mut Vec<Diagnostic>,
) {
    let n = topology.nodes.len();
    let is = |b: usize, across: bool| {
        matches!(
            (&raw.branches[b].1, across),
            (RawBranch::AcrossSource { .. }, true) | (RawBranch::ThroughSource { .. }, false)
        )
    };
    let span = |b: usize| map.branches.get(b).map_or(map.root, |e| e.key_span);
    let node_name = |id: NodeId| topology.nodes[id.index()].name.as_str();

    // Across sources, joined one by one: one that closes a loop contradicts the others.
    let mut joined = UnionFind::<usize>::new(n);
    let mut sources_so_far: Vec<usize> = Vec::new();
    for b in (0..raw.branches.len()).filter(|&b| is(b, true)) {
        let port = topology.ports[b][0];
        if joined.equiv(port.from.index(), port.to.index()) {
            let path = source_path(topology, &sources_so_far, port.from, port.to);
            let mut names: Vec<String> = path
                .iter()
                .map(|&s| format!("'{}'", raw.branches[s].0))
                .collect();
            names.push(format!("'{}'", raw.branches[b].0));
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::AcrossSourceLoop,
                    format!(
                        "across sources {} form a loop through nodes '{}' and '{}': their across variables would have to sum to zero",
                        names.join(", "),
                        node_name(port.from),
                        node_name(port.to)
                    ),
                )
                .at(file, span(b))
                .element(raw.branches[b].0.clone())
                .note("two sources cannot both set one across variable; remove one, or put a D-type or T-type branch in the loop"),
            );
        } else {
            joined.union(port.from.index(), port.to.index());
        }
        sources_so_far.push(b);
    }

    // Through sources: the rest of the graph must join their ends, or they alone cross a cut.
    let mut rest = UnionFind::<usize>::new(n);
    for (b, ports) in topology.ports.iter().enumerate() {
        if is(b, false) {
            continue;
        }
        for port in ports {
            rest.union(port.from.index(), port.to.index());
        }
    }
    let mut reported: Vec<usize> = Vec::new();
    for b in (0..raw.branches.len()).filter(|&b| is(b, false)) {
        let port = topology.ports[b][0];
        let side = rest.find(port.to.index());
        if rest.equiv(port.from.index(), port.to.index()) || reported.contains(&side) {
            continue;
        }
        reported.push(side);
        // Every through source with exactly one end on this side is in the cut-set.
        let crossing: Vec<String> = (0..raw.branches.len())
            .filter(|&s| is(s, false))
            .filter(|&s| {
                let p = topology.ports[s][0];
                (rest.find(p.from.index()) == side) != (rest.find(p.to.index()) == side)
            })
            .map(|s| format!("'{}'", raw.branches[s].0))
            .collect();
        let side_nodes: Vec<String> = (0..n)
            .filter(|&x| rest.find(x) == side)
            .take(4)
            .map(|x| format!("'{}'", topology.nodes[x].name))
            .collect();
        let side_nodes = format!(
            "{} {}",
            if side_nodes.len() == 1 {
                "node"
            } else {
                "nodes"
            },
            side_nodes.join(", ")
        );
        problems.push(
            Diagnostic::new(
                DiagnosticKind::ThroughSourceCutSet,
                format!(
                    "through sources {} form a cut-set: they alone join {side_nodes} to the rest of the graph, so their through variables would have to sum to zero",
                    crossing.join(", "),
                ),
            )
            .at(file, span(b))
            .element(raw.branches[b].0.clone())
            .note("give the through variable a path: an A-, D- or T-type branch from those nodes to the rest of the graph"),
        );
    }
}

/// The across sources among `sources` on a path from `from` to `to` (breadth-first).
fn source_path(topology: &Topology, sources: &[usize], from: NodeId, to: NodeId) -> Vec<usize> {
    let mut previous: HashMap<NodeId, (NodeId, usize)> = HashMap::new();
    let mut queue = std::collections::VecDeque::from([from]);
    let mut seen = vec![from];
    while let Some(node) = queue.pop_front() {
        if node == to {
            break;
        }
        for &s in sources {
            let p = topology.ports[s][0];
            let next = if p.from == node {
                p.to
            } else if p.to == node {
                p.from
            } else {
                continue;
            };
            if !seen.contains(&next) {
                seen.push(next);
                previous.insert(next, (node, s));
                queue.push_back(next);
            }
        }
    }
    let mut path = Vec::new();
    let mut at = to;
    while let Some(&(before, s)) = previous.get(&at) {
        path.push(s);
        at = before;
    }
    path.reverse();
    path
}
