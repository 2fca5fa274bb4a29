//! Property tests on randomly generated valid switching models (issue 12, item 17): a mass on
//! a Karnopp friction contact, a mass on a tension-only string, a cart behind a flow limit,
//! with random positive parameters in sane ranges and random constant, step or ramp forces,
//! each simulated with its energy books kept. Invariants:
//!
//! - **Energy**: supplied = stored + dissipated + lost at events, to 1e-9 of the largest
//!   term. Within a mode the books are closed-form integrals of the same modal solution as
//!   the states, and the textbook models balance to that tolerance (`energy.rs`), so 1e-9
//!   leaves six orders of magnitude above rounding and is far below any physical error (a
//!   lost sticking impact or a wrong dissipation is a few per cent).
//! - **Guards**: at every sample, and at every event's instant in the mode it settled in, the
//!   recorded mode agrees with the signs of the recorded quantities (a stuck contact does not
//!   move and holds at most `F_S`, a slipping one moves its way; a taut string is stretched
//!   and pulls, a slack one is not stretched; an open limit is below its flow, a limiting one
//!   at it, holding back a positive effort), to 1e-9 of the quantity's scale: no guard is
//!   left violated after an event. A slack string carries no tension whatever its state, so
//!   its extension is checked: the integral of its flow from its initial extension.
//! - **Errors**: a run that fails returns a [`SimError`] (the properties would catch a
//!   panic) whose message names a time or an element; a valid model never fails on its
//!   derivation or its inputs.
//!
//! The case counts keep the suite to a few seconds with the workspace's `[profile.test]`.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Signal, SimError, Simulator, Trajectory};
use proptest::prelude::*;

/// A force: `before` until `at`, then `after + slope (t - at)`: a constant, a step, or a
/// ramp (continuous, `after = before`, from `at`).
#[derive(Clone, Copy, Debug)]
struct Force {
    before: f64,
    after: f64,
    slope: f64,
    at: f64,
}

impl Signal for Force {
    fn value(&self, t: f64) -> f64 {
        if t < self.at {
            self.before
        } else {
            self.after + self.slope * (t - self.at)
        }
    }
    fn rate(&self, t: f64) -> f64 {
        if t < self.at { 0.0 } else { self.slope }
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.at]
    }
}

impl Force {
    /// The largest magnitude over the run.
    fn largest(&self) -> f64 {
        let end = self.after + self.slope * (DURATION - self.at);
        self.before.abs().max(self.after.abs()).max(end.abs())
    }
}

const DURATION: f64 = 2.0;
const SAMPLE: f64 = 1.0e-3;
const TOLERANCE: f64 = 1e-9;

/// A constant force, a step, or a ramp from a constant, at a time off the sampling grid.
fn force() -> impl Strategy<Value = Force> {
    (
        -40.0..40.0f64,
        -40.0..40.0f64,
        -20.0..20.0f64,
        0.1..1.9f64,
        0..3u8,
    )
        .prop_map(|(before, after, slope, at, kind)| Force {
            before,
            after: if kind == 1 { after } else { before },
            slope: if kind == 2 { slope } else { 0.0 },
            at: (at / SAMPLE).floor() * SAMPLE + 0.37 * SAMPLE,
        })
}

fn load(name: &str, text: &str) -> Model {
    bondgraph_ron::model::load_str(name, text).unwrap_or_else(|e| panic!("{name}:\n{e}\n{text}"))
}

