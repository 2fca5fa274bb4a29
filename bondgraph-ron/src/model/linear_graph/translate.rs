//! From a checked linear graph to the raw bond-graph model (and its source map) that the
//! bond-graph validator checks.
//!
//! # The analogy
//! A linear graph's across variable is a bond graph's flow and its through variable the
//! effort (velocity and force; voltage and current; pressure and volume flow). So:
//!
//! - every node but the ground is a 1-junction: one across variable, the through variables
//!   of its branches summing to zero; the ground's across variable is zero, so its bonds are
//!   left out;
//! - every branch between nodes `a` and `b` is a 0-junction joining `1_a` and `1_b`, which
//!   carries the branch's through variable and gives its element the difference
//!   `v_a - v_b`: bonds `1_a -> 0 -> 1_b` and `0 -> element`, so that the element's flow is
//!   the branch's across variable, its effort the through variable, and their product the
//!   power into the branch;
//! - an A-type (mass, capacitor) is an inertia whose co-energy state is its across variable,
//!   a T-type (spring, inductor) a compliance whose co-energy state is its through variable,
//!   a D-type a resistor, an across source a flow source, a through source an effort source;
//! - a transformer `v_1 = N v_2` is a `TF(N)` from its secondary port to its primary, a
//!   gyrator `v_1 = G f_2` a gyrator of modulus `1/G`.
//!
//! An across source's value is its across variable `v_from - v_to`, but a flow source's
//! value is the flow *out of* it; its 0-junction therefore joins `1_to -> 0 -> 1_from`,
//! which makes the flow out of the source exactly `v_from - v_to` (and its effort minus the
//! branch's through variable). A transformer's or gyrator's primary port is joined the same
//! way, since the two-port's bond there points out of it.
//!
//! # Simplification
//! The junctions this builds are mostly trivial: every branch to the ground leaves a
//! 0-junction with two bonds, and a node between two branches a 1-junction with two. A
//! two-bond junction with one bond in and one out is replaced by one bond, which changes no
//! variable. A two-bond 0-junction with both bonds the same way, next to a one-port element,
//! is replaced by one bond whose direction at the other end is kept: the element's laws are
//! written with the sign of its bond (`sign_into`), so its across and through variables come
//! out the same. What is left is the bond graph a textbook would draw: the mass-spring-damper
//! is a force source, a 1-junction and three elements.
//!
//! Names: every element keeps its branch's name, so states are `v_mass` and `f_spring` as in
//! the linear graph; a node's 1-junction takes the node's name where it is a free name, and
//! a branch's 0-junction the branch's name with `_j`.

use std::collections::HashSet;

use bondgraph_core::model::source_map::{EntrySpans, FieldSpan, ItemSpans, SourceMap};
use bondgraph_core::model::spec::{BondSpec, ElementSpec, ModelSpec};
use bondgraph_core::model::{BondId, ElementId};
use bondgraph_core::source::Span;

use super::check::Topology;
use super::format::{RawBranch, RawLinearGraph};
use super::graph::{Branch, BranchKind, Edge, JunctionOf, LinearGraph, NodeId};

/// The translation: the raw bond graph, its synthetic source map (every span in the
/// linear-graph file), the linear graph as it sits in the bond graph, and the words to
/// translate the validator's diagnostics back.
pub(crate) struct Translated {
    pub raw: ModelSpec,
    pub map: SourceMap,
    pub graph: LinearGraph,
    /// `(bond-graph field, linear-graph field)` per branch, for diagnostics.
    pub fields: Vec<Vec<(&'static str, &'static str)>>,
}

/// What a draft element is.
#[derive(Clone, Debug)]
enum Draft {
    /// A node's 1-junction.
    Node(NodeId),
    /// A branch's 0-junction at one port.
    Junction(usize, usize),
    /// A branch's element.
    Element(usize),
}

