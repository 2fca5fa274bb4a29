//! Numerical trouble is detected and reported with the elements involved.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Run, Settings, Signal, SimError, Simulator};

use crate::support::{Constant, load};

/// An input that stops being a number after `at` seconds.
struct Broken {
    at: f64,
}

impl Signal for Broken {
    fn value(&self, t: f64) -> f64 {
        if t < self.at { 1.0 } else { f64::NAN }
    }
    fn rate(&self, _: f64) -> f64 {
        0.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.at]
    }
}

#[test]
fn chattering_is_detected_and_names_the_element() {
    // The belt's stick-slip cycle has two events per period of about 1.16 s (see
    // stick_slip.rs); with a limit of 3 events in any window of 10 s that is chattering.
    let model = load("models/examples/belt_friction.ron");
    let mut simulator = Simulator::new(&model, Vec::new()).with_settings(Settings {
        max_events: 1000,
        chatter_events: 3,
        chatter_window: 10.0,
        ..Settings::default()
    });
    let belt = Constant(0.1);
    let inputs: [&dyn Signal; 1] = [&belt];
    let error = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.1, 0.0],
            duration: 10.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap_err();
    match &error {
        SimError::Chattering {
            events,
            elements,
            t,
            ..
        } => {
            assert_eq!(*events, 3);
            assert_eq!(elements, &["friction"]);
            // The third event: breakaway at 1 s, stick at 1.363 s, breakaway at 2.163 s.
            assert!((t - (1.8 + (std::f64::consts::PI - 4f64.atan()) / 5.0)).abs() < 1e-9);
        }
        other => panic!("expected chattering, got {other}"),
    }
    assert!(error.to_string().contains("'friction'"), "{error}");
}

#[test]
fn non_finite_states_are_detected_and_named() {
    let model = load("models/examples/mass_spring_damper.ron");
    let mut simulator = Simulator::new(&model, Vec::new());
    let force = Broken { at: 0.5 };
    let inputs: [&dyn Signal; 1] = [&force];
    let error = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0, 0.0],
            duration: 1.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap_err();
    match &error {
        SimError::NonFinite { t, states, .. } => {
            assert!(*t >= 0.5 && *t <= 1.0, "{t}");
            assert_eq!(states, &["p_mass", "q_spring"]);
        }
        other => panic!("expected non-finite states, got {other}"),
    }
}

/// A velocity falling at 1 m/s² from 1 m/s.
struct Falling;

impl Signal for Falling {
    fn value(&self, t: f64) -> f64 {
        1.0 - t
    }
    fn rate(&self, _: f64) -> f64 {
        -1.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }
}

#[test]
fn a_contact_whose_velocity_is_imposed_slips_through_zero() {
    // A friction contact driven by a velocity source against the ground can never stick
    // (sticking would impose a second velocity on its bond): when the source slows through
    // zero at t = 1 s the contact passes from slip+ to slip-.
    let text = r#"Model(
        name: "driven_contact",
        parameters: {"F_S": (value: 2.0), "F_C": (value: 1.0), "b": (value: 0.5)},
        inputs: {"v": ()},
        elements: {
            "drive": Sf(flow: "v"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C", viscous: "b", initial: "slip+"),
        },
        bonds: [("drive", "contact")],
    )"#;
    let model = bondgraph_ron::model::load_str("driven_contact.ron", text).unwrap();
    let mut simulator = Simulator::new(&model, Vec::new());
    let inputs: [&dyn Signal; 1] = [&Falling];
    let trajectory = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![],
            duration: 2.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap();
    assert_eq!(trajectory.events.len(), 1, "{:#?}", trajectory.events);
    assert!((trajectory.events[0].t - 1.0).abs() < 1e-12);
    assert_eq!(trajectory.events[0].to, "contact=slip-");
}

