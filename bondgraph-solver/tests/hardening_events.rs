//! Hardening of time stepping, sampling and events (issue 30, third round; issue 37): each
//! test failed before its fix.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Signal, Simulator};

use crate::support::{Constant, load};

fn output(model: &Model, spec: &str) -> Output {
    Output {
        name: spec.into(),
        spec: OutputSpec::parse(model, spec).unwrap(),
        integral: false,
    }
}

/// Item 6: the sample at `t = duration` is recorded although `3 × 0.1` is
/// `0.30000000000000004 > 0.3`. The two masses (`m1 = 1`, `m2 = 3`, `k = 50`, `b = 2.5`)
/// pushed by 1 N from rest: `flow:mass1` at 0.1, 0.2 and 0.3 s from the matrix exponential
/// of the system with the input as a constant state (mpmath, 40 digits).
#[test]
fn the_sample_at_the_duration_is_recorded() {
    let model = load("models/examples/two_masses.ron");
    let mut simulator = Simulator::new(&model, vec![output(&model, "flow:mass1")]);
    let force = Constant(1.0);
    let inputs: [&dyn Signal; 1] = [&force];
    let trajectory = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0; 3],
            duration: 0.3,
            sample: Some(0.1),
            audit_energy: false,
        })
        .unwrap();
    assert_eq!(trajectory.times, [0.0, 0.1, 0.2, 0.3]);
    let expected = [
        0.0,
        0.091_939_145_186_535_5,
        0.141_623_473_170_071_6,
        0.133_072_038_149_844_27,
    ];
    for (k, value) in expected.iter().enumerate() {
        let got = trajectory.value(k, 0).unwrap();
        assert!(
            (got - value).abs() <= 1e-13,
            "sample {k}: {got} against {value}"
        );
    }
}

/// Item 6, on the integrated path: the pendulum (`models/examples/nonlinear/pendulum.ron`)
/// sampled every 0.1 s for 0.7 s (`7 × 0.1 = 0.7000000000000001`) ends with a sample at 0.7.
#[test]
fn the_sample_at_the_duration_is_recorded_on_the_integrated_path() {
    let model = load("models/examples/nonlinear/pendulum.ron");
    let mut simulator = Simulator::new(&model, vec![output(&model, "flow:bob")]);
    let trajectory = simulator
        .run(&Run {
            inputs: &[],
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0, 0.1],
            duration: 0.7,
            sample: Some(0.1),
            audit_energy: false,
        })
        .unwrap();
    assert_eq!(trajectory.times.len(), 8, "{:?}", trajectory.times);
    assert_eq!(trajectory.times.last(), Some(&0.7));
}