/// Simulates `model` under `force` from `state`, recording `outputs` (an `integral:` prefix
/// records an output's time integral), with the energy books. A run that fails must say
/// when, or which of `elements` (by name).
fn simulate(
    model: &Model,
    outputs: &[&str],
    force: Force,
    state: Vec<f64>,
    elements: &[&str],
) -> Result<Option<Trajectory>, TestCaseError> {
    let outputs = outputs
        .iter()
        .map(|name| {
            let (integral, spec) = match name.strip_prefix("integral:") {
                Some(spec) => (true, spec),
                None => (false, *name),
            };
            Output {
                name: (*name).into(),
                spec: OutputSpec::parse(model, spec).unwrap(),
                integral,
            }
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
    match result {
        Ok(trajectory) => Ok(Some(trajectory)),
        Err(error) => {
            prop_assert!(
                !matches!(error, SimError::Derivation(_) | SimError::Inputs(_)),
                "a valid model failed: {error}"
            );
            let message = error.to_string();
            prop_assert!(
                message.contains("t = ")
                    || elements.iter().any(|e| message.contains(&format!("'{e}'"))),
                "the error names neither a time nor an element: {message}"
            );
            Ok(None)
        }
    }
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

/// A recorded sample: its time, mode and outputs.
type Recorded<'a> = (f64, &'a str, &'a [f64]);

/// Each sample's mode with its time and outputs, but for a sample at the force's step: it
/// is recorded as the left limit there (the mode and outputs before the step), while the
/// force is right-continuous, so the two cannot be compared.
fn samples(trajectory: &Trajectory, force: Force) -> impl Iterator<Item = Recorded<'_>> {
    (0..trajectory.times.len())
        .filter(move |k| trajectory.times[*k] != force.at)
        .map(|k| sample(trajectory, k))
}

fn sample(trajectory: &Trajectory, k: usize) -> Recorded<'_> {
    (
        trajectory.times[k],
        trajectory.modes[trajectory.sample_modes[k]].as_str(),
        trajectory.row(k).unwrap(),
    )
}

/// The sample recorded at each event's instant in the mode the event settled in (the last
/// event at that instant), checked to be there.
fn at_events(trajectory: &Trajectory) -> Result<Vec<Recorded<'_>>, TestCaseError> {
    let mut found = Vec::new();
    for (i, event) in trajectory.events.iter().enumerate() {
        if trajectory
            .events
            .get(i + 1)
            .is_some_and(|next| next.t == event.t)
        {
            continue;
        }
        let k = (0..trajectory.times.len())
            .rev()
            .find(|&k| trajectory.times[k] == event.t);
        let Some(k) = k else {
            return Err(TestCaseError::fail(format!(
                "no sample at the event {event:?}"
            )));
        };
        let recorded = sample(trajectory, k);
        prop_assert_eq!(recorded.1, event.to.as_str(), "at the event {:?}", event);
        found.push(recorded);
    }
    Ok(found)
}

/// A mass `m` on a spring `k` to the wall, pushed by `F`, on a Karnopp contact with the
/// ground (`F_S = excess F_C`, viscous `b`), released from `(p0, q0)`, stuck or slipping.
#[derive(Clone, Copy, Debug)]
struct Contact {
    m: f64,
    k: f64,
    coulomb: f64,
    excess: f64,
    b: f64,
    force: Force,
    q0: f64,
    p0: f64,
    stuck: bool,
}

fn contact_keeps_its_books_and_its_guards(case: Contact) -> Result<(), TestCaseError> {
    let Contact {
        m,
        k,
        coulomb,
        excess,
        b,
        force,
        q0,
        p0,
        stuck,
    } = case;
    let breakaway = coulomb * excess;
    let initial = if stuck {
        "stuck"
    } else if p0 >= 0.0 {
        "slip+"
    } else {
        "slip-"
    };
    let text = format!(
        r#"Model(name: "contact",
    parameters: {{"m": (value: {m:e}), "k": (value: {k:e}), "F_S": (value: {breakaway:e}),
        "F_C": (value: {coulomb:e}), "b": (value: {b:e})}},
    inputs: {{"F": ()}},
    elements: {{"push": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
        "spring": C(stiffness: "k"),
        "contact": Friction(breakaway: "F_S", coulomb: "F_C", viscous: "b", initial: "{initial}")}},
    bonds: [("push", "v"), ("v", "mass"), ("v", "spring"), ("v", "contact")])"#
    );
    let model = load("contact.ron", &text);
    let p0 = if stuck { 0.0 } else { p0 };
    let elements = ["push", "mass", "spring", "contact"];
    let outputs = ["flow:mass", "effort:spring"];
    let Some(trajectory) = simulate(&model, &outputs, force, vec![p0, q0], &elements)? else {
        return Ok(());
    };
    check_energy(&trajectory)?;
    let v_scale = TOLERANCE * scale(&trajectory, 0, 1e-12);
    let f_scale = TOLERANCE * scale(&trajectory, 1, breakaway).max(force.largest());
    let check = |(t, mode, row): (f64, &str, &[f64])| -> Result<(), TestCaseError> {
        let (v, spring) = (row[0], row[1]);
        let holding = force.value(t) - spring;
        match mode {
            "contact=stuck" => {
                prop_assert!(v.abs() <= v_scale, "t = {t}: stuck at v = {v}");
                prop_assert!(
                    holding.abs() <= breakaway + f_scale,
                    "t = {t}: stuck holding {holding} past F_S = {breakaway}"
                );
            }
            "contact=slip+" => prop_assert!(v >= -v_scale, "t = {t}: slip+ at v = {v}"),
            "contact=slip-" => prop_assert!(v <= v_scale, "t = {t}: slip- at v = {v}"),
            other => prop_assert!(false, "mode {other}"),
        }
        Ok(())
    };
    for recorded in samples(&trajectory, force).chain(at_events(&trajectory)?) {
        check(recorded)?;
    }
    Ok(())
}