#[test]
fn no_consistent_mode_is_reported_with_the_modes_tried() {
    // A block pushed by 3 N on a contact whose Coulomb force grows with an input past its
    // breakaway force (F_C = u, F_S = 2): at u = 4 N the stuck block's holding force, 3 N,
    // exceeds F_S, so it must slip; but slipping forward, F_C = 4 N > 3 N decelerates it back
    // through zero, and slipping backward it is pushed forward again. No mode holds: the
    // data violates F_S >= F_C, which the validator can only check for constant forces.
    let text = r#"Model(
        name: "inconsistent_friction",
        parameters: {"m": (value: 1.0), "F_S": (value: 2.0), "F": (value: 3.0)},
        inputs: {"u": ()},
        elements: {
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "contact": Friction(breakaway: "F_S", coulomb: "u"),
        },
        bonds: [("push", "v"), ("v", "block"), ("v", "contact")],
    )"#;
    let model = bondgraph_ron::model::load_str("inconsistent.ron", text).unwrap();
    let mut simulator = Simulator::new(&model, Vec::new());
    let coulomb = Constant(4.0);
    let inputs: [&dyn Signal; 1] = [&coulomb];
    let error = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0],
            duration: 1.0,
            sample: None,
            audit_energy: false,
        })
        .unwrap_err();
    match &error {
        SimError::NoConsistentMode { t, tried, elements } => {
            assert_eq!(*t, 0.0);
            assert!(tried.contains(&"contact=slip+".to_string()), "{tried:?}");
            assert!(tried.contains(&"contact=slip-".to_string()), "{tried:?}");
            assert_eq!(elements, &["contact"]);
        }
        other => panic!("expected no consistent mode, got {other}"),
    }
}

#[test]
fn two_contacts_that_cannot_hold_alone_break_away_together() {
    // A light body pushed by F = 13 N rests on a nozzle contact (F_S = 11.5 N, F_C = 0,
    // viscous b = 2000 N·s/m) and carries a load through a second contact (F_S = 6 N,
    // F_C = 5.5 N); the load is held back by a damper R = 5e4 N·s/m. Neither contact can
    // hold alone: all stuck, the nozzle must hold all 13 N; nozzle slipping, the second
    // contact must pass all 13 N to the load. Switching one contact at a time sends them round
    // in a circle (each looks as if it could stick again while its velocity is still in the
    // dead band); both slip. Steady state by hand: the body obeys F - F_C2 - b v = 0,
    // v = 7.5/2000 = 3.75 mm/s; the load F_C2 = R w, w = 0.11 mm/s < v, so the second
    // contact keeps slipping forward.
    let text = r#"Model(
        name: "two_contacts",
        parameters: {
            "m": (value: 1.0e-12), "F": (value: 13.0),
            "F_S1": (value: 11.5), "F_C1": (value: 0.0), "b": (value: 2000.0),
            "F_S2": (value: 6.0), "F_C2": (value: 5.5),
            "m_2": (value: 5.0e-4), "R": (value: 5.0e4), "dv": (value: 1.0e-6),
        },
        elements: {
            "push": Se(effort: "F"),
            "body": One,
            "mass": I(inertance: "m"),
            "nozzle": Friction(breakaway: "F_S1", coulomb: "F_C1", viscous: "b", dead_band: "dv"),
            "rubbing": Zero,
            "contact": Friction(breakaway: "F_S2", coulomb: "F_C2", dead_band: "dv"),
            "carried": One,
            "load": I(inertance: "m_2"),
            "damper": R(resistance: "R"),
        },
        bonds: [
            ("push", "body"), ("body", "mass"), ("body", "nozzle"), ("body", "rubbing"),
            ("rubbing", "contact"), ("rubbing", "carried"), ("carried", "load"),
            ("carried", "damper"),
        ],
    )"#;
    let model = bondgraph_ron::model::load_str("two_contacts.ron", text).unwrap();
    let outputs = ["flow:mass", "flow:load"]
        .iter()
        .map(|name| Output {
            name: name.to_string(),
            spec: OutputSpec::parse(&model, name).unwrap(),
            integral: false,
        })
        .collect();
    let mut simulator = Simulator::new(&model, outputs);
    let n = simulator.storage().len();
    let steady = steady_state(
        &mut simulator,
        &[],
        Mode::initial(&model),
        vec![0.0; n],
        &SteadySettings::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(steady.mode, "nozzle=slip+,contact=slip+");
    assert!(
        (steady.outputs[0] - 3.75e-3).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
    assert!(
        (steady.outputs[1] - 1.1e-4).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
    // Found at once, at t = 0, not after a detour through a wrong mode.
    let last = steady.events.last().unwrap();
    assert_eq!(
        (last.t, last.to.as_str()),
        (0.0, "nozzle=slip+,contact=slip+"),
        "{:#?}",
        steady.events
    );
}
