//! Steady states continued to nearby parameter values: the equilibrium a simulation would
//! settle in, against closed forms and fresh searches, and refused where the branch cannot
//! be vouched for.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::continuation::{continue_branch, continue_steady};
use bondgraph_solver::steady::{Steady, SteadySettings, steady_state};
use bondgraph_solver::{Output, Simulator};

use crate::support::{DOUBLE_WELL, load};

fn simulator<'m>(model: &'m Model, outputs: &[&str]) -> Simulator<'m> {
    let outputs = outputs
        .iter()
        .map(|o| Output {
            name: o.to_string(),
            spec: OutputSpec::parse(model, o).unwrap(),
            integral: false,
        })
        .collect();
    Simulator::new(model, outputs)
}

fn settle(simulator: &mut Simulator<'_>, inputs: &[f64], start: &[(&str, f64)]) -> Steady {
    let names = simulator.storage().names.clone();
    let mut state = vec![0.0; names.len()];
    for (name, value) in start {
        state[names.iter().position(|n| n == name).unwrap()] = *value;
    }
    let mode = Mode::initial(simulator.model());
    steady_state(simulator, inputs, mode, state, &SteadySettings::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The model's values with `name` set to `value`.
fn with_value(model: &Model, name: &str, value: f64) -> Vec<f64> {
    let mut values = model.values().to_vec();
    let parameter = model.parameters().iter().find(|p| p.name == name).unwrap();
    values[parameter.symbol.index()] = value;
    values
}

/// The two-tank rig filled from empty at Q = 30 mL/s settles where the orifice passes the
/// pump's flow: `p₂ = (Q/c_d)²`, `p₁ = p₂ + R₁₂ Q`. Continued from `c_d = 1.5e-6` to
/// `c_d (1 + 1e-5)` (a forward-difference step of a fit), the equilibrium is the closed form
/// at the new value and what a fresh search from empty tanks finds, without simulating.
#[test]
fn the_two_tank_is_continued_to_the_closed_form_at_a_nearby_orifice() {
    let model = load("models/examples/two_tank/two_tank.ron");
    let outputs = ["effort:tank_1", "effort:tank_2", "flow:outlet"];
    let mut simulator = simulator(&model, &outputs);
    let q = 30e-6;
    let first = settle(&mut simulator, &[q], &[]);
    let anchor = first
        .anchor
        .clone()
        .expect("an equilibrium reached with no event");
    assert!(first.work.steps > 100, "{:?}", first.work);

    let (c_d, r_12) = (1.5e-6 * (1.0 + 1e-5), 5.0e6);
    simulator
        .set_parameter_values(&with_value(&model, "c_d", c_d))
        .unwrap();
    let continued = continue_steady(&mut simulator, &anchor, &SteadySettings::default())
        .expect("a nearby equilibrium on the same branch");
    assert_eq!(continued.work.steps, 0);
    assert!(continued.anchor.is_none(), "only searches make anchors");
    let p2 = (q / c_d) * (q / c_d);
    let expected = [p2 + r_12 * q, p2, q];
    for (got, want) in continued.outputs.iter().zip(&expected) {
        assert!((got - want).abs() <= 1e-12 * want, "{got} against {want}");
    }
    let fresh = settle(&mut simulator, &[q], &[]);
    for (a, b) in continued.outputs.iter().zip(&fresh.outputs) {
        assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} against {b}");
    }
    assert_eq!(continued.mode, fresh.mode);
}

/// The double well ([`DOUBLE_WELL`]) pushed from `q = 0` with `p = 2.2` settles in the left
/// well, `q = -√(k/k₃) = -1` (`steady_polish.rs`). Continued to `k (1 + 1e-4)`, its bottom
/// moves to `-√(k/k₃)`; continued to `4 k` it would move to `q = -2`, a move of its whole
/// scale: refused (the search must say where the trajectory goes, not Newton's method).
#[test]
fn a_well_is_followed_a_hair_and_refused_a_leap() {
    let model = bondgraph_ron::model::load_str("double_well.ron", DOUBLE_WELL).unwrap();
    let mut simulator = simulator(&model, &["effort:spring"]);
    let first = settle(&mut simulator, &[], &[("p_mass", 2.2)]);
    let anchor = first.anchor.clone().expect("a stable equilibrium");
    let index = |name: &str| {
        let names = &simulator.storage().names;
        names.iter().position(|n| n == name).unwrap()
    };
    let q_index = index("q_spring");
    assert!(
        (first.state[q_index] + 1.0).abs() < 1e-12,
        "{:?}",
        first.state
    );

    let k = 1.0 + 1e-4;
    simulator
        .set_parameter_values(&with_value(&model, "k", k))
        .unwrap();
    let near = continue_steady(&mut simulator, &anchor, &SteadySettings::default()).unwrap();
    let expected = -k.sqrt();
    assert!(
        (near.state[q_index] - expected).abs() < 1e-14,
        "{} against {expected}",
        near.state[q_index]
    );

    simulator
        .set_parameter_values(&with_value(&model, "k", 4.0))
        .unwrap();
    assert!(continue_steady(&mut simulator, &anchor, &SteadySettings::default()).is_none());
}

/// A mass pulled through a damper (`F = 3 N`, `b = 2 N s/m`) settles at `v = F/b` in a
/// linear mode with no guards, reached without an event: an anchor that is not
/// path-dependent, continued to `b (1 + 1e-5)` exactly (the asymptote of the mode at the new
/// value, no iteration), where a fresh search finds the same.
#[test]
fn a_linear_mode_is_continued_to_its_asymptote_at_nearby_values() {
    let linear = bondgraph_ron::model::load_str(
        "drag.ron",
        r#"Model(
            name: "drag",
            parameters: { "m": (value: 1.0, unit: "kg"), "b": (value: 2.0, unit: "N*s/m") },
            inputs: { "F": (unit: "N") },
            elements: { "pull": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
                        "damper": R(resistance: "b") },
            bonds: [("pull", "v"), ("v", "mass"), ("v", "damper")],
        )"#,
    )
    .unwrap();
    let mut simulator = self::simulator(&linear, &["flow:mass"]);
    let steady = settle(&mut simulator, &[3.0], &[]);
    assert!((steady.outputs[0] - 1.5).abs() < 1e-12);
    let anchor = steady
        .anchor
        .expect("the asymptote of a stable linear mode");
    assert!(!anchor.path_dependent);

    let b = 2.0 * (1.0 + 1e-5);
    simulator
        .set_parameter_values(&with_value(&linear, "b", b))
        .unwrap();
    let continued = continue_steady(&mut simulator, &anchor, &SteadySettings::default())
        .expect("the same mode, stable");
    assert_eq!(continued.work.steps, 0);
    assert!(
        (continued.outputs[0] - 3.0 / b).abs() <= 1e-15 * 1.5,
        "{:?}",
        continued.outputs
    );
    let fresh = settle(&mut simulator, &[3.0], &[]);
    assert!((fresh.outputs[0] - continued.outputs[0]).abs() <= 1e-15 * 1.5);
}

