//! A generator of random valid bond graphs, and the graphs it makes: RON text for the
//! library, and their elements, bonds and parameter values for an independent assembly.
//!
//! [`graph_spec`] draws a [`GraphSpec`]: junctions, the links that join them (a random tree
//! plus a few extra links, which close cycles), transformers and gyrators spliced into
//! links, and one-ports hung on junctions. [`GraphSpec::build`] makes it a concrete
//! [`Graph`], with one parameter per coefficient (`p0`, `p1`, ...) and one input per source
//! (`u0`, ...), that [`Graph::ron`] writes as a model file.

use proptest::prelude::*;
use proptest::sample::Index;

/// The kind of a junction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum JunctionKind {
    Zero,
    One,
}

/// The kind of a two-port spliced into a junction-junction link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TwoPortKind {
    Transformer,
    Gyrator,
}

/// A two-port spliced into a link, with its ratio (any non-zero value, either sign).
#[derive(Clone, Copy, Debug)]
struct TwoPortSpec {
    kind: TwoPortKind,
    ratio: f64,
    /// The bond out of the two-port is listed before the bond into it (the library must
    /// not take the first bond for the input).
    out_first: bool,
}

/// A junction-junction link: a bond, or two bonds through a transformer or gyrator.
#[derive(Clone, Debug)]
struct LinkSpec {
    /// Picks the ends: for a tree link, the parent among the earlier junctions; for an
    /// extra link, both ends.
    ends: (Index, Index),
    /// Power flows from the first end to the second (else the other way).
    forward: bool,
    /// A two-port spliced into the link.
    through: Option<TwoPortSpec>,
}

/// The kind of a one-port.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PortKind {
    Inertia,
    Compliance,
    Resistor,
    EffortSource,
    FlowSource,
}

/// A one-port hung on a junction.
#[derive(Clone, Debug)]
struct PortSpec {
    /// The kind of the one-port if it is hung on a 0-junction.
    at_zero: PortKind,
    /// The kind of the one-port if it is hung on a 1-junction.
    at_one: PortKind,
    /// Picks the junction.
    at: Index,
    /// The bond points the unconventional way: into a source, out of storage or a resistor.
    reversed: bool,
    /// The inertance, compliance (or stiffness) or resistance: positive.
    value: f64,
    /// A compliance is written as `C(stiffness: ..)` (else `C(compliance: ..)`).
    stiffness: bool,
    /// A source's value is `gain * u` (else `u`).
    gain: Option<f64>,
    /// A source's value has a constant offset (`.. + offset`), which makes `c` non-zero.
    offset: Option<f64>,
}

/// A random bond graph, before it is made concrete.
#[derive(Clone, Debug)]
pub(crate) struct GraphSpec {
    junctions: Vec<JunctionKind>,
    /// Junction `i + 1` hangs on an earlier junction by `tree[i]`: a spanning tree.
    tree: Vec<LinkSpec>,
    /// Extra junction-junction links: cycles of the junction structure.
    extra: Vec<LinkSpec>,
    ports: Vec<PortSpec>,
    /// Two spare one-ports per junction, used where a junction has fewer than two bonds.
    fillers: Vec<PortSpec>,
    /// Seeds the point the Jacobian is taken at.
    pub(crate) point_seed: u64,
}

/// A positive value spanning four decades, 0.01 to 100, log-uniform.
fn positive() -> impl Strategy<Value = f64> {
    (-2.0..2.0f64).prop_map(|e| 10f64.powf(e))
}

/// A value of either sign, magnitude 0.1 to 10, log-uniform.
fn signed() -> impl Strategy<Value = f64> {
    (any::<bool>(), -1.0..1.0f64).prop_map(|(negative, e)| {
        let magnitude = 10f64.powf(e);
        if negative { -magnitude } else { magnitude }
    })
}

fn link() -> impl Strategy<Value = LinkSpec> {
    let two_port = prop_oneof![
        3 => Just(None),
        1 => (
            prop_oneof![Just(TwoPortKind::Transformer), Just(TwoPortKind::Gyrator)],
            signed(),
            any::<bool>(),
        )
            .prop_map(|(kind, ratio, out_first)| Some(TwoPortSpec {
                kind,
                ratio,
                out_first
            })),
    ];
    (any::<(Index, Index)>(), any::<bool>(), two_port).prop_map(|(ends, forward, through)| {
        LinkSpec {
            ends,
            forward,
            through,
        }
    })
}

