//! Hardening of time stepping, sampling and events (issue 30, third round; issue 37): each
//! test failed before its fix.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
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
    let integrated = bondgraph_ron::model::load_str(path, &softened).unwrap();
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
    let model =
        bondgraph_ron::model::load_str("runaway.ron", text).unwrap_or_else(|e| panic!("{e}"));
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

/// The geared motor (`models/examples/geared_motor/geared_motor.ron`) with frictionless
/// bearings (`T_S = T_C = 0`, their dead band kept at 1e-6 rad/s) and `K = 0.05 N·m/A`, so
/// that 1 V against a brake of 0.5 N·m is an exact balance at rest: the stall torque
/// `N K V/R_a = 20 · 0.05 · 1/2` is 0.5 N·m.
fn motor_at_balance() -> Model {
    let path = "models/examples/geared_motor/geared_motor.ron";
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(path),
    )
    .unwrap();
    let mut edited = text.clone();
    for (from, to) in [
        ("\"K\": (value: 0.04,", "\"K\": (value: 0.05,"),
        ("\"T_S\": (value: 0.25,", "\"T_S\": (value: 0.0,"),
        ("\"T_C\": (value: 0.2,", "\"T_C\": (value: 0.0,"),
    ] {
        assert!(edited.contains(from), "{from}");
        edited = edited.replace(from, to);
    }
    bondgraph_ron::model::load_str(path, &edited).unwrap_or_else(|e| panic!("{e}"))
}