#[derive(Clone, Debug)]
struct DraftElement {
    what: Draft,
    name: String,
    raw: ElementSpec,
    alive: bool,
    /// Kept by the simplification however few its bonds (a terminal's node).
    keep: bool,
}

#[derive(Clone, Copy, Debug)]
struct DraftBond {
    from: usize,
    to: usize,
    /// The branch (and port) whose structure made the bond, for its span.
    branch: usize,
    port: usize,
    alive: bool,
}

/// Translates `raw` (checked into `topology`, positions in `map`).
pub(crate) fn translate(raw: &RawLinearGraph, map: &SourceMap, topology: &Topology) -> Translated {
    let Drafted {
        mut elements,
        mut bonds,
        element_of_branch,
        fields,
    } = draft(raw, topology);
    // A terminal's node keeps its junction: it is the port the outside's branches join.
    let terminal_node = |name: &str| topology.nodes.iter().position(|n| n.name == name);
    let terminals: Vec<(String, usize)> = raw
        .terminals
        .iter()
        .filter_map(|(terminal, t)| Some((terminal.clone(), terminal_node(&t.node)?)))
        .filter(|(_, n)| *n != topology.ground.index())
        .collect();
    for element in &mut elements {
        if let Draft::Node(n) = element.what
            && terminals.iter().any(|(_, t)| *t == n.index())
        {
            element.keep = true;
        }
    }
    simplify(&mut elements, &mut bonds);
    let ports = terminals
        .iter()
        .filter_map(|(terminal, n)| {
            let junction = elements
                .iter()
                .find(|e| e.alive && matches!(e.what, Draft::Node(m) if m.index() == *n))?;
            Some((
                terminal.clone(),
                bondgraph_core::model::PortSpec {
                    element: junction.name.clone(),
                    description: None,
                },
            ))
        })
        .collect();
    let emitted = emit(&elements, &bonds, map, topology, &fields);
    let new_index = &emitted.new_index;
    let branches = branches(raw, map, topology, &bonds, &element_of_branch, &emitted);
    let junctions = elements
        .iter()
        .enumerate()
        .filter(|(_, e)| e.alive)
        .filter_map(|(i, e)| {
            let of = match e.what {
                Draft::Node(n) => JunctionOf::Node(n),
                Draft::Junction(b, p) => JunctionOf::Branch(b, p),
                Draft::Element(_) => return None,
            };
            Some((ElementId(new_index[i] as u32), of))
        })
        .collect();

    let mut map_fields = map.fields.clone();
    if let Some(branches_field) = map.field("branches") {
        for alias in ["elements", "bonds"] {
            map_fields.push(FieldSpan {
                name: alias.to_string(),
                ..branches_field.clone()
            });
        }
    }
    Translated {
        raw: ModelSpec {
            name: raw.name.clone(),
            description: raw.description.clone(),
            parameters: raw.parameters.clone(),
            inputs: raw.inputs.clone(),
            elements: emitted.raw_elements,
            bonds: emitted.raw_bonds,
            ports,
            parts: Vec::new(),
        },
        map: SourceMap {
            root: map.root,
            fields: map_fields,
            parameters: map.parameters.clone(),
            inputs: map.inputs.clone(),
            elements: emitted.element_spans,
            bonds: emitted.bond_spans,
            ..SourceMap::default()
        },
        graph: LinearGraph {
            nodes: topology.nodes.clone(),
            ground: topology.ground,
            branches,
            junctions,
        },
        fields,
    }
}

/// The draft of a translation, before simplification: a 1-junction per node (ground
/// apart), a 0-junction per port, each branch's element, and the bonds between them.
struct Drafted {
    elements: Vec<DraftElement>,
    bonds: Vec<DraftBond>,
    /// The draft index of each branch's element.
    element_of_branch: Vec<usize>,
    /// `(bond-graph field, linear-graph field)` per branch, for diagnostics.
    fields: Vec<Vec<(&'static str, &'static str)>>,
}

