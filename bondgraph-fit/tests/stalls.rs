//! Numerical trouble met on the flagship's extensions, kept as regressions: a stick-slip
//! catheter that once hung the solver (the stall is now reported), and a Stribeck contact
//! held at its Stribeck velocity that once chattered.

use crate::support::*;
use bondgraph_core::model::Model;
use bondgraph_core::model::extension::{self, Extension};
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data::Measurement;

/// A predictor of the flagship extended with `id`.
fn extended(id: &str) -> bondgraph_fit::experiment::Predictor {
    let base = SourceFile::new(
        "models/eversion/robot.ron",
        std::fs::read_to_string(root().join("models/eversion/robot.ron")).unwrap(),
    );
    let path = format!("models/eversion/extensions/{id}.ron");
    let fragment = Extension::load(&SourceFile::new(
        &path,
        std::fs::read_to_string(root().join(&path)).unwrap(),
    ))
    .unwrap();
    let extended = extension::merge(&base, &[fragment]).unwrap();
    let model: Model = extended.load().unwrap();
    bondgraph_fit::experiment::Predictor::new(model, &extended.file, &experiment()).unwrap()
}

#[test]
fn a_stalled_steady_state_is_reported_not_looped() {
    let predictor = extended("catheter-pressure-friction");
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

#[test]
fn a_stribeck_contact_held_at_its_stribeck_velocity_settles() {
    // 150 kPa with the channel at 5.8 mm/s: the taut inner structure holds the tip at
    // v_ac/2 = 2.9 mm/s, and on the way the tip's speed follows the string's growing tension
    // down through v_st = 3.276 mm/s, where creeping and sliding friction meet. Switching at
    // one threshold there chattered (200 events in 1 µs); with the dead band as hysteresis
    // it settles, channel-limited, at exactly v_ac/2.
    let predictor = extended("velocity-weakening-friction");
    let mut evaluator = predictor.evaluator(&["v_st".to_string()]).unwrap();
    evaluator.set(&[0.0032762323403969455]);
    let row = Measurement {
        pressure_kpa: 150.0,
        channel_velocity_mm_s: 5.8,
        catheter_velocity_mm_s: None,
        tip_velocity_mm_s: 0.0,
        row: 2,
    };
    let prediction = evaluator.predict(&[row]).unwrap().remove(0);
    assert!(
        (prediction.tip_velocity_mm_s - 2.9).abs() < 1e-9,
        "{prediction:?}"
    );
    assert_eq!(prediction.mode, "fr_ge=creep+,k=taut");
}
