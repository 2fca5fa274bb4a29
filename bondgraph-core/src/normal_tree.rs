//! The normal tree of a linear graph in one mode (Rowell & Wormley), and the equations it
//! gives: which variables are states, which are primary, and the continuity and
//! compatibility equations that relate the rest.
//!
//! A tree of the graph joins every node without a loop; each branch left out (a *link*)
//! closes one loop with the tree, and each tree branch, taken out, cuts the tree in two. The
//! normal tree takes branches in a fixed order of preference: across sources first, then
//! A-types, D-types and T-types, each in file order, a branch joining the tree when it
//! reaches a node the tree does not yet reach; through sources are links. So A-types sit in
//! the tree where they can (their across variables are states) and T-types are links where
//! they can (their through variables are states). An A-type that ends up a link, or a T-type
//! that must join the tree, is *dependent* storage: its variable is fixed by others, and the
//! derivation merges it into the states it follows.
//!
//! Transformers and gyrators are two branches each: a transformer puts exactly one of them
//! in the tree, a gyrator both or neither. The plain order can dead-end there (a gear
//! between two inertias: both inertias join the tree, then neither side of the gear can), so
//! every alternative for every two-port is tried, its tree branches placed right after the
//! across sources, and the tree kept that has the most A-types in the tree and then the
//! fewest T-types (the fewest dependent storage elements); among equals, the first (primary
//! side in the tree, both sides of a gyrator).
//!
//! In a mode, a switching branch takes its mode's role: a stuck friction contact is an
//! across source (zero relative velocity), a slipping one a D-type or a through source, a
//! slack string a through source (zero tension). [`crate::causality`] treats the tree's
//! storage as the independent storage, so that the states the bond-graph derivation gives
//! are the normal tree's.
//!
//! # Complexity
//! `O(2^k · E · N)` for `k` two-ports, `E` edges and `N` nodes (each edge's loop is found by a
//! search of the tree); `k` is at most [`MAX_TWO_PORTS`] (beyond that only the first
//! alternatives are tried).
//!
//! # Example
//! ```
//! use bondgraph_core::{laws, model, normal_tree};
//! let model = bondgraph_ron::model::load_str("msd.lg.ron", r#"LinearGraph(name: "msd", ground: "g",
//!     parameters: {"m": (value: 2.0), "k": (value: 200.0), "b": (value: 4.0)},
//!     inputs: {"F": ()},
//!     branches: {
//!         "force": ThroughSource(value: "F", from: "g", to: "v1"),
//!         "mass": A(capacitance: "m", from: "v1", to: "g"),
//!         "spring": T(stiffness: "k", from: "v1", to: "g"),
//!         "damper": D(conductance: "b", from: "v1", to: "g"),
//!     })"#).unwrap();
//! let tree = normal_tree::of_mode(&model, &laws::plain_laws(&model)).unwrap();
//! let graph = model.linear_graph().unwrap();
//! let in_tree: Vec<&str> = tree.tree_edges().map(|(b, _)| graph.branches[b].name.as_str()).collect();
//! assert_eq!(in_tree, ["mass"]);
//! assert_eq!(tree.states(graph), ["v_mass", "f_spring"]);
//! ```

use std::collections::VecDeque;

use crate::laws::Law;
use crate::model::linear_graph::{LinearGraph, NodeId};
use crate::model::{ElementId, Model, NonlinearLaw};

/// At most this many two-ports have all their alternatives tried (`2^k` trees).
pub const MAX_TWO_PORTS: usize = 12;

/// The role of an edge in the tree's order of preference, in one mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// Imposes its across variable (an across source, a stuck contact).
    AcrossSource,
    /// Stores energy in its across variable.
    A,
    /// Dissipates.
    D,
    /// Stores energy in its through variable.
    T,
    /// Imposes its through variable (a through source, a contact slipping without viscous
    /// friction, a slack string).
    ThroughSource,
    /// A port of a transformer.
    Transformer,
    /// A port of a gyrator.
    Gyrator,
}