/// Drafts the bond graph of `raw`: fresh names for the junctions, the branches' elements
/// under their own names.
fn draft(raw: &RawLinearGraph, topology: &Topology) -> Drafted {
    let mut taken: HashSet<String> = raw
        .branches
        .iter()
        .map(|(n, _)| n.clone())
        .chain(raw.parameters.iter().map(|(n, _)| n.clone()))
        .chain(raw.inputs.iter().map(|(n, _)| n.clone()))
        .collect();
    let mut fresh = |base: String| -> String {
        let mut name = base.clone();
        let mut k = 2;
        while taken.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        taken.insert(name.clone());
        name
    };

    let mut elements: Vec<DraftElement> = Vec::new();
    let mut node_junction: Vec<Option<usize>> = vec![None; topology.nodes.len()];
    for (n, node) in topology.nodes.iter().enumerate() {
        if n == topology.ground.index() {
            continue;
        }
        node_junction[n] = Some(elements.len());
        elements.push(DraftElement {
            what: Draft::Node(NodeId(n as u32)),
            name: fresh(identifier(&node.name, "node")),
            raw: ElementSpec::One,
            alive: true,
            keep: false,
        });
    }
    let mut bonds: Vec<DraftBond> = Vec::new();
    let mut element_of_branch = Vec::new();
    let mut fields = Vec::new();
    for (b, (name, branch)) in raw.branches.iter().enumerate() {
        let ports = &topology.ports[b];
        let mut junctions = Vec::new();
        for p in 0..ports.len() {
            let suffix = match (ports.len(), p) {
                (1, _) => "j",
                (_, 0) => "primary",
                _ => "secondary",
            };
            junctions.push(elements.len());
            elements.push(DraftElement {
                what: Draft::Junction(b, p),
                name: fresh(identifier(&format!("{name}_{suffix}"), "branch")),
                raw: ElementSpec::Zero,
                alive: true,
                keep: false,
            });
        }
        let (element, element_fields) = element_of(branch);
        fields.push(element_fields);
        let e = elements.len();
        element_of_branch.push(e);
        elements.push(DraftElement {
            what: Draft::Element(b),
            name: name.clone(),
            raw: element,
            alive: true,
            keep: false,
        });
        for (p, port) in ports.iter().enumerate() {
            let j = junctions[p];
            // The port's 0-junction between its nodes: `1_from -> 0 -> 1_to` for a passive
            // port, the other way round for a port whose element bond points into the
            // junction (an across source, a two-port's primary).
            let reversed = is_reversed(branch, p);
            let (into, out_of) = if reversed {
                (port.to, port.from)
            } else {
                (port.from, port.to)
            };
            let mut bond = |from: usize, to: usize| {
                bonds.push(DraftBond {
                    from,
                    to,
                    branch: b,
                    port: p,
                    alive: true,
                })
            };
            if let Some(n) = node_junction[into.index()] {
                bond(n, j);
            }
            if let Some(n) = node_junction[out_of.index()] {
                bond(j, n);
            }
            if reversed {
                bond(e, j);
            } else {
                bond(j, e);
            }
        }
    }

    Drafted {
        elements,
        bonds,
        element_of_branch,
        fields,
    }
}

/// The survivors of simplification as a model spec's elements and bonds, with their spans
/// in the linear-graph file, and where each draft element and bond went.
struct Emitted {
    /// The new index of each draft element (`usize::MAX`: removed).
    new_index: Vec<usize>,
    raw_elements: Vec<(String, ElementSpec)>,
    element_spans: Vec<EntrySpans>,
    raw_bonds: Vec<BondSpec>,
    bond_spans: Vec<ItemSpans>,
    /// The new index of each draft bond (`usize::MAX`: removed).
    bond_index: Vec<usize>,
}

