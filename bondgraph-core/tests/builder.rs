//! A model built in code is the model its file describes: same values, same equations.

use bondgraph_core::model::{Builder, ElementSpec, Model, ParameterSpec};
use bondgraph_core::{equations, laws};

const FILE: &str = r#"Model(
    name: "msd",
    parameters: {
        "m": (value: 2000.0, unit: "g"),
        "k": (value: 200.0, unit: "N/m"),
        "b": (value: 4.0, unit: "N*s/m", bounds: (0.0, 10.0)),
    },
    inputs: { "F": (unit: "N") },
    elements: {
        "force": Se(effort: "F"),
        "v": One,
        "mass": I(inertance: "m"),
        "spring": C(compliance: "1/k"),
        "damper": R(resistance: "b"),
    },
    bonds: [("force", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")],
)"#;

fn built() -> Model {
    Builder::new("msd")
        .parameter("m", 2000.0, "g")
        .parameter("k", 200.0, "N/m")
        .parameter_spec(
            "b",
            ParameterSpec {
                bounds: Some((0.0, 10.0)),
                ..ParameterSpec::new(4.0, "N*s/m")
            },
        )
        .input("F", "N")
        .element("force", ElementSpec::effort_source("F"))
        .element("v", ElementSpec::One)
        .element("mass", ElementSpec::inertance("m"))
        .element("spring", ElementSpec::compliance("1/k"))
        .element("damper", ElementSpec::resistance("b"))
        .bonds([("force", "v"), ("v", "mass"), ("v", "spring")])
        .bond("v", "damper")
        .build()
        .unwrap()
}

fn a_matrix(model: &Model) -> Vec<Vec<String>> {
    let options = equations::Options::default();
    let eq = equations::derive(model, &laws::plain_laws(model), &options).unwrap();
    eq.a()
        .iter()
        .map(|row| row.iter().map(|e| e.text(&eq.symbols)).collect())
        .collect()
}

#[test]
fn a_built_model_is_the_model_its_file_describes() {
    let from_code = built();
    let from_file = bondgraph_ron::model::load_str("msd.ron", FILE).unwrap();
    // 2000 g is 2 kg either way; the bounds and units are kept.
    let values = |m: &Model| -> Vec<f64> { m.parameters().iter().map(|p| p.value).collect() };
    assert_eq!(values(&from_code), [2.0, 200.0, 4.0]);
    assert_eq!(from_code.values(), from_file.values());
    assert_eq!(from_code.parameters()[2].bounds, Some((0.0, 10.0)));
    assert_eq!(from_code.inputs()[0].unit.as_deref(), Some("N"));
    // p' = -b/m p - k q + F and q' = p/m, by hand.
    assert_eq!(a_matrix(&from_code), [["-b/m", "-k"], ["1/m", "0"]]);
    assert_eq!(a_matrix(&from_code), a_matrix(&from_file));
    let kinds =
        |m: &Model| -> Vec<&str> { m.elements().iter().map(|e| e.kind.keyword()).collect() };
    assert_eq!(kinds(&from_code), kinds(&from_file));
}

/// Names joined by '.' are a sub-model's qualified names: a state keeps the prefix in front
/// of its own name (`front.q_spring`), and an expression can name it.
#[test]
fn qualified_names_give_qualified_states_that_expressions_can_name() {
    let model = Builder::new("qualified")
        .parameter("front.m", 2.0, "kg")
        .parameter("front.k", 200.0, "N/m")
        .parameter("c", 3.0, "N*s/m^2")
        .input("F", "N")
        .element("force", ElementSpec::effort_source("F"))
        .element("front.v", ElementSpec::One)
        .element("front.mass", ElementSpec::inertance("front.m"))
        .element("front.spring", ElementSpec::stiffness("front.k"))
        // A damper modulated by the spring's stretch.
        .element("front.damper", ElementSpec::resistance("c*front.q_spring"))
        .bonds([
            ("force", "front.v"),
            ("front.v", "front.mass"),
            ("front.v", "front.spring"),
            ("front.v", "front.damper"),
        ])
        .build()
        .unwrap();
    let names: Vec<String> = model
        .element_ids()
        .filter_map(|id| model.storage_name(id))
        .collect();
    assert_eq!(names, ["front.p_mass", "front.q_spring"]);
    let options = equations::Options::default();
    let derived =
        equations::nonlinear::derive(&model, &laws::plain_laws(&model), &options).unwrap();
    let text = derived.to_text(None);
    // The damper's force c q v, with v = p/m, by hand.
    assert!(text.contains("front.q_spring"), "{text}");
    assert!(text.contains("front.p_mass"), "{text}");
    // Without the modulated damper: p' = -k q + F, q' = p/m, by hand.
    let linear = Builder::new("qualified")
        .parameter("front.m", 2.0, "kg")
        .parameter("front.k", 200.0, "N/m")
        .input("F", "N")
        .element("force", ElementSpec::effort_source("F"))
        .element("front.v", ElementSpec::One)
        .element("front.mass", ElementSpec::inertance("front.m"))
        .element("front.spring", ElementSpec::stiffness("front.k"))
        .bonds([
            ("force", "front.v"),
            ("front.v", "front.mass"),
            ("front.v", "front.spring"),
        ])
        .build()
        .unwrap();
    assert_eq!(a_matrix(&linear), [["0", "-front.k"], ["1/front.m", "0"]]);
}

#[test]
fn a_name_with_an_empty_part_is_refused() {
    let error = Builder::new("bad")
        .parameter("m", 1.0, "kg")
        .element("v", ElementSpec::One)
        .element("front..mass", ElementSpec::inertance("m"))
        .element("push", ElementSpec::effort_source("1"))
        .bonds([("push", "v"), ("v", "front..mass")])
        .build()
        .unwrap_err();
    assert!(
        error
            .to_string()
            .contains("'front..mass' is not a valid name"),
        "{error}"
    );
}

/// A port is a junction the outside's bonds join: it counts as one of the junction's bonds,
/// so a part whose port junction has a single bond of its own is whole.
#[test]
fn ports_are_junctions_and_count_as_a_bond() {
    let part = || {
        Builder::new("mass")
            .parameter("m", 2.0, "kg")
            .element("v", ElementSpec::One)
            .element("mass", ElementSpec::inertance("m"))
            .bond("v", "mass")
    };
    let model = part().port("hub", "v").build().unwrap();
    assert_eq!(model.ports().len(), 1);
    assert_eq!(model.ports()[0].name, "hub");
    assert_eq!(model.element(model.ports()[0].element).name, "v");

    // Without the port, the junction has one bond.
    let error = part().build().unwrap_err().to_string();
    assert!(
        error.contains("has 1 bond; a junction joins two or more"),
        "{error}"
    );

    let error = part().port("hub", "mass").build().unwrap_err().to_string();
    assert!(
        error.contains("port 'hub': 'mass' is an inertia; a port is a 0- or 1-junction"),
        "{error}"
    );
    let error = part().port("hub", "vv").build().unwrap_err().to_string();
    assert!(error.contains("port 'hub': no element 'vv'"), "{error}");
}
