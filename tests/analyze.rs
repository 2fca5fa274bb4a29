//! `bondgraph analyze` and `bondgraph compare` against hand-derived closed forms: the
//! characteristic polynomial and transfer functions of the mass-spring-damper, the dependent
//! spring (an input-rate term) and the quarter car, step metrics of a second-order system,
//! every example and every mode of the flagship, and answers that are equal, similar and
//! different.

use bondgraph_core::analysis::{Analysis, Channel};
use bondgraph_core::equations::OutputSpec;
use bondgraph_core::equations::Variables;
use bondgraph_core::symbolic::RatFunc;
use serde_json::Value;

use crate::cli::{run, succeed};
use crate::support::{derive, expected, linear_graph_files, load, ron_files, value};

/// Runs `bondgraph ARGS` (which ask for JSON), expecting success, and parses its output.
fn json(args: &[&str]) -> Value {
    let text = succeed(args);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}:\n{text}"))
}

const QUARTER_CAR: &str = "tests/fixtures/analysis/quarter_car.ron";

fn exprs(model: &bondgraph_core::model::Model, texts: &[&str]) -> Vec<RatFunc> {
    texts.iter().map(|t| expected(model, t)).collect()
}

#[test]
fn mass_spring_damper_transfer_functions_by_hand() {
    // m x'' + b x' + k x = F: X/F = 1/(m s^2 + b s + k), P/F = m s X/F, and the mass's force
    // F - k x - b x' = m s^2 X has a direct feedthrough: m s^2/(m s^2 + b s + k).
    let model = load("models/examples/mass_spring_damper.ron");
    let eq = derive(&model, Variables::Energy);
    let analysis = Analysis::new(&eq);
    assert_eq!(
        analysis.characteristic.coefficients,
        exprs(&model, &["k/m", "b/m", "1"])
    );
    let to_q = analysis.transfer(&Channel::to_state(&eq, 0, 1));
    assert_eq!(to_q.numerator, exprs(&model, &["1"]));
    assert_eq!(to_q.denominator, exprs(&model, &["m", "b", "k"]));
    let to_p = analysis.transfer(&Channel::to_state(&eq, 0, 0));
    assert_eq!(to_p.numerator, exprs(&model, &["m", "0"]));
    let spec = OutputSpec::parse(&model, "effort:mass").unwrap();
    let row = eq.output(&spec).row;
    let mass_force = analysis.transfer(&Channel::new(&eq, 0, &row, false));
    assert_eq!(mass_force.numerator, exprs(&model, &["m", "0", "0"]));
    assert_eq!(mass_force.denominator, exprs(&model, &["m", "b", "k"]));
    assert_eq!(mass_force.cancelled, 0);
}

#[test]
fn quarter_car_against_its_textbook_polynomial() {
    // Body velocity over road velocity = body over road displacement:
    //   k_t (b_s s + k_s) / (m_s m_u s^4 + b_s (m_s + m_u) s^3
    //                        + (k_s (m_s + m_u) + k_t m_s) s^2 + b_s k_t s + k_s k_t).
    let model = load(QUARTER_CAR);
    let eq = derive(&model, Variables::Energy);
    let analysis = Analysis::new(&eq);
    let den = exprs(
        &model,
        &[
            "m_s*m_u",
            "b_s*(m_s + m_u)",
            "k_s*(m_s + m_u) + k_t*m_s",
            "b_s*k_t",
            "k_s*k_t",
        ],
    );
    let lead = den[0].clone();
    let monic: Vec<RatFunc> = den
        .iter()
        .rev()
        .map(|c| c.checked_div(&lead).unwrap())
        .collect();
    assert_eq!(analysis.characteristic.coefficients, monic);
    let spec = OutputSpec::parse(&model, "flow:body_mass").unwrap();
    let tf = analysis.transfer(&Channel::new(&eq, 0, &eq.output(&spec).row, false));
    assert_eq!(tf.numerator, exprs(&model, &["b_s*k_t", "k_s*k_t"]));
    assert_eq!(tf.denominator, den);

    // Numbers: the eigenvalues are the polynomial's roots, the DC gain 1, the zero -k_s/b_s.
    let out = json(&[
        "analyze",
        QUARTER_CAR,
        "--output",
        "flow:body_mass",
        "--format",
        "json",
    ]);
    let p: Vec<f64> = monic.iter().rev().map(|c| c.eval(&eq.values)).collect();
    for e in out["eigenvalues"].as_array().unwrap() {
        let (re, im) = (e["re"].as_f64().unwrap(), e["im"].as_f64().unwrap());
        let z = bondgraph_solver::analysis::Complex64::new(re, im);
        let residual = p.iter().fold(
            bondgraph_solver::analysis::Complex64::new(0.0, 0.0),
            |acc, c| acc * z + c,
        );
        assert!(residual.norm() < 1e-9 * p[4], "{re} {im}: p = {residual}");
    }
    assert_eq!(out["dc_gain"].as_f64().unwrap(), 1.0);
    let zero = out["zeros"][0]["re"].as_f64().unwrap();
    let (k_s, b_s) = (value(&model, "k_s"), value(&model, "b_s"));
    assert!((zero + k_s / b_s).abs() < 1e-12 * k_s / b_s);
    assert_eq!(out["step"]["final_value"].as_f64().unwrap(), 1.0);
}

