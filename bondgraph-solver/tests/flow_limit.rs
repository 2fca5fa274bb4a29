//! A flow limit: a cart pushed through a damper by a force, its speed capped, against closed
//! forms derived by hand.
//!
//! The cart (m = 2 kg) is pushed by F through a damper b = 4 N·s/m, its speed limited to
//! v_max = 1.5 m/s. Open, m v' = F - b v; limiting, v = v_max and the limit holds back
//! F - b v_max.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Run, Signal, Simulator};

use crate::support::Constant;

const CART: &str = r#"Model(
    name: "limited_cart",
    parameters: {"m": (value: 2.0), "b": (value: 4.0), "v_max": (value: 1.5)},
    inputs: {"F": ()},
    elements: {
        "push": Se(effort: "F"),
        "v": One,
        "cart": I(inertance: "m"),
        "damper": R(resistance: "b"),
        "limit": FlowLimit(max_flow: "v_max"),
    },
    bonds: [("push", "v"), ("v", "cart"), ("v", "damper"), ("v", "limit")],
)"#;

fn cart() -> Model {
    bondgraph_ron::model::load_str("limited_cart.ron", CART).unwrap()
}

fn outputs(model: &Model) -> Vec<Output> {
    ["flow:cart", "effort:limit"]
        .into_iter()
        .map(|name| Output {
            name: name.into(),
            spec: OutputSpec::parse(model, name).unwrap(),
            integral: false,
        })
        .collect()
}

/// `before` until t = 5 s, `after` from then on.
struct Step {
    before: f64,
    after: f64,
}

impl Signal for Step {
    fn value(&self, t: f64) -> f64 {
        if t < 5.0 { self.before } else { self.after }
    }
    fn rate(&self, _: f64) -> f64 {
        0.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![5.0]
    }
}

#[test]
fn the_cart_reaches_the_limit_is_held_there_and_released_when_the_push_drops() {
    // F = 10 N from rest: v(t) = (F/b)(1 - e^{-bt/m}) = 2.5 (1 - e^{-2t}) reaches 1.5 m/s at
    // t₁ = ln(2.5)/2 = 0.4581453659... s; held there, the limit absorbs 10 - 4·1.5 = 4 N.
    // At t = 5 s F drops to 2 N < b v_max: the limit opens and the cart slows towards
    // F/b = 0.5 m/s, v = 0.5 + e^{-2(t - 5)}, so p = m v = 1 + 2e^{-6} at t = 8 s.
    let model = cart();
    let mut simulator = Simulator::new(&model, outputs(&model));
    let push = Step {
        before: 10.0,
        after: 2.0,
    };
    let inputs: [&dyn Signal; 1] = [&push];
    let run = Run {
        inputs: &inputs,
        initial_mode: Mode::initial(&model),
        initial_state: vec![0.0],
        duration: 8.0,
        sample: Some(0.5),
        audit_energy: true,
    };
    let trajectory = simulator.run(&run).unwrap();
    let events: Vec<(f64, &str, &str)> = trajectory
        .events
        .iter()
        .map(|e| (e.t, e.to.as_str(), e.reason.as_str()))
        .collect();
    assert_eq!(events.len(), 2, "{events:?}");
    let t1 = 2.5f64.ln() / 2.0;
    assert!((events[0].0 - t1).abs() < 1e-12, "{events:?} vs {t1}");
    assert_eq!(events[0].1, "limit=limiting");
    assert_eq!(events[0].2, "flow reached its limit");
    assert_eq!((events[1].0, events[1].1), (5.0, "limit=open"));
    assert_eq!(events[1].2, "restraining effort fell to zero");
    // Sampled at t = 2 s (held at the limit): v = 1.5, restraining effort 4 N.
    let held = trajectory.row(4).unwrap();
    assert!((held[0] - 1.5).abs() < 1e-12, "{held:?}");
    assert!((held[1] - 4.0).abs() < 1e-12, "{held:?}");
    let p = trajectory.final_state[0].1;
    let expected = 1.0 + 2.0 * (-6.0f64).exp();
    assert!((p - expected).abs() < 1e-12, "p = {p}, expected {expected}");
    // Power in = kinetic energy + damper + what the limit absorbed.
    let energy = trajectory.energy.unwrap();
    assert!(
        energy.residual().abs() <= 1e-9 * energy.scale(),
        "{energy:?}"
    );
}