/// A mass `m` pushed by `F` through a damper `b`, tied by a tension-only string `k`,
/// released from `(p0, q0)`: taut, the string is stretched (`q >= 0`) and pulls
/// (`k q >= 0`); slack, it carries nothing and is not stretched (`q <= 0`), its extension
/// `q = q0 + ∫ flow`.
#[derive(Clone, Copy, Debug)]
struct Tether {
    m: f64,
    k: f64,
    b: f64,
    force: Force,
    q0: f64,
    p0: f64,
}

fn tether_keeps_its_books_and_its_guards(case: Tether) -> Result<(), TestCaseError> {
    let Tether {
        m,
        k,
        b,
        force,
        q0,
        p0,
    } = case;
    let initial = if q0 >= 0.0 { "taut" } else { "slack" };
    let text = format!(
        r#"Model(name: "tether",
    parameters: {{"m": (value: {m:e}), "k": (value: {k:e}), "b": (value: {b:e})}},
    inputs: {{"F": ()}},
    elements: {{"push": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
        "damper": R(resistance: "b"), "string": TensionOnly(stiffness: "k", initial: "{initial}")}},
    bonds: [("push", "v"), ("v", "mass"), ("v", "damper"), ("v", "string")])"#
    );
    let model = load("tether.ron", &text);
    let elements = ["push", "mass", "damper", "string"];
    let outputs = ["effort:string", "flow:mass", "integral:flow:string"];
    let Some(trajectory) = simulate(&model, &outputs, force, vec![p0, q0], &elements)? else {
        return Ok(());
    };
    check_energy(&trajectory)?;
    let f_scale = TOLERANCE * scale(&trajectory, 0, k * 0.2);
    let extension = |row: &[f64]| q0 + row[2];
    let q_scale = TOLERANCE
        * (0..trajectory.times.len())
            .filter_map(|j| trajectory.row(j))
            .fold(q0.abs().max(1e-3), |largest, row| {
                largest.max(extension(row).abs())
            });
    let check = |(t, mode, row): (f64, &str, &[f64])| -> Result<(), TestCaseError> {
        let (tension, q) = (row[0], extension(row));
        match mode {
            "string=taut" => {
                prop_assert!(tension >= -f_scale, "t = {t}: taut pushing {tension}");
                prop_assert!(q >= -q_scale, "t = {t}: taut at extension {q}");
            }
            "string=slack" => {
                prop_assert!(tension.abs() <= f_scale, "t = {t}: slack pulling {tension}");
                prop_assert!(q <= q_scale, "t = {t}: slack at extension {q}");
            }
            other => prop_assert!(false, "mode {other}"),
        }
        Ok(())
    };
    for recorded in samples(&trajectory, force).chain(at_events(&trajectory)?) {
        check(recorded)?;
    }
    Ok(())
}

/// A cart `m` pushed by `F` through a damper `b`, its speed capped at `v_max`, starting at
/// `fraction` of it.
#[derive(Clone, Copy, Debug)]
struct Limited {
    m: f64,
    b: f64,
    v_max: f64,
    force: Force,
    fraction: f64,
}

fn limit_keeps_its_books_and_its_guards(case: Limited) -> Result<(), TestCaseError> {
    let Limited {
        m,
        b,
        v_max,
        force,
        fraction,
    } = case;
    let text = format!(
        r#"Model(name: "limited",
    parameters: {{"m": (value: {m:e}), "b": (value: {b:e}), "v_max": (value: {v_max:e})}},
    inputs: {{"F": ()}},
    elements: {{"push": Se(effort: "F"), "v": One, "cart": I(inertance: "m"),
        "damper": R(resistance: "b"), "limit": FlowLimit(max_flow: "v_max")}},
    bonds: [("push", "v"), ("v", "cart"), ("v", "damper"), ("v", "limit")])"#
    );
    let model = load("limited.ron", &text);
    let p0 = fraction * v_max * m;
    let elements = ["push", "cart", "damper", "limit"];
    let outputs = ["flow:cart", "effort:limit"];
    let Some(trajectory) = simulate(&model, &outputs, force, vec![p0], &elements)? else {
        return Ok(());
    };
    check_energy(&trajectory)?;
    let v_scale = TOLERANCE * v_max;
    let f_scale = TOLERANCE * scale(&trajectory, 1, force.largest().max(1.0));
    let check = |(t, mode, row): (f64, &str, &[f64])| -> Result<(), TestCaseError> {
        let (v, held) = (row[0], row[1]);
        let holding = force.value(t) - b * v_max;
        match mode {
            "limit=open" => prop_assert!(v <= v_max + v_scale, "t = {t}: open at {v} > {v_max}"),
            "limit=limiting" => {
                prop_assert!((v - v_max).abs() <= v_scale, "t = {t}: limiting at {v}");
                prop_assert!(
                    holding >= -f_scale,
                    "t = {t}: limiting holds {holding} ({held})"
                );
            }
            other => prop_assert!(false, "mode {other}"),
        }
        Ok(())
    };
    for recorded in samples(&trajectory, force).chain(at_events(&trajectory)?) {
        check(recorded)?;
    }
    Ok(())
}

