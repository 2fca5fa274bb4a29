//! Units on every shipped file, and in the words that describe states: the checks of the
//! units through the readers and the derivation together.

use bondgraph_core::model;

/// Extensions written for what the library cannot read yet, each with
/// the error it gives today (none at present). Whoever makes one pass takes it off this list.
const AWAITING_THE_LIBRARY: &[(&str, &str)] = &[];

/// Every shipped model, and each with each of its extensions, passes the check (those
/// awaiting the library fail as listed).
#[test]
fn every_shipped_model_and_extension_passes() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models");
    let mut files = Vec::new();
    let mut folders = vec![root];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "ron") {
                files.push(path);
            }
        }
    }
    let mut checked = 0;
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap();
        let first = text
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty() && !l.starts_with("//"))
            .unwrap_or("");
        if first.starts_with("Model(") || first.starts_with("LinearGraph(") {
            let source =
                bondgraph_core::source::SourceFile::new(path.display().to_string(), text.clone());
            if let Err(error) = bondgraph_ron::model::load_source(&source) {
                panic!("{}: {error}", path.display());
            }
            checked += 1;
        }
        if first.starts_with("Extension(") {
            let folder = path.parent().unwrap().parent().unwrap();
            // A linear-graph fragment (it gives branches) extends the folder's linear graph.
            let linear = text.contains("branches:");
            let base = std::fs::read_dir(folder)
                .unwrap()
                .map(|e| e.unwrap().path())
                .find(|p| {
                    let name = p.file_name().unwrap().to_string_lossy();
                    name.ends_with(".ron")
                        && name.contains(".lg.") == linear
                        && [
                            "thermal.lg.ron",
                            "robot.ron",
                            "geared_motor.ron",
                            "two_tank.ron",
                            "actuator.ron",
                            "thermal.ron",
                        ]
                        .contains(&name.as_ref())
                })
                .unwrap();
            let base = bondgraph_core::source::SourceFile::new(
                base.display().to_string(),
                std::fs::read_to_string(&base).unwrap(),
            );
            let outcome = bondgraph_ron::extension::Extension::read(path)
                .map_err(|e| e.to_string())
                .and_then(|extension| {
                    bondgraph_ron::extension::merge(&base, &[extension]).map_err(|e| e.to_string())
                })
                .and_then(|merged| merged.load().map(|_| ()).map_err(|e| e.to_string()));
            let awaiting = AWAITING_THE_LIBRARY
                .iter()
                .find(|(file, _)| path.ends_with(file));
            match (outcome, awaiting) {
                (Ok(()), None) => {}
                (Err(error), None) => panic!("{} + {}: {error}", base.name(), path.display()),
                (Err(error), Some((_, expected))) => {
                    assert!(error.contains(expected), "{}: {error}", path.display());
                }
                (Ok(()), Some(_)) => panic!(
                    "{} now passes: take it off AWAITING_THE_LIBRARY",
                    path.display()
                ),
            }
            checked += 1;
        }
    }
    // 23 bond graphs, 13 linear graphs and 11 extensions at the time of writing.
    assert!(checked >= 47, "only {checked} files checked");
}

#[test]
fn states_are_described_in_their_domain_words() {
    use bondgraph_core::equations;
    let describe = |model: &model::Model, variables| {
        let options = equations::Options { variables };
        let eq =
            equations::derive(model, &bondgraph_core::laws::plain_laws(model), &options).unwrap();
        eq.states
            .iter()
            .map(|s| {
                format!(
                    "{} {}",
                    s.name,
                    s.quantity
                        .description_in(s.domain, model.linear_graph().is_some())
                )
            })
            .collect::<Vec<_>>()
    };
    // A motor: its armature is electrical, its rotor turns.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/units/motor.ron"
    );
    let motor =
        bondgraph_ron::model::load_str(path, &std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(
        describe(&motor, equations::Variables::Energy),
        ["p_inductance flux linkage", "p_inertia angular momentum"]
    );
    assert_eq!(
        describe(&motor, equations::Variables::CoEnergy),
        ["v_inductance current", "v_inertia angular velocity"]
    );
    let thermal = bondgraph_ron::model::load_str(
        "thermal.ron",
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/fixtures/units/thermal.ron"
        ))
        .unwrap(),
    )
    .unwrap();
    assert_eq!(
        describe(&thermal, equations::Variables::Energy),
        ["q_body heat"]
    );
    assert_eq!(
        describe(&thermal, equations::Variables::CoEnergy),
        ["f_body temperature"]
    );
    // A linear-graph circuit: the capacitor (an A-type, the bond graph's inertia) holds a
    // charge and its state is its voltage.
    let rc = bondgraph_ron::model::load_str(
        "rc.lg.ron",
        r#"LinearGraph(name: "rc",
    parameters: {"R": (value: 1000.0, unit: "ohm"), "C": (value: 1e-6, unit: "F")},
    inputs: {"u": (unit: "V")},
    ground: "g",
    branches: {
        "supply": AcrossSource(value: "u", from: "a", to: "g"),
        "resistor": D(resistance: "R", from: "a", to: "b"),
        "capacitor": A(capacitance: "C", from: "b", to: "g"),
    })"#,
    )
    .unwrap();
    assert_eq!(
        describe(&rc, equations::Variables::Energy),
        ["p_capacitor charge"]
    );
    assert_eq!(
        describe(&rc, equations::Variables::CoEnergy),
        ["v_capacitor voltage"]
    );
    // Without units, the general words.
    let plain = bondgraph_ron::model::load_str(
        "msd.ron",
        r#"Model(name: "msd",
    parameters: {"m": (value: 2.0), "k": (value: 200.0), "b": (value: 4.0)},
    elements: {"push": Se(effort: "1"), "v": One, "mass": I(inertance: "m"),
               "spring": C(stiffness: "k"), "damper": R(resistance: "b")},
    bonds: [("push", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")])"#,
    )
    .unwrap();
    assert_eq!(
        describe(&plain, equations::Variables::Energy),
        ["p_mass momentum", "q_spring displacement"]
    );
}
