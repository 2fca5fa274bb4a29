//! Hardening of time stepping, sampling and events (issue 30, third round; issue 37): each
//! test failed before its fix.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::{self, Model};
use bondgraph_core::modes::Mode;
use bondgraph_core::scenario::Signal as Table;
use bondgraph_solver::{Event, Output, Run, Signal, Simulator, Trajectory};

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

/// A belt table reversing every microsecond, at 1 m/s, in one of eight shapes.
fn reversing_table(shape: usize, reversals: usize) -> Table {
    let microsecond = 1e-6;
    let mut points = Vec::new();
    for k in 0..=reversals {
        let t = k as f64 * microsecond;
        let even = k % 2 == 0;
        match shape {
            // Triangles: +1, -1, +1, ...; -1, +1, ...; asymmetric +1, -0.5.
            0 => points.push((t, if even { 1.0 } else { -1.0 })),
            1 => points.push((t, if even { -1.0 } else { 1.0 })),
            2 => points.push((t, if even { 1.0 } else { -0.5 })),
            // Through zero at every other point: 0, 1, 0, -1, ...
            3 => points.push((t, [0.0, 1.0, 0.0, -1.0][k % 4])),
            // Half a microsecond late: the first reversal at 0.5 µs.
            4 => points.push((t + 0.5 * microsecond, if even { -1.0 } else { 1.0 })),
            // Forwards only, the slope reversing: 1, 0, 1, ...
            5 => points.push((t, if even { 1.0 } else { 0.0 })),
            // A square wave with 1 ns edges.
            6 => {
                let v = if even { 1.0 } else { -1.0 };
                points.push((t, v));
                points.push((t + microsecond - 1e-9, v));
            }
            // A sawtooth: rising from -1 to 1 over a microsecond, then back in 1 ns.
            _ => {
                points.push((t, -1.0));
                points.push((t + microsecond - 1e-9, 1.0));
            }
        }
    }
    Table::Table(points)
}

/// The events of a belt model driven by `table` for `duration`, from rest, stuck.
fn belt_events(model: &Model, table: &Table, duration: f64) -> Result<Vec<Event>, String> {
    let mut simulator = Simulator::new(model, Vec::new());
    let inputs: [&dyn Signal; 1] = [table];
    simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(model),
            initial_state: vec![0.0, 0.0],
            duration,
            sample: None,
            audit_energy: false,
        })
        .map(|t: Trajectory| t.events)
        .map_err(|e| e.to_string())
}

/// Item 14: a belt reversing every microsecond at 1 m/s, on the integrated path. The
/// stick-slip spring (`models/examples/nonlinear/stick_slip_spring.ron`) with its hardening
/// `k_3` set to zero is the belt example (`belt_friction.ron`) integrated instead of
/// propagated in closed form: the same events at the same times (to 1e-9 of a
/// microsecond's reversal). Near each reversal the contact's velocity crosses zero while
/// the belt accelerates at 2e6 m/s², too fast for static friction: the stick is declined and
/// the block slips the other way. The crossing's root rounded to a time before it, where the
/// velocity was still -6e-15 m/s; the declined guard was re-armed, found 3e-21 s later (under
/// half the spacing of doubles at 43 µs), and time stood still while the state moved:
/// `time stopped advancing ... whose switch was declined` in the tables that reverse through
/// zero. The example with its hardening runs them too, with the same events.
#[test]
fn a_belt_reversing_every_microsecond_runs_on_the_integrated_path() {
    let linear = load("models/examples/belt_friction.ron");
    let path = "models/examples/nonlinear/stick_slip_spring.ron";
    let hardening = load(path);
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../models/examples/nonlinear/stick_slip_spring.ron"
    ))
    .unwrap();
    let softened = text.replace("\"k_3\": (value: 2.0e4", "\"k_3\": (value: 0.0");
    assert_ne!(softened, text);
    let integrated = model::load_str(path, &softened).unwrap();
    assert!(integrated.is_nonlinear());
    let duration = 1e-4;
    for shape in 0..8 {
        let table = reversing_table(shape, 100);
        let expected = belt_events(&linear, &table, duration)
            .unwrap_or_else(|e| panic!("table {shape}, closed form: {e}"));
        assert!(expected.len() >= 20, "table {shape}: {expected:#?}");
        for (model, name) in [(&integrated, "k_3 = 0"), (&hardening, "k_3 = 2e4")] {
            let events = belt_events(model, &table, duration)
                .unwrap_or_else(|e| panic!("table {shape}, {name}: {e}"));
            assert_eq!(
                events.len(),
                expected.len(),
                "table {shape}, {name}: {events:#?}"
            );
            for (got, want) in events.iter().zip(&expected) {
                assert_eq!(got.to, want.to, "table {shape}, {name}: at {} s", want.t);
                assert!(
                    (got.t - want.t).abs() <= 1e-15,
                    "table {shape}, {name}: {} s against {} s",
                    got.t,
                    want.t
                );
            }
        }
    }
}

/// Item 15: the resolution of time near zero is the smallest subnormal, 4.9e-324 s, not
/// 8.88e-316 s (four ε times a floor of 1e-300). A mass of inertance `m = 1e-154` whose
/// momentum feeds itself through a negative quadratic damper (`dp/dt = (p/m)²`) blows up at
/// `t = m²/p₀ = 1e-308 s` from `p₀ = 1`. Below 2.2e-308 s doubles are subnormal, 4.9e-324 s
/// apart, and the integrator's steps lose their digits there: time stops advancing before
/// the blow-up, and says so with that resolution. (It once stopped at t = 0, its error
/// estimate overflowing on rates of 1e308 N before they were multiplied by the step, and
/// quoted 8.88e-316 s as the resolution there.)
#[test]
fn time_stopping_near_zero_quotes_the_resolution_of_time_there() {
    use bondgraph_solver::{SimError, Stall};
    let text = r#"Model(name: "runaway", parameters: {"m": (value: 1.0e-154)},
    elements: {"v": One, "mass": I(inertance: "m"), "push": R(effort: "-flow^2")},
    bonds: [("v", "mass"), ("v", "push")])"#;
    let model = model::load_str("runaway.ron", text).unwrap_or_else(|e| panic!("{e}"));
    let mut simulator = Simulator::new(&model, Vec::new());
    let error = simulator
        .run(&Run {
            inputs: &[],
            initial_mode: Mode::initial(&model),
            initial_state: vec![1.0],
            duration: 1.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap_err();
    let message = error.to_string();
    match error {
        SimError::Stalled {
            t,
            cause: Stall::Steps { step, resolution },
            ..
        } => {
            assert!(t > 0.0 && t <= 1e-308, "{message}");
            assert_eq!(resolution, f64::from_bits(1), "{message}");
            assert!(step <= 4.0 * resolution, "{message}");
        }
        _ => panic!("{message}"),
    }
    assert!(
        message.contains("the resolution of time there (5e-324 s)"),
        "{message}"
    );
}
