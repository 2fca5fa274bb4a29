//! The bond graph as a graph: petgraph for algorithms, text and Graphviz DOT for people.
//!
//! A [`Model`] keeps its elements and bonds in vectors (indexed by [`ElementId`] and
//! [`BondId`]); [`Model::bond_graph`] views them as a petgraph `DiGraph` whose node and edge
//! indices are those ids, with edges pointing the way power flows. The printers show the two stages a
//! teacher draws on the board: the graph as modelled, and the graph with its causal strokes.

use std::fmt::Write;

use crate::causality::{Causality, Stroke};
use crate::laws::Law;
use crate::model::{BondId, ElementId, ElementKind, Model};

/// What an element is, with its coefficient: `I(m)`, `C(1/k)`, `Se(A*P_s)`, `0`.
///
/// Coefficients print in canonical form (a stiffness `k` shows as the compliance `1/k`);
/// source values print as written.
pub fn element_label(model: &Model, element: ElementId) -> String {
    let kind = &model.element(element).kind;
    match kind {
        ElementKind::EffortSource(v) | ElementKind::FlowSource(v) => {
            format!("{}({})", kind.keyword(), v.text)
        }
        ElementKind::Inertia(c)
        | ElementKind::Compliance(c)
        | ElementKind::Resistor(c)
        | ElementKind::Transformer(c)
        | ElementKind::Gyrator(c) => {
            format!("{}({})", kind.keyword(), c.value.text(&model.symbols))
        }
        ElementKind::Friction(f) => format!(
            "Friction(F_S = {}, F_C = {}, b = {})",
            f.breakaway.text,
            f.coulomb.text,
            f.viscous.value.text(&model.symbols)
        ),
        ElementKind::TensionOnly(t) => {
            format!("TensionOnly({})", t.compliance.value.text(&model.symbols))
        }
        ElementKind::FlowLimit(l) => format!("FlowLimit(<= {})", l.max_flow.text),
        ElementKind::Nonlinear(n) => format!("{}({}: {})", kind.keyword(), n.field, n.text),
        ElementKind::ZeroJunction => "0".to_string(),
        ElementKind::OneJunction => "1".to_string(),
    }
}

/// The graph as modelled: every element with its law, every bond with its power direction.
pub fn describe(model: &Model) -> String {
    let mut out = String::new();
    let width = model
        .elements
        .iter()
        .map(|e| e.name.len())
        .max()
        .unwrap_or(0);
    let _ = writeln!(out, "elements:");
    for element in model.element_ids() {
        let _ = writeln!(
            out,
            "  {:width$}  {}",
            model.element(element).name,
            element_label(model, element)
        );
    }
    let _ = writeln!(out, "bonds (numbered; power flows from -> to):");
    let number_width = model.bonds.len().to_string().len();
    for bond in model.bond_ids() {
        let _ = writeln!(
            out,
            "  {:>number_width$}  {}",
            bond.index() + 1,
            model.bond_label(bond)
        );
    }
    out
}

/// Whether `bond` is the bond of a storage element in derivative causality.
pub fn is_derivative_bond(model: &Model, causality: &Causality, bond: BondId) -> bool {
    causality
        .dependent
        .iter()
        .any(|&e| model.element(e).bonds.contains(&bond))
}