/// Emits the survivors, in draft order: node junctions, then each branch's junctions and
/// element.
fn emit(
    elements: &[DraftElement],
    bonds: &[DraftBond],
    map: &SourceMap,
    topology: &Topology,
    fields: &[Vec<(&'static str, &'static str)>],
) -> Emitted {
    let mut new_index = vec![usize::MAX; elements.len()];
    let mut raw_elements = Vec::new();
    let mut element_spans = Vec::new();
    for (i, element) in elements.iter().enumerate() {
        if !element.alive {
            continue;
        }
        new_index[i] = raw_elements.len();
        raw_elements.push((element.name.clone(), element.raw.clone()));
        element_spans.push(entry_spans(element, map, topology, fields));
    }
    let mut raw_bonds = Vec::new();
    let mut bond_spans = Vec::new();
    let mut bond_index = vec![usize::MAX; bonds.len()];
    for (i, bond) in bonds.iter().enumerate() {
        if !bond.alive {
            continue;
        }
        bond_index[i] = raw_bonds.len();
        raw_bonds.push(BondSpec(
            elements[bond.from].name.clone(),
            elements[bond.to].name.clone(),
        ));
        let port = topology.ports[bond.branch][bond.port];
        let span = map.branches.get(bond.branch).map_or(map.root, |e| e.span());
        bond_spans.push(ItemSpans {
            span,
            strings: vec![
                (elements[bond.from].name.clone(), port.from_span),
                (elements[bond.to].name.clone(), port.to_span),
            ],
        });
    }

    Emitted {
        new_index,
        raw_elements,
        element_spans,
        raw_bonds,
        bond_spans,
        bond_index,
    }
}

/// Where each branch's across and through variables are in the emitted bond graph.
fn branches(
    raw: &RawLinearGraph,
    map: &SourceMap,
    topology: &Topology,
    bonds: &[DraftBond],
    element_of_branch: &[usize],
    emitted: &Emitted,
) -> Vec<Branch> {
    let (new_index, bond_index) = (&emitted.new_index, &emitted.bond_index);
    let mut branches = Vec::new();
    for (b, (name, branch)) in raw.branches.iter().enumerate() {
        let e = element_of_branch[b];
        let element_bonds: Vec<usize> = (0..bonds.len())
            .filter(|&i| bonds[i].alive && (bonds[i].from == e || bonds[i].to == e))
            .collect();
        let ports = &topology.ports[b];
        let edges = ports
            .iter()
            .enumerate()
            .map(|(p, port)| {
                // A one-port's only bond; a two-port's primary bond points out of it and its
                // secondary bond into it (simplification keeps the two-port's directions).
                let bond = if ports.len() == 1 {
                    element_bonds[0]
                } else {
                    let out = p == 0;
                    *element_bonds
                        .iter()
                        .find(|&&i| (bonds[i].from == e) == out)
                        .expect("a two-port keeps one bond in and one out")
                };
                let sign_into: i64 = if bonds[bond].to == e { 1 } else { -1 };
                let reversed = is_reversed(branch, p);
                Edge {
                    from: port.from,
                    to: port.to,
                    bond: BondId(bond_index[bond] as u32),
                    across_sign: if reversed { -sign_into } else { sign_into },
                    through_sign: if reversed { -1 } else { 1 },
                }
            })
            .collect();
        branches.push(Branch {
            name: name.clone(),
            kind: kind_of(branch),
            edges,
            value: value_of(branch),
            span: map.branches.get(b).map_or(map.root, |e| e.key_span),
            element: ElementId(new_index[e] as u32),
        });
    }
    branches
}

/// Whether port `port` of `branch` has its element bond pointing into its 0-junction.
fn is_reversed(branch: &RawBranch, port: usize) -> bool {
    match branch {
        RawBranch::AcrossSource { .. } => true,
        RawBranch::Transformer { .. } | RawBranch::Gyrator { .. } => port == 0,
        _ => false,
    }
}