impl Role {
    /// The role of a branch whose element has law `law` in the mode.
    pub fn of_law(law: &Law) -> Self {
        match law {
            Law::FlowSource(_) => Role::AcrossSource,
            Law::EffortSource(_) | Law::SlackStorage => Role::ThroughSource,
            Law::Inertia(_) => Role::A,
            Law::Compliance(_) => Role::T,
            Law::Resistor { .. } => Role::D,
            Law::Transformer(_) => Role::Transformer,
            Law::Gyrator(_) => Role::Gyrator,
            Law::Nonlinear(law) => match law.as_ref() {
                NonlinearLaw::EffortSource(_) => Role::ThroughSource,
                NonlinearLaw::FlowSource(_) => Role::AcrossSource,
                NonlinearLaw::Inertia(_) => Role::A,
                NonlinearLaw::Compliance(_) => Role::T,
                NonlinearLaw::Resistor(_) => Role::D,
                NonlinearLaw::Transformer(_) => Role::Transformer,
                NonlinearLaw::Gyrator(_) => Role::Gyrator,
            },
            // Never a branch's element: junctions stand for nodes and through variables.
            Law::ZeroJunction | Law::OneJunction => Role::D,
        }
    }

    /// How the role is named in explanations.
    pub fn description(self) -> &'static str {
        match self {
            Role::AcrossSource => "across source",
            Role::A => "A-type",
            Role::D => "D-type",
            Role::T => "T-type",
            Role::ThroughSource => "through source",
            Role::Transformer => "transformer port",
            Role::Gyrator => "gyrator port",
        }
    }
}

/// Why an edge joined the tree or became a link.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reason {
    /// It reached a node the tree did not reach yet.
    Reaches,
    /// It would have closed a loop with these tree edges (`(branch, port)`).
    ClosesLoop(Vec<(usize, usize)>),
    /// The two-port alternative chosen puts it in the tree.
    TwoPortInTree,
    /// The two-port alternative chosen leaves it out of the tree.
    TwoPortLink,
    /// A through source: always a link, unless nothing else reaches its node.
    Source,
}

/// One decision of the construction, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    /// The branch.
    pub branch: usize,
    /// The port (0 for a one-port).
    pub port: usize,
    /// Its role in the mode.
    pub role: Role,
    /// Whether it joined the tree.
    pub in_tree: bool,
    /// Why.
    pub reason: Reason,
}

/// One way of placing the two-ports, and what it gave.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Alternative {
    /// For each two-port (by branch), which ports it put in the tree.
    pub placement: Vec<(usize, Vec<usize>)>,
    /// Whether the tree could be built this way.
    pub feasible: bool,
    /// A-types in the tree.
    pub a_in_tree: usize,
    /// T-types in the tree.
    pub t_in_tree: usize,
}

/// The normal tree of one mode.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NormalTree {
    /// The role of every edge, by branch and port.
    pub roles: Vec<Vec<Role>>,
    /// Whether each edge is in the tree, by branch and port.
    pub in_tree: Vec<Vec<bool>>,
    /// The decisions, in the order taken.
    pub steps: Vec<Step>,
    /// The two-port alternatives tried (empty without two-ports), and the one chosen.
    pub alternatives: Vec<Alternative>,
    /// Which alternative was chosen.
    pub chosen: usize,
}

/// The normal tree of the mode whose laws are `laws`, if `model` is a linear graph.
pub fn of_mode(model: &Model, laws: &[Law]) -> Option<NormalTree> {
    let graph = model.linear_graph.as_ref()?;
    let roles = graph
        .branches
        .iter()
        .map(|b| vec![Role::of_law(&laws[b.element.index()]); b.edges.len()])
        .collect();
    Some(build(graph, roles))
}