fn port() -> impl Strategy<Value = PortSpec> {
    // Storage that shares its junction's common variable with other storage of its kind
    // (two inertias on a 1-junction) is in derivative causality, and so is skipped: each
    // junction kind draws fewer of the storage it would make dependent, and fewer of the
    // sources that would fight over its common variable.
    let kind = |i: u32, c: u32, se: u32, sf: u32| {
        prop_oneof![
            i => Just(PortKind::Inertia),
            c => Just(PortKind::Compliance),
            4 => Just(PortKind::Resistor),
            se => Just(PortKind::EffortSource),
            sf => Just(PortKind::FlowSource),
        ]
    };
    (
        (kind(3, 1, 1, 2), kind(1, 3, 2, 1)),
        any::<Index>(),
        prop::bool::weighted(0.2),
        positive(),
        any::<bool>(),
        prop::option::weighted(0.5, positive()),
        prop::option::weighted(0.4, signed()),
    )
        .prop_map(
            |((at_zero, at_one), at, reversed, value, stiffness, gain, offset)| PortSpec {
                at_zero,
                at_one,
                at,
                reversed,
                value,
                stiffness,
                gain,
                offset,
            },
        )
}

/// Random valid bond graphs: 1 to 6 junctions joined as a random tree, sometimes with one
/// or two extra junction-junction links (cycles, which make algebraic loops), a quarter of
/// the links through a transformer or gyrator, and one-ports (I, C, R, Se, Sf) hung on
/// junctions, a fifth of them with reversed bonds; every junction gets at least two bonds.
pub(crate) fn graph_spec() -> impl Strategy<Value = GraphSpec> {
    (1usize..=6)
        .prop_flat_map(|n| {
            let extra_count = if n >= 2 {
                prop_oneof![5 => Just(0usize), 3 => Just(1), 2 => Just(2)].boxed()
            } else {
                Just(0usize).boxed()
            };
            (
                prop::collection::vec(
                    prop_oneof![Just(JunctionKind::Zero), Just(JunctionKind::One)],
                    n,
                ),
                prop::collection::vec(link(), n - 1),
                extra_count.prop_flat_map(|k| prop::collection::vec(link(), k)),
                prop::collection::vec(port(), 1..=n + 3),
                prop::collection::vec(port(), 2 * n),
                any::<u64>(),
            )
        })
        .prop_map(
            |(junctions, tree, extra, ports, fillers, point_seed)| GraphSpec {
                junctions,
                tree,
                extra,
                ports,
                fillers,
                point_seed,
            },
        )
}

// ---------------------------------------------------------------------------------------
// The concrete graph
// ---------------------------------------------------------------------------------------

/// An element with its numeric law (the values the RON text gives its parameters).
#[derive(Clone, Debug)]
pub(crate) enum Kind {
    Zero,
    One,
    Inertia {
        inertance: f64,
    },
    /// `value` is the stiffness `1/C` if `stiffness`, else the compliance `C`.
    Compliance {
        value: f64,
        stiffness: bool,
    },
    Resistor {
        resistance: f64,
    },
    EffortSource {
        input: usize,
        gain: f64,
        offset: f64,
    },
    FlowSource {
        input: usize,
        gain: f64,
        offset: f64,
    },
    Transformer {
        ratio: f64,
    },
    Gyrator {
        ratio: f64,
    },
}

/// An element: its name, its law, and how the RON text writes it.
#[derive(Clone, Debug)]
pub(crate) struct Element {
    pub(crate) name: String,
    pub(crate) kind: Kind,
    ron: String,
}

/// What a graph contains, for the coverage counts.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Features {
    pub(crate) transformers: usize,
    pub(crate) gyrators: usize,
    pub(crate) negative_ratios: usize,
    pub(crate) extra_links: usize,
    pub(crate) effort_sources: usize,
    pub(crate) flow_sources: usize,
    /// Sources with a constant offset.
    pub(crate) offsets: usize,
    /// Compliances written with a stiffness.
    pub(crate) stiffnesses: usize,
    /// One-ports whose bond points the unconventional way, all kinds.
    pub(crate) reversed: usize,
    /// Sources whose bond points into them.
    pub(crate) reversed_sources: usize,
    /// Storage elements whose bond points out of them.
    pub(crate) reversed_storage: usize,
}

