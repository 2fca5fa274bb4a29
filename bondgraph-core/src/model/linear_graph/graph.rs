//! The checked linear graph: nodes, branches, and where each branch sits in the bond graph
//! the model was translated into.
//!
//! A [`Model`](crate::model::Model) read from a linear-graph file carries this value, so that
//! everything downstream of the bond graph can still speak of the linear graph: outputs
//! written `across:BRANCH` and `through:BRANCH`, the normal tree of a mode
//! ([`crate::normal_tree`]), and the drawings of `bondgraph graph`.

use crate::model::{BondId, ElementId};
use crate::source::Span;

/// Index of a node in [`LinearGraph::nodes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

impl NodeId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A node of the graph: a point of one across variable (a velocity, a voltage, a pressure).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Node {
    /// The name as written in the file.
    pub name: String,
    /// Where it is first named.
    pub span: Span,
}

/// What a branch is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BranchKind {
    /// Stores energy in its across variable (mass, capacitor, tank).
    A,
    /// Stores energy in its through variable (spring, inductor, fluid inertance).
    T,
    /// Dissipates (damper, resistor).
    D,
    /// Imposes its across variable.
    AcrossSource,
    /// Imposes its through variable.
    ThroughSource,
    /// A transformer two-port.
    Transformer,
    /// A gyrator two-port.
    Gyrator,
    /// A friction contact (switching).
    Friction,
    /// A tension-only T-type (switching).
    TensionOnly,
}

impl BranchKind {
    /// The kind as written in files.
    pub fn keyword(self) -> &'static str {
        match self {
            BranchKind::A => "A",
            BranchKind::T => "T",
            BranchKind::D => "D",
            BranchKind::AcrossSource => "AcrossSource",
            BranchKind::ThroughSource => "ThroughSource",
            BranchKind::Transformer => "Transformer",
            BranchKind::Gyrator => "Gyrator",
            BranchKind::Friction => "Friction",
            BranchKind::TensionOnly => "TensionOnly",
        }
    }

    /// A readable description ("A-type", "across source", ...).
    pub fn description(self) -> &'static str {
        match self {
            BranchKind::A => "A-type",
            BranchKind::T => "T-type",
            BranchKind::D => "D-type",
            BranchKind::AcrossSource => "across source",
            BranchKind::ThroughSource => "through source",
            BranchKind::Transformer => "transformer",
            BranchKind::Gyrator => "gyrator",
            BranchKind::Friction => "friction contact",
            BranchKind::TensionOnly => "tension-only T-type",
        }
    }

    /// Whether the branch is a two-port (two edges of the graph).
    pub fn is_two_port(self) -> bool {
        matches!(self, BranchKind::Transformer | BranchKind::Gyrator)
    }
}

/// One edge of the graph: a one-port branch, or one port of a two-port.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The node the edge starts at.
    pub from: NodeId,
    /// The node it ends at.
    pub to: NodeId,
    /// Where the edge's across variable and through variable are in the bond graph:
    /// `across = across_sign · flow(bond)` and `through = through_sign · effort(bond)`.
    pub bond: BondId,
    /// `+1` or `-1`.
    pub across_sign: i64,
    /// `+1` or `-1`.
    pub through_sign: i64,
}

/// A branch: an element between nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    /// The name as written (also the name of its element in the bond graph).
    pub name: String,
    /// What it is.
    pub kind: BranchKind,
    /// Its edges: one, or the primary and the secondary port of a two-port.
    pub edges: Vec<Edge>,
    /// Its coefficient or source value as written (`m`, `1/k` is written `stiffness: "k"`
    /// and kept as `k`), for display.
    pub value: String,
    /// The span of its name in the file.
    pub span: Span,
    /// Its element in the bond graph.
    pub element: ElementId,
}

/// A checked linear graph and its place in the translated bond graph.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearGraph {
    /// Every node, ground included, in the order first named.
    pub nodes: Vec<Node>,
    /// The reference node.
    pub ground: NodeId,
    /// Every branch, in file order.
    pub branches: Vec<Branch>,
    /// The junctions of the bond graph, each with the node it stands for (a 1-junction:
    /// the node's across variable) or the branch whose through variable it shares (a
    /// 0-junction); junctions the translation simplified away are not listed.
    pub junctions: Vec<(ElementId, JunctionOf)>,
}

/// What a junction of the translated bond graph stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JunctionOf {
    /// A node (a 1-junction: common across variable).
    Node(NodeId),
    /// One port of a branch (a 0-junction: common through variable), by branch and port.
    Branch(usize, usize),
}

impl LinearGraph {
    /// The node called `name`.
    pub fn node_named(&self, name: &str) -> Option<NodeId> {
        self.nodes
            .iter()
            .position(|n| n.name == name)
            .map(|i| NodeId(i as u32))
    }

    /// The node with id `id`.
    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id.index()]
    }

    /// The branch called `name`, by index.
    pub fn branch_named(&self, name: &str) -> Option<usize> {
        self.branches.iter().position(|b| b.name == name)
    }

    /// The branch whose element is `element`, by index.
    pub fn branch_of_element(&self, element: ElementId) -> Option<usize> {
        self.branches.iter().position(|b| b.element == element)
    }

    /// Every edge, as `(branch index, port index, edge)`, in branch order.
    pub fn edges(&self) -> impl Iterator<Item = (usize, usize, &Edge)> + '_ {
        self.branches
            .iter()
            .enumerate()
            .flat_map(|(b, branch)| branch.edges.iter().enumerate().map(move |(p, e)| (b, p, e)))
    }

    /// A name for edge `port` of branch `branch`: the branch's name, with `.primary` or
    /// `.secondary` for a two-port.
    pub fn edge_name(&self, branch: usize, port: usize) -> String {
        let b = &self.branches[branch];
        if b.kind.is_two_port() {
            format!(
                "{}.{}",
                b.name,
                if port == 0 { "primary" } else { "secondary" }
            )
        } else {
            b.name.clone()
        }
    }

    /// What the bond-graph junction `element` stands for, if it is one of the graph's.
    pub fn junction(&self, element: ElementId) -> Option<JunctionOf> {
        self.junctions
            .iter()
            .find(|(e, _)| *e == element)
            .map(|(_, j)| *j)
    }
}