#[test]
fn dependent_spring_input_rate_enters_the_transfer_function() {
    // Rowell & Wormley's dependent spring (see the model file): with x the mass's position,
    // X [(K1 + K2)(m s^2 + B s) + K1 K2] = K1 F, so
    //   V/F    = K1 s / ((K1 + K2) m s^2 + (K1 + K2) B s + K1 K2),
    //   F_K1/F = K1 (m s^2 + B s) / (the same),  jumping to K1/(K1 + K2) under a step.
    let path = "models/examples/rowell_wormley_dependent_spring.lg.ron";
    let model = load(path);
    let eq = derive(&model, Variables::CoEnergy);
    let analysis = Analysis::new(&eq);
    let den = exprs(&model, &["(K1 + K2)*m", "(K1 + K2)*B", "K1*K2"]);
    let to_v = analysis.transfer(&Channel::to_state(&eq, 0, 0));
    assert_eq!(to_v.numerator, exprs(&model, &["K1", "0"]));
    assert_eq!(to_v.denominator, den);
    let to_f = analysis.transfer(&Channel::to_state(&eq, 0, 1));
    assert_eq!(to_f.numerator, exprs(&model, &["K1*m", "K1*B", "0"]));
    assert_eq!(to_f.denominator, den);

    let out = json(&["analyze", path, "--output", "f_K1", "--format", "json"]);
    assert_eq!(out["states"], serde_json::json!(["v_mass", "f_K1"]));
    let (k1, k2) = (value(&model, "K1"), value(&model, "K2"));
    let initial = out["step"]["initial_value"].as_f64().unwrap();
    assert!((initial - k1 / (k1 + k2)).abs() < 1e-12, "{initial}");
}

