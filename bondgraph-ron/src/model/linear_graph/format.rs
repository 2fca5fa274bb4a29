//! The linear-graph file format, exactly as serde reads it from RON.
//!
//! As for bond-graph files (the crate's `model::spec`), these types mirror what the user
//! writes and nothing more: node names are plain strings, expressions unparsed text, maps
//! read as lists of entries in file order (duplicates kept for diagnosis), unknown fields
//! denied. A linear-graph file looks like this:
//!
//! ```ron
//! LinearGraph(
//!     name: "mass_spring_damper",
//!     parameters: { "m": (value: 2.0, unit: "kg"), "k": (value: 200.0, unit: "N/m") },
//!     inputs: { "F": (unit: "N") },
//!     ground: "g",
//!     branches: {
//!         "force":  ThroughSource(value: "F", from: "g", to: "v1"),
//!         "mass":   A(capacitance: "m", from: "v1", to: "g"),
//!         "spring": T(stiffness: "k", from: "v1", to: "g"),
//!     },
//! )
//! ```
//!
//! Every branch goes `from` a node `to` a node: its across variable is `v_from - v_to` and
//! its through variable flows from `from` to `to` through the element, so that `f·v` is the
//! power into the branch (a source delivering power has `f·v < 0`). A two-port has a
//! `primary` and a `secondary` pair of nodes, each `(from, to)` in the same sense.

use serde::Deserialize;

use bondgraph_core::model::spec::{InputSpec, ParameterSpec, entries};

/// A whole linear-graph file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "LinearGraph", deny_unknown_fields)]
pub struct RawLinearGraph {
    /// The model's name.
    pub name: String,
    /// A description for people.
    pub description: Option<String>,
    /// Named parameters, in file order, duplicates kept.
    #[serde(default, deserialize_with = "entries")]
    pub parameters: Vec<(String, ParameterSpec)>,
    /// Named external inputs, in file order, duplicates kept.
    #[serde(default, deserialize_with = "entries")]
    pub inputs: Vec<(String, InputSpec)>,
    /// The reference node, whose across variable is zero.
    pub ground: String,
    /// Named branches, in file order, duplicates kept.
    #[serde(default, deserialize_with = "entries")]
    pub branches: Vec<(String, RawBranch)>,
    /// Named terminals, in file order: the nodes that branches from outside join when the
    /// graph is used as a sub-graph of another ([`RawBranch::Subgraph`]).
    #[serde(default, deserialize_with = "entries")]
    pub terminals: Vec<(String, RawTerminal)>,
}

/// A terminal of a graph used as a sub-graph: one of its nodes.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Terminal", deny_unknown_fields)]
pub struct RawTerminal {
    /// The node (in a graph with sub-graphs of its own, possibly a sub-graph's terminal,
    /// `"wall.outside"`).
    pub node: String,
    /// A description for people.
    pub description: Option<String>,
}