/// The cases these properties shrank to when they failed, kept by value: the seeds in
/// `properties.proptest-regressions` were drawn from an earlier force strategy (constants
/// and steps only) and now draw other cases.
#[test]
fn the_cases_the_properties_once_failed_on_still_hold() {
    let step = |before: f64, after: f64, at: f64| Force {
        before,
        after,
        slope: 0.0,
        at,
    };
    let run = |result: Result<(), TestCaseError>| {
        if let Err(error) = result {
            panic!("{error}");
        }
    };
    run(limit_keeps_its_books_and_its_guards(Limited {
        m: 0.1,
        b: 0.1,
        v_max: 0.1,
        force: step(16.545010470666583, 0.0, 0.10037),
        fraction: 0.0,
    }));
    run(contact_keeps_its_books_and_its_guards(Contact {
        m: 0.1,
        k: 944.143461634989,
        coulomb: 6.314287813871979,
        excess: 1.0,
        b: 0.0,
        force: step(12.383354427816661, 0.0, 0.10037),
        q0: 0.0,
        p0: 0.0,
        stuck: false,
    }));
    // Seed 19 drew it: a string going slack as the mass swings back, then pulled taut
    // again by the force 0.075 s later. A rewrite of the eigendecomposition (the slack mode
    // has eigenvalues 0 and -b/m) kept the velocity right but not the stretch: the string
    // never went taut again, and 13 kJ were stored by t = 2 s from 141 J supplied.
    run(tether_keeps_its_books_and_its_guards(Tether {
        m: 3.1847489682331385,
        k: 531.2523621669694,
        b: 0.38682442684666485,
        force: step(19.965126614176747, 19.965126614176747, 0.10037),
        q0: 0.0,
        p0: 0.8573210148791778,
    }));
    run(tether_keeps_its_books_and_its_guards(Tether {
        m: 0.32950256407150785,
        k: 962.4535342161964,
        b: 0.5024740385401693,
        force: step(31.474068747067616, 31.474068747067616, 1.30837),
        q0: 0.0,
        p0: -0.45307108865010737,
    }));
}

proptest! {
    // 96 cases drawn afresh each run (proptest's random seed; a failure prints its seed and
    // shrunk case, and `PROPTEST_RNG_SEED=N` draws a given seed again). The energy books cost
    // what the samples cost, and the friction cases that once ran for minutes (seeds 19, 26,
    // 31, 44 and 52 of a fixed seed: event location crawling by an ulp of time per segment
    // after a declined switch) take milliseconds since a declined guard rests above its modal
    // rounding (`events.rs`).
    #![proptest_config(ProptestConfig {
        cases: 96,
        ..ProptestConfig::default()
    })]

    #[test]
    fn friction_contacts_keep_their_books_and_their_guards(
        m in 0.1..10.0f64, k in 1.0..1000.0f64, coulomb in 0.1..10.0f64,
        excess in 1.0..2.0f64, b in 0.0..2.0f64, force in force(),
        q0 in -0.2..0.2f64, p0 in -1.0..1.0f64, stuck in any::<bool>(),
    ) {
        contact_keeps_its_books_and_its_guards(Contact {
            m, k, coulomb, excess, b, force, q0, p0, stuck,
        })?;
    }

    /// It found `hardening::a_string_pulled_back_from_slack_goes_taut_every_time`.
    #[test]
    fn strings_keep_their_books_and_their_guards(
        m in 0.1..10.0f64, k in 1.0..1000.0f64, b in 0.0..5.0f64, force in force(),
        q0 in -0.2..0.2f64, p0 in -1.0..1.0f64,
    ) {
        tether_keeps_its_books_and_its_guards(Tether { m, k, b, force, q0, p0 })?;
    }

    #[test]
    fn flow_limits_keep_their_books_and_their_guards(
        m in 0.1..10.0f64, b in 0.1..5.0f64, v_max in 0.1..5.0f64, force in force(),
        fraction in -1.0..1.0f64,
    ) {
        limit_keeps_its_books_and_its_guards(Limited { m, b, v_max, force, fraction })?;
    }
}