#[test]
fn second_order_json_has_the_textbook_time_scales_and_overshoot() {
    // wn = sqrt(k/m), zeta = b/(2 sqrt(k m)), overshoot exp(-zeta pi/sqrt(1 - zeta^2)).
    let path = "models/examples/mass_spring_damper.ron";
    let model = load(path);
    let (m, k, b) = (value(&model, "m"), value(&model, "k"), value(&model, "b"));
    let wn = (k / m).sqrt();
    let zeta = b / (2.0 * (k * m).sqrt());
    let out = json(&["analyze", path, "--output", "q_spring", "--format", "json"]);
    for scale in out["eigen_scales"].as_array().unwrap() {
        let close = |field: &str, want: f64| {
            let got = scale[field].as_f64().unwrap();
            assert!(
                (got - want).abs() < 1e-12 * want,
                "{field}: {got} against {want}"
            );
        };
        close("natural_frequency", wn);
        close("damping_ratio", zeta);
    }
    let tf = &out["transfer_function"];
    assert_eq!(tf["input"], "F");
    assert_eq!(tf["output"], "q_spring");
    assert_eq!(tf["numerator_text"], "1");
    assert_eq!(tf["denominator_text"], "m*s^2 + b*s + k");
    let numbers = |v: &Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    assert_eq!(numbers(&tf["numerator"]), [1.0 / m]);
    assert_eq!(numbers(&tf["denominator"]), [1.0, b / m, k / m]);
    assert_eq!(out["dc_gain"].as_f64().unwrap(), 1.0 / k);
    let overshoot = 100.0 * (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
    let got = out["step"]["overshoot_percent"].as_f64().unwrap();
    assert!(
        (got - overshoot).abs() < 1e-9 * overshoot,
        "{got} against {overshoot}"
    );
}

#[test]
fn text_prints_the_transfer_function_as_a_fraction() {
    let text = succeed(&[
        "analyze",
        "models/examples/mass_spring_damper.ron",
        "--output",
        "q_spring",
    ]);
    assert!(
        text.contains("                1\n  G(s) = ---------------\n         m*s^2 + b*s + k\n"),
        "{text}"
    );
    assert!(text.contains("DC gain G(0) = 1/k = 0.005"), "{text}");
}

#[test]
fn every_example_and_every_flagship_mode_analyses() {
    let mut paths = ron_files("models/examples");
    paths.extend(linear_graph_files("models/examples"));
    for path in &paths {
        let out = json(&["analyze", path, "--format", "json"]);
        let states = out["states"].as_array().unwrap().len();
        assert_eq!(
            out["eigenvalues"].as_array().unwrap().len(),
            states,
            "{path}"
        );
        if path.ends_with(".lg.ron") {
            assert_eq!(out["variables"], "coenergy", "{path}");
        }
    }
    let modes = json(&["modes", "models/eversion/robot.ron", "--format", "json"]);
    let mut integrators = 0;
    for mode in modes["modes"].as_array().unwrap() {
        let spec = mode["spec"].as_str().unwrap();
        let out = json(&[
            "analyze",
            "models/eversion/robot.ron",
            "--mode",
            spec,
            "--format",
            "json",
        ]);
        assert_eq!(out["mode"], spec);
        assert!(out["transfer_function"].is_object(), "{spec}");
        // The channel's free length q_k: a pole at the origin while the channel is slack
        // and the sheath slips, which has no DC gain and no final value.
        let out = json(&[
            "analyze",
            "models/eversion/robot.ron",
            "--mode",
            spec,
            "--output",
            "q_k",
            "--format",
            "json",
        ]);
        let den = out["transfer_function"]["denominator"].as_array().unwrap();
        if den.len() > 1 && den.last().and_then(Value::as_f64) == Some(0.0) {
            integrators += 1;
            assert!(out["dc_gain"].is_null(), "{spec}");
            assert!(out["step"]["final_value"].is_null(), "{spec}");
        } else {
            assert!(out["dc_gain"].is_number(), "{spec}");
        }
    }
    assert!(integrators > 0, "the slack modes integrate");
}

#[test]
fn a_nonlinear_model_is_analysed_at_its_linearisation() {
    // The pendulum about its bottom: s^2 + g/l, eigenvalues ±i sqrt(g/l), no decay.
    let path = "models/examples/nonlinear/pendulum.ron";
    let model = load(path);
    let omega = (value(&model, "g") / value(&model, "l")).sqrt();
    let out = json(&["analyze", path, "--at", "q_gravity=0", "--format", "json"]);
    assert!(out["linearised_at"].is_string());
    for e in out["eigenvalues"].as_array().unwrap() {
        assert_eq!(e["re"].as_f64().unwrap(), 0.0);
        let im = e["im"].as_f64().unwrap().abs();
        assert!((im - omega).abs() < 1e-12 * omega, "{im} against {omega}");
    }
    // --equilibrium finds the point itself.
    let out = json(&[
        "analyze",
        "models/examples/nonlinear/duffing.ron",
        "--equilibrium",
        "--format",
        "json",
    ]);
    assert_eq!(out["eigenvalues"].as_array().unwrap().len(), 2);
}

#[test]
fn unknown_input_is_an_error_naming_the_inputs() {
    let out = run(&[
        "analyze",
        "models/examples/mass_spring_damper.ron",
        "--input",
        "G",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("'G'") && err.contains("F"), "{err}");
}

fn compare(answer: &str) -> (i32, String) {
    let out = run(&[
        "compare",
        "models/examples/mass_spring_damper.ron",
        &format!("tests/fixtures/analysis/{answer}"),
    ]);
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap(), text)
}

#[test]
fn compare_equal_similar_and_different_answers() {
    let (code, text) = compare("msd_equal.ron");
    assert_eq!(code, 0, "{text}");
    assert!(text.starts_with("equal"), "{text}");

    let (code, text) = compare("msd_similar.ron");
    assert_eq!(code, 0, "{text}");
    assert!(text.starts_with("similar"), "{text}");
    assert!(text.contains("v_mass = p_mass/m"), "{text}");

    let (code, text) = compare("msd_different.ron");
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains(
            "B[2][1] (dv_mass/dt, coefficient of F) is 1 in the answer, 1/m in the model"
        ),
        "{text}"
    );

    let (code, text) = compare("msd_wrong_damping.ron");
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("det(sI - A): the coefficient of s is 2*b/m in the answer, b/m in the model"),
        "{text}"
    );

    // Unnamed (displacement, velocity): T is found, and it is diag(1, 1/m) reordered.
    let (code, text) = compare("msd_unnamed_similar.ron");
    assert_eq!(code, 0, "{text}");
    assert!(text.starts_with("similar"), "{text}");
    assert!(
        text.contains("  z1 = q_spring\n  z2 = p_mass/m\n")
            && text.contains("T = [[0, 1], [1/m, 0]]"),
        "{text}"
    );

    let (code, text) = compare("msd_bad_entry.ron");
    assert_eq!(code, 2, "{text}");
    assert!(
        text.contains("A[2][2]") && text.contains("msd_bad_entry.ron:4"),
        "{text}"
    );
}

