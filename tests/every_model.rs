//! The teaching commands on every model: `analyze`, `explain`, `graph --format svg` and
//! `compare` work on every model file under `models/examples` (its subfolders included) and
//! on every mode of the flagship, through the library functions the binary prints.
//!
//! A nonlinear model is analysed at the equilibrium found from zero (the command's default)
//! and is refused by `compare`, which compares linear modes only; every other model's own
//! `equations --format json`, turned into an answer file, compares equal.

use std::sync::Arc;

use bondgraph_core::equations::{Options, Variables};
use bondgraph_core::model::Model;
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::source::SourceFile;
use bondgraph_core::{causality, laws, normal_tree};
use bondgraph_view::analyze::{self, Request};
use bondgraph_view::explain_bg::{self, ExplainFormat};
use bondgraph_view::{Failure, bg_svg, compare, explain_lg, lg_svg, load};
use serde_json::Value;

use crate::bond_graph_views;
use crate::support::{model_files_under, root};

fn failed(what: &str, failure: Failure) -> ! {
    let messages: Vec<String> = failure
        .diagnostics
        .iter()
        .map(|d| d.message.clone())
        .collect();
    panic!("{what}: {}", messages.join("; "))
}

/// The model's own equations of `mode` as an answer file: its states, `A`, `B` and `E`
/// from the document `bondgraph equations --format json` prints.
fn own_answer(model: &Model, mode: &Mode) -> String {
    let variables = Variables::preferred(model);
    let derived = modes::derive(model, mode, &Options { variables })
        .unwrap_or_else(|e| panic!("{}: {e}", model.name()));
    let document = serde_json::to_value(derived.equations.to_json(&mode.spec(model), &[]))
        .expect("the equations' JSON");
    let names: Vec<&Value> = document["states"]
        .as_array()
        .expect("states")
        .iter()
        .map(|s| &s["name"])
        .collect();
    let mut answer = format!(
        "Answer(\n    states: {},\n    A: {},\n    B: {},\n",
        serde_json::to_string(&names).expect("names"),
        document["A"],
        document["B"]
    );
    if document["E"].is_array() {
        answer.push_str(&format!("    E: {},\n", document["E"]));
    }
    answer.push_str(")\n");
    answer
}

/// Every teaching command on `model` in `mode` (`spec` names it, for messages).
fn every_command(model: &Model, source: &Arc<SourceFile>, mode: &Mode, what: &str) {
    let spec = mode.spec(model);
    let request = Request {
        mode: (!spec.is_empty()).then(|| spec.clone()),
        ..Request::default()
    };

    // analyze: one eigenvalue per state; a nonlinear model at its linearisation.
    let analyzed = analyze::analyze(model, source, &request)
        .unwrap_or_else(|e| failed(&format!("{what}: analyze"), e))
        .json();
    let states = analyzed["states"].as_array().expect("states").len();
    assert_eq!(
        analyzed["eigenvalues"]
            .as_array()
            .expect("eigenvalues")
            .len(),
        states,
        "{what}: eigenvalues"
    );
    assert_eq!(
        analyzed["linearised_at"].is_string(),
        model.is_nonlinear(),
        "{what}: linearised"
    );

    // explain: the steps, and the states they end with.
    let text = if let Some(graph) = &model.linear_graph() {
        explain_lg::document(model, graph, mode, source, ExplainFormat::Markdown)
            .unwrap_or_else(|e| failed(&format!("{what}: explain"), e))
    } else {
        let explanation = explain_bg::document(model, mode, source, ExplainFormat::Markdown)
            .unwrap_or_else(|e| failed(&format!("{what}: explain"), e));
        if let Some(e) = explanation.underivable {
            failed(&format!("{what}: explain"), e);
        }
        explanation.text
    };
    assert!(text.starts_with("# "), "{what}: explain\n{text}");
    for state in analyzed["states"].as_array().expect("states") {
        let name = state.as_str().expect("a state's name");
        assert!(text.contains(name), "{what}: explain does not name {name}");
    }

    // graph --format svg: every bond, or every branch, drawn once.
    let laws = laws::for_mode(model, mode);
    match &model.linear_graph() {
        Some(graph) => {
            let tree = normal_tree::of_mode(model, &laws).expect("a normal tree");
            let svg = lg_svg::draw(model, graph, &tree, &spec);
            let edges = graph.edges().count();
            assert_eq!(svg.matches("<path ").count(), edges, "{what}: branches");
            for (b, p, _) in graph.edges() {
                let label = format!(">{}</text>", graph.edge_name(b, p));
                assert_eq!(svg.matches(&label).count(), 1, "{what}: {label}");
            }
        }
        None => {
            let causal = causality::assign(model, &laws).expect("causality");
            let svg = bg_svg::draw(model, mode, &causal);
            let drawing = bond_graph_views::read(&svg);
            assert_eq!(drawing.bonds.len(), model.bonds().len(), "{what}: bonds");
            for n in 1..=model.bonds().len() {
                assert_eq!(drawing.bonds[&n].len(), 1, "{what}: bond {n}");
            }
        }
    }

    // compare: the model's own equations are equal to it; a nonlinear model is refused.
    let answer_text = if model.is_nonlinear() {
        "Answer(A: [[\"0\"]], B: [[\"0\"]])\n".to_string()
    } else {
        own_answer(model, mode)
    };
    let answer = SourceFile::new(format!("{what}.answer.ron"), answer_text);
    let mode_arg = (!spec.is_empty()).then_some(spec.as_str());
    match compare::check(model, source, &answer, mode_arg) {
        Ok(compared) if !model.is_nonlinear() => {
            assert!(compared.agrees, "{what}: {}", compared.text);
            assert!(
                compared.text.starts_with("equal"),
                "{what}: {}\n{}",
                compared.text,
                answer.text()
            );
        }
        Ok(compared) => panic!("{what}: a nonlinear model compared: {}", compared.text),
        Err(e) if model.is_nonlinear() => {
            let message = &e.diagnostics.iter().next().expect("a diagnostic").message;
            assert!(
                message.contains(
                    "is nonlinear: an answer's A and B are compared with a linear mode's"
                ),
                "{what}: {message}"
            );
        }
        Err(e) => failed(&format!("{what}: compare"), e),
    }
}

#[test]
fn analyze_explain_graph_and_compare_work_on_every_example_and_flagship_mode() {
    let files = model_files_under("models/examples");
    // The subfolders are searched: the nonlinear examples and the geared motor.
    assert!(files.iter().any(|f| f.contains("/nonlinear/")), "{files:?}");
    assert!(
        files.iter().any(|f| f.contains("/geared_motor/")),
        "{files:?}"
    );
    assert!(
        !files
            .iter()
            .any(|f| f.contains("extensions/") || f.ends_with("step.ron"))
    );
    for path in &files {
        let (model, source) = load(&root().join(path)).unwrap_or_else(|e| failed(path, e));
        every_command(&model, &source, &Mode::initial(&model), path);
    }
    let path = "models/eversion/robot.ron";
    let (model, source) = load(&root().join(path)).unwrap_or_else(|e| failed(path, e));
    let reachable = modes::reachable(&model, &Options::default()).expect("flagship modes");
    assert_eq!(reachable.modes.len(), 18);
    for derived in &reachable.modes {
        let what = format!("{path} in mode {}", derived.mode.spec(&model));
        every_command(&model, &source, &derived.mode, &what);
    }
}
