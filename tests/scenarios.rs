//! Model edits and scenarios on the real model files: the eversion robot without its
//! catheter, parameter changes, and the example scenarios in `models/scenarios/`.

use bondgraph_core::equations::Options;
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::scenario::{Record, Signal};
use bondgraph_core::source::SourceFile;
use bondgraph_core::{Diagnostic, DiagnosticKind};
use bondgraph_ron::model::edit::{self, Edit};

use crate::support::{ron_files, root};

const ROBOT: &str = "models/eversion/robot.ron";

/// The catheter and everything that only serves it.
const CATHETER: [&str; 7] = [
    "rubbing",
    "fr_ct",
    "catheter",
    "ct",
    "servo_force",
    "servo",
    "servo_command",
];

fn read(relative: &str) -> std::sync::Arc<SourceFile> {
    let text = std::fs::read_to_string(root().join(relative))
        .unwrap_or_else(|e| panic!("{relative}: {e}"));
    SourceFile::new(relative, text)
}

fn remove(names: &[&str]) -> Edit {
    Edit {
        remove: names.iter().map(|s| s.to_string()).collect(),
        parameters: Vec::new(),
    }
}

/// Kind, message, line and column of a located diagnostic.
fn summary(d: &Diagnostic) -> (DiagnosticKind, &str, usize, usize) {
    let location = d.location.as_ref().expect("located");
    (d.kind, d.message.as_str(), location.line, location.column)
}

#[test]
fn the_robot_without_its_catheter() {
    let robot = read(ROBOT);
    let edited = edit::apply(&robot, &remove(&CATHETER)).unwrap();
    assert_eq!(edited.name(), "models/eversion/robot.ron (edited)");
    let model = bondgraph_ron::model::load_source(&edited).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.elements().len(), 10);
    assert_eq!(model.bonds().len(), 9);
    for name in CATHETER {
        assert_eq!(model.element_named(name), None, "{name}");
    }
    // The comments and the rest of the file are kept as written.
    assert!(
        edited
            .text()
            .starts_with(robot.text().lines().next().unwrap())
    );
    assert!(edited.text().contains("        // Tip to inner structure:"));
    assert!(
        edited
            .text()
            .contains("        (\"active_channel\", \"channel\"),\n    ],\n")
    );
    // The tip is stuck at the nozzle and the string taut: the initial mode derives, with
    // the string's stretch as its only state (the stuck tip holds no momentum).
    let initial = Mode::initial(&model);
    assert_eq!(initial.spec(&model), "fr_ge=stuck,k=taut");
    let derived = modes::derive(&model, &initial, &Options::default()).unwrap();
    let states: Vec<&str> = derived
        .equations
        .states
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(states, ["q_k"]);
}

#[test]
fn setting_the_dead_band() {
    let robot = read(ROBOT);
    let edit = Edit {
        remove: Vec::new(),
        parameters: vec![("dv".into(), 2.5e-7), ("K_p".into(), 6.0e4)],
    };
    let edited = edit::apply(&robot, &edit).unwrap();
    assert!(edited.text().contains(
        "\"dv\": (value: 2.5e-7, unit: \"m/s\", description: \"Karnopp dead band (not given in the paper)\"),"
    ));
    let model = bondgraph_ron::model::load_source(&edited).unwrap();
    let value = |name: &str| {
        model
            .parameters()
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.value)
    };
    assert_eq!(value("dv"), Some(2.5e-7));
    assert_eq!(value("K_p"), Some(6.0e4));
    assert_eq!(value("b"), Some(1250.0));
    assert_eq!(edited.text().lines().count(), robot.text().lines().count());
}

#[test]
fn edits_the_robot_does_not_allow() {
    let robot = read(ROBOT);
    let edit = Edit {
        remove: vec!["catheterr".into()],
        parameters: vec![("dV".into(), 1.0), ("b".into(), f64::NAN)],
    };
    let error = edit::apply(&robot, &edit).unwrap_err();
    let got: Vec<_> = error.iter().map(summary).collect();
    assert_eq!(
        got,
        [
            (
                DiagnosticKind::UnknownName,
                "cannot remove element 'catheterr': model 'eversion_robot' has no element 'catheterr'",
                62,
                5
            ),
            (
                DiagnosticKind::UnknownName,
                "cannot set parameter 'dV': model 'eversion_robot' has no parameter 'dV'",
                38,
                5
            ),
            (
                DiagnosticKind::InvalidValue,
                "cannot set parameter 'b' to NaN: the value must be a finite number",
                47,
                9
            ),
        ]
    );
    assert_eq!(error.0[0].notes, ["did you mean 'catheter'?"]);
    assert_eq!(error.0[1].notes, ["did you mean 'dv'?"]);
    assert_eq!(error.0[2].element.as_deref(), Some("b"));
}