/// The causal graph: for every bond, which end sets the effort and which the flow; then the
/// causality of each storage element and the choices that were arbitrary.
pub fn describe_causality(model: &Model, laws: &[Law], causality: &Causality) -> String {
    let mut out = String::new();
    let labels: Vec<String> = model.bond_ids().map(|b| model.bond_label(b)).collect();
    let width = labels.iter().map(String::len).max().unwrap_or(0);
    let _ = writeln!(
        out,
        "causal strokes (| at the end that receives the effort):"
    );
    let number_width = model.bonds.len().to_string().len();
    for bond in model.bond_ids() {
        let b = model.bond(bond);
        let (from, to) = (&model.element(b.from).name, &model.element(b.to).name);
        let stroked = match causality.strokes[bond.index()] {
            Stroke::AtFrom => format!("|{from} -> {to}"),
            Stroke::AtTo => format!("{from} -> {to}|"),
        };
        let giver = &model.element(causality.effort_giver(model, bond)).name;
        let receiver = &model.element(causality.effort_receiver(model, bond)).name;
        let mark = if is_derivative_bond(model, causality, bond) {
            "  (derivative causality)"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "  {:>number_width$}  {stroked:w$}  effort set by {giver}, flow by {receiver}{mark}",
            bond.index() + 1,
            w = width + 1
        );
    }
    let storage: Vec<String> = model
        .element_ids()
        .filter_map(|e| {
            causality.storage(e, laws).map(|c| {
                format!(
                    "{} {}",
                    model.element(e).name,
                    match c {
                        crate::causality::StorageCausality::Integral => "integral",
                        crate::causality::StorageCausality::Derivative => "derivative",
                    }
                )
            })
        })
        .collect();
    if !storage.is_empty() {
        let _ = writeln!(out, "storage: {}", storage.join(", "));
    }
    if !causality.arbitrary.is_empty() {
        let names: Vec<&str> = causality
            .arbitrary
            .iter()
            .map(|e| model.element(*e).name.as_str())
            .collect();
        let _ = writeln!(out, "chosen arbitrarily: {}", names.join(", "));
    }
    out
}

/// The graph in Graphviz DOT: half-arrows for power, and, when a causality is given, the
/// causal stroke drawn as a bar at the end that receives the effort.
pub fn to_dot(model: &Model, causality: Option<&Causality>) -> String {
    to_dot_titled(model, causality, None)
}

/// The graph in Graphviz DOT as [`to_dot`], with bond numbers as edge labels, the bonds of
/// storage in derivative causality in red, and `title` (naming the mode, say) as the
/// graph's label with a legend for the red bonds.
pub fn to_dot_titled(model: &Model, causality: Option<&Causality>, title: Option<&str>) -> String {
    let mut out = dot_header(
        model,
        title,
        "bond numbers on the bonds; red: derivative causality",
    );
    element_nodes(model, &mut out);
    for bond in model.bond_ids() {
        let b = model.bond(bond);
        let (head, tail) = arrows(causality, bond);
        let derivative = causality.is_some_and(|c| is_derivative_bond(model, c, bond));
        let colour = if derivative {
            ", color=red, fontcolor=red, penwidth=2"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "  \"{}\" -> \"{}\" [dir=both, arrowhead={head}, arrowtail={tail}, label=\"{}\"{colour}];",
            escape(&model.element(b.from).name),
            escape(&model.element(b.to).name),
            bond.index() + 1
        );
    }
    out.push_str("}\n");
    out
}

/// The sub-model use element `name` belongs to, most nested first: `front.suspension` for
/// `front.suspension.spring`; `None` for an element of the model's own file.
fn part_of<'m>(model: &'m Model, name: &str) -> Option<&'m crate::model::PartSpec> {
    model
        .parts()
        .iter()
        .filter(|p| name.starts_with(&format!("{}.", p.name)))
        .max_by_key(|p| p.name.len())
}

/// The element declarations of `to_dot`, each sub-model's inside a cluster labelled with its
/// use and model (nested uses nested), so that a drawing shows what came from which part.
fn element_nodes(model: &Model, out: &mut String) {
    let declare =
        |out: &mut String, element: ElementId, indent: &str| declare(model, element, indent, out);
    fn cluster(
        model: &Model,
        out: &mut String,
        part: Option<&str>,
        depth: usize,
        declare: &dyn Fn(&mut String, ElementId, &str),
    ) {
        let indent = "  ".repeat(depth + 1);
        for element in model.element_ids() {
            let owner = part_of(model, &model.element(element).name).map(|p| p.name.as_str());
            if owner == part {
                declare(out, element, &indent);
            }
        }
        let children = model.parts().iter().filter(|p| match part {
            None => !p.name.contains('.'),
            Some(parent) => p
                .name
                .strip_prefix(&format!("{parent}."))
                .is_some_and(|rest| !rest.contains('.')),
        });
        for child in children {
            let _ = writeln!(
                out,
                "{indent}subgraph \"cluster_{}\" {{ label=\"{}: {}\"; style=rounded;",
                escape(&child.name),
                escape(&child.name),
                escape(&child.model)
            );
            cluster(model, out, Some(&child.name), depth + 1, declare);
            let _ = writeln!(out, "{indent}}}");
        }
    }
    cluster(model, out, None, 0, &declare);
}

