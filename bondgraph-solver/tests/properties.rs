//! Property tests on randomly generated valid switching models (issue 12, item 17): a mass on
//! a Karnopp friction contact, a mass on a tension-only string, a cart behind a flow limit,
//! with random positive parameters in sane ranges and random constant or step forces, each
//! simulated with its energy books kept. Invariants:
//!
//! - **Energy**: supplied = stored + dissipated + lost at events, to 1e-9 of the largest
//!   term. Within a mode the books are quadratures of the same closed form as the states, and
//!   the textbook models balance to that tolerance (`energy.rs`), so 1e-9 leaves six orders
//!   of magnitude above rounding and is far below any physical error (a lost sticking impact
//!   or a wrong dissipation is a few per cent).
//! - **Guards**: at every sample the recorded mode agrees with the signs of the recorded
//!   quantities (a stuck contact does not move and holds at most `F_S`, a slipping one moves
//!   its way; a taut string is stretched, a slack one is not; an open limit is below its
//!   flow, a limiting one at it, holding back a positive effort), to 1e-9 of the quantity's
//!   scale: no guard is left violated after an event.
//! - **Errors**: a run that fails returns a [`SimError`] (the properties would catch a
//!   panic); a valid model never fails on its derivation or its inputs.
//!
//! The case counts keep the suite to a few seconds with the workspace's `[profile.test]`.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::{self, Model};
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Signal, SimError, Simulator, Trajectory};
use proptest::prelude::*;

/// A force: `before` until `at`, `after` from then on (a constant when they are equal).
#[derive(Clone, Copy, Debug)]
struct Force {
    before: f64,
    after: f64,
    at: f64,
}

impl Signal for Force {
    fn value(&self, t: f64) -> f64 {
        if t < self.at { self.before } else { self.after }
    }
    fn rate(&self, _: f64) -> f64 {
        0.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.at]
    }
}

const DURATION: f64 = 2.0;
const SAMPLE: f64 = 1.0e-3;
const TOLERANCE: f64 = 1e-9;

/// A constant force, or a step at a time off the sampling grid.
fn force() -> impl Strategy<Value = Force> {
    (-40.0..40.0f64, -40.0..40.0f64, 0.1..1.9f64, any::<bool>()).prop_map(
        |(before, after, at, step)| Force {
            before,
            after: if step { after } else { before },
            at: (at / SAMPLE).floor() * SAMPLE + 0.37 * SAMPLE,
        },
    )
}

fn load(name: &str, text: &str) -> Model {
    model::load_str(name, text).unwrap_or_else(|e| panic!("{name}:\n{e}\n{text}"))
}

/// Simulates `model` under `force` from `state`, recording `outputs`, with the energy books.
fn simulate(
    model: &Model,
    outputs: &[&str],
    force: Force,
    state: Vec<f64>,
) -> Result<Trajectory, SimError> {
    let outputs = outputs
        .iter()
        .map(|name| Output {
            name: (*name).into(),
            spec: OutputSpec::parse(model, name).unwrap(),
            integral: false,
        })
        .collect();
    let mut simulator = Simulator::new(model, outputs);
    let inputs: [&dyn Signal; 1] = [&force];
    let result = simulator.run(&Run {
        inputs: &inputs,
        initial_mode: Mode::initial(model),
        initial_state: state,
        duration: DURATION,
        sample: Some(SAMPLE),
        audit_energy: true,
    });
    if let Err(error) = &result {
        assert!(
            !matches!(error, SimError::Derivation(_) | SimError::Inputs(_)),
            "a valid model failed: {error}"
        );
        assert!(!error.to_string().is_empty());
    }
    result
}

/// The energy books balance to [`TOLERANCE`] of their largest term.
fn check_energy(trajectory: &Trajectory) -> Result<(), TestCaseError> {
    let energy = trajectory.energy.expect("audited");
    prop_assert!(
        energy.residual().abs() <= TOLERANCE * energy.scale(),
        "residual {} of {:?}",
        energy.residual(),
        energy
    );
    Ok(())
}

/// The largest magnitude of output `j` over the run (at least `floor`).
fn scale(trajectory: &Trajectory, j: usize, floor: f64) -> f64 {
    (0..trajectory.times.len())
        .filter_map(|k| trajectory.value(k, j))
        .fold(floor, |m, v| m.max(v.abs()))
}

