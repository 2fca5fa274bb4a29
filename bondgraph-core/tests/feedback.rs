//! Sources that feed back states: a source affine in states and inputs, with parameter
//! coefficients, is a linear controller, and the model stays linear.
//!
//! The mass-spring-damper with a PD controller on the mass, `Se(effort: "-K_c*q_spring -
//! K_d/m*p_mass")`, by hand: the controller's force `-K_c q - K_d v` adds to the spring's
//! `-k q` and the damper's `-b v`, so
//! `dp/dt = -(b + K_d)/m p - (k + K_c) q + F` and `dq/dt = p/m`.

use bondgraph_core::DiagnosticKind;
use bondgraph_core::equations::{self, Options, Variables};
use bondgraph_core::laws;
use bondgraph_core::linear::Var;
use bondgraph_core::model::Model;
use bondgraph_core::symbolic::RatFunc;

fn load(text: &str) -> Model {
    bondgraph_ron::model::load_str("feedback.ron", text).unwrap_or_else(|e| panic!("{e}"))
}

fn controlled(controller: &str) -> String {
    format!(
        r#"Model(name: "controlled",
            parameters: {{"m": (value: 2.0), "k": (value: 200.0), "b": (value: 4.0),
                          "K_c": (value: 50.0), "K_d": (value: 4.0)}},
            inputs: {{"F": ()}},
            elements: {{"force": Se(effort: "F"), "controller": Se(effort: "{controller}"),
                        "v_mass": One, "mass": I(inertance: "m"), "spring": C(stiffness: "k"),
                        "damper": R(resistance: "b")}},
            bonds: [("force", "v_mass"), ("controller", "v_mass"), ("v_mass", "mass"),
                    ("v_mass", "spring"), ("v_mass", "damper")])"#
    )
}

fn symbol(model: &Model, name: &str) -> RatFunc {
    RatFunc::symbol(model.symbols().get(name).expect("parameter"))
}

fn derive(model: &Model, variables: Variables) -> equations::StateEquations {
    equations::derive(model, &laws::plain_laws(model), &Options { variables })
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_pd_controller_keeps_the_model_linear() {
    let model = load(&controlled("-K_c*q_spring - K_d/m*p_mass"));
    assert!(!model.is_nonlinear());
    let eq = derive(&model, Variables::Energy);
    let (m, k, b, k_c, k_d) = (
        symbol(&model, "m"),
        symbol(&model, "k"),
        symbol(&model, "b"),
        symbol(&model, "K_c"),
        symbol(&model, "K_d"),
    );
    let names: Vec<&str> = eq.states.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["p_mass", "q_spring"]);
    assert_eq!(
        eq.a(),
        [
            vec![-(&b + &k_d).checked_div(&m).unwrap(), -(&k + &k_c)],
            vec![m.inv().unwrap(), RatFunc::zero()],
        ]
    );
    assert_eq!(eq.b(), [vec![RatFunc::one()], vec![RatFunc::zero()]]);
    assert!(eq.c().iter().all(RatFunc::is_zero));
    // m = 2, k = 200, b = 4, K_c = 50, K_d = 4.
    let a: Vec<Vec<f64>> = eq
        .a()
        .iter()
        .map(|row| row.iter().map(|e| eq.evaluate(e)).collect())
        .collect();
    assert_eq!(a, [[-4.0, -250.0], [0.5, 0.0]]);
}

#[test]
fn a_source_nonlinear_in_a_state_stays_nonlinear() {
    for law in [
        "-K_c*sin(q_spring)",
        "-K_c*q_spring*p_mass",
        "K_c/q_spring",
        "q_spring^2",
    ] {
        let model = load(&controlled(law));
        assert!(model.is_nonlinear(), "{law}");
        let error = equations::derive(&model, &laws::plain_laws(&model), &Options::default())
            .expect_err(law);
        assert_eq!(error.first().kind, DiagnosticKind::NotLinear, "{law}");
        assert_eq!(
            error.first().element.as_deref(),
            Some("controller"),
            "{law}"
        );
    }
}

