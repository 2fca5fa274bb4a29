//! A Stribeck velocity of zero: no creeping range, so the contact is a Karnopp contact with
//! the same breakaway and Coulomb forces; and as the Stribeck velocity shrinks towards zero
//! the motion converges to that one.
//!
//! The block (m = 1 kg) rests on a contact with F_S = 2 N, F_C = 1 N, no viscous part and no
//! dead band, pushed by F(t) = 3t N up to 3 N at t = 1 s, held to t = 2 s, let go linearly to
//! 0 at t = 2.5 s. By hand (Karnopp): it breaks away when F = F_S, at t = 2/3 s; sliding,
//! v' = F - F_C, so
//!
//! - v = 1.5 (t² - 4/9) - (t - 2/3) up to t = 1 s (v = 0.5 m/s there),
//! - v = 0.5 + 2 (t - 1) up to t = 2 s (2.5 m/s),
//! - v = 2.5 + 2 τ - 3 τ², τ = t - 2, up to t = 2.5 s (2.75 m/s),
//! - v = 2.75 - (t - 2.5) until it stops at t = 5.25 s, where F = 0 < F_S holds it.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_core::scenario::Signal as Table;
use bondgraph_solver::{Output, Run, Signal, Simulator, Trajectory};

/// The block on a contact whose `Friction(...)` fields after the forces are `stribeck`
/// (`None`: a Karnopp contact), with `v_s` the parameter's value.
fn block(stribeck: Option<&str>, v_s: f64) -> Model {
    let stribeck = stribeck.map_or(String::new(), |s| format!(", stribeck: \"{s}\""));
    let text = format!(
        r#"Model(
        name: "block",
        parameters: {{
            "m": (value: 1.0), "F_S": (value: 2.0), "F_C": (value: 1.0), "v_s": (value: {v_s:?}),
        }},
        inputs: {{"F": ()}},
        elements: {{
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C"{stribeck}),
        }},
        bonds: [("push", "v"), ("v", "block"), ("v", "contact")],
    )"#
    );
    bondgraph_ron::model::load_str("block.ron", &text).unwrap_or_else(|e| panic!("{e}"))
}

fn push() -> Table {
    Table::Table(vec![(0.0, 0.0), (1.0, 3.0), (2.0, 3.0), (2.5, 0.0)])
}

/// The block's velocity by hand (see the module doc).
fn by_hand(t: f64) -> f64 {
    let t0 = 2.0 / 3.0;
    if t < t0 {
        0.0
    } else if t <= 1.0 {
        1.5 * (t * t - t0 * t0) - (t - t0)
    } else if t <= 2.0 {
        0.5 + 2.0 * (t - 1.0)
    } else if t <= 2.5 {
        let tau = t - 2.0;
        2.5 + 2.0 * tau - 3.0 * tau * tau
    } else if t <= 5.25 {
        2.75 - (t - 2.5)
    } else {
        0.0
    }
}

fn simulator(model: &Model) -> Simulator<'_> {
    let outputs = vec![Output {
        name: "flow:block".into(),
        spec: OutputSpec::parse(model, "flow:block").unwrap(),
        integral: false,
    }];
    Simulator::new(model, outputs)
}

fn run(simulator: &mut Simulator<'_>) -> Trajectory {
    let signal = push();
    let inputs: [&dyn Signal; 1] = [&signal];
    let model = simulator.model();
    simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(model),
            initial_state: vec![0.0],
            duration: 6.0,
            sample: Some(0.01),
            audit_energy: false,
        })
        .unwrap_or_else(|e| panic!("{e}"))
}

fn events(trajectory: &Trajectory) -> Vec<(f64, String)> {
    trajectory
        .events
        .iter()
        .map(|e| (e.t, e.to.clone()))
        .collect()
}

