//! Nonlinear and modulated models through the `bondgraph` program: `f(x, u)` and its
//! Jacobians as text and JSON, an operating point (`--at`), equilibria, simulation of the
//! bundled scenarios, and the diagnostics of laws that cannot be used.

use std::process::Command;

use bondgraph_core::equations::Options;
use bondgraph_core::equations::nonlinear::{self, OperatingPoint};
use bondgraph_core::{DiagnosticKind, laws};

use crate::support::{load, root};

fn run(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_bondgraph"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("the program runs");
    (
        output.status.success(),
        String::from_utf8(output.stdout).expect("UTF-8"),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn succeed(args: &[&str]) -> String {
    let (ok, out, err) = run(args);
    assert!(ok, "bondgraph {}: {err}", args.join(" "));
    out
}

const PENDULUM: &str = "models/examples/nonlinear/pendulum.ron";

#[test]
fn the_pendulum_s_equations_read_like_a_textbook() {
    let text = succeed(&["equations", PENDULUM]);
    assert!(text.starts_with(
        "model 'pendulum': 2 states in energy variables, 0 inputs, nonlinear: dx/dt = f(x, u)\n"
    ));
    assert!(
        text.contains("dp_bob/dt     = -g*l*m*sin(q_gravity)\n"),
        "{text}"
    );
    assert!(text.contains("dq_gravity/dt = p_bob/(l^2*m)\n"), "{text}");
    assert!(
        text.contains("df/dx = [         0  -g*l*m*cos(q_gravity) ]\n"),
        "{text}"
    );
    let latex = succeed(&["equations", PENDULUM, "--format", "latex"]);
    assert!(
        latex.contains(
            "\\frac{d p_{\\mathrm{bob}}}{dt} &= -g l m \\sin\\left(q_{\\mathrm{gravity}}\\right)"
        ),
        "{latex}"
    );
}

#[test]
fn an_operating_point_gives_the_jacobians_as_a_and_b() {
    let json: serde_json::Value = serde_json::from_str(&succeed(&[
        "equations",
        PENDULUM,
        "--at",
        "q_gravity=0",
        "--format",
        "json",
    ]))
    .unwrap();
    assert_eq!(json["nonlinear"], true);
    assert_eq!(
        json["f"],
        serde_json::json!(["-g*l*m*sin(q_gravity)", "p_bob/(l^2*m)"])
    );
    // At rest the pendulum is the linear oscillator: A = [0, -m g l; 1/(m l²), 0].
    assert_eq!(
        json["A"],
        serde_json::json!([["0", "-g*l*m"], ["1/(l^2*m)", "0"]])
    );
    assert_eq!(
        json["A_value"],
        serde_json::json!([[0.0, -9.81], [1.0, 0.0]])
    );
    assert_eq!(json["f_value"], serde_json::json!([0.0, 0.0]));
    // Without a point there are no matrices, only f and its symbolic Jacobians.
    let json: serde_json::Value =
        serde_json::from_str(&succeed(&["equations", PENDULUM, "--format", "json"])).unwrap();
    assert!(json.get("A").is_none() && json.get("A_value").is_none());
    assert_eq!(json["df_dx"][0][1], "-g*l*m*cos(q_gravity)");
    // The lever's B has the modulating input's column: -F/(c_theta² r_0).
    let json: serde_json::Value = serde_json::from_str(&succeed(&[
        "equations",
        "models/examples/nonlinear/lever.ron",
        "--at",
        "F=12,c_theta=1.5",
        "--format",
        "json",
    ]))
    .unwrap();
    assert_eq!(
        json["B"][0],
        serde_json::json!(["2/(3*r_0)", "-16/(3*r_0)"])
    );
    let b = json["B_value"][0].as_array().unwrap();
    assert!((b[0].as_f64().unwrap() - 1.0 / 3.0).abs() < 1e-15);
    assert!((b[1].as_f64().unwrap() + 12.0 / (2.0 * 1.5 * 1.5)).abs() < 1e-14);
    // A name that is neither a state nor an input is an error with a suggestion.
    let (ok, _, err) = run(&["equations", PENDULUM, "--at", "q_gravty=1"]);
    assert!(!ok);
    assert!(
        err.contains("'q_gravty' is neither a state nor an input"),
        "{err}"
    );
    assert!(err.contains("did you mean 'q_gravity'?"), "{err}");
}

#[test]
fn the_linearisation_is_a_linear_mode_with_exact_entries() {
    let model = load(PENDULUM);
    let eq = nonlinear::derive(&model, &laws::plain_laws(&model), &Options::default()).unwrap();
    let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
    let linear = eq.linearise(&OperatingPoint::parse(&names, &[], "q_gravity=0").unwrap());
    let a: Vec<Vec<String>> = linear
        .a()
        .iter()
        .map(|row| row.iter().map(|e| e.text(&linear.symbols)).collect())
        .collect();
    assert_eq!(a, [["0", "-g*l*m"], ["1/(l^2*m)", "0"]]);
    // Hanging down at rest: no offset.
    assert!(linear.c().iter().all(|c| c.is_zero()));
}

#[test]
fn equilibria_are_found_from_a_starting_point() {
    // From 3 rad Newton's method finds the inverted pendulum, from 0.4 rad the hanging one.
    for (start, expected) in [("3", std::f64::consts::PI), ("0.4", 0.0)] {
        let json: serde_json::Value = serde_json::from_str(&succeed(&[
            "equations",
            PENDULUM,
            "--equilibrium",
            "--at",
            &format!("q_gravity={start}"),
            "--format",
            "json",
        ]))
        .unwrap();
        let angle = json["at"]["q_gravity"].as_f64().unwrap();
        assert!((angle - expected).abs() < 1e-12, "{start}: {angle}");
        // Inverted, the linearisation is unstable: A[0][1] = +m g l.
        let a01 = json["A_value"][0][1].as_f64().unwrap();
        assert!(
            (a01 - 9.81 * if expected > 0.0 { 1.0 } else { -1.0 }).abs() < 1e-9,
            "{a01}"
        );
    }
    // The Duffing oscillator pushed by 2 N rests where k q + k_3 q³ = 2.
    let json: serde_json::Value = serde_json::from_str(&succeed(&[
        "equations",
        "models/examples/nonlinear/duffing.ron",
        "--equilibrium",
        "--at",
        "F=2",
        "--format",
        "json",
    ]))
    .unwrap();
    let q = json["at"]["q_spring"].as_f64().unwrap();
    assert!((q + 5.0 * q * q * q - 2.0).abs() < 1e-12, "{q}");
}

#[test]
fn every_nonlinear_scenario_simulates() {
    for (model, scenario) in [
        ("pendulum", "pendulum_release"),
        ("orifice_tank", "tank_draining"),
        ("diode_rc", "diode_discharge"),
        ("lever", "lever_step"),
        ("duffing", "duffing_release"),
        ("stick_slip_spring", "stick_slip_spring"),
    ] {
        let model = format!("models/examples/nonlinear/{model}.ron");
        let scenario = format!("models/scenarios/nonlinear/{scenario}.ron");
        let json: serde_json::Value = serde_json::from_str(&succeed(&[
            "simulate",
            &model,
            "--scenario",
            &scenario,
            "--format",
            "json",
        ]))
        .unwrap();
        assert!(json["final"]["t"].as_f64().unwrap() > 0.0, "{model}");
        succeed(&["check", &model]);
        succeed(&["modes", &model]);
    }
    // The stick-slip spring's modes: stuck, slip+ and slip-, with guards in the spring's
    // nonlinear force.
    let modes = succeed(&["modes", "models/examples/nonlinear/stick_slip_spring.ron"]);
    assert!(
        modes.contains("friction: holding force k*q_spring + k_3*q_spring^3 + m*der(v_belt) >= F_S -> friction=slip+"),
        "{modes}"
    );
}

fn diagnose(elements: &str, bonds: &str) -> bondgraph_core::Diagnostic {
    let text = format!(
        "Model(name: \"m\", parameters: {{\"k\": (value: 2.0), \"c\": (value: 1.0)}},\n\
         inputs: {{\"u\": ()}},\n\
         elements: {{{elements}}},\n\
         bonds: [{bonds}])"
    );
    let model = match bondgraph_ron::model::load_str("m.ron", &text) {
        Err(e) => return e.first().clone(),
        Ok(model) => model,
    };
    let laws = laws::plain_laws(&model);
    nonlinear::derive(&model, &laws, &Options::default())
        .expect_err("a diagnostic")
        .first()
        .clone()
}

#[test]
fn laws_that_cannot_be_used_are_diagnosed_at_their_place() {
    let d = diagnose(
        r#""j": One, "s": C(effort: "k*tanhh(q_s)"), "i": I(inertance: "c")"#,
        r#"("j", "s"), ("j", "i")"#,
    );
    assert_eq!(d.kind, DiagnosticKind::BadExpression);
    assert!(
        d.message
            .contains("unknown function 'tanhh'; did you mean 'tanh'?"),
        "{}",
        d.message
    );
    assert_eq!(d.location.map(|l| (l.line, l.column)), Some((3, 40)));
    let d = diagnose(
        r#""j": One, "s": C(effort: "k*sin(q_s)*u"), "i": I(inertance: "c")"#,
        r#"("j", "s"), ("j", "i")"#,
    );
    assert_eq!(d.kind, DiagnosticKind::NotLinear);
    assert!(
        d.message
            .contains("depends on input 'u'; a compliance's law may not depend on inputs"),
        "{}",
        d.message
    );
    let d = diagnose(
        r#""j": One, "s": C(effort: "k*sin(p_i)"), "i": I(inertance: "c")"#,
        r#"("j", "s"), ("j", "i")"#,
    );
    assert!(
        d.message.contains("uses the state 'p_i'; a compliance's law may depend on its own state 'q_s' and parameters only"),
        "{}",
        d.message
    );
    let d = diagnose(
        r#""j": One, "s": C(effort: "k*sin(q_x)"), "i": I(inertance: "c")"#,
        r#"("j", "s"), ("j", "i")"#,
    );
    assert_eq!(d.kind, DiagnosticKind::UnknownSymbol);
    assert_eq!(d.notes, ["did you mean 'q_s'?"]);
    // A resistor whose law only gives its flow needs its effort given; a flow source
    // imposes its flow instead: a conflict that says why.
    let d = diagnose(
        r#""src": Sf(flow: "u"), "r": R(flow: "c*sin(effort)")"#,
        r#"("src", "r")"#,
    );
    assert_eq!(d.kind, DiagnosticKind::CausalConflict);
    assert!(
        d.notes.iter().any(|n| n.contains(
            "'r' has its law as flow: f(effort), which could not be solved for the effort"
        )),
        "{d:?}"
    );
    // The same law solved for its effort where it can be: an orifice behind a flow source.
    let text = r#"Model(name: "m", parameters: {"c": (value: 1.0)}, inputs: {"u": ()},
        elements: {"src": Sf(flow: "u"), "r": R(flow: "c*sign(effort)*sqrt(abs(effort))")},
        bonds: [("src", "r")])"#;
    let model = bondgraph_ron::model::load_str("m.ron", text).unwrap();
    assert!(nonlinear::derive(&model, &laws::plain_laws(&model), &Options::default()).is_ok());
}

#[test]
fn linear_laws_written_as_nonlinear_ones_stay_linear() {
    let text = r#"Model(name: "m", parameters: {"k": (value: 2.0), "b": (value: 1.0), "m": (value: 1.0)},
        elements: {"j": One, "s": C(effort: "k*q_s"), "d": R(effort: "b*flow"), "i": I(flow: "p_i/m")},
        bonds: [("j", "s"), ("j", "d"), ("j", "i")])"#;
    let model = bondgraph_ron::model::load_str("m.ron", text).unwrap();
    assert!(!model.is_nonlinear());
    let eq =
        bondgraph_core::equations::derive(&model, &laws::plain_laws(&model), &Options::default())
            .unwrap();
    assert_eq!(eq.form_text(&eq.derivatives[0]), "p_i/m");
    assert_eq!(eq.form_text(&eq.derivatives[1]), "-k*q_s - b/m*p_i");
}
