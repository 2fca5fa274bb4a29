//! A source that feeds back states linearly (a PD controller on a mass) keeps the model
//! linear through every command: `check`, `equations` (symbolic and numeric `A`), `analyze`,
//! `modes`, and `simulate` on the closed-form path with its energy books, each against the
//! hand solution in `tests/fixtures/feedback/pd_controlled.ron`; and feedback that is not a
//! controller is refused, naming the element.

use bondgraph_core::DiagnosticKind;
use serde_json::Value;

use crate::cli::{json, run, succeed};
use crate::diagnostics::{Expect, check_file};

const MODEL: &str = "tests/fixtures/feedback/pd_controlled.ron";

#[test]
fn a_pd_controller_is_linear_in_check_equations_and_modes() {
    assert!(
        succeed(&["check", MODEL]).contains(": ok: model 'pd_controlled'"),
        "not a linear model"
    );
    let doc = json(&[MODEL]);
    assert_eq!(
        doc["A"],
        serde_json::json!([["-(b + K_d)/m", "-(k + K_c)"], ["1/m", "0"]])
    );
    assert_eq!(doc["B"], serde_json::json!([["1"], ["0"]]));
    // m = 2, k = 200, b = 4, K_c = 50, K_d = 4.
    assert_eq!(
        doc["A_value"],
        serde_json::json!([[-4.0, -250.0], [0.5, 0.0]])
    );
    assert_eq!(doc["c_value"], serde_json::json!([0.0, 0.0]));
    let modes = succeed(&["modes", MODEL]);
    assert!(
        modes.contains("mode (its only mode): 2 states (p_mass, q_spring)"),
        "{modes}"
    );
}

#[test]
fn a_pd_controller_moves_the_poles_as_by_hand() {
    // s^2 + (b + K_d)/m s + (k + K_c)/m = s^2 + 4 s + 125: s = -2 ± 11i.
    let text = succeed(&["analyze", MODEL, "--format", "json"]);
    let doc: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}:\n{text}"));
    let mut poles: Vec<(f64, f64)> = doc["eigenvalues"]
        .as_array()
        .unwrap_or_else(|| panic!("no eigenvalues in {doc}"))
        .iter()
        .map(|p| (p["re"].as_f64().unwrap(), p["im"].as_f64().unwrap()))
        .collect();
    // A linear model: its own A, not a linearisation at an equilibrium.
    assert_eq!(doc["linearised_at"], Value::Null, "{doc}");
    poles.sort_by(|a, b| a.1.total_cmp(&b.1));
    assert_eq!(poles.len(), 2);
    for ((re, im), want) in poles.iter().zip([-11.0, 11.0]) {
        assert!(
            (re + 2.0).abs() < 1e-12 && (im - want).abs() < 1e-12,
            "{poles:?}"
        );
    }
}

#[test]
fn a_pd_controlled_release_follows_the_hand_solution() {
    // q(t) = e^(-2t) (0.1 cos 11t + 0.2/11 sin 11t); the spring's force is k q, the mass's
    // velocity dq/dt.
    let csv = succeed(&[
        "simulate",
        MODEL,
        "--scenario",
        "tests/fixtures/feedback/release.ron",
    ]);
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t,mode,effort:spring,flow:mass"));
    let mut samples = 0;
    for line in lines {
        let fields: Vec<f64> = line
            .split(',')
            .filter(|f| !f.is_empty())
            .map(|f| f.parse().unwrap())
            .collect();
        let (t, force, velocity) = (fields[0], fields[1], fields[2]);
        let (c, s) = ((11.0 * t).cos(), (11.0 * t).sin());
        let decay = (-2.0 * t).exp();
        let q = decay * (0.1 * c + 0.2 / 11.0 * s);
        let dq = -2.0 * q + decay * (-1.1 * s + 0.2 * c);
        assert!(
            (force - 200.0 * q).abs() < 1e-12,
            "t = {t}: {force} vs {}",
            200.0 * q
        );
        assert!((velocity - dq).abs() < 1e-12, "t = {t}: {velocity} vs {dq}");
        samples += 1;
    }
    assert_eq!(samples, 201);
}

/// The released mass at time `t`: the spring's displacement and the mass's velocity.
fn released(t: f64) -> (f64, f64) {
    let (c, s) = ((11.0 * t).cos(), (11.0 * t).sin());
    let decay = (-2.0 * t).exp();
    let q = decay * (0.1 * c + 0.2 / 11.0 * s);
    (q, -2.0 * q + decay * (-1.1 * s + 0.2 * c))
}

