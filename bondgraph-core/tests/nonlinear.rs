//! Nonlinear derivations through the public interface: algebraic loops through modulated
//! and nonlinear laws, one-way laws, and the linear machinery underneath (merging of
//! rigidly joined masses in a nonlinear model).

use bondgraph_core::DiagnosticKind;
use bondgraph_core::equations::Options;
use bondgraph_core::equations::nonlinear::{self, NonlinearEquations, OperatingPoint};
use bondgraph_core::laws;

/// A mass pushed by F and held back by two dampers in series, the first with `damper1`.
fn series_dampers(damper1: &str) -> String {
    format!(
        r#"Model(name: "series", parameters: {{"m": (value: 2.0), "b1": (value: 6.0), "b2": (value: 3.0), "c": (value: 0.5)}},
        inputs: {{"F": (), "u": ()}},
        elements: {{"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"), "node": Zero,
                   "damper1": {damper1}, "damper2": R(resistance: "b2")}},
        bonds: [("force", "v"), ("v", "mass"), ("v", "node"), ("node", "damper1"), ("node", "damper2")])"#
    )
}

fn derive(text: &str) -> Result<NonlinearEquations, bondgraph_core::Diagnostics> {
    let model = bondgraph_ron::model::load_str("m.ron", text).unwrap();
    assert!(model.is_nonlinear());
    nonlinear::derive(&model, &laws::plain_laws(&model), &Options::default())
}

#[test]
fn a_loop_through_a_modulated_resistor_is_solved_symbolically() {
    // Dampers in series, the first modulated by u: together b1(1+u)·b2/(b1(1+u) + b2).
    let eq = derive(&series_dampers(r#"R(resistance: "b1*(1 + u)")"#)).unwrap();
    assert!(
        eq.notes
            .iter()
            .any(|n| matches!(n, bondgraph_core::equations::Note::AlgebraicLoop { .. }))
    );
    let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
    for (p, u) in [(1.0, 0.0), (-0.5, 2.0)] {
        let point = OperatingPoint::from_values(vec![p], vec![0.0, u]);
        let dp = eq.evaluate(&eq.derivatives[0], &point);
        let (b1, b2, m) = (6.0 * (1.0 + u), 3.0, 2.0);
        let expected = -(b1 * b2 / (b1 + b2)) * p / m;
        assert!(
            (dp - expected).abs() < 1e-14,
            "{names:?} at u = {u}: {dp} vs {expected}"
        );
    }
}

#[test]
fn a_loop_through_a_truly_nonlinear_law_is_diagnosed() {
    // b1·f + c·f³ cannot be solved for f: damper1 takes resistance causality, and the
    // force it must carry depends on its own flow through damper2.
    let error = derive(&series_dampers(r#"R(effort: "b1*flow + c*flow^3")"#)).unwrap_err();
    let d = error.first();
    assert_eq!(d.kind, DiagnosticKind::SingularLoop);
    assert_eq!(
        d.message,
        "the algebraic loop through the nonlinear laws of 'damper1' cannot be solved symbolically"
    );
    // Invertible (f³ is) or not, two dampers in series always close a loop: with this
    // cubic damper in either causality it is not affine in its unknown.
    let error = derive(&series_dampers(r#"R(effort: "c*flow^3")"#)).unwrap_err();
    assert_eq!(error.first().kind, DiagnosticKind::SingularLoop);
}

#[test]
fn rigid_masses_merge_in_a_nonlinear_model() {
    // Two masses on one 1-junction with a nonlinear spring: one state, storage m1 + m2.
    let text = r#"Model(name: "rigid", parameters: {"m1": (value: 1.0), "m2": (value: 3.0), "k": (value: 2.0)},
        elements: {"v": One, "mass1": I(inertance: "m1"), "mass2": I(inertance: "m2"),
                   "spring": C(effort: "k*sin(q_spring)")},
        bonds: [("v", "mass1"), ("v", "mass2"), ("v", "spring")])"#;
    let eq = derive(text).unwrap();
    assert_eq!(eq.states.len(), 2);
    assert_eq!(eq.states[0].merged, ["mass2"]);
    assert_eq!(eq.sym_text(&eq.derivatives[1]), "p_mass1/(m1 + m2)");
    assert_eq!(eq.sym_text(&eq.derivatives[0]), "-k*sin(q_spring)");
    // A nonlinear inertia in derivative causality cannot be merged: said, by name.
    let text = text.replace(
        r#""mass2": I(inertance: "m2")"#,
        r#""mass2": I(flow: "p_mass2/m2*(1 + p_mass2^2)")"#,
    );
    let error = derive(&text).unwrap_err();
    assert_eq!(error.first().kind, DiagnosticKind::DependentStorage);
    assert_eq!(error.first().element.as_deref(), Some("mass2"));
}

#[test]
fn a_nonlinear_model_is_not_derived_as_a_linear_one() {
    let text = series_dampers(r#"R(effort: "c*flow^3")"#);
    let model = bondgraph_ron::model::load_str("m.ron", &text).unwrap();
    let error =
        bondgraph_core::equations::derive(&model, &laws::plain_laws(&model), &Options::default())
            .unwrap_err();
    assert_eq!(error.first().kind, DiagnosticKind::NotLinear);
    assert!(
        error
            .first()
            .message
            .contains("'damper1' has a nonlinear law (effort: \"c*flow^3\")"),
        "{}",
        error.first().message
    );
}