/// A concrete bond graph.
#[derive(Clone, Debug)]
pub(crate) struct Graph {
    pub(crate) elements: Vec<Element>,
    /// `(from, to)`: power flows from `from` to `to`.
    pub(crate) bonds: Vec<(usize, usize)>,
    /// Parameter values, `p0`, `p1`, ...
    parameters: Vec<f64>,
    /// Number of inputs, `u0`, `u1`, ...
    pub(crate) inputs: usize,
    pub(crate) features: Features,
}

impl Graph {
    fn new() -> Self {
        Self {
            elements: Vec::new(),
            bonds: Vec::new(),
            parameters: Vec::new(),
            inputs: 0,
            features: Features::default(),
        }
    }

    fn parameter(&mut self, value: f64) -> String {
        self.parameters.push(value);
        format!("p{}", self.parameters.len() - 1)
    }

    fn element(&mut self, prefix: &str, kind: Kind, ron: String) -> usize {
        let index = self.elements.len();
        self.elements.push(Element {
            name: format!("{prefix}{index}"),
            kind,
            ron,
        });
        index
    }

    /// Joins junctions `a` and `b` (power from `a` to `b` if `forward`).
    fn link(&mut self, a: usize, b: usize, link: &LinkSpec) {
        let (from, to) = if link.forward { (a, b) } else { (b, a) };
        match link.through {
            None => self.bonds.push((from, to)),
            Some(TwoPortSpec {
                kind,
                ratio,
                out_first,
            }) => {
                let name = self.parameter(ratio);
                if ratio < 0.0 {
                    self.features.negative_ratios += 1;
                }
                let middle = match kind {
                    TwoPortKind::Transformer => {
                        self.features.transformers += 1;
                        self.element(
                            "tf",
                            Kind::Transformer { ratio },
                            format!("TF(ratio: {name:?})"),
                        )
                    }
                    TwoPortKind::Gyrator => {
                        self.features.gyrators += 1;
                        self.element(
                            "gy",
                            Kind::Gyrator { ratio },
                            format!("GY(ratio: {name:?})"),
                        )
                    }
                };
                if out_first {
                    self.bonds.push((middle, to));
                    self.bonds.push((from, middle));
                } else {
                    self.bonds.push((from, middle));
                    self.bonds.push((middle, to));
                }
            }
        }
    }

    /// Hangs a one-port on junction `junction`.
    fn port(&mut self, junction: usize, port: &PortSpec) {
        let kind = match self.elements[junction].kind {
            Kind::Zero => port.at_zero,
            _ => port.at_one,
        };
        let (element, source) = match kind {
            PortKind::Inertia => {
                let p = self.parameter(port.value);
                let kind = Kind::Inertia {
                    inertance: port.value,
                };
                (
                    self.element("i", kind, format!("I(inertance: {p:?})")),
                    false,
                )
            }
            PortKind::Compliance => {
                let p = self.parameter(port.value);
                let field = if port.stiffness {
                    self.features.stiffnesses += 1;
                    "stiffness"
                } else {
                    "compliance"
                };
                let kind = Kind::Compliance {
                    value: port.value,
                    stiffness: port.stiffness,
                };
                (self.element("c", kind, format!("C({field}: {p:?})")), false)
            }
            PortKind::Resistor => {
                let p = self.parameter(port.value);
                let kind = Kind::Resistor {
                    resistance: port.value,
                };
                (
                    self.element("r", kind, format!("R(resistance: {p:?})")),
                    false,
                )
            }
            PortKind::EffortSource | PortKind::FlowSource => {
                let input = self.inputs;
                self.inputs += 1;
                let mut text = format!("u{input}");
                let mut gain = 1.0;
                if let Some(g) = port.gain {
                    gain = g;
                    text = format!("{}*{text}", self.parameter(g));
                }
                let mut offset = 0.0;
                if let Some(o) = port.offset {
                    offset = o;
                    self.features.offsets += 1;
                    text = format!("{text} + {}", self.parameter(o));
                }
                let (prefix, kind, ron) = if kind == PortKind::EffortSource {
                    self.features.effort_sources += 1;
                    let kind = Kind::EffortSource {
                        input,
                        gain,
                        offset,
                    };
                    ("se", kind, format!("Se(effort: {text:?})"))
                } else {
                    self.features.flow_sources += 1;
                    let kind = Kind::FlowSource {
                        input,
                        gain,
                        offset,
                    };
                    ("sf", kind, format!("Sf(flow: {text:?})"))
                };
                (self.element(prefix, kind, ron), true)
            }
        };
        // Conventionally power flows out of a source and into everything else.
        if port.reversed {
            self.features.reversed += 1;
            match kind {
                PortKind::EffortSource | PortKind::FlowSource => {
                    self.features.reversed_sources += 1;
                }
                PortKind::Inertia | PortKind::Compliance => self.features.reversed_storage += 1,
                PortKind::Resistor => {}
            }
        }
        if source != port.reversed {
            self.bonds.push((element, junction));
        } else {
            self.bonds.push((junction, element));
        }
    }

