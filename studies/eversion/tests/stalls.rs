//! Numerical trouble met on the flagship's extensions, kept as regressions: a stick-slip
//! catheter that once stalled the solver, and a Stribeck contact held at its Stribeck
//! velocity that once chattered.

use crate::support::*;
use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_eversion::columns::{self, catheter, channel};
use bondgraph_ron::extension::{self, Extension};

/// A predictor of the flagship extended with `id`.
fn extended(id: &str) -> bondgraph_fit::predict::Predictor {
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
    bondgraph_fit::predict::Predictor::new(model, &extended.file, &experiment()).unwrap()
}

#[test]
fn a_catheter_that_once_stalled_the_stepper_slips_behind_and_settles() {
    let predictor = extended("catheter-pressure-friction");
    let names: Vec<String> = ["F_C_ge", "b", "F_S_ge", "F_C_ct", "F_S_ct", "mu_ct"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut evaluator = predictor.evaluator(&names).unwrap();
    evaluator.set_budget(&bondgraph_fit::budget::Budget::default());
    // Breakaway far above Coulomb at the catheter. The catheter is driven at 6.3 mm/s, faster
    // than the inner structure can move (2 v_ge <= v_ac = 5.8 mm/s with the string taut), so
    // it cannot stay stuck: it slips ahead of the inner structure (slip-: the relative
    // velocity 2 v_ge - v_ct is negative) and the tip is channel-limited at v_ac/2 = 2.9 mm/s.
    // On the way a dead-band guard declined for static friction kept re-firing on rounding
    // noise one ulp of time at a time, and the stepper stopped advancing ("time stopped
    // advancing"); a declined guard now re-arms only once it is left by more than rounding.
    evaluator.set(&[
        9.125,
        1250.0,
        11.62494945526123,
        5.5,
        18.333333333333332,
        0.25,
    ]);
    let row = dataset("table6.csv").rows[5].clone();
    assert_eq!(catheter(&row), Some(6.3));
    assert_eq!(channel(&row), 5.8);
    let prediction = evaluator.predict(&[row]).unwrap().remove(0);
    assert_eq!(prediction.mode, "fr_ge=slip+,k=taut,fr_ct=slip-");
    assert!(
        (prediction.observed[0] - 2.9).abs() < 1e-9,
        "{prediction:?}"
    );
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
    let row = columns::row(&"stribeck".into(), 2, 150.0, 5.8, None, 0.0);
    let prediction = evaluator.predict(&[row]).unwrap().remove(0);
    assert!(
        (prediction.observed[0] - 2.9).abs() < 1e-9,
        "{prediction:?}"
    );
    assert_eq!(prediction.mode, "fr_ge=creep+,k=taut");
}