#[test]
fn a_pd_controller_supplies_the_energy_it_takes_out() {
    // m = 2, k = 200, b = 4, K_c = 50, K_d = 4. Stored E = m v²/2 + k q²/2, and
    // dE/dt = v (m dv/dt + k q) = -K_c q v - (b + K_d) v², so with D(t) = ∫ v² dt:
    // D = (E(0) - E(t) - K_c (q² - q0²)/2)/(b + K_d), the controller supplies
    // -K_c (q² - q0²)/2 - K_d D and the damper dissipates b D. Power into the controller
    // is -(its force)·v = (K_c q + K_d v) v.
    let (m, k, b, k_c, k_d, q0) = (2.0, 200.0, 4.0, 50.0, 4.0, 0.1);
    let csv = succeed(&[
        "simulate",
        MODEL,
        "--scenario",
        "tests/fixtures/feedback/books.ron",
    ]);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "t,mode,effort:spring,flow:mass,energy:stored,energy:supplied,energy:dissipated,power:controller"
        )
    );
    let stored_0 = k * q0 * q0 / 2.0;
    let mut samples = 0;
    for line in lines {
        let fields: Vec<f64> = line
            .split(',')
            .filter(|f| !f.is_empty())
            .map(|f| f.parse().unwrap())
            .collect();
        let [t, _, _, stored, supplied, dissipated, power] = fields[..] else {
            panic!("{line}");
        };
        let (q, v) = released(t);
        let expected_stored = m * v * v / 2.0 + k * q * q / 2.0;
        let spring_work = -k_c * (q * q - q0 * q0) / 2.0;
        let squares = (stored_0 - expected_stored + spring_work) / (b + k_d);
        for (what, got, want) in [
            ("stored", stored, expected_stored),
            ("supplied", supplied, spring_work - k_d * squares),
            ("dissipated", dissipated, b * squares),
            ("power into the controller", power, (k_c * q + k_d * v) * v),
        ] {
            assert!(
                (got - want).abs() < 1e-12,
                "t = {t}: {what} {got} vs {want}"
            );
        }
        samples += 1;
    }
    assert_eq!(samples, 201);
}

/// Feedback of storage whose energy variable the source itself sets is an algebraic loop.
#[test]
fn feedback_of_what_the_source_sets_is_refused_at_the_source() {
    check_file(
        "tests/fixtures/feedback/feeds_back_what_it_sets.ron",
        Expect {
            kind: DiagnosticKind::DependentStorage,
            line: 8,
            column: 9,
            element: Some("servo"),
            underlined: "\"servo\"",
            message: "source 'servo' feeds back p_mass, but 'mass' is in derivative causality and its p_mass follows from what 'servo' imposes: an algebraic loop, not a controller",
        },
    );
}

/// Storage in derivative causality that follows a state through a source's feedback.
#[test]
fn storage_following_a_state_through_feedback_is_refused_by_name() {
    check_file(
        "tests/fixtures/feedback/follows_through_feedback.ron",
        Expect {
            kind: DiagnosticKind::DependentStorage,
            line: 10,
            column: 9,
            element: Some("m2"),
            underlined: "\"m2\"",
            message: "'m2' is in derivative causality and follows a state through the feedback of 'servo'; it cannot be merged into one state",
        },
    );
}

/// A feedback that is not affine in the states makes the model nonlinear; `compare`, which
/// needs a linear mode, says which element's law does that, at its line.
#[test]
fn a_non_affine_feedback_is_named_where_a_linear_model_is_needed() {
    const CUBIC: &str = "tests/fixtures/feedback/cubic_controller.ron";
    assert!(succeed(&["check", CUBIC]).contains(": ok: nonlinear model 'cubic_controller'"));
    let output = run(&["compare", CUBIC, "tests/fixtures/analysis/msd_equal.ron"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with(&format!(
            "error: '{CUBIC}' is nonlinear: an answer's A and B are compared with a linear mode's, and effort source 'controller' has the nonlinear law effort: \"-K_c*q_spring^3\"\n"
        )),
        "{stderr}"
    );
    assert!(stderr.contains(&format!("--> {CUBIC}:10:35\n")), "{stderr}");
}

/// `power:ELEMENT` is the power into the element along its bond, on the nonlinear path as
/// on the linear one: the cubic controller's bond points out of it, so its power is minus
/// its effort times the bond's flow (negative while it pushes the mass along its motion).
#[test]
fn a_nonlinear_source_takes_in_minus_effort_times_its_bonds_flow() {
    let csv = succeed(&[
        "simulate",
        "tests/fixtures/feedback/cubic_controller.ron",
        "--scenario",
        "tests/fixtures/feedback/cubic_power.ron",
    ]);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("t,mode,effort:controller,flow:controller,power:controller")
    );
    let mut delivering = 0;
    for line in lines {
        let fields: Vec<f64> = line
            .split(',')
            .filter(|f| !f.is_empty())
            .map(|f| f.parse().unwrap())
            .collect();
        let [t, effort, flow, power] = fields[..] else {
            panic!("{line}");
        };
        let want = -effort * flow;
        assert!(
            (power - want).abs() <= 1e-15 * want.abs().max(1e-300),
            "t = {t}: power {power} vs {want}"
        );
        delivering += usize::from(want < 0.0);
    }
    assert!(delivering > 0, "the controller never delivers");
}
