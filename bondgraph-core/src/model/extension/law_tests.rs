//! Extension laws written as a user writes them: the law's inverse where causality needs it,
//! and what is said where it cannot be found.

use crate::model;

fn tank_draining_through(law: &str) -> String {
    format!(
        r#"Model(name: "tank",
            parameters: {{"C": (value: 2.0), "R_2": (value: 4.0), "K_o": (value: 0.5)}},
            inputs: {{"Q": ()}},
            elements: {{"pump": Sf(flow: "Q"), "p": Zero, "tank": C(compliance: "C"),
                       "drain": R(effort: "{law}")}},
            bonds: [("pump", "p"), ("p", "tank"), ("p", "drain")])"#
    )
}

fn derive(text: &str) -> crate::diagnostics::Result<()> {
    let model = model::load_str("tank.ron", text)?;
    crate::modes::reachable_nonlinear(&model, &crate::equations::Options::default()).map(|_| ())
}

#[test]
fn a_laminar_and_turbulent_drain_takes_the_flow_its_tank_gives() {
    derive(&tank_draining_through("R_2*flow + K_o*flow*abs(flow)"))
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_law_that_cannot_be_turned_round_is_named_as_the_cause() {
    let error = derive(&tank_draining_through("R_2*flow + K_o*flow^3")).unwrap_err();
    let first = error.first();
    assert!(first.message.contains("'tank'"), "{error}");
    let notes = first.notes.join("\n");
    assert!(
        notes.contains(
            "'drain' has its law as effort: f(flow), which could not be solved for the flow"
        ),
        "{error}"
    );
    assert!(!notes.contains("mass"), "{error}");
}
