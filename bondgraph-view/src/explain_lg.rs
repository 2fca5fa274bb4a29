//! `bondgraph explain` on a linear graph: the normal tree built step by step, as Rowell &
//! Wormley teach it, then the primary and secondary variables, the continuity (cut-set)
//! and compatibility (loop) equations the tree gives, the elemental equations of the mode,
//! and the state equations they lead to.
//!
//! A bond-graph model is explained by `explain_bg`, which also dispatches here.

use bondgraph_core::model::state_symbol;
use std::sync::Arc;

use bondgraph_core::causality;
use bondgraph_core::equations::{Options, Variables};
use bondgraph_core::laws::{self, Law};
use bondgraph_core::linear::{LinearForm, Var};
use bondgraph_core::model::Model;
use bondgraph_core::model::linear_graph::{LinearGraph, reword};
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::normal_tree::{self, NormalTree, Reason, Role, Terms};
use bondgraph_core::source::SourceFile;
use bondgraph_core::symbolic::RatFunc;

use crate::formats::ExplainFormat;
use crate::{Failure, with_source};

/// The explanation of linear graph `model` in `mode`; in Markdown, with headings, numbered
/// lists and the equations in code blocks, as a bond graph's. A bond graph is explained by
/// `explain_bg`.
///
/// # Errors
/// A failure when the mode has no causality or its equations cannot be derived.
pub fn document(
    model: &Model,
    graph: &LinearGraph,
    mode: &Mode,
    source: &Arc<SourceFile>,
    format: ExplainFormat,
) -> Result<String, Failure> {
    let laws = laws::for_mode(model, mode);
    causality::assign(model, &laws).map_err(|d| with_source(reword(model, d), source))?;
    let tree = normal_tree::of_mode(model, &laws).expect("a linear graph has a normal tree");
    let derived = modes::derive(
        model,
        mode,
        &Options {
            variables: Variables::CoEnergy,
        },
    )
    .map_err(|d| with_source(d, source))?;
    let writer = Writer {
        markdown: format == ExplainFormat::Markdown,
    };
    let mut text = explain(&writer, model, graph, &tree, &laws, &mode.spec(model));
    writer.heading(
        &mut text,
        "State equations (co-energy variables), from the elemental, continuity and compatibility equations",
    );
    if writer.markdown {
        text.push_str(&format!("```text\n{}```\n", derived.equations.to_text()));
    } else {
        text.push('\n');
        text.push_str(&derived.equations.to_text());
    }
    Ok(text)
}

/// How the explanation is written: plain text, or Markdown for lecture notes.
struct Writer {
    markdown: bool,
}

impl Writer {
    /// A title: `# title` in Markdown.
    fn title(&self, out: &mut String, text: &str) {
        if self.markdown {
            out.push_str(&format!("# {text}\n\n"));
        } else {
            out.push_str(&format!("{text}\n\n"));
        }
    }

    /// A section's heading: `## heading` in Markdown, `heading:` in text.
    fn heading(&self, out: &mut String, text: &str) {
        if self.markdown {
            out.push_str(&format!("\n## {text}\n\n"));
        } else {
            out.push_str(&format!("\n{text}:\n"));
        }
    }

    /// `'name'` in text, `` `name` `` in Markdown.
    fn name(&self, name: &str) -> String {
        if self.markdown {
            format!("`{name}`")
        } else {
            format!("'{name}'")
        }
    }

    /// Code (a variable, a list of them): as is in text, quoted in Markdown.
    fn code(&self, text: &str) -> String {
        if self.markdown {
            format!("`{text}`")
        } else {
            text.to_string()
        }
    }

    /// A numbered list.
    fn items(&self, out: &mut String, items: &[String]) {
        for (i, item) in items.iter().enumerate() {
            if self.markdown {
                out.push_str(&format!("{}. {item}\n", i + 1));
            } else {
                out.push_str(&format!("  {}. {item}\n", i + 1));
            }
        }
    }

    /// Lines of equations: a code block in Markdown, indented in text.
    fn block(&self, out: &mut String, lines: &[String]) {
        if self.markdown {
            out.push_str("```text\n");
        }
        for line in lines {
            if !self.markdown {
                out.push_str("  ");
            }
            out.push_str(line);
            out.push('\n');
        }
        if self.markdown {
            out.push_str("```\n");
        }
    }
}