/// A damper pushed at a constant speed through a spring in series (`Sf`, a one-junction):
/// the spring's compression is an integrator (`q̇ = v`, eigenvalue zero) whose value at the
/// steady motion depends on how long the push has lasted. The damper's force, `b v`, reads
/// none of it: an anchor, continued to `b (1 + 1e-5)`. The spring's force reads it: no
/// anchor where it is an output, for what it reads is where the path left it.
#[test]
fn a_linear_anchor_needs_outputs_that_read_no_integrator() {
    let pushed = bondgraph_ron::model::load_str(
        "pushed.ron",
        r#"Model(
            name: "pushed",
            parameters: { "k": (value: 50.0, unit: "N/m"), "b": (value: 4.0, unit: "N*s/m") },
            inputs: { "v": (unit: "m/s") },
            elements: { "push": Sf(flow: "v"), "joint": One, "spring": C(compliance: "1/k"),
                        "damper": R(resistance: "b") },
            bonds: [("push", "joint"), ("joint", "spring"), ("joint", "damper")],
        )"#,
    )
    .unwrap();
    let mut damper_only = self::simulator(&pushed, &["effort:damper"]);
    let steady = settle(&mut damper_only, &[0.2], &[("q_spring", 0.01)]);
    assert!(
        (steady.outputs[0] - 0.8).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
    let anchor = steady.anchor.expect("the damper reads no integrator");
    let b = 4.0 * (1.0 + 1e-5);
    damper_only
        .set_parameter_values(&with_value(&pushed, "b", b))
        .unwrap();
    let continued = continue_steady(&mut damper_only, &anchor, &SteadySettings::default())
        .expect("the same mode");
    assert!((continued.outputs[0] - b * 0.2).abs() <= 1e-15 * 0.8);

    let mut with_spring = self::simulator(&pushed, &["effort:damper", "effort:spring"]);
    let steady = settle(&mut with_spring, &[0.2], &[("q_spring", 0.01)]);
    assert!(steady.anchor.is_none(), "{:?}", steady.anchor);
}

