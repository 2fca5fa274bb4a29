//! Units checked on whole model files: each case is a small model whose expected verdict
//! (and line, and the units named) is worked out by hand in its comment.

use crate::diagnostics::{DiagnosticKind, Diagnostics};
use crate::model;

fn error(text: &str) -> Diagnostics {
    match model::load_str("units.ron", text) {
        Ok(_) => panic!("the model should be rejected"),
        Err(error) => error,
    }
}

#[test]
fn an_unknown_unit_is_named_at_its_parameter_line() {
    let error = error(
        r#"Model(name: "u",
    parameters: {
        "m": (value: 1.0, unit: "kg"),
        "b": (value: 1.0, unit: "N*s/furlong"),
    },
    elements: {"push": Se(effort: "1"), "j": One, "mass": I(inertance: "m"), "damper": R(resistance: "b")},
    bonds: [("push", "j"), ("j", "mass"), ("j", "damper")])"#,
    );
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnknownUnit);
    assert_eq!(first.location.as_ref().unwrap().line, 4);
    assert_eq!(first.element.as_deref(), Some("b"));
    assert_eq!(
        first.message,
        "parameter 'b' has unit \"N*s/furlong\": unknown unit 'furlong'"
    );
}