/// Builds the normal tree of `graph` with the edge `roles` (by branch and port).
pub fn build(graph: &LinearGraph, roles: Vec<Vec<Role>>) -> NormalTree {
    let two_ports: Vec<usize> = graph
        .branches
        .iter()
        .enumerate()
        .filter(|(_, b)| b.kind.is_two_port())
        .map(|(i, _)| i)
        .collect();
    let tried = two_ports.len().min(MAX_TWO_PORTS);
    let mut best: Option<(usize, (bool, usize, usize), Attempt)> = None;
    let mut alternatives = Vec::new();
    for combination in 0..(1usize << tried) {
        let placement: Vec<(usize, Vec<usize>)> = two_ports
            .iter()
            .enumerate()
            .map(|(k, &b)| {
                let second = k < tried && combination & (1 << k) != 0;
                let ports = match (roles[b][0], second) {
                    (Role::Gyrator, false) => vec![0, 1],
                    (Role::Gyrator, true) => vec![],
                    (_, false) => vec![0],
                    (_, true) => vec![1],
                };
                (b, ports)
            })
            .collect();
        let attempt = attempt(graph, &roles, &placement);
        let count = |role: Role| {
            attempt
                .in_tree
                .iter()
                .zip(&roles)
                .flat_map(|(t, r)| t.iter().zip(r))
                .filter(|(t, r)| **t && **r == role)
                .count()
        };
        let (a, t) = (count(Role::A), count(Role::T));
        alternatives.push(Alternative {
            placement,
            feasible: attempt.feasible,
            a_in_tree: a,
            t_in_tree: t,
        });
        // Feasible first, then most A-types in the tree, then fewest T-types.
        let score = (attempt.feasible, a, usize::MAX - t);
        if best.as_ref().is_none_or(|(_, s, _)| score > *s) {
            best = Some((combination, score, attempt));
        }
    }
    let (chosen, _, attempt) = best.expect("at least one alternative");
    if two_ports.is_empty() {
        alternatives.clear();
    }
    NormalTree {
        roles,
        in_tree: attempt.in_tree,
        steps: attempt.steps,
        alternatives,
        chosen,
    }
}

struct Attempt {
    in_tree: Vec<Vec<bool>>,
    steps: Vec<Step>,
    feasible: bool,
}

/// The tree built with the two-ports placed as `placement` says.
fn attempt(graph: &LinearGraph, roles: &[Vec<Role>], placement: &[(usize, Vec<usize>)]) -> Attempt {
    let mut in_tree: Vec<Vec<bool>> = roles.iter().map(|r| vec![false; r.len()]).collect();
    let mut steps = Vec::new();
    let mut feasible = true;
    let mut tree = Forest::new(graph.nodes.len());
    let edge = |b: usize, p: usize| {
        let e = &graph.branches[b].edges[p];
        (e.from, e.to)
    };
    let consider = |b: usize,
                    p: usize,
                    tree: &mut Forest,
                    in_tree: &mut Vec<Vec<bool>>,
                    steps: &mut Vec<Step>| {
        let (from, to) = edge(b, p);
        let reason = match tree.path(from, to) {
            None => {
                tree.add(from, to, (b, p));
                in_tree[b][p] = true;
                Reason::Reaches
            }
            Some(path) => Reason::ClosesLoop(path),
        };
        steps.push(Step {
            branch: b,
            port: p,
            role: roles[b][p],
            in_tree: in_tree[b][p],
            reason,
        });
    };
    let edges_of = |role: Role| -> Vec<(usize, usize)> {
        roles
            .iter()
            .enumerate()
            .flat_map(|(b, r)| r.iter().enumerate().map(move |(p, role)| (b, p, *role)))
            .filter(|(_, _, r)| *r == role)
            .map(|(b, p, _)| (b, p))
            .collect()
    };
    for (b, p) in edges_of(Role::AcrossSource) {
        consider(b, p, &mut tree, &mut in_tree, &mut steps);
    }
    for (b, ports) in placement {
        for &p in ports {
            let (from, to) = edge(*b, p);
            let joined = tree.path(from, to).is_none();
            if joined {
                tree.add(from, to, (*b, p));
                in_tree[*b][p] = true;
            } else {
                feasible = false;
            }
            steps.push(Step {
                branch: *b,
                port: p,
                role: roles[*b][p],
                in_tree: joined,
                reason: if joined {
                    Reason::TwoPortInTree
                } else {
                    Reason::ClosesLoop(tree.path(from, to).unwrap_or_default())
                },
            });
        }
    }
    for role in [Role::A, Role::D, Role::T] {
        for (b, p) in edges_of(role) {
            consider(b, p, &mut tree, &mut in_tree, &mut steps);
        }
    }
    for (b, p) in edges_of(Role::ThroughSource) {
        let (from, to) = edge(b, p);
        // A through source joins the tree only where nothing else reaches its node: a
        // cut-set of sources, which the derivation reports in this mode's terms.
        let joined = tree.path(from, to).is_none();
        if joined {
            tree.add(from, to, (b, p));
            in_tree[b][p] = true;
        }
        steps.push(Step {
            branch: b,
            port: p,
            role: Role::ThroughSource,
            in_tree: joined,
            reason: Reason::Source,
        });
    }
    for (b, ports) in placement {
        for (p, &role) in roles[*b].iter().enumerate() {
            if ports.contains(&p) {
                continue;
            }
            let (from, to) = edge(*b, p);
            if tree.path(from, to).is_none() {
                // The tree cannot span without it.
                feasible = false;
            }
            steps.push(Step {
                branch: *b,
                port: p,
                role,
                in_tree: false,
                reason: Reason::TwoPortLink,
            });
        }
    }
    Attempt {
        in_tree,
        steps,
        feasible,
    }
}