/// Removes trivial two-bond junctions until none is left; see the module documentation.
fn simplify(elements: &mut [DraftElement], bonds: &mut [DraftBond]) {
    let one_port = |e: &DraftElement| {
        matches!(e.what, Draft::Element(_))
            && !matches!(
                e.raw,
                ElementSpec::TF { .. } | ElementSpec::GY { .. } | ElementSpec::ReciprocalGY { .. }
            )
    };
    loop {
        let mut changed = false;
        for j in 0..elements.len() {
            if !elements[j].alive
                || elements[j].keep
                || matches!(elements[j].what, Draft::Element(_))
            {
                continue;
            }
            let at: Vec<usize> = (0..bonds.len())
                .filter(|&i| bonds[i].alive && (bonds[i].from == j || bonds[i].to == j))
                .collect();
            let [first, second] = at[..] else {
                continue;
            };
            let (b1, b2) = (bonds[first], bonds[second]);
            let other = |b: &DraftBond| if b.from == j { b.to } else { b.from };
            let (x, y) = (other(&b1), other(&b2));
            let into = |b: &DraftBond| b.to == j;
            let replacement = if into(&b1) != into(&b2) {
                // One in, one out: a pass-through.
                let (source, target) = if into(&b1) { (x, y) } else { (y, x) };
                Some((source, target, b1))
            } else if matches!(elements[j].what, Draft::Junction(..)) {
                // A 0-junction with both bonds the same way: next to a one-port element,
                // keep the other end's direction.
                let (element, other_end, other_bond) = if one_port(&elements[x]) {
                    (x, y, b2)
                } else if one_port(&elements[y]) {
                    (y, x, b1)
                } else {
                    continue;
                };
                if into(&other_bond) {
                    // other -> J: now other -> element.
                    Some((other_end, element, other_bond))
                } else {
                    Some((element, other_end, other_bond))
                }
            } else {
                None
            };
            let Some((from, to, origin)) = replacement else {
                continue;
            };
            // The new bond takes the place of the first one it replaces, so that bond
            // order follows the file.
            elements[j].alive = false;
            bonds[first] = DraftBond {
                from,
                to,
                branch: origin.branch,
                port: origin.port,
                alive: true,
            };
            bonds[second].alive = false;
            changed = true;
        }
        if !changed {
            break;
        }
    }
}

/// A valid element name: `name` if it is an identifier (or identifiers joined by `.`, a
/// sub-graph's qualified name), else a readable transliteration (node `1` becomes `node_1`,
/// `front.1` becomes `front.node_1`).
fn identifier(name: &str, prefix: &str) -> String {
    if name.contains('.') {
        return name
            .split('.')
            .map(|part| identifier(part, prefix))
            .collect::<Vec<_>>()
            .join(".");
    }
    let cleaned: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    match cleaned.chars().next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => cleaned,
        _ => format!("{prefix}_{cleaned}"),
    }
}

