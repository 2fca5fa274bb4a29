//! The model file format as serde reads it into a [`ModelSpec`]: every section, in file
//! order, duplicates kept for the validator.

use bondgraph_core::model::spec::{BondSpec, ElementSpec, ModelSpec, ParameterSpec};

use super::parse::ron_options;

fn from_ron(text: &str) -> Result<ModelSpec, ron::error::SpannedError> {
    ron_options().from_str(text)
}

const MODEL: &str = r#"
    Model(
        name: "mass-spring-damper",
        description: "a mass on a spring and a damper",
        parameters: {
            "m": (value: 1.5, unit: "kg", description: "the mass"),
            "k": (value: 100, unit: "N/m"),
            "b": (value: 2.0),
        },
        inputs: { "F": (unit: "N") },
        elements: {
            "force": Se(effort: "F"),
            "j": One,
            "mass": I(inertance: "m"),
            "spring": C(stiffness: "k"),
            "damper": R(resistance: "b"),
        },
        bonds: [("force", "j"), ("j", "mass"), Bond("j", "spring"), ("j", "damper")],
    )
"#;

#[test]
fn reads_a_whole_model_in_file_order() {
    let model = from_ron(MODEL).unwrap();
    assert_eq!(model.name, "mass-spring-damper");
    assert_eq!(
        model.description.as_deref(),
        Some("a mass on a spring and a damper")
    );
    let names: Vec<&str> = model.parameters.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["m", "k", "b"]);
    assert_eq!(
        model.parameters[0].1,
        ParameterSpec {
            value: 1.5,
            unit: Some("kg".into()),
            description: Some("the mass".into()),
            bounds: None,
        }
    );
    assert_eq!(model.parameters[1].1.value, 100.0);
    assert_eq!(model.inputs[0].0, "F");
    assert_eq!(model.inputs[0].1.unit.as_deref(), Some("N"));
    let elements: Vec<(&str, &ElementSpec)> = model
        .elements
        .iter()
        .map(|(n, e)| (n.as_str(), e))
        .collect();
    assert_eq!(
        elements,
        [
            ("force", &ElementSpec::Se { effort: "F".into() }),
            ("j", &ElementSpec::One),
            (
                "mass",
                &ElementSpec::I {
                    inertance: Some("m".into()),
                    flow: None,
                    symbol: None,
                }
            ),
            (
                "spring",
                &ElementSpec::C {
                    compliance: None,
                    stiffness: Some("k".into()),
                    effort: None,
                    symbol: None,
                }
            ),
            (
                "damper",
                &ElementSpec::R {
                    resistance: Some("b".into()),
                    effort: None,
                    flow: None,
                }
            ),
        ]
    );
    assert_eq!(model.bonds[2], BondSpec("j".into(), "spring".into()));
    assert_eq!(model.bonds.len(), 4);
}

#[test]
fn the_model_name_is_optional_and_sections_default_to_empty() {
    let model = from_ron(r#"(name: "empty")"#).unwrap();
    assert_eq!(model.name, "empty");
    assert_eq!(model.description, None);
    assert!(model.parameters.is_empty() && model.inputs.is_empty());
    assert!(model.elements.is_empty() && model.bonds.is_empty());
    let named = from_ron(MODEL).unwrap();
    let unnamed = from_ron(MODEL.replacen("Model(", "(", 1).as_str()).unwrap();
    assert_eq!(named, unnamed);
}

#[test]
fn duplicate_names_are_kept_for_later_diagnosis() {
    let model = from_ron(
        r#"(name: "d", parameters: {"m": (value: 1), "m": (value: 2)},
            elements: {"a": Zero, "b": One, "a": I(inertance: "m")})"#,
    )
    .unwrap();
    let values: Vec<f64> = model.parameters.iter().map(|(_, p)| p.value).collect();
    assert_eq!(values, [1.0, 2.0]);
    let names: Vec<&str> = model.elements.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["a", "b", "a"]);
}

#[test]
fn explicit_some_and_every_element_kind_are_accepted() {
    let model = from_ron(
        r#"(name: "all", description: Some("d"), elements: {
            "se": Se(effort: "e"), "sf": Sf(flow: "f"), "i": I(inertance: "m"),
            "c": C(compliance: "1/k"), "r": R(resistance: "b"), "tf": TF(ratio: "n"),
            "gy": GY(ratio: "K"), "z": Zero, "o": One, "cc": C(),
        })"#,
    )
    .unwrap();
    assert_eq!(model.description.as_deref(), Some("d"));
    assert_eq!(model.elements.len(), 10);
    assert_eq!(
        model.elements[3].1,
        ElementSpec::C {
            compliance: Some("1/k".into()),
            stiffness: None,
            effort: None,
            symbol: None,
        }
    );
    // Neither or both of compliance and stiffness is the validator's business.
    assert_eq!(
        model.elements[9].1,
        ElementSpec::C {
            compliance: None,
            stiffness: None,
            effort: None,
            symbol: None,
        }
    );
}

#[test]
fn unknown_fields_are_denied_everywhere() {
    let cases = [
        r#"(name: "x", extra: 1)"#,
        r#"(name: "x", parameters: {"m": (value: 1, units: "kg")})"#,
        r#"(name: "x", inputs: {"u": (value: 1)})"#,
        r#"(name: "x", elements: {"m": I(inertance: "m", mass: "m")})"#,
        r#"(name: "x", elements: {"c": C(compliance: "m", damping: "b")})"#,
    ];
    for case in cases {
        let error = from_ron(case).unwrap_err();
        assert!(
            matches!(error.code, ron::Error::NoSuchStructField { .. }),
            "{case}: {error}"
        );
    }
}