/// The largest difference between two trajectories' samples (the same sample times).
fn largest_difference(a: &Trajectory, b: &Trajectory) -> f64 {
    assert_eq!(a.times, b.times);
    a.values
        .iter()
        .zip(&b.values)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The largest difference between a trajectory and the velocity by hand.
fn error_by_hand(trajectory: &Trajectory) -> f64 {
    trajectory
        .times
        .iter()
        .zip(&trajectory.values)
        .map(|(&t, &v)| (v - by_hand(t)).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_zero_stribeck_velocity_is_the_karnopp_contact() {
    let karnopp_model = block(None, 0.0);
    let karnopp = run(&mut simulator(&karnopp_model));
    let expected = [
        (2.0 / 3.0, "contact=slip+".to_string()),
        (5.25, "contact=stuck".to_string()),
    ];
    let found = events(&karnopp);
    assert_eq!(found.len(), 2, "{found:?}");
    for ((t, to), (t_hand, to_hand)) in found.iter().zip(&expected) {
        assert_eq!(to, to_hand, "{found:?}");
        assert!((t - t_hand).abs() < 1e-12, "{found:?}");
    }
    assert!(
        error_by_hand(&karnopp) < 1e-12,
        "{}",
        error_by_hand(&karnopp)
    );

    // A parameter at zero and a literal zero: the same events and samples.
    for stribeck in ["v_s", "0"] {
        let model = block(Some(stribeck), 0.0);
        let zero = run(&mut simulator(&model));
        assert_eq!(events(&zero), found, "stribeck: \"{stribeck}\"");
        assert!(
            largest_difference(&zero, &karnopp) < 1e-15,
            "stribeck: \"{stribeck}\": {}",
            largest_difference(&zero, &karnopp)
        );
    }
}

/// How far a contact with Stribeck velocity `v_s` lags the Karnopp one after breaking away:
/// `(T, D)`, the time it creeps and the speed it is then behind.
///
/// At breakaway F - F_S = 3τ, so creeping (force F_S - v/v_s) the block obeys
/// v' = 3τ + v/v_s from rest: v = 3 v_s² (e^σ - 1 - σ), σ = τ/v_s, which reaches v_s at
/// e^σ - 1 - σ = 1/(3 v_s) (solved here by Newton's method), T = σ v_s. The Karnopp block
/// (v' = 1 + 3τ) is then at T + 1.5 T², so D = T + 1.5 T² - v_s, about v_s ln(1/(3 v_s)).
fn creep_lag(v_s: f64) -> (f64, f64) {
    let target = 1.0 / (3.0 * v_s);
    let mut sigma = target.ln().max(1.0);
    for _ in 0..100 {
        let step = (sigma.exp() - 1.0 - sigma - target) / (sigma.exp() - 1.0);
        sigma -= step;
        if step.abs() < 1e-15 * sigma {
            break;
        }
    }
    let t = sigma * v_s;
    (t, t + 1.5 * t * t - v_s)
}

/// The samples two trajectories share (the same time), as pairs of values.
fn shared_samples(a: &Trajectory, b: &Trajectory) -> Vec<(f64, f64, f64)> {
    a.times
        .iter()
        .zip(&a.values)
        .filter_map(|(&t, &x)| {
            let k = b.times.iter().position(|&s| s == t)?;
            Some((t, x, b.values[k]))
        })
        .collect()
}

/// Checks a run with Stribeck velocity `v_s` against the motion by hand and the run at zero.
///
/// Sliding, both blocks obey v' = F - F_C, so the lag D stays until the Stribeck block
/// slows to v_s, at t₁ = 5.25 - v_s - D (the Karnopp block then at v_s + D); creeping to rest
/// (v' = -F_S + v/v_s: v = 2 v_s - v_s e^{τ/v_s}) it stops v_s ln 2 later. The two differ by D
/// while sliding and by at most D + v_s (1 - ln 2) anywhere.
fn check_against_zero(creeping: &Trajectory, at_zero: &Trajectory, v_s: f64) {
    let (creep, lag) = creep_lag(v_s);
    let t1 = 5.25 - v_s - lag;
    let expected = [
        (2.0 / 3.0, "contact=creep+"),
        (2.0 / 3.0 + creep, "contact=slip+"),
        (t1, "contact=creep+"),
        (t1 + v_s * std::f64::consts::LN_2, "contact=stuck"),
    ];
    let found = events(creeping);
    assert_eq!(found.len(), expected.len(), "v_s = {v_s}: {found:?}");
    for ((t, to), (t_hand, to_hand)) in found.iter().zip(expected) {
        assert_eq!(to, to_hand, "v_s = {v_s}: {found:?}");
        assert!(
            (t - t_hand).abs() < 1e-12,
            "v_s = {v_s}: {to} at {t}, by hand {t_hand}"
        );
    }
    let shared = shared_samples(creeping, at_zero);
    assert!(shared.len() >= 600, "v_s = {v_s}: {} shared", shared.len());
    let bound = lag + v_s * (1.0 - std::f64::consts::LN_2);
    for (t, v, zero) in shared {
        assert!(
            zero - v >= -1e-12 && zero - v <= bound + 1e-12,
            "v_s = {v_s}: at t = {t} v = {v}, at zero {zero}, bound {bound}"
        );
        if (1.0..5.0).contains(&t) {
            assert!(
                ((zero - v) - lag).abs() < 1e-12,
                "v_s = {v_s}: at t = {t} behind by {}, by hand {lag}",
                zero - v
            );
        }
    }
}

#[test]
fn a_shrinking_stribeck_velocity_converges_to_the_karnopp_motion() {
    let model = block(Some("v_s"), 0.0);
    let mut simulator = simulator(&model);
    let at_zero = run(&mut simulator);
    assert!(error_by_hand(&at_zero) < 1e-12);
    let speed = 2.75; // the motion's top speed
    for scale in [1e-3, 1e-5, 1e-7] {
        let v_s = scale * speed;
        // The same checked model, its Stribeck velocity set as a fit sets a trial value.
        simulator
            .set_parameter_values(&[1.0, 2.0, 1.0, v_s])
            .unwrap();
        check_against_zero(&run(&mut simulator), &at_zero, v_s);
    }
    // Back at zero, the same motion as before the trials.
    simulator
        .set_parameter_values(&[1.0, 2.0, 1.0, 0.0])
        .unwrap();
    let again = run(&mut simulator);
    assert_eq!(events(&again), events(&at_zero));
    assert_eq!(again.values, at_zero.values);
}

#[test]
fn a_tiny_stribeck_velocity_is_stiff_but_exact() {
    // v_s = 1e-12 m/s: creeping runs away at (F_S - F_C)/(m v_s) = 1e12 /s; the creep lasts
    // T = 2.6e-11 s and leaves the block D = 2.5e-11 m/s behind, as by hand.
    let model = block(Some("v_s"), 1e-12);
    let tiny = run(&mut simulator(&model));
    let at_zero = run(&mut simulator(&block(Some("v_s"), 0.0)));
    check_against_zero(&tiny, &at_zero, 1e-12);
}

/// The block with a quadratic drag as well (a nonlinear resistor), so that its modes are
/// integrated rather than propagated.
fn dragged_block(stribeck: Option<&str>) -> Model {
    let stribeck = stribeck.map_or(String::new(), |s| format!(", stribeck: \"{s}\""));
    let text = format!(
        r#"Model(
        name: "dragged_block",
        parameters: {{
            "m": (value: 1.0), "F_S": (value: 2.0), "F_C": (value: 1.0), "v_s": (value: 0.0),
            "c": (value: 0.1),
        }},
        inputs: {{"F": ()}},
        elements: {{
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "drag": R(effort: "c*flow*abs(flow)"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C"{stribeck}),
        }},
        bonds: [("push", "v"), ("v", "block"), ("v", "drag"), ("v", "contact")],
    )"#
    );
    bondgraph_ron::model::load_str("dragged_block.ron", &text).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_zero_stribeck_velocity_in_a_nonlinear_model_is_the_karnopp_contact() {
    // The same push: the drag slows the slide, but it still breaks away at t = 2/3 s (at
    // rest the drag is zero) and comes to rest after the push ends. The Karnopp model's run
    // is the reference.
    let karnopp_model = dragged_block(None);
    assert!(karnopp_model.is_nonlinear());
    let karnopp = run(&mut simulator(&karnopp_model));
    let found = events(&karnopp);
    let modes: Vec<&str> = found.iter().map(|(_, to)| to.as_str()).collect();
    assert_eq!(modes, ["contact=slip+", "contact=stuck"], "{found:?}");
    assert!((found[0].0 - 2.0 / 3.0).abs() < 1e-12, "{found:?}");
    // (`held_nonlinear.rs` checks this run against an independent reference.)
    let model = dragged_block(Some("v_s"));
    let zero = run(&mut simulator(&model));
    assert_eq!(events(&zero), found);
    assert!(largest_difference(&zero, &karnopp) < 1e-15);
}

/// The actuator example and the same with its guide replaced by the library's Stribeck
/// extension (`stribeck: "v_s"`, v_s = 0 as shipped).
fn actuator_and_stribeck_extension() -> (Model, Model) {
    use bondgraph_core::source::SourceFile;
    use bondgraph_ron::extension::{Extension, merge};
    let folder =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/examples/actuator");
    let path = folder.join("actuator.ron");
    let base = SourceFile::new(
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    );
    let extension = Extension::read(&folder.join("extensions/stribeck-weakening.ron"))
        .unwrap_or_else(|e| panic!("{e}"));
    let extended = merge(&base, &[extension])
        .and_then(|merged| merged.load())
        .unwrap_or_else(|e| panic!("{e}"));
    (bondgraph_ron::model::load_source(&base).unwrap(), extended)
}

/// The actuator from rest, 6 V from 10 ms on against no load (its `step.ron`).
fn actuator_step(model: &Model) -> Trajectory {
    let outputs = ["flow:carriage", "flow:winding_inductance"]
        .into_iter()
        .map(|spec| Output {
            name: spec.into(),
            spec: OutputSpec::parse(model, spec).unwrap(),
            integral: false,
        })
        .collect();
    let mut simulator = Simulator::new(model, outputs);
    let voltage = Table::Step {
        at: 0.01,
        before: 0.0,
        after: 6.0,
    };
    let load = Table::Constant(0.0);
    let inputs: [&dyn Signal; 2] = [&voltage, &load];
    let state = vec![0.0; simulator.storage().len()];
    simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::parse(model, "guide=stuck").unwrap(),
            initial_state: state,
            duration: 0.3,
            sample: Some(0.001),
            audit_energy: false,
        })
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_actuator_with_a_zero_stribeck_velocity_runs_as_its_base() {
    // The guide breaks away when the motor's force reaches F_S = 12 N and slides: the
    // Karnopp base model's run is the reference, event for event and sample for sample.
    let (base, stribeck) = actuator_and_stribeck_extension();
    let expected = actuator_step(&base);
    let found = actuator_step(&stribeck);
    let modes: Vec<String> = events(&expected).into_iter().map(|(_, to)| to).collect();
    assert_eq!(modes[0], "guide=slip+", "{modes:?}");
    assert_eq!(events(&found), events(&expected));
    assert_eq!(found.times, expected.times);
    for (x, y) in found.values.iter().zip(&expected.values) {
        assert!((x - y).abs() <= 1e-12 * y.abs().max(1e-3), "{x} vs {y}");
    }
}