/// A block carried by a belt (0.1 m/s) on a hardening spring, damped: it sticks until the
/// spring pulls F_S = 10 N, breaks away, and comes to rest slipping where the spring holds
/// the Coulomb force, `k q + k₃ q³ = F_C = 6 N`: a stable equilibrium of a nonlinear mode,
/// reached after a mode change, so a path-dependent anchor: not continued to new trial
/// values, and continued for a difference to `k q + k₃ q³ = F_C (1 + 1e-5)`, what a fresh
/// search finds there. (The stuck mode's rates do not depend on the state, `q̇ = v_belt`; the
/// search once took that for steady motion and ended at t = 0 with the spring slack, the
/// guard it drifts into unseen.)
#[test]
fn a_block_carried_into_its_breakaway_settles_slipping_and_is_continued_only_for_a_difference() {
    let belt = bondgraph_ron::model::load_str("belt.ron", BELT).unwrap();
    let mut simulator = self::simulator(&belt, &["effort:spring"]);
    let names = simulator.storage().names.clone();
    let steady = steady_state(
        &mut simulator,
        &[0.1],
        Mode::initial(&belt),
        vec![0.0; names.len()],
        &SteadySettings::default(),
    )
    .unwrap();
    assert!(
        (steady.outputs[0] - 6.0).abs() < 1e-9,
        "{:?}",
        steady.outputs
    );
    assert!(steady.mode.contains("slip"), "{}", steady.mode);
    let anchor = steady.anchor.expect("a polished equilibrium");
    assert!(anchor.path_dependent);

    let f_c = 6.0 * (1.0 + 1e-5);
    simulator
        .set_parameter_values(&with_value(&belt, "F_C", f_c))
        .unwrap();
    let settings = SteadySettings::default();
    assert!(continue_steady(&mut simulator, &anchor, &settings).is_none());
    let branch = continue_branch(&mut simulator, &anchor, &settings).expect("still slipping");
    assert_eq!(branch.work.steps, 0);
    assert!(
        (branch.outputs[0] - f_c).abs() < 1e-12 * f_c,
        "{:?}",
        branch.outputs
    );
    let fresh = steady_state(
        &mut simulator,
        &[0.1],
        Mode::initial(&belt),
        vec![0.0; names.len()],
        &settings,
    )
    .unwrap();
    assert!((fresh.outputs[0] - branch.outputs[0]).abs() < 1e-12 * f_c);
    assert_eq!(fresh.mode, branch.mode);
}

const BELT: &str = r#"Model(
            name: "belt",
            parameters: {
                "m": (value: 1.0, unit: "kg"), "k": (value: 100.0, unit: "N/m"),
                "k_3": (value: 2.0e4, unit: "N/m^3"), "b": (value: 20.0, unit: "N*s/m"),
                "F_S": (value: 10.0, unit: "N"), "F_C": (value: 6.0, unit: "N"),
            },
            inputs: { "v_belt": (unit: "m/s") },
            elements: {
                "belt": Sf(flow: "v_belt"), "contact": Zero,
                "friction": Friction(breakaway: "F_S", coulomb: "F_C", initial: "stuck"),
                "v_block": One, "block": I(inertance: "m"),
                "spring": C(effort: "k*q_spring + k_3*q_spring^3"), "damper": R(resistance: "b"),
            },
            bonds: [("belt", "contact"), ("contact", "friction"), ("contact", "v_block"),
                    ("v_block", "block"), ("v_block", "spring"), ("v_block", "damper")],
        )"#;