/// Each sample's mode with its time and outputs, but for a sample at the force's step: it
/// is recorded as the left limit there (the mode and outputs before the step), while the
/// force is right-continuous, so the two cannot be compared.
fn samples(trajectory: &Trajectory, force: Force) -> impl Iterator<Item = (f64, &str, &[f64])> {
    (0..trajectory.times.len())
        .filter(move |k| trajectory.times[*k] != force.at)
        .map(|k| {
            (
                trajectory.times[k],
                trajectory.modes[trajectory.sample_modes[k]].as_str(),
                trajectory.row(k).unwrap(),
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// A mass `m` on a spring `k` to the wall, pushed by `F`, on a Karnopp contact with the
    /// ground (`F_S >= F_C`, viscous `b`), released from a random stretch and speed.
    #[test]
    fn friction_contacts_keep_their_books_and_their_guards(
        m in 0.1..10.0f64, k in 1.0..1000.0f64, coulomb in 0.1..10.0f64,
        excess in 1.0..2.0f64, b in 0.0..2.0f64, force in force(),
        q0 in -0.2..0.2f64, p0 in -1.0..1.0f64, stuck in any::<bool>(),
    ) {
        let breakaway = coulomb * excess;
        let initial = if stuck { "stuck" } else if p0 >= 0.0 { "slip+" } else { "slip-" };
        let text = format!(r#"Model(name: "contact",
    parameters: {{"m": (value: {m:e}), "k": (value: {k:e}), "F_S": (value: {breakaway:e}),
        "F_C": (value: {coulomb:e}), "b": (value: {b:e})}},
    inputs: {{"F": ()}},
    elements: {{"push": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
        "spring": C(stiffness: "k"),
        "contact": Friction(breakaway: "F_S", coulomb: "F_C", viscous: "b", initial: "{initial}")}},
    bonds: [("push", "v"), ("v", "mass"), ("v", "spring"), ("v", "contact")])"#);
        let model = load("contact.ron", &text);
        let p0 = if stuck { 0.0 } else { p0 };
        let Ok(trajectory) = simulate(&model, &["flow:mass", "effort:spring"], force, vec![p0, q0])
        else {
            return Ok(());
        };
        check_energy(&trajectory)?;
        let v_scale = TOLERANCE * scale(&trajectory, 0, 1e-12);
        let f_scale = TOLERANCE * scale(&trajectory, 1, breakaway).max(40.0);
        for (t, mode, row) in samples(&trajectory, force) {
            let (v, spring) = (row[0], row[1]);
            let holding = force.value(t) - spring;
            match mode {
                "contact=stuck" => {
                    prop_assert!(v.abs() <= v_scale, "t = {t}: stuck at v = {v}");
                    prop_assert!(holding.abs() <= breakaway + f_scale,
                        "t = {t}: stuck holding {holding} past F_S = {breakaway}");
                }
                "contact=slip+" => prop_assert!(v >= -v_scale, "t = {t}: slip+ at v = {v}"),
                "contact=slip-" => prop_assert!(v <= v_scale, "t = {t}: slip- at v = {v}"),
                other => prop_assert!(false, "mode {other}"),
            }
        }
    }

    /// A mass pushed by `F` through a damper `b`, tied by a tension-only string `k`.
    ///
    /// It found `hardening::a_string_pulled_back_from_slack_goes_taut_every_time`.
    #[test]
    fn strings_keep_their_books_and_their_guards(
        m in 0.1..10.0f64, k in 1.0..1000.0f64, b in 0.0..5.0f64, force in force(),
        q0 in -0.2..0.2f64, p0 in -1.0..1.0f64,
    ) {
        let initial = if q0 >= 0.0 { "taut" } else { "slack" };
        let text = format!(r#"Model(name: "tether",
    parameters: {{"m": (value: {m:e}), "k": (value: {k:e}), "b": (value: {b:e})}},
    inputs: {{"F": ()}},
    elements: {{"push": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
        "damper": R(resistance: "b"), "string": TensionOnly(stiffness: "k", initial: "{initial}")}},
    bonds: [("push", "v"), ("v", "mass"), ("v", "damper"), ("v", "string")])"#);
        let model = load("tether.ron", &text);
        let Ok(trajectory) =
            simulate(&model, &["effort:string", "flow:mass"], force, vec![p0, q0])
        else {
            return Ok(());
        };
        check_energy(&trajectory)?;
        let f_scale = TOLERANCE * scale(&trajectory, 0, k * 0.2);
        for (t, mode, row) in samples(&trajectory, force) {
            let tension = row[0];
            match mode {
                "string=taut" => prop_assert!(tension >= -f_scale, "t = {t}: taut pushing {tension}"),
                "string=slack" => prop_assert!(tension.abs() <= f_scale, "t = {t}: slack pulling {tension}"),
                other => prop_assert!(false, "mode {other}"),
            }
        }
    }

    /// A cart `m` pushed by `F` through a damper `b`, its speed capped at `v_max`.
    #[test]
    fn flow_limits_keep_their_books_and_their_guards(
        m in 0.1..10.0f64, b in 0.1..5.0f64, v_max in 0.1..5.0f64, force in force(),
        fraction in -1.0..1.0f64,
    ) {
        let text = format!(r#"Model(name: "limited",
    parameters: {{"m": (value: {m:e}), "b": (value: {b:e}), "v_max": (value: {v_max:e})}},
    inputs: {{"F": ()}},
    elements: {{"push": Se(effort: "F"), "v": One, "cart": I(inertance: "m"),
        "damper": R(resistance: "b"), "limit": FlowLimit(max_flow: "v_max")}},
    bonds: [("push", "v"), ("v", "cart"), ("v", "damper"), ("v", "limit")])"#);
        let model = load("limited.ron", &text);
        let p0 = fraction * v_max * m;
        let Ok(trajectory) = simulate(&model, &["flow:cart", "effort:limit"], force, vec![p0])
        else {
            return Ok(());
        };
        check_energy(&trajectory)?;
        let v_scale = TOLERANCE * v_max;
        let f_scale = TOLERANCE * scale(&trajectory, 1, 40.0);
        for (t, mode, row) in samples(&trajectory, force) {
            let (v, held) = (row[0], row[1]);
            let holding = force.value(t) - b * v_max;
            match mode {
                "limit=open" => prop_assert!(v <= v_max + v_scale, "t = {t}: open at {v} > {v_max}"),
                "limit=limiting" => {
                    prop_assert!((v - v_max).abs() <= v_scale, "t = {t}: limiting at {v}");
                    prop_assert!(holding >= -f_scale, "t = {t}: limiting holds {holding} ({held})");
                }
                other => prop_assert!(false, "mode {other}"),
            }
        }
    }
}
