//! The easy-to-reverse conventions of a model, echoed back in words.
//!
//! Two conventions are written once and read many times: a transformer's ratio
//! (`e_in = n e_out`, so the flow out is `n` times the flow in) and the direction of a
//! source's bond (a source's bond points away from it, so a positive value delivers power).
//! Written backwards, both give a model that checks and simulates, and is wrong: a gear
//! written as a step-up, an ambient temperature that cools a warmer body. [`describe`]
//! says what the file means, element by element, so that a reader sees it at once.
//!
//! # Example
//! ```
//! let model = bondgraph_ron::model::load_str("gear.ron", r#"Model(name: "gear",
//!     parameters: {"n": (value: 0.1), "J": (value: 1.0)},
//!     inputs: {"T": (unit: "N*m")},
//!     elements: {"motor": Se(effort: "T"), "gear": TF(ratio: "n"), "load": I(inertance: "J")},
//!     bonds: [("motor", "gear"), ("gear", "load")])"#).unwrap();
//! let lines = bondgraph_core::conventions::describe(&model);
//! assert_eq!(lines[0], "Se 'motor' imposes effort T on its bond to 'gear'; \
//!     a positive T with a positive flow out of the source delivers power");
//! assert_eq!(lines[1], "TF 'gear' (n = 0.1): effort on the side of 'motor' = n × effort on \
//!     the side of 'load'; flow to 'load' = n × flow from 'motor': the flow is reduced 10 \
//!     times and the effort amplified 10 times");
//! ```

use crate::model::linear_graph::{BranchKind, LinearGraph};
use crate::model::{ElementId, ElementKind, Model, NonlinearLaw};

/// One line per source and per transformer or gyrator of `model`, in element order,
/// saying what its written direction and ratio mean (for a linear graph, per branch in
/// the graph's own terms).
pub fn describe(model: &Model) -> Vec<String> {
    if let Some(graph) = &model.linear_graph {
        return describe_graph(model, graph);
    }
    let mut lines = Vec::new();
    for id in model.element_ids() {
        let element = model.element(id);
        let (letter, quantity, text) = match &element.kind {
            ElementKind::EffortSource(v) => ("Se", "effort", v.text.as_str()),
            ElementKind::FlowSource(v) => ("Sf", "flow", v.text.as_str()),
            ElementKind::Nonlinear(n) => match n.law {
                NonlinearLaw::EffortSource(_) => ("Se", "effort", n.text.as_str()),
                NonlinearLaw::FlowSource(_) => ("Sf", "flow", n.text.as_str()),
                NonlinearLaw::Transformer(_) | NonlinearLaw::Gyrator(_) => {
                    lines.extend(two_port(model, id, &n.text, None));
                    continue;
                }
                _ => continue,
            },
            ElementKind::Transformer(c) | ElementKind::Gyrator(c) => {
                lines.extend(two_port(
                    model,
                    id,
                    &c.text,
                    Some(c.value.eval(&model.values)),
                ));
                continue;
            }
            _ => continue,
        };
        let Some(&bond) = element.bonds.first() else {
            continue;
        };
        let bond = model.bond(bond);
        let name = &element.name;
        if bond.from == id {
            let other = &model.element(bond.to).name;
            let power = if quantity == "effort" {
                format!("a positive {text} with a positive flow out of the source delivers power")
            } else {
                format!("a positive {text} against a positive effort delivers power")
            };
            lines.push(format!(
                "{letter} '{name}' imposes {quantity} {text} on its bond to '{other}'; {power}"
            ));
        } else {
            let other = &model.element(bond.from).name;
            lines.push(format!(
                "{letter} '{name}' imposes {quantity} {text} on a bond that points into it from \
                 '{other}': a positive {text} takes power out of the system (a load, not a \
                 supply); sources usually point away"
            ));
        }
    }
    lines
}