/// `compare MODEL tests/fixtures/analysis/ANSWER`: exit code and output.
fn compare_with(model: &str, answer: &str) -> (i32, String) {
    let out = run(&[
        "compare",
        model,
        &format!("tests/fixtures/analysis/{answer}"),
    ]);
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap(), text)
}

#[test]
fn compare_finds_a_sign_change_of_a_state() {
    // z = (-q, p), worked out by hand in the fixture: T = [[0, -1], [1, 0]].
    let (code, text) = compare("msd_sign_change.ron");
    assert_eq!(code, 0, "{text}");
    assert!(text.starts_with("similar"), "{text}");
    assert!(
        text.contains("  z1 = -q_spring\n  z2 = p_mass\n")
            && text.contains("T = [[0, -1], [1, 0]]")
            && text.contains("the only solution"),
        "{text}"
    );
    // The same states written as the model's: T is given, every entry checked.
    let (code, text) = compare("msd_sign_change_named.ron");
    assert_eq!(code, 0, "{text}");
    assert!(
        text.starts_with("similar") && text.contains("T = [[0, -1], [1, 0]]"),
        "{text}"
    );
}

#[test]
fn compare_finds_a_mixed_change_of_variables() {
    // z1 = q, z2 = p + b q: A' = T A T⁻¹ by hand in the fixture.
    let (code, text) = compare("msd_mixed.ron");
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("  z1 = q_spring\n  z2 = p_mass + b*q_spring\n")
            && text.contains("T = [[0, 1], [1, b]]"),
        "{text}"
    );
    let (code, text) = compare("msd_mixed_named.ron");
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("every entry of A and B agrees"), "{text}");
    // Two masses: the stretch, the total momentum and the relative velocity.
    let (code, text) = compare_with("models/examples/two_masses.ron", "two_masses_momentum.ron");
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("  z2 = p_mass1 + p_mass2\n  z3 = p_mass1/m1 - p_mass2/m2\n"),
        "{text}"
    );
    let (code, text) = compare_with(
        "models/examples/two_masses.ron",
        "two_masses_momentum_named.ron",
    );
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("v_mass1 - v_mass2 = p_mass1/m1 - p_mass2/m2"),
        "{text}"
    );
    // The quarter car's tyre and total compressions and velocities, unnamed and named.
    let (code, text) = compare_with(
        "models/teaching/quarter_car.ron",
        "quarter_car_deflections.ron",
    );
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("T = [[1, 0, 0, 0], [1, 0, 1, 0], [0, 1/m_w, 0, 0], [0, 0, 0, 1/m_b]]"),
        "{text}"
    );
    let (code, text) = compare_with(
        "models/teaching/quarter_car.ron",
        "quarter_car_deflections_named.ron",
    );
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("v_wheel = p_wheel/m_w"), "{text}");
}

#[test]
fn compare_says_when_the_input_coupling_differs() {
    // The model's states and A, B with the wrong sign: the polynomials agree.
    let (code, text) = compare("msd_wrong_input_sign.ron");
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("B[1][1] (dp_mass/dt, coefficient of F) is -1 in the answer, 1 in the model")
            && text.contains("same characteristic polynomial")
            && text.contains("the input coupling differs")
            // The same A and B would be right for the states -p_mass, -q_spring.
            && text.contains("z1 = -p_mass, z2 = -q_spring"),
        "{text}"
    );
    // Unnamed, no input at all: no invertible T can exist.
    let (code, text) = compare("msd_no_input.ron");
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("the characteristic polynomials agree")
            && text
                .contains("the inputs reach 0 state directions in the answer and 2 in the model")
            && text.contains("the input coupling differs"),
        "{text}"
    );
    // The force on the wrong mass, states named: caught at B.
    let (code, text) = compare_with(
        "models/examples/two_masses.ron",
        "two_masses_wrong_mass.ron",
    );
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("B[3][1] (d(v_mass1 - v_mass2)/dt, coefficient of F) is 1/m2 in the answer, 1/m1 in the model"),
        "{text}"
    );
}

