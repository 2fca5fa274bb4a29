//! Causal conflicts name the junction or the bond, at its place in the file.

use bondgraph_core::causality::assign;
use bondgraph_core::laws;
use bondgraph_core::{Diagnostic, DiagnosticKind};
use bondgraph_ron::model;

fn conflict(elements: &str, bonds: &str) -> Diagnostic {
    let text = format!(
        "Model(name: \"m\", parameters: {{\"b\": (value: 1.0)}}, inputs: {{\"u\": (), \"w\": ()}},\n\
         elements: {{{elements}}},\nbonds: [{bonds}])"
    );
    let model = model::load_str("m.ron", &text).unwrap();
    let error = assign(&model, &laws::plain_laws(&model)).unwrap_err();
    assert_eq!(error.0.len(), 1);
    error.first().clone()
}

#[test]
fn two_sources_of_a_junctions_common_variable_name_the_junction() {
    let d = conflict(
        r#""a": Sf(flow: "u"), "b": Sf(flow: "w"), "v": One, "r": R(resistance: "b")"#,
        r#"("a", "v"), ("b", "v"), ("v", "r")"#,
    );
    assert_eq!(d.kind, DiagnosticKind::CausalConflict);
    assert_eq!(
        d.message,
        "causal conflict at 1-junction 'v': its flow is imposed by both flow source 'a' and flow source 'b'"
    );
    assert_eq!(d.element.as_deref(), Some("v"));
    assert_eq!(d.location.map(|l| (l.line, l.column)), Some((2, 52)));
}

#[test]
fn sources_fighting_over_anything_else_name_the_bond() {
    // Two flow sources alone on a 0-junction: its common effort is free, but the flow
    // balance is imposed twice.
    let d = conflict(
        r#""a": Sf(flow: "u"), "n": Zero, "b": Sf(flow: "w")"#,
        r#"("a", "n"), ("n", "b")"#,
    );
    assert_eq!(d.kind, DiagnosticKind::CausalConflict);
    assert_eq!(
        d.message,
        "causal conflict on bond n -> b: flow source 'a' and flow source 'b' both impose its causality"
    );
    assert_eq!(d.element.as_deref(), Some("b"));
    assert_eq!(d.location.map(|l| (l.line, l.column)), Some((3, 21)));
}