/// A growing forest over the nodes, to find tree paths.
struct Forest {
    adjacent: Vec<Vec<(NodeId, (usize, usize))>>,
}

impl Forest {
    fn new(nodes: usize) -> Self {
        Self {
            adjacent: vec![Vec::new(); nodes],
        }
    }

    fn add(&mut self, a: NodeId, b: NodeId, edge: (usize, usize)) {
        self.adjacent[a.index()].push((b, edge));
        self.adjacent[b.index()].push((a, edge));
    }

    /// The edges of the forest path from `a` to `b`, if they are joined.
    fn path(&self, a: NodeId, b: NodeId) -> Option<Vec<(usize, usize)>> {
        let mut previous: Vec<Option<(NodeId, (usize, usize))>> = vec![None; self.adjacent.len()];
        let mut seen = vec![false; self.adjacent.len()];
        seen[a.index()] = true;
        let mut queue = VecDeque::from([a]);
        while let Some(node) = queue.pop_front() {
            if node == b {
                let mut path = Vec::new();
                let mut at = b;
                while let Some((before, edge)) = previous[at.index()] {
                    path.push(edge);
                    at = before;
                }
                path.reverse();
                return Some(path);
            }
            for &(next, edge) in &self.adjacent[node.index()] {
                if !seen[next.index()] {
                    seen[next.index()] = true;
                    previous[next.index()] = Some((node, edge));
                    queue.push_back(next);
                }
            }
        }
        None
    }
}

/// A signed sum of edge variables: `(branch, port, sign)`.
pub type Terms = Vec<(usize, usize, i64)>;

impl NormalTree {
    /// The tree's edges, as `(branch, port)`, in branch order.
    pub fn tree_edges(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.in_tree
            .iter()
            .enumerate()
            .flat_map(|(b, ports)| ports.iter().enumerate().map(move |(p, t)| (b, p, *t)))
            .filter(|(_, _, t)| *t)
            .map(|(b, p, _)| (b, p))
    }

    /// The links, as `(branch, port)`, in branch order.
    pub fn links(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.in_tree
            .iter()
            .enumerate()
            .flat_map(|(b, ports)| ports.iter().enumerate().map(move |(p, t)| (b, p, *t)))
            .filter(|(_, _, t)| !*t)
            .map(|(b, p, _)| (b, p))
    }