/// The bond-graph element of a branch, and which of its fields are which branch fields.
fn element_of(branch: &RawBranch) -> (ElementSpec, Vec<(&'static str, &'static str)>) {
    match branch.clone() {
        // A law: the across variable is the bond graph's flow, the through its effort.
        RawBranch::A {
            capacitance,
            across,
            ..
        } => (
            ElementSpec::I {
                inertance: capacitance,
                flow: across,
                symbol: None,
            },
            vec![("inertance", "capacitance"), ("flow", "across")],
        ),
        RawBranch::T {
            inductance,
            stiffness,
            through,
            ..
        } => (
            ElementSpec::C {
                compliance: inductance,
                stiffness,
                effort: through,
                symbol: None,
            },
            vec![
                ("compliance", "inductance"),
                ("stiffness", "stiffness"),
                ("effort", "through"),
            ],
        ),
        RawBranch::D {
            resistance,
            conductance,
            through,
            across,
            ..
        } => match (resistance, conductance) {
            // A law: across is the bond graph's flow and through its effort.
            (None, None) if through.is_some() || across.is_some() => (
                ElementSpec::R {
                    resistance: None,
                    effort: through.map(|law| port_names_of_bond_graph(&law)),
                    flow: across.map(|law| port_names_of_bond_graph(&law)),
                },
                vec![("effort", "through"), ("flow", "across")],
            ),
            (Some(resistance), _) => (
                ElementSpec::Conductance {
                    conductance: resistance,
                },
                vec![("conductance", "resistance")],
            ),
            (None, conductance) => (
                ElementSpec::R {
                    resistance: Some(conductance.unwrap_or_default()),
                    effort: None,
                    flow: None,
                },
                vec![("resistance", "conductance")],
            ),
        },
        RawBranch::AcrossSource { value, .. } => {
            (ElementSpec::Sf { flow: value }, vec![("flow", "value")])
        }
        RawBranch::ThroughSource { value, .. } => {
            (ElementSpec::Se { effort: value }, vec![("effort", "value")])
        }
        RawBranch::Transformer { ratio, .. } => {
            (ElementSpec::TF { ratio }, vec![("ratio", "ratio")])
        }
        RawBranch::Gyrator { ratio, .. } => (
            ElementSpec::ReciprocalGY { ratio },
            vec![("ratio", "ratio")],
        ),
        RawBranch::Friction {
            breakaway,
            coulomb,
            viscous,
            dead_band,
            stribeck,
            initial,
            ..
        } => (
            ElementSpec::Friction {
                breakaway,
                coulomb,
                viscous,
                dead_band,
                stribeck,
                initial,
            },
            [
                "breakaway",
                "coulomb",
                "viscous",
                "dead_band",
                "stribeck",
                "initial",
            ]
            .into_iter()
            .map(|f| (f, f))
            .collect(),
        ),
        RawBranch::TensionOnly {
            inductance,
            stiffness,
            initial,
            ..
        } => (
            ElementSpec::TensionOnly {
                compliance: inductance,
                stiffness,
                initial,
                symbol: None,
            },
            vec![
                ("compliance", "inductance"),
                ("stiffness", "stiffness"),
                ("initial", "initial"),
            ],
        ),
        // Flattened before translation (`compose_graph`); the validator refuses it otherwise.
        RawBranch::Subgraph {
            file,
            parameters,
            inputs,
            ..
        } => (
            ElementSpec::Submodel {
                file,
                parameters,
                inputs,
            },
            Vec::new(),
        ),
    }
}

/// A D-type's law with the branch's `across` and `through` variables written as the bond
/// graph's `flow` and `effort`; every other name, and the layout, as written.
fn port_names_of_bond_graph(law: &str) -> String {
    let mut out = String::with_capacity(law.len());
    let mut rest = law;
    while let Some(start) = rest.find(|c: char| c.is_ascii_alphabetic() || c == '_') {
        out.push_str(&rest[..start]);
        let word = &rest[start..];
        let end = word
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(word.len());
        let after_digit = out.ends_with(|c: char| c.is_ascii_digit() || c == '.');
        out.push_str(match &word[..end] {
            "across" if !after_digit => "flow",
            "through" if !after_digit => "effort",
            other => other,
        });
        rest = &word[end..];
    }
    out.push_str(rest);
    out
}

fn kind_of(branch: &RawBranch) -> BranchKind {
    match branch {
        RawBranch::A { .. } => BranchKind::A,
        RawBranch::T { .. } => BranchKind::T,
        RawBranch::D { .. } => BranchKind::D,
        RawBranch::AcrossSource { .. } => BranchKind::AcrossSource,
        RawBranch::ThroughSource { .. } => BranchKind::ThroughSource,
        RawBranch::Transformer { .. } => BranchKind::Transformer,
        RawBranch::Gyrator { .. } => BranchKind::Gyrator,
        RawBranch::Friction { .. } => BranchKind::Friction,
        RawBranch::TensionOnly { .. } => BranchKind::TensionOnly,
        // Flattened before translation (`compose_graph`); a two-terminal element otherwise.
        RawBranch::Subgraph { .. } => BranchKind::D,
    }
}

