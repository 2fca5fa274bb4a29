//! Velocity-weakening (Stribeck) friction: a block pushed by a constant force, against
//! closed forms derived by hand.
//!
//! The block (m = 1 kg) rests on a contact with F_S = 2 N, F_C = 1 N and a Stribeck velocity
//! v_s = 0.1 m/s: creeping (0 < v < v_s) the contact resists with F_S + (b - (F_S - F_C)/v_s) v
//! = 2 + (b - 10) v, sliding faster with F_C + b v.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_core::source::SourceFile;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Simulator};

fn block(push: f64, viscous: f64) -> Model {
    let text = format!(
        r#"Model(
        name: "stribeck_block",
        parameters: {{
            "m": (value: 1.0), "F": (value: {push:?}), "F_S": (value: 2.0), "F_C": (value: 1.0),
            "b": (value: {viscous:?}), "v_s": (value: 0.1), "dv": (value: 1.0e-9),
        }},
        elements: {{
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C", viscous: "b", dead_band: "dv", stribeck: "v_s"),
        }},
        bonds: [("push", "v"), ("v", "block"), ("v", "contact")],
    )"#
    );
    bondgraph_ron::model::load_str("stribeck_block.ron", &text).unwrap()
}

fn settle(model: &Model) -> bondgraph_solver::steady::Steady {
    let outputs = vec![Output {
        name: "flow:block".into(),
        spec: OutputSpec::parse(model, "flow:block").unwrap(),
        integral: false,
    }];
    let mut simulator = Simulator::new(model, outputs);
    steady_state(
        &mut simulator,
        &[],
        Mode::initial(model),
        vec![0.0],
        &SteadySettings::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn weakening_faster_than_viscosity_grows_runs_away_to_sliding() {
    // F = 3 N > F_S breaks away into creep+ with b = 0.5: m v' = 1 + 9.5 v, unstable, so
    // v(t) = (e^{9.5 t} - 1)/9.5 reaches v_s = 0.1 (plus the dead band's hysteresis, 1e-9)
    // at t₁ = ln(1 + 9.5 (v_s + Δv))/9.5 = 0.0702990... s; sliding, 3 - 1 - 0.5 v = 0 gives
    // v = 4 m/s.
    let steady = settle(&block(3.0, 0.5));
    assert_eq!(steady.mode, "contact=slip+");
    assert!(
        (steady.outputs[0] - 4.0).abs() < 1e-9,
        "{:?}",
        steady.outputs
    );
    let events: Vec<(f64, &str)> = steady.events.iter().map(|e| (e.t, e.to.as_str())).collect();
    assert_eq!(events[0], (0.0, "contact=creep+"), "{events:?}");
    let t1 = (1.0 + 9.5 * (0.1 + 1e-9f64)).ln() / 9.5;
    assert_eq!(events[1].1, "contact=slip+", "{events:?}");
    assert!((events[1].0 - t1).abs() < 1e-9, "{events:?} vs {t1}");
}

#[test]
fn a_search_asked_for_no_events_settles_in_the_same_place() {
    // The runaway block above, its two events not kept: the same steady state, bit for bit.
    let model = block(3.0, 0.5);
    let kept = settle(&model);
    let outputs = vec![Output {
        name: "flow:block".into(),
        spec: OutputSpec::parse(&model, "flow:block").unwrap(),
        integral: false,
    }];
    let quiet = steady_state(
        &mut Simulator::new(&model, outputs),
        &[],
        Mode::initial(&model),
        vec![0.0],
        &SteadySettings {
            events: false,
            ..SteadySettings::default()
        },
    )
    .unwrap();
    assert_eq!(kept.events.len(), 2);
    assert!(quiet.events.is_empty());
    // Sliding at 3 N: 3 - 1 - 0.5 v = 0, v = 4 m/s.
    assert!((quiet.outputs[0] - 4.0).abs() < 1e-9, "{:?}", quiet.outputs);
    assert_eq!((quiet.outputs, quiet.mode), (kept.outputs, kept.mode));
}

#[test]
fn a_light_block_runs_away_to_sliding_within_attoseconds() {
    // The same block with m = 1e-12 kg (the flagship's tip weighs 5e-15 kg), pushed by a
    // force ramped at 100 N/s up to 3 N: it breaks away at F = F_S, t₀ = 0.02 s, and creeping
    // runs away at 9.5/m = 9.5e12 /s, so it reaches the slip speed v_s within a few
    // hundred time constants, 1e-11 s; sliding at 3 N it settles at (3 - 1)/0.5 = 4 m/s.
    // Sampled only on the ramp's scale of milliseconds, the creep read infinity first.
    let text = r#"Model(
        name: "light_stribeck_block",
        parameters: {
            "m": (value: 1.0e-12), "F_S": (value: 2.0), "F_C": (value: 1.0),
            "b": (value: 0.5), "v_s": (value: 0.1), "dv": (value: 1.0e-9),
        },
        inputs: {"F": ()},
        elements: {
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C", viscous: "b", dead_band: "dv", stribeck: "v_s"),
        },
        bonds: [("push", "v"), ("v", "block"), ("v", "contact")],
    )"#;
    let model = SourceFile::new("light_stribeck_block.ron", text.to_string());
    let scenario = bondgraph_ron::scenario::load(
        &SourceFile::new(
            "push.ron",
            r#"Scenario(name: "push", inputs: {"F": Ramp(slope: 100.0, ceiling: 3.0)},
                initial_mode: "contact=stuck", duration: 0.1, record: ["flow:block"],
                sample: 0.01)"#
                .to_string(),
        ),
        &model,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let run = bondgraph_solver::scenario::run(&scenario, false).unwrap_or_else(|e| panic!("{e}"));
    let events: Vec<(f64, &str)> = run.events.iter().map(|e| (e.t, e.to.as_str())).collect();
    assert_eq!(events.len(), 2, "{events:?}");
    assert_eq!(events[0].1, "contact=creep+", "{events:?}");
    assert!((events[0].0 - 0.02).abs() < 1e-15, "{events:?}");
    assert_eq!(events[1].1, "contact=slip+", "{events:?}");
    assert!(events[1].0 - events[0].0 < 1e-11, "{events:?}");
    let last = run.times.len() - 1;
    assert!((run.value(last, 0).unwrap() - 4.0).abs() < 1e-12);
}

#[test]
fn weakening_slower_than_viscosity_grows_creeps_below_the_coulomb_prediction() {
    // F = 2.5 N with b = 20: creeping, 2.5 - 2 - 10 v = 0 gives v = 0.05 m/s < v_s, so it
    // stays in creep+. The Coulomb law alone would give (2.5 - 1)/20 = 0.075 m/s.
    let steady = settle(&block(2.5, 20.0));
    assert_eq!(steady.mode, "contact=creep+");
    assert!(
        (steady.outputs[0] - 0.05).abs() < 1e-9,
        "{:?}",
        steady.outputs
    );
}

#[test]
fn below_breakaway_it_holds() {
    let steady = settle(&block(1.5, 0.5));
    assert_eq!(steady.mode, "contact=stuck");
    assert_eq!(steady.outputs[0], 0.0);
}
