//! A stick-slip catheter that once hung the solver: the stall is now reported.

use crate::support::*;
use bondgraph_core::model::extension::{self, Extension};
use bondgraph_core::source::SourceFile;

#[test]
fn a_stalled_steady_state_is_reported_not_looped() {
    let base = SourceFile::new(
        "models/eversion/robot.ron",
        std::fs::read_to_string(root().join("models/eversion/robot.ron")).unwrap(),
    );
    let path = "models/eversion/extensions/catheter-pressure-friction.ron";
    let fragment = Extension::load(&SourceFile::new(
        path,
        std::fs::read_to_string(root().join(path)).unwrap(),
    ))
    .unwrap();
    let extended = extension::merge(&base, &[fragment]).unwrap();
    let model = extended.load().unwrap();
    let predictor =
        bondgraph_fit::experiment::Predictor::new(model, &extended.file, &experiment()).unwrap();
    let names: Vec<String> = ["F_C_ge", "b", "F_S_ge", "F_C_ct", "F_S_ct", "mu_ct"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut evaluator = predictor.evaluator(&names).unwrap();
    evaluator.set_max_time(2.0);
    // Breakaway far above Coulomb at the catheter: a stick-slip cycle in which the stepper
    // once stopped advancing time (and looped forever).
    evaluator.set(&[
        9.125,
        1250.0,
        11.62494945526123,
        5.5,
        18.333333333333332,
        0.25,
    ]);
    let row = dataset("table6.csv").rows[5].clone();
    assert_eq!(row.catheter_velocity_mm_s, Some(6.3));
    let error = evaluator.predict(&[row]).unwrap_err();
    assert!(error.0.contains("time stopped advancing"), "{}", error.0);
}