/// The bond graph in Graphviz DOT with each sub-model drawn as one box: its elements and
/// the bonds between them hidden, the bonds to it ending at the box, labelled with the port
/// they join. The model's own elements are drawn as in [`to_dot_titled`].
pub fn to_dot_collapsed(
    model: &Model,
    causality: Option<&Causality>,
    title: Option<&str>,
) -> String {
    let mut out = dot_header(
        model,
        title,
        "sub-models collapsed, their ports at the bonds' ends; bond numbers on the bonds",
    );
    // Each element's box: its own, or its outermost sub-model's.
    let outermost = |name: &str| -> Option<&crate::model::PartSpec> {
        model
            .parts()
            .iter()
            .filter(|p| !p.name.contains('.'))
            .find(|p| name.starts_with(&format!("{}.", p.name)))
    };
    for part in model.parts().iter().filter(|p| !p.name.contains('.')) {
        let _ = writeln!(
            out,
            "  \"{}\" [shape=box, style=rounded, label=\"{}\\n{}\"];",
            escape(&part.name),
            escape(&part.name),
            escape(&part.model)
        );
    }
    for element in model.element_ids() {
        let name = &model.element(element).name;
        if outermost(name).is_none() {
            declare(model, element, "  ", &mut out);
        }
    }
    let end = |element: ElementId| -> (String, Option<String>) {
        let name = &model.element(element).name;
        match outermost(name) {
            Some(part) => {
                let port = part
                    .ports
                    .iter()
                    .find(|(_, junction)| junction == name)
                    .map(|(port, _)| port.clone());
                (part.name.clone(), port)
            }
            None => (name.clone(), None),
        }
    };
    for bond in model.bond_ids() {
        let b = model.bond(bond);
        let ((from, from_port), (to, to_port)) = (end(b.from), end(b.to));
        if from == to {
            continue;
        }
        let port_labels = [("taillabel", from_port), ("headlabel", to_port)]
            .into_iter()
            .filter_map(|(key, port)| port.map(|p| format!(", {key}=\"{}\"", escape(&p))))
            .collect::<String>();
        let (head, tail) = arrows(causality, bond);
        let _ = writeln!(
            out,
            "  \"{}\" -> \"{}\" [dir=both, arrowhead={head}, arrowtail={tail}, label=\"{}\"{port_labels}];",
            escape(&from),
            escape(&to),
            bond.index() + 1
        );
    }
    out.push_str("}\n");
    out
}

/// The opening of a DOT drawing of `model`: its name, left to right, `title` and `legend`
/// as its label, plain-text nodes.
fn dot_header(model: &Model, title: Option<&str>, legend: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "digraph \"{}\" {{", escape(&model.name));
    let _ = writeln!(out, "  rankdir=LR;");
    if let Some(title) = title {
        let _ = writeln!(out, "  labelloc=t; label=\"{}\\n{legend}\";", escape(title));
    }
    let _ = writeln!(out, "  node [shape=plaintext];");
    out
}

/// The arrow head and tail of `bond`: its causal stroke, where causality is given.
fn arrows(causality: Option<&Causality>, bond: BondId) -> (&'static str, &'static str) {
    match causality.map(|c| c.strokes[bond.index()]) {
        Some(Stroke::AtTo) => ("teelvee", "none"),
        Some(Stroke::AtFrom) => ("lvee", "tee"),
        None => ("lvee", "none"),
    }
}

/// Declares `element` as a DOT node labelled with its law and its name.
fn declare(model: &Model, element: ElementId, indent: &str, out: &mut String) {
    let name = &model.element(element).name;
    let _ = writeln!(
        out,
        "{indent}\"{}\" [label=\"{}\\n{}\"];",
        escape(name),
        escape(&element_label(model, element)),
        escape(name)
    );
}

fn escape(text: &str) -> String {
    text.replace('\\', "\\\\").replace('"', "\\\"")
}