/// Two masses rigidly joined (`m2` is in derivative causality and merged into `m1`), braked
/// by a force proportional to `m2`'s momentum. By hand: the body's momentum is
/// `P = (m1 + m2) v` and `p_m2 = m2 v = m2 P/(m1 + m2)`, so `dP/dt = -c m2/(m1 + m2) P`.
#[test]
fn feedback_of_merged_storage_is_written_in_the_state_it_follows() {
    let model = load(
        r#"Model(name: "rigid",
            parameters: {"m1": (value: 1.0), "m2": (value: 3.0), "c": (value: 8.0)},
            elements: {"brake": Se(effort: "-c*p_m2"), "v": One,
                       "m1": I(inertance: "m1"), "m2": I(inertance: "m2")},
            bonds: [("brake", "v"), ("v", "m1"), ("v", "m2")])"#,
    );
    assert!(!model.is_nonlinear());
    let eq = derive(&model, Variables::Energy);
    assert_eq!(eq.states.len(), 1);
    assert_eq!(eq.states[0].merged, ["m2"]);
    let (m1, m2, c) = (
        symbol(&model, "m1"),
        symbol(&model, "m2"),
        symbol(&model, "c"),
    );
    let expected = -(&c * &m2).checked_div(&(&m1 + &m2)).unwrap();
    assert_eq!(eq.a(), [vec![expected.clone()]]);
    assert_eq!(eq.evaluate(&expected), -6.0);
}

/// A flow source that sets one mass's velocity from another's momentum imposes it as a
/// controller would, not as a rigid link: the driven mass cannot be merged, and that is
/// said, naming it and the source.
#[test]
fn storage_driven_through_a_feedback_source_is_refused_by_name() {
    let model = load(
        r#"Model(name: "follower",
            parameters: {"m1": (value: 1.0), "m2": (value: 3.0), "a": (value: 0.5), "k": (value: 10.0)},
            elements: {"servo": Sf(flow: "a*p_m1"), "v2": One, "m2": I(inertance: "m2"),
                       "n": Zero, "spring": C(stiffness: "k"), "v1": One, "m1": I(inertance: "m1")},
            bonds: [("servo", "v2"), ("v2", "m2"), ("n", "v2"), ("n", "spring"),
                    ("v1", "n"), ("v1", "m1")])"#,
    );
    let error = equations::derive(&model, &laws::plain_laws(&model), &Options::default())
        .expect_err("m2 follows p_m1 through the servo");
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::DependentStorage);
    assert_eq!(
        first.message,
        "'m2' is in derivative causality and follows a state through the feedback of 'servo'; it cannot be merged into one state"
    );
}

/// The same controller on the linear graph of the mass-spring-damper: its states are
/// `v_mass` and `f_spring = k q_spring`, so `q_spring = f_spring/k`, `p_mass = m v_mass`, and
/// `m dv/dt = -(b + K_d) v - (1 + K_c/k) f + F`, `df/dt = k v`.
#[test]
fn a_through_source_feeding_back_states_keeps_a_linear_graph_linear() {
    let model = bondgraph_ron::model::load_str(
        "controlled.lg.ron",
        r#"LinearGraph(name: "controlled",
            parameters: {"m": (value: 2.0), "k": (value: 200.0), "b": (value: 4.0),
                         "K_c": (value: 50.0), "K_d": (value: 4.0)},
            inputs: {"F": ()},
            ground: "g",
            branches: {
                "force": ThroughSource(value: "F", from: "g", to: "v1"),
                "controller": ThroughSource(value: "-K_c*q_spring - K_d/m*p_mass", from: "g", to: "v1"),
                "mass": A(capacitance: "m", from: "v1", to: "g"),
                "spring": T(stiffness: "k", from: "v1", to: "g"),
                "damper": D(conductance: "b", from: "v1", to: "g"),
            })"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(!model.is_nonlinear());
    let eq = derive(&model, Variables::CoEnergy);
    let names: Vec<&str> = eq.states.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["v_mass", "f_spring"]);
    let (m, k, b, k_c, k_d) = (
        symbol(&model, "m"),
        symbol(&model, "k"),
        symbol(&model, "b"),
        symbol(&model, "K_c"),
        symbol(&model, "K_d"),
    );
    assert_eq!(
        eq.a(),
        [
            vec![
                -(&b + &k_d).checked_div(&m).unwrap(),
                -(&k + &k_c).checked_div(&(&k * &m)).unwrap()
            ],
            vec![k.clone(), RatFunc::zero()],
        ]
    );
    assert_eq!(eq.b(), [vec![m.inv().unwrap()], vec![RatFunc::zero()]]);
}