/// The branch's main coefficient as written, with its field: `capacitance m`, `stiffness k`.
fn value_of(branch: &RawBranch) -> String {
    let either = |a: &Option<String>, an: &str, b: &Option<String>, bn: &str| match (a, b) {
        (Some(a), _) => format!("{an} {a}"),
        (None, Some(b)) => format!("{bn} {b}"),
        _ => String::new(),
    };
    match branch {
        RawBranch::A {
            capacitance,
            across,
            ..
        } => either(capacitance, "capacitance", across, "across"),
        RawBranch::T {
            through: Some(law), ..
        } => format!("through {law}"),
        RawBranch::T {
            inductance,
            stiffness,
            ..
        }
        | RawBranch::TensionOnly {
            inductance,
            stiffness,
            ..
        } => either(inductance, "inductance", stiffness, "stiffness"),
        RawBranch::D {
            resistance,
            conductance,
            through,
            across,
            ..
        } => match (through, across) {
            (Some(law), _) => format!("through {law}"),
            (None, Some(law)) => format!("across {law}"),
            _ => either(resistance, "resistance", conductance, "conductance"),
        },
        RawBranch::AcrossSource { value, .. } | RawBranch::ThroughSource { value, .. } => {
            value.clone()
        }
        RawBranch::Subgraph { file, .. } => format!("file {file}"),
        RawBranch::Transformer { ratio, .. } | RawBranch::Gyrator { ratio, .. } => {
            format!("ratio {ratio}")
        }
        RawBranch::Friction {
            breakaway, coulomb, ..
        } => format!("breakaway {breakaway}, coulomb {coulomb}"),
    }
}

/// The synthetic source-map entry of a draft element: a branch's element is its branch's
/// entry, with the bond-graph field names pointing at the branch's fields; a junction is
/// the branch, or the first mention of the node, it stands for.
fn entry_spans(
    element: &DraftElement,
    map: &SourceMap,
    topology: &Topology,
    fields: &[Vec<(&'static str, &'static str)>],
) -> EntrySpans {
    let kind = Some(raw_keyword(&element.raw).to_string());
    match element.what {
        Draft::Element(b) | Draft::Junction(b, _) => {
            let Some(entry) = map.branches.get(b) else {
                return empty_entry(element, map.root, kind);
            };
            let mapped = match element.what {
                Draft::Element(_) => fields[b]
                    .iter()
                    .filter_map(|(bg, lg)| {
                        entry.field(lg).map(|f| FieldSpan {
                            name: (*bg).to_string(),
                            ..f.clone()
                        })
                    })
                    .collect(),
                _ => Vec::new(),
            };
            EntrySpans {
                key: element.name.clone(),
                key_span: entry.key_span,
                value_span: entry.value_span,
                kind,
                fields: mapped,
            }
        }
        Draft::Node(n) => empty_entry(element, topology.nodes[n.index()].span, kind),
    }
}

fn empty_entry(element: &DraftElement, span: Span, kind: Option<String>) -> EntrySpans {
    EntrySpans {
        key: element.name.clone(),
        key_span: span,
        value_span: span,
        kind,
        fields: Vec::new(),
    }
}

fn raw_keyword(raw: &ElementSpec) -> &'static str {
    match raw {
        ElementSpec::Se { .. } => "Se",
        ElementSpec::Sf { .. } => "Sf",
        ElementSpec::I { .. } => "I",
        ElementSpec::C { .. } => "C",
        ElementSpec::R { .. } | ElementSpec::Conductance { .. } => "R",
        ElementSpec::TF { .. } => "TF",
        ElementSpec::GY { .. } | ElementSpec::ReciprocalGY { .. } => "GY",
        ElementSpec::Friction { .. } => "Friction",
        ElementSpec::TensionOnly { .. } => "TensionOnly",
        ElementSpec::FlowLimit { .. } => "FlowLimit",
        ElementSpec::Submodel { .. } => "Submodel",
        ElementSpec::Zero => "Zero",
        ElementSpec::One => "One",
    }
}

