//! Experiments against a model: what they name must exist, and every mistake is reported at
//! the entry of the experiment file that made it.

use std::path::PathBuf;

use bondgraph_core::model;
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data;
use bondgraph_fit::experiment::{Experiment, ExperimentError};
use bondgraph_fit::predict::Predictor;

fn motor() -> (model::Model, std::sync::Arc<SourceFile>) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/examples/dc_motor.ron");
    let source = SourceFile::new("dc_motor.ron", std::fs::read_to_string(path).unwrap());
    (bondgraph_ron::model::load_source(&source).unwrap(), source)
}

#[test]
fn a_removal_that_leaves_an_element_dangling_names_the_absent_entry() {
    // Removing the gear leaves the gyrator `motor` with one bond.
    let text = "Experiment(\n    kind: Steady,\n    conditions: [(\"V_V\", \"V\", 1.0)],\n    absent: [(\"gear_on\", [\"gear\"])],\n    observed: [(\"w_rad_s\", \"flow:load_inertia\", 1.0)],\n)";
    let experiment = Experiment::parse("motor.ron", text).unwrap();
    let (model, source) = motor();
    let Err(ExperimentError::Diagnostics(d)) = Predictor::new(model, &source, &experiment) else {
        panic!("the removal must be refused");
    };
    let first = &d.0[0];
    let location = first.location.as_ref().unwrap();
    assert_eq!(
        (location.file.as_str(), location.line, location.column),
        ("motor.ron", 4, 15)
    );
    assert!(
        first.message.starts_with(
            "experiment: the `absent` entry for `gear_on` removes 'gear' from model 'dc_motor'"
        ),
        "{}",
        first.message
    );
    assert!(first.message.contains("'motor'"), "{}", first.message);
    // The model's own diagnostic follows, pointing into the model file.
    assert!(
        d.0.len() >= 2 && d.0[1].location.as_ref().unwrap().file == "dc_motor.ron",
        "{d}"
    );
}

#[test]
fn an_input_or_output_the_model_lacks_is_reported_at_the_entry() {
    let text = "Experiment(\n    kind: Steady,\n    conditions: [(\"V_V\", \"U\", 1.0)],\n    observed: [(\"w_rad_s\", \"flow:load_inertai\", 1.0)],\n)";
    let experiment = Experiment::parse("motor.ron", text).unwrap();
    let (model, source) = motor();
    let error = Predictor::new(model, &source, &experiment).err().unwrap();
    let text = error.to_string();
    assert!(
        text.starts_with(
            "motor.ron:3:26: error: experiment: column `V_V` sets input 'U', which model 'dc_motor' does not have"
        ),
        "{text}"
    );
    assert!(
        text.contains("\nmotor.ron:4:28: error: experiment: column `w_rad_s`: "),
        "{text}"
    );
    assert!(text.contains("load_inertai"), "{text}");
}

#[test]
fn steady_states_of_a_linear_motor_by_hand() {
    // At steady state the inductance carries no voltage and the inertia no torque:
    // i = (V - K N w)/R_a and N K i = b w (the gear multiplies the torque by N and divides
    // the speed), so w = N K V / (R_a b + N^2 K^2) = 10 * 0.05 * 12 / (1.2e-3 + 0.25)
    // = 23.885 rad/s at 12 V.
    let text = "Experiment(\n    kind: Steady,\n    conditions: [(\"V_V\", \"V\", 1.0)],\n    observed: [(\"w_rad_s\", \"flow:load_inertia\", 1.0), (\"i_mA\", \"flow:winding_resistance\", 0.001)],\n)";
    let experiment = Experiment::parse("motor.ron", text).unwrap();
    let (model, source) = motor();
    let predictor = Predictor::new(model, &source, &experiment).unwrap();
    let rows = data::read("d.csv", "V_V,w_rad_s,i_mA\n12,0,0\n6,0,0\n", &experiment)
        .unwrap()
        .rows;
    let predicted = predictor.predict(&rows).unwrap();
    for (row, p) in rows.iter().zip(&predicted) {
        let v = row.conditions[0].unwrap();
        let w = 10.0 * 0.05 * v / (1.2 * 0.001 + 0.25);
        let i = (v - 0.05 * 10.0 * w) / 1.2;
        assert!((p[0] - w).abs() < 1e-9 * w, "{p:?} vs {w}");
        assert!((p[1] - i * 1e3).abs() < 1e-9 * i * 1e3, "{p:?} vs {i}");
    }
}

#[test]
fn a_fit_takes_every_row_or_none() {
    // `predict_all` is what a fit's trial values get: every row's steady state (the same as
    // `predict_each`'s, and the hand value w = N K V / (R_a b + N² K²)), or nothing at all
    // once one row has none. With a negative armature resistance the motor runs away
    // (L J s² + (R_a J + L b) s + ... has a negative middle coefficient): no row settles,
    // and `predict_each` says why, at the row.
    let text = "Experiment(\n    kind: Steady,\n    conditions: [(\"V_V\", \"V\", 1.0)],\n    observed: [(\"w_rad_s\", \"flow:load_inertia\", 1.0)],\n)";
    let experiment = Experiment::parse("motor.ron", text).unwrap();
    let (model, source) = motor();
    let predictor = Predictor::new(model, &source, &experiment).unwrap();
    let rows = data::read("d.csv", "V_V,w_rad_s\n12,0\n6,0\n", &experiment)
        .unwrap()
        .rows;
    let mut evaluator = predictor.evaluator(&["R_a".to_string()]).unwrap();
    evaluator.set(&[2.4]);
    let all = evaluator.predict_all(&rows).expect("every row settles");
    for ((row, p), each) in rows.iter().zip(&all).zip(evaluator.predict_each(&rows)) {
        let w = 10.0 * 0.05 * row.conditions[0].unwrap() / (2.4 * 0.001 + 0.25);
        assert!((p.observed[0] - w).abs() < 1e-9 * w, "{p:?} vs {w}");
        assert_eq!(p.observed, each.unwrap().observed);
    }
    evaluator.set(&[-1.0]);
    assert!(evaluator.predict_all(&rows).is_none());
    let each = evaluator.predict_each(&rows);
    let Err(error) = &each[0] else {
        panic!("a runaway motor has no steady state: {each:?}")
    };
    let text = error.to_string();
    assert!(
        text.contains("d.csv") && text.contains("V_V = 12"),
        "{text}"
    );
    assert!(text.contains("does not decay"), "{text}");
}
