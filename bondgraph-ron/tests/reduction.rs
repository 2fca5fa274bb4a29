//! A model without a storage element: the reduced model derives what a hand derivation
//! without it gives.

use bondgraph_core::DiagnosticKind;
use bondgraph_core::source::SourceFile;
use bondgraph_ron::model::reduction::without_storage;

const TWO_MASSES: &str = r#"Model(name: "tip",
    parameters: {"m": (value: 1e-12), "M": (value: 2.0), "b": (value: 3.0), "k": (value: 5.0)},
    inputs: {"F": ()},
    elements: {"push": Se(effort: "F"), "v": One, "tiny": I(inertance: "m"),
               "damper": R(resistance: "b"), "coupling": Zero, "spring": C(stiffness: "k"),
               "w": One, "body": I(inertance: "M")},
    bonds: [("push", "v"), ("v", "tiny"), ("v", "damper"), ("v", "coupling"),
            ("coupling", "spring"), ("coupling", "w"), ("w", "body")])"#;

#[test]
fn removing_a_tiny_mass_leaves_a_valid_model_with_one_state_less() {
    let source = SourceFile::new("tip.ron", TWO_MASSES);
    let model = bondgraph_ron::model::load_source(&source).unwrap();
    let reduced = without_storage(&model, &source, &["tiny".into()]).unwrap();
    assert_eq!(reduced.removed, ["tiny"]);
    assert_eq!(reduced.model.elements().len(), model.elements().len() - 1);
    assert_eq!(reduced.source.name(), "tip.ron (without tiny)");
    // By hand: without the tiny mass the damper sets v from F - k q = b v, so with states
    // (q_spring, p_body): dq/dt = v - p/M = -(k/b) q - p/M + F/b and dp/dt = k q.
    let laws = bondgraph_core::laws::plain_laws(&reduced.model);
    let eq = bondgraph_core::equations::derive(&reduced.model, &laws, &Default::default()).unwrap();
    let names: Vec<&str> = eq.states.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["q_spring", "p_body"]);
    let text = |rows: Vec<Vec<bondgraph_core::symbolic::RatFunc>>| -> Vec<Vec<String>> {
        rows.iter()
            .map(|r| r.iter().map(|e| e.text(&eq.symbols)).collect())
            .collect()
    };
    assert_eq!(text(eq.a()), [["-k/b", "-1/M"], ["k", "0"]]);
    assert_eq!(text(eq.b()), [["1/b"], ["0"]]);
}

#[test]
fn only_storage_can_be_removed() {
    let source = SourceFile::new("tip.ron", TWO_MASSES);
    let model = bondgraph_ron::model::load_source(&source).unwrap();
    let error = without_storage(&model, &source, &["damper".into()]).unwrap_err();
    assert_eq!(error.first().kind, DiagnosticKind::InvalidValue);
    let error = without_storage(&model, &source, &["nope".into()]).unwrap_err();
    assert_eq!(error.first().kind, DiagnosticKind::UndefinedElement);
}