/// The explanation of the normal tree and its equations.
fn explain(
    writer: &Writer,
    model: &Model,
    graph: &LinearGraph,
    tree: &NormalTree,
    laws: &[Law],
    spec: &str,
) -> String {
    let mut out = String::new();
    writer.title(
        &mut out,
        &format!(
            "linear graph {}{}: the normal tree (Rowell & Wormley)",
            writer.name(model.name()),
            if spec.is_empty() {
                String::new()
            } else {
                format!(" in mode {spec}")
            }
        ),
    );
    out.push_str(
        "A tree joins every node without a loop. The normal tree takes across sources first, then \
         A-types, D-types and T-types, each in file order, a branch joining where it reaches a \
         node the tree does not reach yet; through sources are links. A-types in the tree and \
         T-types among the links are the independent storage: their across and through \
         variables are the states.\n",
    );
    if !model.parts().is_empty() {
        writer.heading(
            &mut out,
            "Sub-graphs, flattened: each branch and node named with its use's name in front",
        );
        let lines = crate::parts::part_lines(model, &|node| format!("node '{node}'"));
        writer.block(&mut out, &lines);
    }
    two_ports(writer, graph, tree, &mut out);
    writer.heading(&mut out, "Construction");
    construction(writer, graph, tree, &mut out);

    let codes =
        |items: Vec<String>| -> Vec<String> { items.iter().map(|v| writer.code(v)).collect() };
    let list = |items: Vec<String>| {
        if items.is_empty() {
            "none".to_string()
        } else {
            items.join(", ")
        }
    };
    let states = tree.states(graph);
    let dependent = tree.dependent_storage();
    let dependent_text = (!dependent.is_empty()).then(|| {
        let names: Vec<String> = dependent
            .iter()
            .map(|&b| writer.name(&graph.branches[b].name))
            .collect();
        format!(
            "Dependent storage: {} (merged into the states it follows; see the notes below)",
            names.join(", ")
        )
    });
    let across = |b: usize, p: usize| state_symbol("v", &variable(graph, b, p));
    let through = |b: usize, p: usize| state_symbol("f", &variable(graph, b, p));
    let primary = format!(
        "Primary variables: the across variables of the tree, {}; the through variables of the links, {}.",
        list(codes(
            tree.tree_edges().map(|(b, p)| across(b, p)).collect()
        )),
        list(codes(tree.links().map(|(b, p)| through(b, p)).collect()))
    );
    let secondary = format!(
        "Secondary variables: the through variables of the tree, {}; the across variables of the links, {}.",
        list(codes(
            tree.tree_edges().map(|(b, p)| through(b, p)).collect()
        )),
        list(codes(tree.links().map(|(b, p)| across(b, p)).collect()))
    );
    if writer.markdown {
        writer.heading(&mut out, "States and variables");
        out.push_str(&format!("- States: {}.\n", list(codes(states))));
        if let Some(text) = &dependent_text {
            out.push_str(&format!("- {text}.\n"));
        }
        out.push_str(&format!("- {primary}\n- {secondary}\n"));
    } else {
        out.push_str(&format!("\nStates: {}\n", list(states)));
        if let Some(text) = &dependent_text {
            out.push_str(&format!("{text}\n"));
        }
        out.push_str(&format!("\n{primary}\n{secondary}\n"));
    }

    writer.heading(
        &mut out,
        "Continuity (cut-set) equations, one per tree branch",
    );
    let lines: Vec<String> = tree
        .tree_edges()
        .map(|(b, p)| {
            let terms = tree.cut_set_equation(graph, b, p);
            format!("{} = {}", through(b, p), sum(&terms, through))
        })
        .collect();
    writer.block(&mut out, &lines);
    writer.heading(&mut out, "Compatibility (loop) equations, one per link");
    let lines: Vec<String> = tree
        .links()
        .map(|(b, p)| {
            let terms = tree.loop_equation(graph, b, p);
            format!("{} = {}", across(b, p), sum(&terms, across))
        })
        .collect();
    writer.block(&mut out, &lines);
    writer.heading(&mut out, "Elemental equations in this mode");
    let lines: Vec<String> = graph
        .branches
        .iter()
        .enumerate()
        .map(|(b, branch)| {
            let law = &laws[branch.element.index()];
            format!("{}: {}", branch.name, elemental(model, graph, b, law))
        })
        .collect();
    writer.block(&mut out, &lines);
    out
}