#[test]
fn a_junction_left_with_one_bond_is_reported_when_the_edit_is_loaded() {
    let robot = read(ROBOT);
    // Without the tip's mass (a line above 'rubbing') and without what 'rubbing' joins.
    let edited = edit::apply_traced(&robot, &remove(&["ge", "fr_ct", "catheter"])).unwrap();
    let error = bondgraph_ron::model::load_source(&edited.file).unwrap_err();
    let first = error.first();
    assert_eq!(
        summary(first),
        (
            DiagnosticKind::BondCount,
            "0-junction 'rubbing' has 1 bond; a junction joins two or more",
            73,
            9
        )
    );
    assert_eq!(
        first.location.as_ref().unwrap().file,
        "models/eversion/robot.ron (edited)"
    );
    // Traced back to the robot's own file, line 74.
    let relocated = edited.relocate(first.clone(), &robot);
    let location = relocated.location.unwrap();
    assert_eq!(
        (location.file.as_str(), location.line, location.column),
        (ROBOT, 74, 9)
    );
    assert_eq!(
        &robot.text()[location.span.start..location.span.end],
        "\"rubbing\""
    );
}

/// Every file in `models/scenarios/` loads against the model it names in its first line.
#[test]
fn every_example_scenario_loads() {
    let files = ron_files("models/scenarios");
    assert!(files.len() >= 2, "{files:?}");
    for relative in files {
        let source = read(&relative);
        let first = source.text().lines().next().unwrap();
        let model = first
            .split(['(', ')'])
            .find(|part| part.starts_with("models/"))
            .unwrap_or_else(|| panic!("{relative}: the first line names the model"));
        bondgraph_ron::scenario::load(&source, &read(model))
            .unwrap_or_else(|e| panic!("{relative}:\n{e}"));
    }
}

#[test]
fn belt_stick_slip() {
    let scenario = bondgraph_ron::scenario::load(
        &read("models/scenarios/belt_stick_slip.ron"),
        &read("models/examples/belt_friction.ron"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scenario.name, "belt_stick_slip");
    assert_eq!(
        scenario.model.source().name(),
        "models/examples/belt_friction.ron"
    );
    assert_eq!(scenario.inputs, [Signal::Constant(0.1)]);
    assert_eq!(scenario.duration, 3.0);
    assert_eq!(scenario.sample, Some(1.0e-3));
    let records: Vec<String> = scenario.record.iter().map(Record::name).collect();
    assert_eq!(records, ["flow:block", "effort:spring"]);
    assert_eq!(
        scenario.initial_mode.spec(&scenario.model),
        "friction=stuck"
    );
    assert!(scenario.initial_state.is_empty());
    assert!(scenario.breakpoints().is_empty());
}

#[test]
fn robot_growth_without_the_catheter() {
    let scenario =
        bondgraph_ron::scenario::load(&read("models/scenarios/robot_growth.ron"), &read(ROBOT))
            .unwrap_or_else(|e| panic!("{e}"));
    let model = &scenario.model;
    assert_eq!(model.source().name(), "models/eversion/robot.ron (edited)");
    assert_eq!((model.elements().len(), model.bonds().len()), (10, 9));
    // P_s, v_ac, and v_ct_des, which drives nothing once the servo is removed.
    let names: Vec<&str> = model.inputs().iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["P_s", "v_ac", "v_ct_des"]);
    assert_eq!(scenario.inputs[2], Signal::Constant(0.0));
    // The tip breaks away when A P_s = 1e-4 m^2 * P_s reaches 11.7 N: at 117 kPa, t = 0.117 s.
    let pressure = &scenario.inputs[0];
    assert_eq!(pressure.ceiling_time(), Some(0.13));
    assert!((pressure.value(0.117) - 1.17e5).abs() < 1e-6);
    assert_eq!(scenario.breakpoints(), [0.0, 0.13]);
    assert_eq!(scenario.initial_mode.spec(model), "fr_ge=stuck,k=slack");
    let derived = modes::derive(model, &scenario.initial_mode, &Options::default()).unwrap();
    assert_eq!(derived.equations.states.len(), 1);
    assert!(matches!(scenario.record[2], Record::Integral(_)));
}

/// A scenario that asks for the catheter it removes is told so, in its own file.
#[test]
fn a_scenario_that_uses_what_it_removes() {
    let text = read("models/scenarios/robot_growth.ron")
        .text()
        .replace("\"effort:k\"", "\"flow:ct\"");
    let error =
        bondgraph_ron::scenario::load(&SourceFile::new("robot_growth.ron", text), &read(ROBOT))
            .unwrap_err();
    let d = error.first();
    assert_eq!(
        summary(d),
        (
            DiagnosticKind::BadOutput,
            "output 'flow:ct': the model has no element 'ct'",
            19,
            26
        )
    );
    assert_eq!(d.notes, ["the scenario removes 'ct'"]);
    assert_eq!(d.element.as_deref(), Some("ct"));
}
