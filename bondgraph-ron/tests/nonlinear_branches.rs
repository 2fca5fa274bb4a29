//! Nonlinear linear-graph branches derive what a hand derivation, and the same model as a
//! bond graph, derive.

use bondgraph_core::equations::{self, Variables};
use bondgraph_core::laws;
use bondgraph_core::model::Model;

fn load(name: &str, text: &str) -> Model {
    bondgraph_ron::model::load_str(name, text).unwrap_or_else(|e| panic!("{e}"))
}

/// The right-hand sides as printed, one line per state (`dq/dt = ...`), in the variables the
/// model is best read in.
fn derivatives(model: &Model) -> Vec<String> {
    let options = equations::Options {
        variables: Variables::preferred(model),
    };
    let eq = equations::nonlinear::derive(model, &laws::plain_laws(model), &options).unwrap();
    eq.to_text(None)
        .lines()
        .filter(|l| l.starts_with('d') && l.contains("/dt"))
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect()
}

const DUFFING_LG: &str = r#"LinearGraph(
    name: "duffing",
    parameters: {"m": (value: 1.0, unit: "kg"), "k": (value: 100.0, unit: "N/m"),
        "k_3": (value: 1.0e4, unit: "N/m^3"), "b": (value: 2.0, unit: "N*s/m")},
    inputs: {"F": (unit: "N")},
    ground: "g",
    branches: {
        "force": ThroughSource(value: "F", from: "g", to: "v1"),
        "mass": A(capacitance: "m", from: "v1", to: "g"),
        "spring": T(through: "k*q_spring + k_3*q_spring^3", from: "v1", to: "g"),
        "damper": D(conductance: "b", from: "v1", to: "g"),
    },
)"#;

const DUFFING_BG: &str = r#"Model(
    name: "duffing",
    parameters: {"m": (value: 1.0, unit: "kg"), "k": (value: 100.0, unit: "N/m"),
        "k_3": (value: 1.0e4, unit: "N/m^3"), "b": (value: 2.0, unit: "N*s/m")},
    inputs: {"F": (unit: "N")},
    elements: {"force": Se(effort: "F"), "v1": One, "mass": I(inertance: "m"),
        "spring": C(effort: "k*q_spring + k_3*q_spring^3"), "damper": R(resistance: "b")},
    bonds: [("force", "v1"), ("v1", "mass"), ("v1", "spring"), ("v1", "damper")],
)"#;

#[test]
fn a_hardening_spring_as_a_t_type_is_the_bond_graphs_nonlinear_compliance() {
    let graph = derivatives(&load("duffing.lg.ron", DUFFING_LG));
    // By hand: m x'' = F - b x' - k x - k_3 x^3, in the mass's momentum and the spring's
    // stretch (energy variables: the spring's co-energy would need its law's inverse).
    assert_eq!(
        graph,
        [
            "dp_mass/dt = -b/m*p_mass - k*q_spring - k_3*q_spring^3 + F",
            "dq_spring/dt = p_mass/m",
        ]
    );
    assert_eq!(graph, derivatives(&load("duffing.ron", DUFFING_BG)));
}

#[test]
fn a_tank_whose_pressure_grows_with_the_square_of_its_volume_drains_by_hand() {
    let tank = load(
        "tank.lg.ron",
        r#"LinearGraph(
    name: "cone_tank",
    parameters: {"a": (value: 2.0e-3, unit: "Pa/m^6"), "R": (value: 1.0e5, unit: "Pa*s/m^3")},
    inputs: {"Q_in": (unit: "m^3/s")},
    ground: "g",
    branches: {
        "inflow": ThroughSource(value: "Q_in", from: "g", to: "p1"),
        "tank": A(across: "a*p_tank^2", from: "p1", to: "g"),
        "outlet": D(resistance: "R", from: "p1", to: "g"),
    },
)"#,
    );
    // By hand: V' = Q_in - P/R with P = a V^2.
    assert_eq!(derivatives(&tank), ["dp_tank/dt = -a/R*p_tank^2 + Q_in"]);
}

#[test]
fn a_law_and_a_coefficient_together_are_refused() {
    let both = DUFFING_LG.replace(r#"T(through:"#, r#"T(stiffness: "k", through:"#);
    let error = bondgraph_ron::model::load_str("d.lg.ron", &both).unwrap_err();
    assert_eq!(
        error.first().message,
        "branch 'spring' gives both through and stiffness; give one"
    );
    let neither = DUFFING_LG.replace(r#"A(capacitance: "m", "#, "A(");
    let error = bondgraph_ron::model::load_str("d.lg.ron", &neither).unwrap_err();
    assert_eq!(
        error.first().message,
        "A branch 'mass' needs a capacitance or an across law"
    );
}