#[cfg(test)]
mod tests {
    use bondgraph_core::model::{ElementKind, Model};

    fn load(branches: &str) -> Model {
        crate::model::load_str(
            "t.lg.ron",
            &format!(
                r#"LinearGraph(name: "t", ground: "g",
                    parameters: {{"m": (value: 2.0), "k": (value: 3.0), "b": (value: 1.0)}},
                    inputs: {{"u": ()}}, branches: {{{branches}}})"#
            ),
        )
        .unwrap()
    }

    /// The bond graph as `kind name` per element and `from -> to` per bond.
    fn structure(model: &Model) -> (Vec<String>, Vec<String>) {
        let elements = model
            .elements()
            .iter()
            .map(|e| format!("{} {}", e.kind.keyword(), e.name))
            .collect();
        let bonds = model.bond_ids().map(|b| model.bond_label(b)).collect();
        (elements, bonds)
    }

    #[test]
    fn the_mass_spring_damper_becomes_the_textbook_bond_graph() {
        let model = load(
            r#""force": ThroughSource(value: "u", from: "g", to: "v1"),
               "mass": A(capacitance: "m", from: "v1", to: "g"),
               "spring": T(stiffness: "k", from: "v1", to: "g"),
               "damper": D(conductance: "b", from: "v1", to: "g")"#,
        );
        let (elements, bonds) = structure(&model);
        assert_eq!(
            elements,
            ["One v1", "Se force", "I mass", "C spring", "R damper"]
        );
        assert_eq!(
            bonds,
            ["force -> v1", "v1 -> mass", "v1 -> spring", "v1 -> damper"]
        );
        let graph = model.linear_graph().unwrap();
        // The mass's across variable is the flow into it, its through variable the effort.
        let mass = &graph.branches[1].edges[0];
        assert_eq!((mass.across_sign, mass.through_sign), (1, 1));
    }

    #[test]
    fn a_branch_from_the_ground_keeps_its_sign() {
        // An A-type written from the ground: its across variable is -v_1, so its bond points
        // out of it (the element counts its flow the other way) and its state is -v_1.
        let model = load(
            r#""push": ThroughSource(value: "u", from: "g", to: "n"),
               "mass": A(capacitance: "m", from: "g", to: "n"),
               "spring": T(stiffness: "k", from: "n", to: "g")"#,
        );
        let (_, bonds) = structure(&model);
        assert_eq!(bonds, ["push -> n", "mass -> n", "n -> spring"]);
        let graph = model.linear_graph().unwrap();
        assert_eq!(graph.branches[1].edges[0].across_sign, -1);
    }

    #[test]
    fn an_across_source_imposes_its_across_variable_and_a_resistance_is_a_conductance() {
        let model = load(
            r#""drive": AcrossSource(value: "u", from: "n", to: "g"),
               "damper": D(resistance: "k", from: "n", to: "g")"#,
        );
        // Node n joins just two branches, one bond in and one out: simplified away.
        let (elements, bonds) = structure(&model);
        assert_eq!(elements, ["Sf drive", "R damper"]);
        assert_eq!(bonds, ["drive -> damper"]);
        let graph = model.linear_graph().unwrap();
        // The flow out of the source is its across variable; its through variable runs the
        // other way through it.
        let drive = &graph.branches[0].edges[0];
        assert_eq!((drive.across_sign, drive.through_sign), (1, -1));
        // D(resistance: k): across = k through, so the bond graph's resistance is 1/k.
        let ElementKind::Resistor(c) = &model.element(graph.branches[1].element).kind else {
            panic!("a resistor");
        };
        assert_eq!(model.evaluate(&c.value), 1.0 / 3.0);
        assert_eq!(c.text, "1/(k)");
    }
}