#[test]
fn compare_json_gives_t_and_both_polynomials() {
    let out = run(&[
        "compare",
        "models/examples/mass_spring_damper.ron",
        "tests/fixtures/analysis/msd_mixed.ron",
        "--format",
        "json",
    ]);
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(value["verdict"], "similar");
    assert_eq!(
        value["transformation"]["T"],
        serde_json::json!([["0", "1"], ["1", "b"]])
    );
    assert_eq!(
        value["transformation"]["from"],
        serde_json::json!(["p_mass", "q_spring"])
    );
    assert_eq!(value["transformation"]["unique"], true);
    assert_eq!(
        value["characteristic_polynomial"]["model"],
        "s^2 + (b/m)*s + k/m"
    );
    let out = run(&[
        "compare",
        "models/examples/mass_spring_damper.ron",
        "tests/fixtures/analysis/msd_wrong_damping.ron",
        "--format",
        "json",
    ]);
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(value["verdict"], "different");
    assert_eq!(
        value["characteristic_polynomial"]["answer"],
        "s^2 + (2*b/m)*s + k/m"
    );
}

#[test]
fn compare_energy_answer_to_a_linear_graph_is_similar() {
    // The linear graph's own states are co-energy (v_mass, f_spring); momentum and
    // displacement are the same equations rescaled.
    let out = run(&[
        "compare",
        "models/examples/mass_spring_damper.lg.ron",
        "tests/fixtures/analysis/msd_equal.ron",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.starts_with("similar"), "{text}");
}

/// Whether an SVG the program wrote has a text element reading `text` (plotters puts the
/// text on a line of its own).
fn svg_has_text(svg: &str, text: &str) -> bool {
    svg.split("<text").skip(1).any(|element| {
        element
            .split_once('>')
            .and_then(|(_, rest)| rest.split_once("</text>"))
            .is_some_and(|(inside, _)| inside.trim() == text)
    })
}

#[test]
fn plots_label_their_axes_with_quantity_and_unit() {
    let scratch = std::env::temp_dir().join(format!("bondgraph-units-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let file = |name: &str| scratch.join(name).to_string_lossy().into_owned();
    let read = |name: &str| std::fs::read_to_string(scratch.join(name)).unwrap();

    // simulate --plot: one output per panel with its unit; a shared panel with the
    // quantity they share, their names in the key.
    succeed(&[
        "simulate",
        "models/teaching/rc.ron",
        "--scenario",
        "models/teaching/scenarios/rc_step.ron",
        "--plot",
        &file("rc.svg"),
        "--panel",
        "effort:capacitor",
        "--panel",
        "flow:capacitor",
        "--panel",
        "energy:supplied,energy:stored,energy:dissipated",
    ]);
    let svg = read("rc.svg");
    for label in [
        "effort:capacitor: voltage (V)",
        "flow:capacitor: current (A)",
        "energy (J)",
        "energy:dissipated",
    ] {
        assert!(svg_has_text(&svg, label), "simulate --plot: no {label:?}");
    }

    // analyze --step and --bode: the output's quantity and unit; the magnitude in dB of
    // the output's unit per the input's.
    for (model, input, output, step_label, magnitude) in [
        (
            "rc",
            "V",
            "effort:capacitor",
            "effort:capacitor: voltage (V)",
            "magnitude (dB of V/V)",
        ),
        (
            "tank",
            "Q_in",
            "effort:tank",
            "effort:tank: pressure (Pa)",
            "magnitude (dB of Pa/(m^3/s))",
        ),
        (
            "dc_motor",
            "V",
            "flow:load_inertia",
            "flow:load_inertia: angular velocity (rad/s)",
            "magnitude (dB of (rad/s)/V)",
        ),
        (
            "mass_spring_damper",
            "F",
            "q_spring",
            "q_spring: displacement (m)",
            "magnitude (dB of m/N)",
        ),
    ] {
        succeed(&[
            "analyze",
            &format!("models/teaching/{model}.ron"),
            "--input",
            input,
            "--output",
            output,
            "--step",
            &file("step.svg"),
            "--bode",
            &file("bode.svg"),
        ]);
        let (step, bode) = (read("step.svg"), read("bode.svg"));
        assert!(
            svg_has_text(&step, step_label),
            "{model} --step: no {step_label:?}"
        );
        assert!(svg_has_text(&step, "time (s)"), "{model} --step");
        assert!(
            svg_has_text(&bode, magnitude),
            "{model} --bode: no {magnitude:?}"
        );
        assert!(svg_has_text(&bode, "phase (deg)"), "{model} --bode");
        assert!(
            svg_has_text(&bode, "angular frequency (rad/s)"),
            "{model} --bode"
        );
    }
    // The step is one unit of the input, in the input's unit.
    assert!(svg_has_text(
        &read("step.svg"),
        "mass_spring_damper: response to a step of 1 N in F"
    ));
    let _ = std::fs::remove_dir_all(&scratch);
}