/// Where the two-ports' placements were tried: each placement and the tree it gives, the
/// chosen one marked (nothing without two-ports).
fn two_ports(writer: &Writer, graph: &LinearGraph, tree: &NormalTree, out: &mut String) {
    let edge = |b: usize, p: usize| writer.name(&graph.edge_name(b, p));
    if !tree.alternatives.is_empty() {
        let placements = "puts one of its ports in the tree, a gyrator both or neither. Every \
             placement was tried; the tree kept has the most A-types in it, then the fewest \
             T-types:";
        if writer.markdown {
            writer.heading(out, "Two-ports");
            out.push_str(&format!("A transformer {placements}\n\n"));
        } else {
            out.push_str(&format!("\nTwo-ports: a transformer {placements}\n"));
        }
        let items: Vec<String> = tree
            .alternatives
            .iter()
            .enumerate()
            .map(|(i, alternative)| {
                let placed: Vec<String> = alternative
                    .placement
                    .iter()
                    .map(|(b, ports)| {
                        let names: Vec<String> = ports.iter().map(|&p| edge(*b, p)).collect();
                        if names.is_empty() {
                            format!("neither port of {}", writer.name(&graph.branches[*b].name))
                        } else {
                            names.join(" and ")
                        }
                    })
                    .collect();
                let result = if alternative.feasible {
                    format!(
                        "{} A-type{} and {} T-type{} in the tree",
                        alternative.a_in_tree,
                        plural(alternative.a_in_tree),
                        alternative.t_in_tree,
                        plural(alternative.t_in_tree)
                    )
                } else {
                    "no tree (a port would close a loop, or the tree would not reach every node)"
                        .to_string()
                };
                let chosen = match (i == tree.chosen, writer.markdown) {
                    (false, _) => "",
                    (true, false) => "  <- chosen",
                    (true, true) => " (**chosen**)",
                };
                format!("{} in the tree: {result}{chosen}", placed.join(", "))
            })
            .collect();
        writer.items(out, &items);
    }
}

/// The normal tree's construction, branch by branch: joined or a link, and why.
fn construction(writer: &Writer, graph: &LinearGraph, tree: &NormalTree, out: &mut String) {
    let edge = |b: usize, p: usize| writer.name(&graph.edge_name(b, p));
    let steps: Vec<String> = tree
        .steps
        .iter()
        .map(|step| {
            let e = &graph.branches[step.branch].edges[step.port];
            let what = format!(
                "{} ({}, {} -> {})",
                edge(step.branch, step.port),
                role_text(graph, step.branch, step.role),
                graph.node(e.from).name,
                graph.node(e.to).name
            );
            let why = match &step.reason {
                Reason::Reaches => {
                    let mut s =
                        "joins the tree: it reaches a node the tree did not reach".to_string();
                    if step.role == Role::A {
                        s.push_str(&format!(
                            "; its across variable {} is a state",
                            writer.code(&state_symbol("v", &graph.branches[step.branch].name))
                        ));
                    }
                    if step.role == Role::T {
                        s.push_str(
                            "; a T-type in the tree is dependent storage: its through variable is set by the links of its cut-set",
                        );
                    }
                    s
                }
                Reason::ClosesLoop(path) => {
                    let names: Vec<String> = path.iter().map(|&(b, p)| edge(b, p)).collect();
                    let mut s = format!(
                        "becomes a link: it would close a loop with {}",
                        names.join(", ")
                    );
                    match step.role {
                        Role::A => s.push_str(
                            "; an A-type link is dependent storage: its across variable is set by the loop",
                        ),
                        Role::T => s.push_str(&format!(
                            "; its through variable {} is a state",
                            writer.code(&state_symbol("f", &graph.branches[step.branch].name))
                        )),
                        Role::AcrossSource => s.push_str(
                            "; across sources in a loop contradict each other, so this mode cannot be entered",
                        ),
                        _ => {}
                    }
                    s
                }
                Reason::TwoPortInTree => {
                    "joins the tree, as the chosen two-port placement puts it there".to_string()
                }
                Reason::TwoPortLink => {
                    "is a link, as the chosen two-port placement leaves it out".to_string()
                }
                Reason::Source if step.in_tree => {
                    "joins the tree: nothing else reaches its node, so its cut-set holds only sources"
                        .to_string()
                }
                Reason::Source => "is a link: through sources are links".to_string(),
            };
            format!("{what} {why}.")
        })
        .collect();
    writer.items(out, &steps);
}

/// The variable suffix of an edge: the branch's name, with `_1`, `_2` for a two-port's ports.
fn variable(graph: &LinearGraph, b: usize, p: usize) -> String {
    let branch = &graph.branches[b];
    if branch.kind.is_two_port() {
        format!("{}_{}", branch.name, p + 1)
    } else {
        branch.name.clone()
    }
}