/// A branch, tagged with its kind; coefficients are unparsed expressions.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Branch", deny_unknown_fields)]
pub enum RawBranch {
    /// A-type (mass, electrical capacitor, fluid or thermal capacitance): `f = C dv/dt`,
    /// given by exactly one of capacitance or a nonlinear law.
    A {
        /// The capacitance `C` (a mass, for a mechanical A-type).
        capacitance: Option<String>,
        /// A nonlinear law: the across variable as an expression of `p_NAME`, the time
        /// integral of the through variable (a momentum, a charge, a volume, a heat): a tank
        /// whose cross-section changes with its level (the bond graph's `I(flow: ...)`).
        across: Option<String>,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// T-type (spring, inductor, fluid inertance): `v = L df/dt`, given by exactly one of
    /// inductance or stiffness (`L = 1/k`).
    T {
        /// The inductance `L` (a compliance, for a spring).
        inductance: Option<String>,
        /// The stiffness `k = 1/L`.
        stiffness: Option<String>,
        /// A nonlinear law: the through variable as an expression of `q_NAME`, the time
        /// integral of the across variable (a displacement, a flux linkage): a hardening
        /// spring `k*q_spring + k_3*q_spring^3` (the bond graph's `C(effort: ...)`).
        through: Option<String>,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// D-type (damper, resistor, fluid or thermal resistance): `v = R f`, given by exactly
    /// one of resistance, conductance (`b = 1/R`, a damping coefficient), or a nonlinear
    /// law: `through` as an expression of the branch's `across` variable, or `across` of
    /// its `through` variable (the bond graph's `R(effort: ...)` and `R(flow: ...)`).
    D {
        /// The resistance `R`: across per through.
        resistance: Option<String>,
        /// The conductance `1/R`: through per across (a damper's `b`).
        conductance: Option<String>,
        /// A nonlinear law: the through variable as an expression of `across`.
        through: Option<String>,
        /// A nonlinear law: the across variable as an expression of `through`.
        across: Option<String>,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// An ideal across-variable source (velocity, voltage, pressure): `v_from - v_to = value`.
    AcrossSource {
        /// The across variable it imposes, affine in the inputs.
        value: String,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// An ideal through-variable source (force, current, flow): `value` flows through it
    /// from `from` to `to`, into node `to`.
    ThroughSource {
        /// The through variable it imposes, affine in the inputs.
        value: String,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// An ideal transformer (gear, lever, DC motor): `v_1 = N v_2`, `f_1 = -f_2 / N`.
    Transformer {
        /// The ratio `N`.
        ratio: String,
        /// The primary port's nodes `(from, to)`.
        primary: (String, String),
        /// The secondary port's nodes `(from, to)`.
        secondary: (String, String),
    },
    /// An ideal gyrator (hydraulic piston, gyroscope): `v_1 = G f_2`, `f_1 = -v_2 / G`.
    Gyrator {
        /// The ratio `G`.
        ratio: String,
        /// The primary port's nodes `(from, to)`.
        primary: (String, String),
        /// The secondary port's nodes `(from, to)`.
        secondary: (String, String),
    },
    /// A Karnopp friction contact on the branch's across variable (a relative velocity),
    /// its through variable the friction force; as the bond-graph contact.
    Friction {
        /// The breakaway (static) force; may depend on inputs.
        breakaway: String,
        /// The Coulomb (kinetic) force; may depend on inputs.
        coulomb: String,
        /// The viscous coefficient (default 0).
        viscous: Option<String>,
        /// Karnopp's dead band (default 0).
        dead_band: Option<String>,
        /// The Stribeck velocity (default none).
        stribeck: Option<String>,
        /// The mode at the start: `"stuck"` (default), `"slip+"` or `"slip-"`.
        initial: Option<String>,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// A T-type branch that carries tension only (a string): taut it is a spring, slack it
    /// carries no through variable while its slack is tracked. Given by exactly one of
    /// inductance or stiffness.
    TensionOnly {
        /// The inductance (compliance) when taut.
        inductance: Option<String>,
        /// The stiffness when taut.
        stiffness: Option<String>,
        /// The mode at the start: `"taut"` (default) or `"slack"`.
        initial: Option<String>,
        /// The node the branch starts at.
        from: String,
        /// The node the branch ends at.
        to: String,
    },
    /// A sub-graph: another linear-graph file used here, its terminals joined by this
    /// graph's branches as nodes (`"wall.outside"`), its ground this graph's ground. Read
    /// and flattened into its branches (`wall.capacity`) before the graph is checked.
    Subgraph {
        /// The linear-graph file, relative to the file that uses it.
        file: String,
        /// Values for the sub-graph's parameters in this use, by its names.
        #[serde(default, deserialize_with = "entries")]
        parameters: Vec<(String, bondgraph_core::model::ParameterValue)>,
        /// Signals for its inputs in this use, by its names.
        #[serde(default, deserialize_with = "entries")]
        inputs: Vec<(String, String)>,
        /// Nodes of this graph its terminals are, by terminal (`{"inside": "air"}`); a
        /// terminal not given here is named `"use.terminal"` by this graph's branches.
        #[serde(default, deserialize_with = "entries")]
        terminals: Vec<(String, String)>,
    },
}

impl RawBranch {
    /// The branch's ports as `(from, to)` pairs: one for a one-port, primary and secondary
    /// for a two-port.
    pub fn ports(&self) -> Vec<(&str, &str)> {
        match self {
            RawBranch::Transformer {
                primary, secondary, ..
            }
            | RawBranch::Gyrator {
                primary, secondary, ..
            } => vec![
                (primary.0.as_str(), primary.1.as_str()),
                (secondary.0.as_str(), secondary.1.as_str()),
            ],
            RawBranch::A { from, to, .. }
            | RawBranch::T { from, to, .. }
            | RawBranch::D { from, to, .. }
            | RawBranch::AcrossSource { from, to, .. }
            | RawBranch::ThroughSource { from, to, .. }
            | RawBranch::Friction { from, to, .. }
            | RawBranch::TensionOnly { from, to, .. } => vec![(from.as_str(), to.as_str())],
            RawBranch::Subgraph { .. } => Vec::new(),
        }
    }

    /// The branch's node names, to rename them.
    pub fn nodes_mut(&mut self) -> Vec<&mut String> {
        match self {
            RawBranch::Transformer {
                primary, secondary, ..
            }
            | RawBranch::Gyrator {
                primary, secondary, ..
            } => vec![
                &mut primary.0,
                &mut primary.1,
                &mut secondary.0,
                &mut secondary.1,
            ],
            RawBranch::A { from, to, .. }
            | RawBranch::T { from, to, .. }
            | RawBranch::D { from, to, .. }
            | RawBranch::AcrossSource { from, to, .. }
            | RawBranch::ThroughSource { from, to, .. }
            | RawBranch::Friction { from, to, .. }
            | RawBranch::TensionOnly { from, to, .. } => vec![from, to],
            RawBranch::Subgraph { .. } => Vec::new(),
        }
    }

    /// The branch's expressions (coefficients, laws, values), to rename their symbols.
    pub fn expressions_mut(&mut self) -> Vec<&mut String> {
        let mut out: Vec<&mut String> = Vec::new();
        match self {
            RawBranch::A {
                capacitance,
                across,
                ..
            } => out.extend([capacitance, across].into_iter().flatten()),
            RawBranch::T {
                inductance,
                stiffness,
                through,
                ..
            } => out.extend([inductance, stiffness, through].into_iter().flatten()),
            RawBranch::D {
                resistance,
                conductance,
                through,
                across,
                ..
            } => out.extend(
                [resistance, conductance, through, across]
                    .into_iter()
                    .flatten(),
            ),
            RawBranch::AcrossSource { value, .. } | RawBranch::ThroughSource { value, .. } => {
                out.push(value);
            }
            RawBranch::Transformer { ratio, .. } | RawBranch::Gyrator { ratio, .. } => {
                out.push(ratio);
            }
            RawBranch::Friction {
                breakaway,
                coulomb,
                viscous,
                dead_band,
                stribeck,
                ..
            } => {
                out.push(breakaway);
                out.push(coulomb);
                out.extend([viscous, dead_band, stribeck].into_iter().flatten());
            }
            RawBranch::TensionOnly {
                inductance,
                stiffness,
                ..
            } => out.extend([inductance, stiffness].into_iter().flatten()),
            RawBranch::Subgraph { .. } => {}
        }
        out
    }

    /// The kind as written in files (`A`, `ThroughSource`, ...).
    pub fn keyword(&self) -> &'static str {
        match self {
            RawBranch::A { .. } => "A",
            RawBranch::T { .. } => "T",
            RawBranch::D { .. } => "D",
            RawBranch::AcrossSource { .. } => "AcrossSource",
            RawBranch::ThroughSource { .. } => "ThroughSource",
            RawBranch::Transformer { .. } => "Transformer",
            RawBranch::Gyrator { .. } => "Gyrator",
            RawBranch::Friction { .. } => "Friction",
            RawBranch::TensionOnly { .. } => "TensionOnly",
            RawBranch::Subgraph { .. } => "Subgraph",
        }
    }
}

impl RawLinearGraph {
    /// Reads a linear graph from RON `text` with the options model files use.
    pub fn from_ron(text: &str) -> Result<Self, ron::error::SpannedError> {
        crate::model::parse::ron_options().from_str(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_branch_kind_in_file_order() {
        let graph = RawLinearGraph::from_ron(
            r#"LinearGraph(name: "all", ground: "g", branches: {
                "a": A(capacitance: "m", from: "1", to: "g"),
                "t": T(stiffness: "k", from: "1", to: "2"),
                "d": D(conductance: "b", from: "2", to: "g"),
                "v": AcrossSource(value: "V", from: "3", to: "g"),
                "f": ThroughSource(value: "F", from: "g", to: "1"),
                "n": Transformer(ratio: "N", primary: ("3", "g"), secondary: ("2", "g")),
                "y": Gyrator(ratio: "G", primary: ("3", "g"), secondary: ("2", "g")),
                "fr": Friction(breakaway: "F_S", coulomb: "F_C", from: "1", to: "2"),
                "s": TensionOnly(stiffness: "k", from: "1", to: "2"),
            })"#,
        )
        .unwrap();
        assert_eq!(graph.ground, "g");
        let kinds: Vec<&str> = graph.branches.iter().map(|(_, b)| b.keyword()).collect();
        assert_eq!(
            kinds,
            [
                "A",
                "T",
                "D",
                "AcrossSource",
                "ThroughSource",
                "Transformer",
                "Gyrator",
                "Friction",
                "TensionOnly"
            ]
        );
        assert_eq!(graph.branches[5].1.ports(), [("3", "g"), ("2", "g")]);
        assert_eq!(graph.branches[1].1.ports(), [("1", "2")]);
    }

    #[test]
    fn unknown_fields_and_missing_pairs_are_errors() {
        for text in [
            r#"(name: "x", ground: "g", branches: {"a": A(mass: "m", from: "1", to: "g")})"#,
            r#"(name: "x", ground: "g", elements: {})"#,
        ] {
            let error = RawLinearGraph::from_ron(text).unwrap_err();
            assert!(
                matches!(error.code, ron::Error::NoSuchStructField { .. }),
                "{text}: {error}"
            );
        }
        let error = RawLinearGraph::from_ron(
            r#"(name: "x", ground: "g", branches: {"n": Transformer(ratio: "2", primary: ("1", "g"))})"#,
        )
        .unwrap_err();
        assert!(
            matches!(error.code, ron::Error::MissingStructField { .. }),
            "{error}"
        );
    }
}