/// A flow source that sets a mass's velocity from that mass's own momentum: the mass is in
/// derivative causality, its momentum `m f` is what the source sets, so `f = a m f` is an
/// algebraic constraint (`f = 0`), not a controller. It is refused at the source, naming
/// the mass.
#[test]
fn feeding_back_storage_the_source_itself_drives_is_refused_by_name() {
    let model = load(
        r#"Model(name: "self",
            parameters: {"m": (value: 1.0), "a": (value: 0.5), "b": (value: 2.0)},
            elements: {"servo": Sf(flow: "a*p_mass"), "v": One, "mass": I(inertance: "m"),
                       "damper": R(resistance: "b")},
            bonds: [("servo", "v"), ("v", "mass"), ("v", "damper")])"#,
    );
    let error = equations::derive(&model, &laws::plain_laws(&model), &Options::default())
        .expect_err("the servo sets the velocity of the mass whose momentum it feeds back");
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::DependentStorage);
    assert_eq!(first.element.as_deref(), Some("servo"));
    assert_eq!(
        first.message,
        "source 'servo' feeds back p_mass, but 'mass' is in derivative causality and its p_mass follows from what 'servo' imposes: an algebraic loop, not a controller"
    );
}

/// The same on the effort side: an effort source on a 0-junction sets a compliance's
/// effort from that compliance's own displacement.
#[test]
fn feeding_back_a_compliance_the_source_itself_loads_is_refused_by_name() {
    let model = load(
        r#"Model(name: "self_c",
            parameters: {"k": (value: 10.0), "K": (value: 2.0), "R": (value: 1.0)},
            elements: {"servo": Se(effort: "-K*q_spring"), "n": Zero,
                       "spring": C(stiffness: "k"), "leak": R(resistance: "R")},
            bonds: [("servo", "n"), ("n", "spring"), ("n", "leak")])"#,
    );
    let error = equations::derive(&model, &laws::plain_laws(&model), &Options::default())
        .expect_err("the servo sets the effort of the spring whose displacement it feeds back");
    assert_eq!(error.first().kind, DiagnosticKind::DependentStorage);
    assert_eq!(error.first().element.as_deref(), Some("servo"));
    assert!(
        error
            .first()
            .message
            .starts_with("source 'servo' feeds back q_spring, but 'spring'"),
        "{}",
        error.first().message
    );
}

/// Feedback of storage in derivative causality outside any loop is written in the bond
/// variable that sets it: a mass moved at `v0` by a flow source has momentum `m v0`, so a
/// brake `-K*p_mass` pushes with `-K m v0`.
#[test]
fn feedback_of_storage_moved_by_another_source_is_its_momentum() {
    let model = load(
        r#"Model(name: "driven",
            parameters: {"m": (value: 3.0), "K": (value: 0.5), "b": (value: 2.0), "v0": (value: 4.0)},
            elements: {"drive": Sf(flow: "v0"), "v": One, "mass": I(inertance: "m"),
                       "brake": Se(effort: "-K*p_mass"), "damper": R(resistance: "b")},
            bonds: [("drive", "v"), ("v", "mass"), ("brake", "v"), ("v", "damper")])"#,
    );
    let eq = derive(&model, Variables::Energy);
    assert!(eq.states.is_empty());
    let brake = model.element_named("brake").expect("brake");
    let bond = model.element(brake).bonds[0];
    let (m, k, v0) = (
        symbol(&model, "m"),
        symbol(&model, "K"),
        symbol(&model, "v0"),
    );
    let effort = eq.bond_effort(bond);
    assert_eq!(effort.coefficient(Var::Constant), -(&(&k * &m) * &v0));
    assert_eq!(eq.evaluate(&effort.coefficient(Var::Constant)), -6.0);
}

/// A misspelt state in a source is unknown among parameters, inputs and states, and the
/// state is suggested.
#[test]
fn a_misspelt_state_in_a_source_is_suggested() {
    let error = bondgraph_ron::model::load_str("feedback.ron", &controlled("-K_c*q_sprin"))
        .expect_err("q_sprin is not a state");
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnknownSymbol);
    assert_eq!(
        first.message,
        "element 'controller': effort \"-K_c*q_sprin\" uses 'q_sprin', which is neither a parameter, an input nor a state"
    );
    assert_eq!(first.notes, ["did you mean 'q_spring'?"]);
}
