//! The three systems of issue 31 (`models/examples/two_tank`, `thermal`, `actuator`)
//! against their independent references: the noise-free data each folder's `generate.py`
//! made with scipy from hand-written equations, not with this project's code.
//!
//! A calibration of a run must find the truth the script used, and a simulation of the
//! actuator's recorded run must follow it through every stick-slip event. The full
//! comparisons (every extension, both runs) are the folders' `compare_with_reference.py`.

use serde_json::Value;

use crate::cli::succeed;
use crate::support::root;

/// `calibrate --format json` of a model on the given runs; the fitted values by name.
fn calibrated(model: &str, experiment: &str, data: &[&str]) -> Value {
    let mut args = vec![
        "calibrate",
        "--model",
        model,
        "--experiment",
        experiment,
        "--format",
        "json",
    ];
    for file in data {
        args.extend(["--data", file]);
    }
    serde_json::from_str(&succeed(&args)).expect("calibrate's JSON")
}

fn assert_recovers(fit: &Value, truth: &[(&str, f64)], relative: f64) {
    for &(name, value) in truth {
        let got = fit["params"][name]["value"].as_f64().expect(name);
        assert!(
            ((got - value) / value).abs() < relative,
            "{name}: calibrated {got}, truth {value}"
        );
    }
}

#[test]
fn the_two_tank_runs_are_calibrated_back_to_the_reference_truth() {
    let fit = calibrated(
        "models/examples/two_tank/two_tank.ron",
        "models/examples/two_tank/experiment_step.ron",
        &[
            "models/examples/two_tank/data/step_1_exact.csv",
            "models/examples/two_tank/data/step_2_exact.csv",
        ],
    );
    // The CSV holds levels to 1e-4 mm: the truth is found to about a millionth.
    assert_recovers(
        &fit,
        &[("L_p", 2.0), ("R_12", 8.0e6), ("c_d", 2.2e-6)],
        1e-5,
    );
}

#[test]
fn the_thermal_linear_graph_runs_are_calibrated_back_to_the_reference_truth() {
    let fit = calibrated(
        "models/examples/thermal/thermal.lg.ron",
        "models/examples/thermal/experiment_step.ron",
        &[
            "models/examples/thermal/data/step_1_exact.csv",
            "models/examples/thermal/data/step_2_exact.csv",
        ],
    );
    let truth = [
        ("C_1", 450.0),
        ("C_2", 900.0),
        ("R_12", 0.8),
        ("R_1a", 4.0),
        ("R_2a", 2.5),
    ];
    assert_recovers(&fit, &truth, 1e-6);
}

#[test]
fn the_actuator_follows_its_reference_through_every_stick_slip_event() {
    // Run 2 of data/step_2_exact.csv: a 25 N weight that makes the carriage slip back for
    // 0.73 ms before the current holds it, then a climb, a stop and a slow back-drive.
    let text =
        std::fs::read_to_string(root().join("models/examples/actuator/data/step_2_exact.csv"))
            .expect("the reference run");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().expect("a number")).collect())
        .collect();
    let table = |k: usize| {
        rows.iter()
            .map(|r| format!("({:?}, {:?})", r[0], r[k]))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let dir = std::env::temp_dir().join(format!("bondgraph-new-systems-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let scenario = dir.join("run_2.ron");
    std::fs::write(
        &scenario,
        format!(
            "Scenario(name: \"run_2\", inputs: {{ \"V\": Table([{}]), \"F_L\": Table([{}]) }}, \
             initial_mode: \"guide=stuck\", duration: 0.6, \
             record: [\"flow:carriage\", \"flow:winding_inductance\"], sample: 0.001)",
            table(1),
            table(2)
        ),
    )
    .expect("the scenario");
    // The model file with generate.py's truth for its fitted parameters.
    let mut model = std::fs::read_to_string(root().join("models/examples/actuator/actuator.ron"))
        .expect("the model");
    for (from, to) in [
        ("\"K\": (value: 0.025,", "\"K\": (value: 0.03,"),
        ("\"J_m\": (value: 2.0e-5,", "\"J_m\": (value: 1.5e-5,"),
        ("\"b\": (value: 60.0,", "\"b\": (value: 40.0,"),
        ("\"F_S\": (value: 12.0,", "\"F_S\": (value: 15.0,"),
        ("\"F_C\": (value: 8.0,", "\"F_C\": (value: 10.0,"),
    ] {
        assert!(model.contains(from), "{from}");
        model = model.replace(from, to);
    }
    let model_path = dir.join("actuator.ron");
    std::fs::write(&model_path, model).expect("the model copy");
    let out: Value = serde_json::from_str(&succeed(&[
        "simulate",
        model_path.to_str().expect("a path"),
        "--scenario",
        scenario.to_str().expect("a path"),
        "--format",
        "json",
    ]))
    .expect("simulate's JSON");
    let events: Vec<(f64, &str)> = out["events"]
        .as_array()
        .expect("events")
        .iter()
        .map(|e| (e["t"].as_f64().expect("t"), e["to"].as_str().expect("to")))
        .collect();
    // The reference's switches (generate.py, solve_ivp's event location), to the microsecond.
    let expected = [
        (0.0, "guide=slip-"),
        (0.000732, "guide=stuck"),
        (0.019372, "guide=slip+"),
        (0.369583, "guide=stuck"),
        (0.420719, "guide=slip-"),
    ];
    assert_eq!(events.len(), expected.len(), "{events:?}");
    for ((t, to), (t_ref, to_ref)) in events.iter().zip(expected) {
        assert_eq!(*to, to_ref);
        assert!((t - t_ref).abs() < 1e-6, "{to} at {t}, reference {t_ref}");
    }
    // Speeds to the CSV's 1e-5 mm/s, currents to its 1e-4 mA.
    let mut compared = 0;
    for sample in out["samples"].as_array().expect("samples") {
        let t = sample["t"].as_f64().expect("t");
        let k = (t / 0.001).round() as usize;
        if (t - k as f64 * 0.001).abs() > 1e-9 {
            continue; // an event's own sample
        }
        let v = 1e3 * sample["values"]["flow:carriage"].as_f64().expect("v");
        let i = 1e3
            * sample["values"]["flow:winding_inductance"]
                .as_f64()
                .expect("i");
        assert!(
            (v - rows[k][3]).abs() < 1e-4,
            "t = {t}: v {v} mm/s, reference {}",
            rows[k][3]
        );
        assert!(
            (i - rows[k][4]).abs() < 1e-3,
            "t = {t}: i {i} mA, reference {}",
            rows[k][4]
        );
        compared += 1;
    }
    assert_eq!(compared, rows.len());
    std::fs::remove_dir_all(&dir).ok();
}
