//! Extension laws written as a user writes them: the law's inverse where causality needs it,
//! and what is said where it cannot be found.

use bondgraph_core::model;

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

fn derive(text: &str) -> bondgraph_core::diagnostics::Result<()> {
    let model = crate::model::load_str("tank.ron", text)?;
    bondgraph_core::modes::reachable_nonlinear(
        &model,
        &bondgraph_core::equations::Options::default(),
    )
    .map(|_| ())
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

/// Two blocks (heat capacities 2 and 3) joined by a bar and a joint in series, the joint's
/// resistance at its no-effect value 0, as a bond graph: the joint must take the heat flow
/// (e = 0·f), the bar the temperature drop.
#[test]
fn a_series_resistor_at_zero_is_accepted_in_a_bond_graph() {
    let text = r#"Model(name: "pair",
        parameters: {"C_1": (value: 2.0), "C_2": (value: 3.0), "R_12": (value: 1.0), "R_c": (value: 0.0)},
        elements: {"T1": Zero, "T2": Zero, "block_1": C(compliance: "C_1"), "block_2": C(compliance: "C_2"),
                   "drop": One, "bar": R(resistance: "R_12"), "joint": R(resistance: "R_c")},
        bonds: [("T1", "block_1"), ("T2", "block_2"), ("T1", "drop"), ("drop", "bar"), ("drop", "joint"), ("drop", "T2")])"#;
    let model = crate::model::load_str("pair.ron", text).unwrap_or_else(|e| panic!("{e}"));
    // States q_1 = C_1 T1, q_2 = C_2 T2: dq_1/dt = -(T1 - T2)/R_12 = -q_1/2 + q_2/3.
    assert_eq!(a_matrix(&model), [[-0.5, 1.0 / 3.0], [0.5, -1.0 / 3.0]]);
}

/// The state matrix at the model's values; panics on any problem.
fn a_matrix(model: &model::Model) -> Vec<Vec<f64>> {
    let equations = bondgraph_core::equations::derive(
        model,
        &bondgraph_core::laws::plain_laws(model),
        &bondgraph_core::equations::Options::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    equations
        .a()
        .iter()
        .map(|row| row.iter().map(|a| equations.evaluate(a)).collect())
        .collect()
}

/// The same as a linear graph, the joint a new node's D-type at resistance 0: across
/// = 0·through, which the joint can only give as a through variable's consequence.
#[test]
fn a_series_resistance_at_zero_is_accepted_in_a_linear_graph() {
    let text = r#"LinearGraph(name: "pair", ground: "g",
        parameters: {"C_1": (value: 2.0), "C_2": (value: 3.0), "R_12": (value: 1.0), "R_c": (value: 0.0)},
        branches: {
            "block_1": A(capacitance: "C_1", from: "T1", to: "g"),
            "block_2": A(capacitance: "C_2", from: "T2", to: "g"),
            "bar": D(resistance: "R_12", from: "T1", to: "contact"),
            "joint": D(resistance: "R_c", from: "contact", to: "T2"),
        })"#;
    let model = crate::model::load_str("pair.lg.ron", text).unwrap_or_else(|e| panic!("{e}"));
    // States the heats p_1 = C_1 T1, p_2 = C_2 T2 (energy variables, as for the bond
    // graph): dp_1/dt = -(T1 - T2)/R_12 = -p_1/2 + p_2/3.
    assert_eq!(a_matrix(&model), [[-0.5, 1.0 / 3.0], [0.5, -1.0 / 3.0]]);
}

/// A tank whose cross-section grows with the level, `A_0 + a h`: its level from its volume
/// is `(sqrt(A_0^2 + 2 a q) - A_0)/a`, which is 0/0 at `a = 0`, the no-effect value of the
/// taper, at every volume. `check` says so, naming the element and the value; the same law
/// written without the division is accepted.
#[test]
fn a_law_that_is_zero_over_zero_at_its_no_effect_value_is_named() {
    let tank = |law: &str| {
        format!(
            r#"Model(name: "tapered",
                parameters: {{"A_0": (value: 2.0), "a": (value: 0.0), "R": (value: 3.0)}},
                elements: {{"tank": C(effort: "{law}"), "p": Zero, "drain": R(resistance: "R")}},
                bonds: [("p", "tank"), ("p", "drain")])"#
        )
    };
    let error = crate::model::load_str("tapered.ron", &tank("(sqrt(A_0^2 + 2*a*q_tank) - A_0)/a"))
        .unwrap_err();
    let first = error.first();
    assert_eq!(
        first.message,
        "element 'tank': effort \"(sqrt(A_0^2 + 2*a*q_tank) - A_0)/a\" is 0/0 at a = 0, its value in the model, whatever the state"
    );
    assert_eq!(first.location.as_ref().unwrap().line, 3);
    crate::model::load_str(
        "tapered.ron",
        &tank("2*q_tank/(sqrt(A_0^2 + 2*a*q_tank) + A_0)"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