    /// The bonds of `element`, in bond order.
    pub(crate) fn bonds_of(&self, element: usize) -> Vec<usize> {
        (0..self.bonds.len())
            .filter(|&b| self.bonds[b].0 == element || self.bonds[b].1 == element)
            .collect()
    }

    /// `+1` if bond `b` points into `element`, `-1` if out of it.
    pub(crate) fn sign_into(&self, b: usize, element: usize) -> f64 {
        if self.bonds[b].1 == element {
            1.0
        } else {
            -1.0
        }
    }

    /// The storage elements (the states), in element order.
    pub(crate) fn storage(&self) -> Vec<usize> {
        (0..self.elements.len())
            .filter(|&e| {
                matches!(
                    self.elements[e].kind,
                    Kind::Inertia { .. } | Kind::Compliance { .. }
                )
            })
            .collect()
    }

    /// The factor from energy to co-energy variable of storage element `e`: `v = p/m`,
    /// `f = q/C`.
    pub(crate) fn coenergy_factor(&self, e: usize) -> f64 {
        match self.elements[e].kind {
            Kind::Inertia { inertance } => 1.0 / inertance,
            Kind::Compliance { value, stiffness } => {
                if stiffness {
                    value
                } else {
                    1.0 / value
                }
            }
            _ => unreachable!("not storage"),
        }
    }

    /// The model as RON text, with its bonds listed in `order` (indices into `bonds`).
    pub(crate) fn ron(&self, order: &[usize]) -> String {
        let mut text = String::from("Model(\n    name: \"random\",\n    parameters: {\n");
        for (i, value) in self.parameters.iter().enumerate() {
            // `{}` writes the shortest text that reads back as the same f64.
            text += &format!("        \"p{i}\": (value: {value}),\n");
        }
        text += "    },\n    inputs: {\n";
        for i in 0..self.inputs {
            text += &format!("        \"u{i}\": (),\n");
        }
        text += "    },\n    elements: {\n";
        for element in &self.elements {
            text += &format!("        {:?}: {},\n", element.name, element.ron);
        }
        text += "    },\n    bonds: [\n";
        for &b in order {
            let (from, to) = self.bonds[b];
            text += &format!(
                "        ({:?}, {:?}),\n",
                self.elements[from].name, self.elements[to].name
            );
        }
        text += "    ],\n)\n";
        text
    }

    /// The model as RON text, bonds in order.
    pub(crate) fn ron_text(&self) -> String {
        self.ron(&(0..self.bonds.len()).collect::<Vec<_>>())
    }
}

impl GraphSpec {
    /// The concrete graph: junctions first, then two-ports and one-ports as they are hung on.
    pub(crate) fn build(&self) -> Graph {
        let mut graph = Graph::new();
        let n = self.junctions.len();
        for &kind in &self.junctions {
            match kind {
                JunctionKind::Zero => graph.element("j", Kind::Zero, "Zero".into()),
                JunctionKind::One => graph.element("j", Kind::One, "One".into()),
            };
        }
        for (i, link) in self.tree.iter().enumerate() {
            let child = i + 1;
            let parent = link.ends.0.index(child);
            graph.link(parent, child, link);
        }
        if n >= 2 {
            for link in &self.extra {
                let a = link.ends.0.index(n);
                let mut b = link.ends.1.index(n - 1);
                if b >= a {
                    b += 1;
                }
                graph.link(a, b, link);
                graph.features.extra_links += 1;
            }
        }
        for port in &self.ports {
            graph.port(port.at.index(n), port);
        }
        for junction in 0..n {
            let mut spare = self.fillers[2 * junction..2 * junction + 2].iter();
            while graph.bonds_of(junction).len() < 2 {
                graph.port(junction, spare.next().expect("two spares suffice"));
            }
        }
        graph
    }
}