/// The motor at balance driven by `brake` (N·m) at 1 V for 5 s from `state` (`p` of the
/// winding, `p` of the load), stuck.
fn run_motor(model: &Model, brake: &dyn Signal, state: Vec<f64>) -> Trajectory {
    let volts = Constant(1.0);
    let inputs: [&dyn Signal; 2] = [&volts, brake];
    Simulator::new(model, Vec::new())
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(model),
            initial_state: state,
            duration: 5.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The current `i = p/L_a` and speed `w = p/J` at the end of a motor run.
fn current_and_speed(trajectory: &Trajectory) -> (f64, f64) {
    let state: Vec<f64> = trajectory.final_state.iter().map(|(_, v)| *v).collect();
    (state[0] / 0.003, state[1] / 0.01)
}

/// Item 13 (issue 37, item 6): a contact with zero breakaway at exact force balance once
/// chattered (stuck -> slip -> stuck every few tens of microseconds, 100 000 events by
/// 2.3 s), each switch set off by rounding: the holding force, exactly zero at balance, read
/// ±1e-17 N·m, and the contact broke away and stuck again at the same instant.
///
/// From rest the motor draws no current yet, so the brake turns the shaft backwards at once
/// (`slip-` at t = 0). Frictionless, `(i, w)` then follow `di/dt = (V - R_a i - K N w)/L_a`,
/// `dw/dt = (K N i - b w - τ)/J`, eigenvalues -56.64 and -612.03 /s: `w = -0.0900 (e^{-56.64
/// t} - e^{-612.03 t})`, negative for every t > 0, tends to zero and `i` to 0.5 A. Once the
/// speed is at rounding level the contact may stick (it is in its dead band and holds zero
/// force), but nothing more happens: at most the breakaway and one stick (two switches at one
/// instant), and at 5 s the motor is at rest at 0.5 A.
#[test]
fn a_contact_at_exact_balance_with_zero_breakaway_does_not_chatter() {
    let model = motor_at_balance();
    let trajectory = run_motor(&model, &Constant(0.5), vec![0.0, 0.0]);
    let events = &trajectory.events;
    assert!(!events.is_empty() && events.len() <= 3, "{events:#?}");
    assert_eq!(
        (events[0].t, events[0].to.as_str()),
        (0.0, "bearings=slip-")
    );
    let (i, w) = current_and_speed(&trajectory);
    assert!((i - 0.5).abs() <= 1e-12, "i = {i}");
    assert!(w.abs() <= 1e-12, "w = {w}");
}

/// Item 13: started at the balance (0.5 A, at rest) the contact is stuck and stays so: a
/// Karnopp contact holds a force within its breakaway force, here zero within rounding, and no
/// event happens in 5 s.
#[test]
fn a_contact_started_at_exact_balance_stays_stuck() {
    let model = motor_at_balance();
    let trajectory = run_motor(&model, &Constant(0.5), vec![0.5 * 0.003, 0.0]);
    assert!(trajectory.events.is_empty(), "{:#?}", trajectory.events);
    assert_eq!(trajectory.final_mode, "bearings=stuck");
    let (i, w) = current_and_speed(&trajectory);
    assert!((i - 0.5).abs() <= 1e-12, "i = {i}");
    assert_eq!(w, 0.0);
}

/// Item 13: a contact resting at balance still breaks away when the balance goes: the brake
/// eases to 0.4 N·m at 1 s, the shaft turns forwards at once and settles where the motor's
/// torque, less the brake, meets the viscous and back-EMF losses:
/// `w = (N K V/R_a - τ)/(b + (N K)²/R_a) = 0.1/0.52 rad/s`, `i = (V - N K w)/R_a`.
#[test]
fn a_contact_resting_at_balance_breaks_away_when_the_balance_goes() {
    let model = motor_at_balance();
    let brake = Table::Step {
        at: 1.0,
        before: 0.5,
        after: 0.4,
    };
    let trajectory = run_motor(&model, &brake, vec![0.5 * 0.003, 0.0]);
    let events: Vec<(f64, &str)> = trajectory
        .events
        .iter()
        .map(|e| (e.t, e.to.as_str()))
        .collect();
    assert_eq!(events, [(1.0, "bearings=slip+")]);
    let (i, w) = current_and_speed(&trajectory);
    let speed = 0.1 / 0.52;
    assert!((w - speed).abs() <= 1e-12, "w = {w}");
    assert!((i - (1.0 - speed) / 2.0).abs() <= 1e-12, "i = {i}");
}

/// Item 13: switching faster than the motion can move is chattering, whatever the time: a
/// number of switches in a row with the inputs steady, closer on average than the fastest
/// time scale of the modes they enter. The belt (`belt_friction.ron` at 0.1 m/s, see
/// `stick_slip.rs`) slips at ω = 10 rad/s, a time scale of 0.1 s (stuck, it has none): it
/// breaks away at 1 s, sticks `s = (π - atan 4)/5` later and breaks away again at 1.8 + s,
/// three switches in 0.8 + s = 1.16 s. Three switches closer than ten time scales each (3 s)
/// are chattering at the third, named with the time scale and the last reason; closer than
/// one (0.3 s, the default factor) they are not, and the cycle runs its 20 s.
#[test]
fn switching_faster_than_the_modes_time_scales_is_chattering() {
    use bondgraph_solver::{Settings, SimError};
    let model = load("models/examples/belt_friction.ron");
    let belt = Constant(0.1);
    let inputs: [&dyn Signal; 1] = [&belt];
    let run = |factor: f64| {
        Simulator::new(&model, Vec::new())
            .with_settings(Settings {
                chatter_events: 3,
                chatter_time_scales: factor,
                ..Settings::default()
            })
            .run(&Run {
                inputs: &inputs,
                initial_mode: Mode::initial(&model),
                initial_state: vec![0.0, 0.0],
                duration: 20.0,
                sample: None,
                audit_energy: false,
            })
    };
    let slip = (std::f64::consts::PI - 4f64.atan()) / 5.0;
    let error = run(10.0).unwrap_err();
    let message = error.to_string();
    match &error {
        SimError::Chattering {
            t,
            events,
            window,
            elements,
            time_scale,
            ..
        } => {
            assert_eq!(*events, 3);
            assert!((t - (1.8 + slip)).abs() < 1e-9, "{message}");
            assert!((window - (0.8 + slip)).abs() < 1e-9, "{message}");
            assert_eq!(elements, &["friction"]);
            assert!((time_scale.unwrap() - 0.1).abs() < 1e-12, "{message}");
        }
        _ => panic!("{message}"),
    }
    assert!(
        message.contains("faster than the modes' fastest time scale (1e-1 s)")
            && message.contains(
                "switching 'friction' (the last: holding force reached the breakaway force)"
            ),
        "{message}"
    );
    let trajectory = run(1.0).unwrap_or_else(|e| panic!("{e}"));
    assert!(trajectory.events.len() > 20, "{:#?}", trajectory.events);
}

/// The Duffing oscillator (`models/examples/nonlinear/duffing.ron`) with its damper seen
/// through a transformer of ratio `r = 1e-154`: the mass is damped at
/// `b/(r² m) = 0.1/1e-308 = 1e307 /s`, a time scale of 1e-307 s. Its steps once crawled
/// (1e-260 s at t = 1e-255 s) to the limit of steps; Radau IIA with RADAU5's step control
/// takes the transient in its stride. Then the damper holds the spring's force: by hand,
/// the velocity is `-(k q + k_3 q³) r²/b = -18.375·1e-308/0.1 = -1.8375e-306` m/s, the spring
/// creeping 4e-305 m in 20 s.
#[test]
fn a_damper_seen_through_a_lever_of_1e_minus_154_holds_the_spring_at_its_creep() {
    let text = r#"Model(name: "duffing_lever",
    parameters: {"m": (value: 1.0), "k": (value: 1.0), "k_3": (value: 5.0), "b": (value: 0.1),
        "r": (value: 1.0e-154)},
    inputs: {"F": ()},
    elements: {"force": Se(effort: "F"), "v": One, "lever": TF(ratio: "r"), "w": One,
        "mass": I(inertance: "m"), "spring": C(effort: "k*q_spring + k_3*q_spring^3"),
        "damper": R(resistance: "b")},
    bonds: [("force", "v"), ("v", "lever"), ("lever", "w"), ("w", "mass"), ("w", "spring"),
        ("v", "damper")])"#;
    let model =
        bondgraph_ron::model::load_str("duffing_lever.ron", text).unwrap_or_else(|e| panic!("{e}"));
    let force = Constant(0.0);
    let inputs: [&dyn Signal; 1] = [&force];
    let outputs = vec![output(&model, "flow:mass"), output(&model, "effort:spring")];
    let trajectory = Simulator::new(&model, outputs)
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0, 1.5],
            duration: 20.0,
            sample: Some(5.0),
            audit_energy: false,
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let last = trajectory.values.len() - 2;
    let (velocity, spring) = (trajectory.values[last], trajectory.values[last + 1]);
    assert!(
        (velocity / -1.8375e-306 - 1.0).abs() < 1e-12,
        "{velocity:e}"
    );
    assert_eq!(spring, 1.5 + 5.0 * 1.5f64.powi(3));
}