/// `v_a - v_b + ...`, or `0`.
fn sum(terms: &Terms, name: impl Fn(usize, usize) -> String) -> String {
    let mut out = String::new();
    for &(b, p, sign) in terms {
        match (out.is_empty(), sign > 0) {
            (true, true) => {}
            (true, false) => out.push('-'),
            (false, true) => out.push_str(" + "),
            (false, false) => out.push_str(" - "),
        }
        out.push_str(&name(b, p));
    }
    if out.is_empty() {
        out.push('0');
    }
    out
}

/// The branch's role, with its kind where the mode makes it something else (a stuck
/// contact is an across source).
fn role_text(graph: &LinearGraph, b: usize, role: Role) -> String {
    let kind = graph.branches[b].kind;
    let described = role.description();
    if described == kind.description() || kind.is_two_port() {
        described.to_string()
    } else {
        format!("{}, here a {described}", kind.description())
    }
}

/// The branch's constitutive law in the mode, in its across and through variables.
fn elemental(model: &Model, graph: &LinearGraph, b: usize, law: &Law) -> String {
    let name = variable(graph, b, 0);
    let text = |r: &RatFunc| r.text(model.symbols());
    let times = |r: &RatFunc, v: &str| {
        if r.is_one() {
            v.to_string()
        } else {
            format!("{}*{v}", parenthesised(&text(r)))
        }
    };
    // A sub-graph's branch keeps its prefix in front: `wall.v_capacity`.
    let v = |n: &str| state_symbol("v", n);
    let f = |n: &str| state_symbol("f", n);
    match law {
        Law::Inertia(c) => format!("{} = {}", f(&name), times(c, &format!("d{}/dt", v(&name)))),
        Law::Compliance(l) => format!("{} = {}", v(&name), times(l, &format!("d{}/dt", f(&name)))),
        Law::Resistor { resistance, offset } => {
            let mut form = LinearForm::term(Var::State(0), resistance.clone());
            form.add(offset);
            format!("{} = {}", f(&name), form_text(model, &form, &v(&name)))
        }
        Law::EffortSource(value) => format!("{} = {}", f(&name), form_text(model, value, "")),
        Law::FlowSource(value) => format!("{} = {}", v(&name), form_text(model, value, "")),
        Law::SlackStorage => format!(
            "{} = 0 (slack: it stretches at {} carrying nothing)",
            f(&name),
            v(&name)
        ),
        Law::Transformer(n) => {
            let (one, two) = (variable(graph, b, 0), variable(graph, b, 1));
            format!(
                "{} = {}, {} = -{}/{}",
                v(&one),
                times(n, &v(&two)),
                f(&one),
                f(&two),
                parenthesised(&text(n))
            )
        }
        Law::Gyrator(r) => {
            let (one, two) = (variable(graph, b, 0), variable(graph, b, 1));
            let g = r.inv().unwrap_or_else(RatFunc::zero);
            format!(
                "{} = {}, {} = -{}/{}",
                v(&one),
                times(&g, &f(&two)),
                f(&one),
                v(&two),
                parenthesised(&text(&g))
            )
        }
        // A linear graph's branches are written with linear laws only.
        Law::Nonlinear(law) => format!("{}: a nonlinear law", law.keyword()),
        Law::ZeroJunction | Law::OneJunction => String::new(),
    }
}

/// An affine form of the inputs (and, in a source with feedback, of storage elements' energy
/// variables), with `Var::State(0)` standing for `variable`.
fn form_text(model: &Model, form: &LinearForm, variable: &str) -> String {
    let mut out = String::new();
    for (var, coefficient) in form.terms() {
        let (negative, magnitude) = coefficient.signed_text(model.symbols());
        let name = match var {
            Var::State(_) => variable.to_string(),
            Var::Input(i) => model.inputs()[*i as usize].name.clone(),
            Var::Storage(e) => model
                .storage_name(bondgraph_core::model::ElementId(*e))
                .unwrap_or_default(),
            _ => String::new(),
        };
        let term = match (name.is_empty(), magnitude.as_str()) {
            (true, _) => magnitude,
            (false, "1") => name,
            (false, m) => format!("{}*{name}", parenthesised(m)),
        };
        match (out.is_empty(), negative) {
            (true, false) => {}
            (true, true) => out.push('-'),
            (false, false) => out.push_str(" + "),
            (false, true) => out.push_str(" - "),
        }
        out.push_str(&term);
    }
    if out.is_empty() {
        out.push('0');
    }
    out
}

fn parenthesised(text: &str) -> String {
    if text.chars().skip(1).any(|c| matches!(c, '+' | '-')) {
        format!("({text})")
    } else {
        text.to_string()
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}
