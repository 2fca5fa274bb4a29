//! States named with `symbol:`: the name in equations, expressions, LaTeX and sub-models,
//! and the clashes refused.

use bondgraph_core::equations::{self, StateEquations};
use bondgraph_core::laws;
use bondgraph_core::model::Model;

/// Two tanks in series, each state the tank's volume, named as a process engineer names it,
/// the pump throttled by the second tank's volume.
const TANKS: &str = r#"Model(name: "tanks",
  parameters: {"A_1": (value: 1.0, unit: "m^2"), "A_2": (value: 2.0, unit: "m^2"),
    "rho_g": (value: 9810.0, unit: "Pa/m"), "R": (value: 1.0e5, unit: "Pa*s/m^3"),
    "K": (value: 1.0e-6, unit: "m^3/(s*Pa)")},
  inputs: {"Q": (unit: "m^3/s")},
  elements: {"pump": Sf(flow: "Q - K*rho_g*V_2/A_2"), "p1": Zero,
    "tank1": C(compliance: "A_1/rho_g", symbol: "V_1"), "pipe": One, "r": R(resistance: "R"),
    "p2": Zero, "tank2": C(compliance: "A_2/rho_g", symbol: "V_2"), "out": One,
    "r2": R(resistance: "R")},
  bonds: [("pump", "p1"), ("p1", "tank1"), ("p1", "pipe"), ("pipe", "r"), ("pipe", "p2"),
    ("p2", "tank2"), ("p2", "out"), ("out", "r2")])"#;

fn derive(model: &Model) -> StateEquations {
    equations::derive(model, &laws::plain_laws(model), &Default::default()).unwrap()
}

#[test]
fn a_symbol_names_the_state_everywhere() {
    let model = bondgraph_ron::model::load_str("tanks.ron", TANKS).unwrap();
    let eq = derive(&model);
    let states: Vec<&str> = eq.states.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(states, ["V_1", "V_2"]);
    let a: Vec<Vec<String>> = eq
        .a()
        .iter()
        .map(|row| row.iter().map(|e| e.text(&eq.symbols)).collect())
        .collect();
    // By hand, with P = rho g V / A: V_1' = Q - K P_2 - (P_1 - P_2)/R and
    // V_2' = (P_1 - P_2)/R - P_2/R.
    assert_eq!(
        a,
        [
            ["-rho_g/(A_1*R)", "rho_g*(-K*R + 1)/(A_2*R)"],
            ["rho_g/(A_1*R)", "-2*rho_g/(A_2*R)"],
        ]
    );
    assert!(
        eq.to_latex()
            .contains(r"\begin{bmatrix} V_{1} \\ V_{2} \end{bmatrix}")
    );
    // Co-energy states are the pressures, named as before.
    let coenergy = equations::derive(
        &model,
        &laws::plain_laws(&model),
        &equations::Options {
            variables: equations::Variables::CoEnergy,
        },
    )
    .unwrap();
    let names: Vec<&str> = coenergy.states.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["f_tank1", "f_tank2"]);
}

#[test]
fn a_symbol_that_names_something_else_is_refused() {
    for (symbol, message) in [
        (
            "V_1",
            "element 'tank2': symbol 'V_1' is already the state of 'tank1'",
        ),
        (
            "R",
            "element 'tank2': symbol 'R' is already the parameter 'R'",
        ),
        (
            "q_tank1",
            "element 'tank2': symbol 'q_tank1' is already the state of 'tank1'",
        ),
    ] {
        let text = TANKS
            .replace(r#"symbol: "V_2""#, &format!(r#"symbol: "{symbol}""#))
            .replace("Q - K*rho_g*V_2/A_2", "Q");
        // Without a symbol of its own, the first tank's state is q_tank1.
        let text = if symbol == "q_tank1" {
            text.replace(r#", symbol: "V_1""#, "")
        } else {
            text
        };
        let error = bondgraph_ron::model::load_str("tanks.ron", &text).unwrap_err();
        assert_eq!(error.first().message, message);
        assert_eq!(error.first().location.as_ref().unwrap().line, 8);
    }
}

#[test]
fn a_parts_symbol_is_qualified_where_it_is_used() {
    let dir = std::env::temp_dir().join(format!("bondgraph-symbols-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("tank.ron"),
        r#"Model(name: "tank", parameters: {"A": (value: 1.0, unit: "m^2"),
    "rho_g": (value: 9810.0, unit: "Pa/m"), "R": (value: 1.0e5, unit: "Pa*s/m^3"),
    "V_0": (value: 1.0, unit: "m^3")},
  ports: {"inlet": (element: "level")},
  elements: {"level": Zero, "tank": C(compliance: "A/rho_g", symbol: "V"), "drain": One,
    "r": R(flow: "effort*V/(R*V_0)")},
  bonds: [("level", "tank"), ("level", "drain"), ("drain", "r")])"#,
    )
    .unwrap();
    let user = dir.join("user.ron");
    std::fs::write(
        &user,
        r#"Model(name: "user", inputs: {"Q": (unit: "m^3/s")},
  elements: {"pump": Sf(flow: "Q"), "first": Submodel(file: "tank.ron")},
  bonds: [("pump", "first.inlet")])"#,
    )
    .unwrap();
    let text = std::fs::read_to_string(&user).unwrap();
    let model = bondgraph_ron::model::load_str(&user.display().to_string(), &text).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let options = equations::Options::default();
    let eq = equations::nonlinear::derive(&model, &laws::plain_laws(&model), &options).unwrap();
    let text = eq.to_text(None);
    // The part's state and the drain's law that names it, both qualified: the drain passes
    // P V/(R V_0) with P = rho g V/A, by hand rho g V^2/(A R V_0).
    assert!(text.contains("first.V  volume of 'first.tank'"), "{text}");
    let derivative = text.lines().find(|l| l.starts_with("dfirst.V/dt")).unwrap();
    assert!(derivative.contains("first.V^2"), "{text}");
}
