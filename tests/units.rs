//! Units end to end: a model written in scaled units (N/mm, kPa, L/min) is the same model as
//! one written in SI units, for every command, and `equations` shows what was converted.

use std::path::PathBuf;

use serde_json::Value;

use crate::cli::{json, numbers, succeed};

/// A mass-spring-damper pushed by a force `F`; `k` and `b` are written as given.
fn msd(k: &str, b: &str) -> String {
    format!(
        r#"Model(name: "msd",
    parameters: {{
        "m": (value: 2.0, unit: "kg"),
        "k": {k},
        "b": {b},
    }},
    inputs: {{"F": (unit: "N")}},
    elements: {{"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
               "spring": C(stiffness: "k"), "damper": R(resistance: "b")}},
    bonds: [("force", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")])"#
    )
}

/// Writes the two models and a step scenario into a fresh folder: the SI model, the
/// same model in N/mm and kN*s/m, and the scenario.
fn files(name: &str) -> (PathBuf, PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("bondgraph-units-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let si = dir.join("si.ron");
    let scaled = dir.join("scaled.ron");
    let scenario = dir.join("step.ron");
    std::fs::write(
        &si,
        msd(
            r#"(value: 200.0, unit: "N/m")"#,
            r#"(value: 4.0, unit: "N*s/m")"#,
        ),
    )
    .unwrap();
    std::fs::write(
        &scaled,
        msd(
            r#"(value: 0.2, unit: "N/mm")"#,
            r#"(value: 0.004, unit: "kN*s/m")"#,
        ),
    )
    .unwrap();
    std::fs::write(
        &scenario,
        r#"Scenario(name: "step", inputs: {"F": Step(at: 0.1, before: 0.0, after: 10.0)},
            duration: 2.0, record: ["flow:mass", "effort:spring"], sample: 0.01)"#,
    )
    .unwrap();
    (si, scaled, scenario)
}

#[test]
fn a_model_in_n_per_mm_has_the_a_matrix_and_the_motion_of_the_same_model_in_n_per_m() {
    let (si, scaled, scenario) = files("same");
    let a = |path: &PathBuf| {
        let document = json(&[path.to_str().unwrap()]);
        numbers(&document["A_value"])
    };
    // By hand, in p_mass, q_spring: A = [[-b/m, -k], [1/m, 0]] with m = 2 kg, k = 200 N/m,
    // b = 4 N*s/m.
    let expected = vec![vec![-2.0, -200.0], vec![0.5, 0.0]];
    assert_eq!(a(&si), expected);
    assert_eq!(a(&scaled), expected);
    // The same trajectory: 10 N on 200 N/m settles at 0.05 m; both runs give the same
    // numbers, sample by sample.
    let run = |path: &PathBuf| {
        succeed(&[
            "simulate",
            path.to_str().unwrap(),
            "--scenario",
            scenario.to_str().unwrap(),
        ])
    };
    let rows = |csv: &str| -> Vec<Vec<f64>> {
        csv.lines()
            .skip(1)
            .map(|l| l.split(',').filter_map(|c| c.parse().ok()).collect())
            .collect()
    };
    let (si_rows, scaled_rows) = (rows(&run(&si)), rows(&run(&scaled)));
    assert_eq!(si_rows.len(), 201);
    assert_eq!(si_rows, scaled_rows);
    // The closed form at t = 2 s, 1.9 s after the 10 N step: damping ratio z = b/(2
    // sqrt(k m)) = 0.1, natural frequency w = sqrt(k/m) = 10 rad/s, wd = w sqrt(1 - z^2);
    // the spring's force is F0 (1 - e^(-z w t) (cos wd t + z/sqrt(1 - z^2) sin wd t)) and
    // the velocity F0/k e^(-z w t) w/sqrt(1 - z^2) sin wd t.
    let (z, w, t) = (0.1f64, 10.0f64, 1.9f64);
    let (root, decay) = ((1.0 - z * z).sqrt(), (-z * w * t).exp());
    let force = 10.0 * (1.0 - decay * ((w * root * t).cos() + z / root * (w * root * t).sin()));
    let velocity = 10.0 / 200.0 * decay * w / root * (w * root * t).sin();
    let last = scaled_rows.last().unwrap();
    let (v, f) = (last[last.len() - 2], last[last.len() - 1]);
    assert!((f - force).abs() < 1e-9, "{f} vs {force}");
    assert!((v - velocity).abs() < 1e-12, "{v} vs {velocity}");
}

#[test]
fn equations_show_a_converted_parameter_in_si_and_as_written() {
    let (_, scaled, _) = files("shown");
    let path = scaled.to_str().unwrap();
    let text = succeed(&["equations", path]);
    assert!(
        text.contains(
            "parameters in SI units (as written in the file):\n  k = 200 N/m (0.2 N/mm)\n  b = 4 N*s/m (0.004 kN*s/m)\n"
        ),
        "{text}"
    );
    let document = json(&[path]);
    let parameters = document["parameters"].as_array().unwrap();
    let k = parameters.iter().find(|p| p["name"] == "k").unwrap();
    assert_eq!(k["value"], Value::from(200.0));
    assert_eq!(k["unit"], Value::from("N/m"));
    assert_eq!(k["as_written"]["value"], Value::from(0.2));
    assert_eq!(k["as_written"]["unit"], Value::from("N/mm"));
    let m = parameters.iter().find(|p| p["name"] == "m").unwrap();
    assert_eq!(m["value"], Value::from(2.0));
    assert_eq!(m["unit"], Value::from("kg"));
    assert!(m.get("as_written").is_none_or(Value::is_null), "{m}");
    let latex = succeed(&["equations", path, "--format", "latex"]);
    assert!(latex.contains("% k = 200 N/m (0.2 N/mm)\n"), "{latex}");
}