    /// The independent storage branches: A-types in the tree and T-types among the links,
    /// in branch order.
    pub fn independent_storage(&self) -> Vec<usize> {
        (0..self.roles.len())
            .filter(|&b| match self.roles[b][0] {
                Role::A => self.in_tree[b][0],
                Role::T => !self.in_tree[b][0],
                _ => false,
            })
            .collect()
    }

    /// The dependent storage branches: A-types among the links and T-types in the tree.
    pub fn dependent_storage(&self) -> Vec<usize> {
        (0..self.roles.len())
            .filter(|&b| match self.roles[b][0] {
                Role::A => !self.in_tree[b][0],
                Role::T => self.in_tree[b][0],
                _ => false,
            })
            .collect()
    }

    /// The co-energy states the tree gives, named as the derivation names them: `v_NAME`
    /// for an A-type in the tree, `f_NAME` for a T-type link.
    pub fn states(&self, graph: &LinearGraph) -> Vec<String> {
        self.independent_storage()
            .into_iter()
            .map(|b| {
                let letter = if self.roles[b][0] == Role::A {
                    "v"
                } else {
                    "f"
                };
                crate::model::state_symbol(letter, &graph.branches[b].name)
            })
            .collect()
    }

    /// The storage elements in the order causality should prefer them: the independent
    /// storage first (so that it is what integral causality is given), then the rest.
    pub fn storage_priority(&self, graph: &LinearGraph) -> Vec<ElementId> {
        let independent = self.independent_storage();
        let dependent = self.dependent_storage();
        independent
            .iter()
            .chain(&dependent)
            .map(|&b| graph.branches[b].element)
            .collect()
    }

    /// The compatibility (loop) equation of link `(branch, port)`: its across variable as
    /// the signed sum of the across variables of the tree path from its `from` node to its
    /// `to` node.
    pub fn loop_equation(&self, graph: &LinearGraph, branch: usize, port: usize) -> Terms {
        let mut tree = Forest::new(graph.nodes.len());
        for (b, p) in self.tree_edges() {
            let e = &graph.branches[b].edges[p];
            tree.add(e.from, e.to, (b, p));
        }
        let link = &graph.branches[branch].edges[port];
        let path = tree.path(link.from, link.to).unwrap_or_default();
        // Walk the path from `from`, adding each edge's across variable with the sign of the
        // direction it is walked in.
        let mut at = link.from;
        let mut terms = Vec::new();
        for (b, p) in path {
            let e = &graph.branches[b].edges[p];
            if e.from == at {
                terms.push((b, p, 1));
                at = e.to;
            } else {
                terms.push((b, p, -1));
                at = e.from;
            }
        }
        terms
    }

    /// The continuity (cut-set) equation of tree edge `(branch, port)`: its through variable
    /// as the signed sum of the through variables of the links its cut-set holds.
    pub fn cut_set_equation(&self, graph: &LinearGraph, branch: usize, port: usize) -> Terms {
        // The side of the tree that holds the edge's `from` node once the edge is taken out.
        let mut tree = Forest::new(graph.nodes.len());
        for (b, p) in self.tree_edges() {
            if (b, p) != (branch, port) {
                let e = &graph.branches[b].edges[p];
                tree.add(e.from, e.to, (b, p));
            }
        }
        let start = graph.branches[branch].edges[port].from;
        let side: Vec<bool> = (0..graph.nodes.len())
            .map(|n| tree.path(start, NodeId(n as u32)).is_some())
            .collect();
        // Through variables leaving the side sum to zero: f_edge + Σ out f_link - Σ in f_link = 0.
        let mut terms = Vec::new();
        for (b, p) in self.links() {
            let e = &graph.branches[b].edges[p];
            match (side[e.from.index()], side[e.to.index()]) {
                (true, false) => terms.push((b, p, -1)),
                (false, true) => terms.push((b, p, 1)),
                _ => {}
            }
        }
        terms
    }
}
