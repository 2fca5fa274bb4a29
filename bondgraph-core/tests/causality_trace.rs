//! The record of SCAP's decisions ([`causality::assign_traced`]): the steps expected by
//! hand on the textbook models, and on every mode of the flagship that replaying the trace
//! gives exactly the strokes the assignment returned, each bond stroked once.

use bondgraph_core::causality::{
    self, Causality, CausalityTrace, Decision, Propagation, Rule, Step, Stroke,
};
use bondgraph_core::equations::Options;
use bondgraph_core::model::{BondId, ElementId, Model};
use bondgraph_core::{laws, modes};

fn load(relative: &str) -> Model {
    let path = format!("{}/../{relative}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    bondgraph_ron::model::load_str(relative, &text).unwrap_or_else(|e| panic!("{relative}:\n{e}"))
}

fn traced(model: &Model, mode: &modes::Mode) -> (Causality, CausalityTrace) {
    causality::assign_traced(model, &laws::for_mode(model, mode))
        .unwrap_or_else(|e| panic!("{}:\n{e}", model.name()))
}

fn id(model: &Model, name: &str) -> ElementId {
    model.element_named(name).expect(name)
}

/// Bond `n` as the explanations number them (from 1).
fn bond(n: u32) -> BondId {
    BondId(n - 1)
}

/// `(element, decision, bond number, stroke, new, earlier step number)` of every step.
type Summary = (String, Decision, u32, Stroke, bool, Option<usize>);

fn summary(model: &Model, trace: &CausalityTrace) -> Vec<Summary> {
    trace
        .steps
        .iter()
        .map(|s: &Step| {
            (
                model.element(s.element).name.clone(),
                s.decision.clone(),
                s.bond.0 + 1,
                s.stroke,
                s.new,
                s.earlier.map(|k| k + 1),
            )
        })
        .collect()
}

fn step(
    name: &str,
    decision: Decision,
    bond: u32,
    stroke: Stroke,
    new: bool,
    earlier: Option<usize>,
) -> Summary {
    (name.to_string(), decision, bond, stroke, new, earlier)
}

/// The trace replays to the assignment's strokes, every bond stroked exactly once.
fn assert_replays(model: &Model, causal: &Causality, trace: &CausalityTrace, what: &str) {
    let mut times = vec![0; model.bonds().len()];
    for (b, _, _) in trace.assignments() {
        times[b.index()] += 1;
    }
    assert!(
        times.iter().all(|&t| t == 1),
        "{what}: strokes per bond {times:?}"
    );
    let replayed: Vec<Stroke> = trace
        .strokes(model.bonds().len())
        .into_iter()
        .map(|s| s.expect("every bond stroked"))
        .collect();
    assert_eq!(replayed, causal.strokes, "{what}");
    // The storage the trace puts in derivative causality is the assignment's.
    let mut derivative: Vec<ElementId> = trace
        .steps
        .iter()
        .filter(|s| s.decision == Decision::Derivative)
        .map(|s| s.element)
        .collect();
    derivative.sort();
    assert_eq!(derivative, causal.dependent, "{what}");
}

#[test]
fn mass_spring_damper_steps() {
    // Se force -> 1-junction v: the effort goes to v. The mass takes integral causality
    // (receives the effort), which sets v's flow: v gives it to the spring and the damper,
    // which give their efforts back, so the spring is integral too and the damper in
    // resistance causality, both decided by the mass's step.
    let model = load("models/examples/mass_spring_damper.ron");
    let (causal, trace) = traced(&model, &modes::Mode::initial(&model));
    assert_eq!(
        summary(&model, &trace),
        [
            step("force", Decision::Source, 1, Stroke::AtTo, true, None),
            step("mass", Decision::Integral, 2, Stroke::AtTo, true, None),
            step(
                "spring",
                Decision::Integral,
                3,
                Stroke::AtFrom,
                false,
                Some(2)
            ),
            step(
                "damper",
                Decision::ResistorForced,
                4,
                Stroke::AtFrom,
                false,
                Some(2)
            ),
        ]
    );
    let v_mass = id(&model, "v_mass");
    assert!(trace.steps[0].propagated.is_empty());
    assert_eq!(
        trace.steps[1].propagated,
        [3, 4].map(|n| Propagation {
            bond: bond(n),
            stroke: Stroke::AtFrom,
            through: v_mass,
            rule: Rule::CommonFlow { from: bond(2) },
        })
    );
    assert_replays(&model, &causal, &trace, "mass_spring_damper");
}

#[test]
fn rigid_masses_second_mass_in_derivative_causality() {
    // The first mass sets the common flow of v; the second mass's bond is then stroked at
    // v (it must give an effort), against its preferred integral causality.
    let model = load("models/examples/rigid_masses.ron");
    let (causal, trace) = traced(&model, &modes::Mode::initial(&model));
    assert_eq!(
        summary(&model, &trace),
        [
            step("force", Decision::Source, 1, Stroke::AtTo, true, None),
            step("mass1", Decision::Integral, 2, Stroke::AtTo, true, None),
            step(
                "mass2",
                Decision::Derivative,
                3,
                Stroke::AtFrom,
                false,
                Some(2)
            ),
            step(
                "spring",
                Decision::Integral,
                4,
                Stroke::AtFrom,
                false,
                Some(2)
            ),
            step(
                "damper",
                Decision::ResistorForced,
                5,
                Stroke::AtFrom,
                false,
                Some(2)
            ),
        ]
    );
    assert_eq!(causal.dependent, [id(&model, "mass2")]);
    assert_replays(&model, &causal, &trace, "rigid_masses");
}

#[test]
fn series_dampers_choice_opens_an_algebraic_loop() {
    // Nothing forces the dampers behind the 0-junction: damper1 is chosen in resistance
    // causality (it gives the effort), and the 0-junction passes that effort to damper2,
    // which is left in conductance causality.
    let model = load("models/examples/series_dampers.ron");
    let (causal, trace) = traced(&model, &modes::Mode::initial(&model));
    assert_eq!(
        summary(&model, &trace),
        [
            step("force", Decision::Source, 1, Stroke::AtTo, true, None),
            step("mass", Decision::Integral, 2, Stroke::AtTo, true, None),
            step(
                "damper1",
                Decision::ResistorChosen,
                4,
                Stroke::AtFrom,
                true,
                None
            ),
        ]
    );
    assert_eq!(
        trace.steps[1].propagated,
        [Propagation {
            bond: bond(3),
            stroke: Stroke::AtFrom,
            through: id(&model, "v"),
            rule: Rule::CommonFlow { from: bond(2) },
        }]
    );
    assert_eq!(
        trace.steps[2].propagated,
        [Propagation {
            bond: bond(5),
            stroke: Stroke::AtTo,
            through: id(&model, "damper_force"),
            rule: Rule::CommonEffort { from: bond(4) },
        }]
    );
    assert_eq!(causal.arbitrary, [id(&model, "damper1")]);
    assert_replays(&model, &causal, &trace, "series_dampers");
}

#[test]
fn flagship_initial_mode_steps() {
    // All three contacts stuck, the string taut. Sources in file order: the pressure, the
    // stuck nozzle contact (a zero flow source: it receives the effort), the active
    // channel, the stuck catheter contact, the servo command. The stuck nozzle contact
    // sets the tip's flow, which reaches the inner structure through the transformer; the
    // active channel leaves the string's 0-junction one bond to bring its effort in, the
    // string's own. Both inertias are then held: derivative causality.
    let model = load("models/eversion/robot.ron");
    let (causal, trace) = traced(&model, &modes::Mode::initial(&model));
    use Decision::*;
    use Stroke::*;
    assert_eq!(
        summary(&model, &trace),
        [
            step("pressure", Source, 1, AtTo, true, None),
            step("fr_ge", Source, 3, AtTo, true, None),
            step("active_channel", Source, 9, AtFrom, true, None),
            step("fr_ct", Source, 11, AtTo, true, None),
            step("servo_command", Source, 14, AtFrom, true, None),
            step("ge", Derivative, 2, AtFrom, false, Some(2)),
            step("k", Integral, 7, AtFrom, false, Some(3)),
            step("ct", Derivative, 13, AtFrom, false, Some(4)),
            step("servo", ResistorForced, 15, AtFrom, false, Some(5)),
        ]
    );
    let through = |s: usize| -> Vec<(u32, String, Rule)> {
        let mut p: Vec<(u32, String, Rule)> = trace.steps[s]
            .propagated
            .iter()
            .map(|p| (p.bond.0 + 1, model.element(p.through).name.clone(), p.rule))
            .collect();
        p.sort_by_key(|x| x.0);
        p
    };
    assert_eq!(
        through(1),
        [
            (2, "tip".into(), Rule::CommonFlow { from: bond(3) }),
            (4, "tip".into(), Rule::CommonFlow { from: bond(3) }),
            (5, "eversion".into(), Rule::Transformer { from: bond(4) }),
            (6, "inner".into(), Rule::CommonFlow { from: bond(5) }),
            (10, "inner".into(), Rule::CommonFlow { from: bond(5) }),
        ]
    );
    assert_eq!(
        through(2),
        [
            (7, "string_force".into(), Rule::LastSetsEffort),
            (8, "channel".into(), Rule::CommonFlow { from: bond(9) }),
        ]
    );
    assert_replays(&model, &causal, &trace, "robot initial mode");
}

#[test]
fn every_flagship_mode_replays_to_its_strokes() {
    let model = load("models/eversion/robot.ron");
    let reachable = modes::reachable(&model, &Options::default()).expect("flagship modes");
    assert_eq!(reachable.modes.len(), 18);
    for derived in &reachable.modes {
        let (causal, trace) = traced(&model, &derived.mode);
        let spec = derived.mode.spec(&model);
        // The traced run is the plain run.
        assert_eq!(
            causal,
            causality::assign(&model, &laws::for_mode(&model, &derived.mode)).unwrap(),
            "{spec}"
        );
        assert_replays(&model, &causal, &trace, &spec);
        // Every storage element and resistor has a step of its own.
        for name in ["ge", "k", "ct", "servo"] {
            let element = id(&model, name);
            let is_storage = laws::for_mode(&model, &derived.mode)[element.index()].is_storage();
            if is_storage || name == "servo" {
                assert!(
                    trace.steps.iter().any(|s| s.element == element),
                    "{spec}: no step for {name}"
                );
            }
        }
    }
}

#[test]
fn an_undone_choice_is_recorded_and_left_out_of_the_strokes() {
    // A 1-junction bonded twice to one 0-junction shorts its effort (E + E = 0); the first
    // free choice fails and is undone (see regressions.rs).
    let model = bondgraph_ron::model::load_str(
        "short.ron",
        r#"Model(
    name: "shorted_junction",
    parameters: { "m": (value: 2.0), "b": (value: 3.0) },
    elements: { "node": Zero, "short": One, "mass": I(inertance: "m"), "damper": R(resistance: "b") },
    bonds: [("node", "short"), ("node", "short"), ("node", "mass"), ("node", "damper")],
)"#,
    )
    .unwrap();
    let (causal, trace) = traced(&model, &modes::Mode::initial(&model));
    assert!(
        trace
            .steps
            .iter()
            .any(|s| matches!(s.decision, Decision::Undone { .. })),
        "{trace:#?}"
    );
    assert_replays(&model, &causal, &trace, "shorted junction");
}