#[test]
fn started_limiting_without_a_push_to_hold_back_it_opens_at_once() {
    // F = 5 N < b v_max = 6 N: limiting would take a negative restraining effort (-1 N),
    // so the run opens at t = 0 and settles at F/b = 1.25 m/s.
    let model = cart();
    let mut simulator = Simulator::new(&model, outputs(&model));
    let settled = steady_state(
        &mut simulator,
        &[5.0],
        Mode::parse(&model, "limit=limiting").unwrap(),
        vec![3.0],
        &SteadySettings::default(),
    )
    .unwrap();
    assert_eq!(settled.mode, "limit=open");
    assert_eq!(settled.events[0].t, 0.0, "{:?}", settled.events);
    assert!((settled.outputs[0] - 1.25).abs() < 1e-12, "{settled:?}");
    assert_eq!(settled.outputs[1], 0.0);
}

#[test]
fn a_push_beyond_the_limit_settles_limiting() {
    // F = 10 N would give 2.5 m/s: held at 1.5 m/s, the limit holding back 4 N.
    let model = cart();
    let mut simulator = Simulator::new(&model, outputs(&model));
    let settled = steady_state(
        &mut simulator,
        &[10.0],
        Mode::initial(&model),
        vec![0.0],
        &SteadySettings::default(),
    )
    .unwrap();
    assert_eq!(settled.mode, "limit=limiting");
    assert!((settled.outputs[0] - 1.5).abs() < 1e-12, "{settled:?}");
    assert!((settled.outputs[1] - 4.0).abs() < 1e-12, "{settled:?}");
}

#[test]
fn a_nearly_massless_body_leaves_the_limit_once_without_chattering() {
    // A body of 1e-17 kg (it follows its force balance within m/b = 2.5e-18 s, less than
    // the spacing of doubles at t = 0.27 s, like the robot's tip) pushed by F = 10 N through
    // b = 4 N·s/m against a spring k = 10 N/m, its speed capped at 1.5 m/s. It reaches the
    // cap at once; limiting, the spring stretches at 1.5 m/s and the restraining effort
    // F - b v_max - k x falls to zero at x* = 0.4 m, t* = 0.4/1.5 s. There the flow only
    // touches the limit, its rate and sign decided by rounding: the limit must open once
    // and stay open (not re-enter limiting, not stall on crossings of rounding noise), and
    // the body creep on, x = 1 - 0.6 e^{-k (t - t*)/b}.
    let model = bondgraph_ron::model::load_str(
        "sprung.ron",
        r#"Model(
            name: "sprung",
            parameters: {"m": (value: 1.0e-17), "b": (value: 4.0), "k": (value: 10.0), "v_max": (value: 1.5)},
            inputs: {"F": ()},
            elements: {
                "push": Se(effort: "F"), "v": One, "body": I(inertance: "m"),
                "damper": R(resistance: "b"), "spring": C(stiffness: "k"),
                "limit": FlowLimit(max_flow: "v_max"),
            },
            bonds: [("push", "v"), ("v", "body"), ("v", "damper"), ("v", "spring"), ("v", "limit")],
        )"#,
    )
    .unwrap();
    let mut simulator = Simulator::new(&model, Vec::new());
    let push = Constant(10.0);
    let inputs: [&dyn Signal; 1] = [&push];
    let run = Run {
        inputs: &inputs,
        initial_mode: Mode::initial(&model),
        initial_state: vec![0.0, 0.0],
        duration: 1.0,
        sample: None,
        audit_energy: false,
    };
    let trajectory = simulator.run(&run).unwrap_or_else(|e| panic!("{e}"));
    let modes: Vec<&str> = trajectory.events.iter().map(|e| e.to.as_str()).collect();
    assert_eq!(
        modes,
        ["limit=limiting", "limit=open"],
        "{:?}",
        trajectory.events
    );
    assert!(trajectory.events[0].t < 1e-10, "{:?}", trajectory.events);
    let t_star = 0.4 / 1.5;
    assert!(
        (trajectory.events[1].t - t_star).abs() < 1e-9,
        "{:?}",
        trajectory.events
    );
    let x = trajectory.final_state[1].1;
    let expected = 1.0 - 0.6 * (-2.5 * (1.0 - t_star)).exp();
    assert!((x - expected).abs() < 1e-9, "x = {x}, expected {expected}");
}