/// [`BELT`] with a linear spring (`k₃` written out of the law), overdamped: the block breaks away
/// and settles slipping where `k q = F_C = 6 N`, the asymptote of a linear mode reached
/// after a mode change, its modes guarded: a path-dependent anchor, not continued to new
/// trial values, continued for a difference to `F_C (1 + 1e-5)` exactly, what a fresh
/// search finds there.
#[test]
fn a_linear_mode_reached_through_a_breakaway_is_continued_only_for_a_difference() {
    // b = 20 N s/m would damp the linear spring critically (b² = 4 m k), a defective matrix
    // whose asymptote the modal form does not give; 25 N s/m is overdamped.
    let linear = BELT
        .replace("k*q_spring + k_3*q_spring^3", "k*q_spring")
        .replace("\"b\": (value: 20.0", "\"b\": (value: 25.0");
    let belt = bondgraph_ron::model::load_str("linear_belt.ron", &linear).unwrap();
    let mut simulator = self::simulator(&belt, &["effort:spring"]);
    let names = simulator.storage().names.clone();
    let settings = SteadySettings::default();
    let start = || vec![0.0; names.len()];
    let steady = steady_state(
        &mut simulator,
        &[0.1],
        Mode::initial(&belt),
        start(),
        &settings,
    )
    .unwrap();
    assert!(
        (steady.outputs[0] - 6.0).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
    assert!(steady.mode.contains("slip"), "{}", steady.mode);
    let anchor = steady
        .anchor
        .expect("the asymptote of a stable linear mode");
    assert!(anchor.path_dependent);

    let f_c = 6.0 * (1.0 + 1e-5);
    simulator
        .set_parameter_values(&with_value(&belt, "F_C", f_c))
        .unwrap();
    assert!(continue_steady(&mut simulator, &anchor, &settings).is_none());
    let branch = continue_branch(&mut simulator, &anchor, &settings).expect("still slipping");
    assert_eq!(branch.work.steps, 0);
    assert!(
        (branch.outputs[0] - f_c).abs() < 1e-14 * f_c,
        "{:?}",
        branch.outputs
    );
    let fresh = steady_state(
        &mut simulator,
        &[0.1],
        Mode::initial(&belt),
        start(),
        &settings,
    )
    .unwrap();
    assert!((fresh.outputs[0] - branch.outputs[0]).abs() < 1e-14 * f_c);
    assert_eq!(fresh.mode, branch.mode);
}

/// A motor held by static friction, its winding's resistance nonlinear (a brush drop
/// `U_b tanh(i/i_0)` beside `R i`): the current settles at a stable equilibrium of the stuck
/// mode, `R i + U_b tanh(i/i_0) = V`, with no mode change, but the mode has a guard (the
/// breakaway), so its anchor is path-dependent. Whether a transient reaches that guard
/// depends on the parameters along the whole path, not at the equilibrium: continuing such
/// rows to trial values once gave a stuck contact where a fresh search breaks away. For a
/// difference it is continued, and refused where its guard has changed sign.
#[test]
fn a_mode_with_guards_is_continued_only_for_a_difference() {
    let motor = bondgraph_ron::model::load_str(
        "held_motor.ron",
        r#"Model(
            name: "held_motor",
            parameters: {
                "R": (value: 1.2, unit: "ohm"), "L": (value: 4.0e-4, unit: "H"),
                "U_b": (value: 0.25, unit: "V"), "i_0": (value: 0.01, unit: "A"),
                "K": (value: 0.03, unit: "N*m/A"), "J": (value: 1.5e-5, unit: "kg*m^2"),
                "T_S": (value: 0.05, unit: "N*m"), "T_C": (value: 0.03, unit: "N*m"),
            },
            inputs: { "V": (unit: "V") },
            elements: {
                "supply": Se(effort: "V"), "armature": One,
                "winding": R(effort: "R*flow + U_b*tanh(flow/i_0)"),
                "inductance": I(inertance: "L"), "motor": GY(ratio: "K"),
                "rotor": One, "inertia": I(inertance: "J"),
                "bearing": Friction(breakaway: "T_S", coulomb: "T_C", initial: "stuck"),
            },
            bonds: [("supply", "armature"), ("armature", "winding"),
                    ("armature", "inductance"), ("armature", "motor"), ("motor", "rotor"),
                    ("rotor", "inertia"), ("rotor", "bearing")],
        )"#,
    )
    .unwrap();
    let mut simulator = self::simulator(&motor, &["flow:winding"]);
    let steady = settle(&mut simulator, &[1.0], &[]);
    assert_eq!(steady.mode, "bearing=stuck");
    // R i + U_b tanh(i/i_0) = 1 V: i = 0.625 A (tanh(62.5) = 1 to rounding), holding
    // K i = 0.01875 N m < T_S.
    let i = steady.outputs[0];
    assert!((i - 0.625).abs() < 1e-12, "{i}");
    let anchor = steady.anchor.expect("a polished equilibrium");
    assert!(anchor.path_dependent);

    // U_b (1 + 1e-5): i = (1 V - U_b)/R to rounding.
    let u_b = 0.25 * (1.0 + 1e-5);
    simulator
        .set_parameter_values(&with_value(&motor, "U_b", u_b))
        .unwrap();
    let settings = SteadySettings::default();
    assert!(continue_steady(&mut simulator, &anchor, &settings).is_none());
    let branch = continue_branch(&mut simulator, &anchor, &settings).expect("still held");
    let expected = (1.0 - u_b) / 1.2;
    assert!(
        (branch.outputs[0] - expected).abs() < 1e-12,
        "{} against {expected}",
        branch.outputs[0]
    );
    // A breakaway torque below the holding torque K i = 0.01875 N m: the stuck branch's
    // guard has changed sign, and the continuation is refused.
    let mut values = with_value(&motor, "T_S", 0.0187);
    let t_c = motor.parameters().iter().find(|p| p.name == "T_C").unwrap();
    values[t_c.symbol.index()] = 0.0187;
    simulator.set_parameter_values(&values).unwrap();
    assert!(continue_branch(&mut simulator, &anchor, &settings).is_none());
}