/// A run's budget of steps is seconds of work, and its message names the time scale that
/// made the steps small. A Duffing oscillator of 1e-12 kg swings at
/// `ω = √((k + 3 k_3 q²)/m)`, between 1e6 and 5.9e6 rad/s for `|q| <= 1.5`: 20 s are
/// about 10^7 swings, more than the million steps a run may take by default.
#[test]
fn a_run_of_crawling_steps_stops_within_seconds_naming_its_time_scale() {
    use bondgraph_solver::{Settings, SimError};
    assert_eq!(Settings::default().max_steps, 1_000_000);
    let text = r#"Model(name: "fast_duffing",
    parameters: {"m": (value: 1.0e-12), "k": (value: 1.0), "k_3": (value: 5.0)},
    inputs: {"F": ()},
    elements: {"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
        "spring": C(effort: "k*q_spring + k_3*q_spring^3")},
    bonds: [("force", "v"), ("v", "mass"), ("v", "spring")])"#;
    let model =
        bondgraph_ron::model::load_str("fast_duffing.ron", text).unwrap_or_else(|e| panic!("{e}"));
    let force = Constant(0.0);
    let inputs: [&dyn Signal; 1] = [&force];
    let error = Simulator::new(&model, Vec::new())
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0, 1.5],
            duration: 20.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap_err();
    let message = error.to_string();
    match &error {
        SimError::TooManySteps {
            t,
            limit,
            step,
            time_scale,
        } => {
            assert_eq!(*limit, 1_000_000);
            assert!(*t < 20.0, "{message}");
            // Steps of a fraction of a swing.
            assert!(step.is_some_and(|s| s < 1e-6), "{message}");
            let scale = time_scale.as_ref().expect("a time scale");
            let (fastest, slowest) = (1.0 / (34.75e12f64).sqrt(), 1e-6);
            assert!(
                scale.seconds >= fastest * (1.0 - 1e-9) && scale.seconds <= slowest * (1.0 + 1e-9),
                "{message}"
            );
            assert_eq!(scale.states, ["p_mass", "q_spring"]);
        }
        _ => panic!("{message}"),
    }
    assert!(
        message.contains("the duration is too long for the model's time scales"),
        "{message}"
    );
}