/// A transformer's or gyrator's ratio in words; `value` its number when constant.
fn two_port(model: &Model, id: ElementId, text: &str, value: Option<f64>) -> Option<String> {
    let element = model.element(id);
    let &[a, b] = &element.bonds[..] else {
        return None;
    };
    let (bond_in, bond_out) = if model.bond(a).to == id {
        (a, b)
    } else {
        (b, a)
    };
    let input = &model.element(model.bond(bond_in).from).name;
    let output = &model.element(model.bond(bond_out).to).name;
    let keyword = element.kind.keyword();
    let shown = value.map_or(text.to_string(), |v| {
        format!("{text} = {}", crate::number::shortest(v))
    });
    let gyrator = matches!(element.kind, ElementKind::Gyrator(_))
        || matches!(&element.kind, ElementKind::Nonlinear(n) if matches!(n.law, NonlinearLaw::Gyrator(_)));
    let name = &element.name;
    if gyrator {
        return Some(format!(
            "{keyword} '{name}' ({shown}): effort on the side of '{input}' = {text} × flow to \
             '{output}'; effort on the side of '{output}' = {text} × flow from '{input}'"
        ));
    }
    let meaning = match value {
        Some(v) if v.abs() < 1.0 && v != 0.0 => format!(
            ": the flow is reduced {} times and the effort amplified {} times",
            reciprocal(v.abs()),
            reciprocal(v.abs())
        ),
        Some(v) if v.abs() > 1.0 => format!(
            ": the flow is amplified {} times and the effort reduced {} times",
            number(v.abs()),
            number(v.abs())
        ),
        Some(v) if v.abs() == 1.0 => String::from(": flow and effort pass unchanged in size"),
        _ => String::new(),
    };
    let reversed = if value.is_some_and(|v| v < 0.0) {
        " (and reversed in sign)"
    } else {
        ""
    };
    Some(format!(
        "{keyword} '{name}' ({shown}): effort on the side of '{input}' = {text} × effort on the \
         side of '{output}'; flow to '{output}' = {text} × flow from '{input}'{meaning}{reversed}"
    ))
}

/// The sources and two-ports of a linear graph, in its own terms.
fn describe_graph(model: &Model, graph: &LinearGraph) -> Vec<String> {
    let node = |id: crate::model::linear_graph::NodeId| graph.nodes[id.index()].name.clone();
    let mut lines = Vec::new();
    for branch in &graph.branches {
        let Some(edge) = branch.edges.first() else {
            continue;
        };
        let (from, to) = (node(edge.from), node(edge.to));
        let (name, value) = (&branch.name, &branch.value);
        match branch.kind {
            BranchKind::AcrossSource => lines.push(format!(
                "AcrossSource '{name}' imposes v_{from} - v_{to} = {value}: a positive {value} \
                 holds '{from}' above '{to}'"
            )),
            BranchKind::ThroughSource => lines.push(format!(
                "ThroughSource '{name}' drives {value} from '{from}' to '{to}' through itself: a \
                 positive {value} flows into node '{to}'"
            )),
            BranchKind::Transformer | BranchKind::Gyrator => {
                let Some(second) = branch.edges.get(1) else {
                    continue;
                };
                let (c, d) = (node(second.from), node(second.to));
                let shown = match &model.element(branch.element).kind {
                    ElementKind::Transformer(c) | ElementKind::Gyrator(c) => {
                        format!("{value} = {}", c.value.eval(&model.values))
                    }
                    _ => value.clone(),
                };
                let law = if branch.kind == BranchKind::Transformer {
                    format!(
                        "v_{from} - v_{to} = {value} × (v_{c} - v_{d}), through ({from}->{to}) = \
                         -through ({c}->{d}) / {value}"
                    )
                } else {
                    format!(
                        "v_{from} - v_{to} = {value} × through ({c}->{d}), through ({from}->{to}) \
                         = -(v_{c} - v_{d}) / {value}"
                    )
                };
                lines.push(format!(
                    "{} '{name}' ({shown}): {law}",
                    branch.kind.keyword()
                ));
            }
            _ => {}
        }
    }
    lines
}

/// A ratio as people read it: `10`, `2.5`, `3.333`, `1.235e8`, `1e308`.
fn number(x: f64) -> String {
    if (1e-3..1e6).contains(&x.abs()) {
        let rounded = (x * 1000.0).round() / 1000.0;
        format!("{rounded}")
    } else {
        crate::number::significant(x, 4)
    }
}

/// `1/x` for `x > 0` as [`number`] says it, also where `1/x` is beyond the largest double
/// (`x = 1e-310`: `1e310`).
fn reciprocal(x: f64) -> String {
    let r = 1.0 / x;
    if r.is_finite() {
        return number(r);
    }
    // 1/x = 10^e with e = -log10(x): its mantissa and exponent in decimal.
    let e = -x.log10();
    let exponent = e.floor();
    let mantissa = crate::number::significant(10f64.powf(e - exponent), 4);
    match mantissa.as_str() {
        "10" => format!("1e{}", exponent + 1.0),
        "1" => format!("1e{exponent}"),
        _ => format!("{mantissa}e{exponent}"),
    }
}
