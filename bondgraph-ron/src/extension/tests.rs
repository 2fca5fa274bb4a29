use super::*;

pub(super) const BASE: &str = r#"// A mass pushed through a damper.
Model(
    name: "msd",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "b": (value: 4.0, unit: "N*s/m"), // the damper
    },
    inputs: { "F": (unit: "N") },
    elements: {
        "push": Se(effort: "F"),
        "v": One,
        "mass": I(inertance: "m"),
        "damper": R(resistance: "b"),
    },
    bonds: [
        ("push", "v"),
        ("v", "mass"),
        ("v", "damper"),
    ],
)
"#;

const SPRING: &str = r#"Extension(
    id: "wall-spring",
    cause: "a spring ties the mass to the wall",
    parameters: {
        "k": (value: 50.0, unit: "N/m", bounds: (0.0, 1000.0)),
    },
    elements: {
        // The spring.
        "spring": C(stiffness: "k"),
    },
    bonds: [("v", "spring")],
)
"#;

fn base() -> Arc<SourceFile> {
    SourceFile::new("models/msd.ron", BASE)
}

fn extension(name: &str, text: &str) -> Extension {
    Extension::load(&SourceFile::new(name, text)).unwrap()
}

#[test]
fn appended_entries_keep_the_base_text_and_its_comments() {
    let extended = merge(&base(), &[extension("spring.ron", SPRING)]).unwrap();
    let text = extended.file.text();
    // Every line of the base is still there, in order, except the renamed name.
    let mut rest = text;
    for line in BASE.lines().filter(|l| !l.contains("name:")) {
        let at = rest
            .find(line)
            .unwrap_or_else(|| panic!("lost line {line:?}"));
        rest = &rest[at + line.len()..];
    }
    assert!(text.contains("name: \"msd+wall-spring\""));
    assert!(text.contains(
        "\"b\": (value: 4.0, unit: \"N*s/m\"), // the damper\n        // added by extension 'wall-spring'\n        \"k\": (value: 50.0, unit: \"N/m\", bounds: (0.0, 1000.0)),\n    },"
    ));
    assert!(text.contains("(\"v\", \"damper\"),\n        // added by extension 'wall-spring'\n        (\"v\", \"spring\"),\n    ],"));
    let model = extended.load().unwrap();
    assert_eq!(model.name(), "msd+wall-spring");
    assert_eq!(model.elements().len(), 5);
    assert_eq!(model.parameters()[2].name, "k");
    assert_eq!(model.parameters()[2].bounds, Some((0.0, 1000.0)));
}

#[test]
fn a_replaced_element_is_rewritten_in_place() {
    let fragment = r#"Extension(
    id: "stiff-damper",
    cause: "the damper is twice as stiff",
    elements: { "damper": R(resistance: "2*b") },
    replace: ["damper"],
)"#;
    let extended = merge(&base(), &[extension("stiff.ron", fragment)]).unwrap();
    assert!(
        extended
            .file
            .text()
            .contains("        \"damper\": R(resistance: \"2*b\"),\n    },")
    );
    assert_eq!(extended.load().unwrap().elements().len(), 4);
}

#[test]
fn a_bond_to_an_unknown_element_is_reported_in_the_extension_file() {
    let fragment = r#"Extension(
    id: "typo",
    cause: "a typo",
    elements: { "spring": C(stiffness: "1") },
    bonds: [("v", "spring"),
        ("vv", "spring")],
)"#;
    let extended = merge(&base(), &[extension("typo.ron", fragment)]).unwrap();
    let error = extended.load().unwrap_err();
    let location = error.first().location.as_ref().unwrap();
    assert_eq!(location.file, "typo.ron");
    assert_eq!(location.line, 6);
    assert!(error.first().message.contains("vv"), "{error}");
}

#[test]
fn an_unknown_symbol_in_a_replacement_points_into_the_extension() {
    let fragment = r#"Extension(
    id: "bad",
    cause: "x",
    elements: {
        "damper": R(resistance: "b + c_missing"),
    },
    replace: ["damper"],
)"#;
    let extended = merge(&base(), &[extension("bad.ron", fragment)]).unwrap();
    let error = extended.load().unwrap_err();
    let location = error.first().location.as_ref().unwrap();
    assert_eq!((location.file.as_str(), location.line), ("bad.ron", 5));
    assert_eq!(error.first().element.as_deref(), Some("damper"));
}

#[test]
fn conflicts_with_the_base_are_located_in_the_extension() {
    let fragment = r#"Extension(
    id: "clash",
    cause: "x",
    parameters: { "b": (value: 1.0) },
    elements: {
        "mass": I(inertance: "m"),
        "dampr": R(resistance: "b"),
    },
    replace: ["dampr"],
)"#;
    let error = merge(&base(), &[extension("clash.ron", fragment)]).unwrap_err();
    let lines: Vec<(usize, &str)> = error
        .0
        .iter()
        .map(|d| {
            (
                d.location.as_ref().unwrap().line,
                d.element.as_deref().unwrap(),
            )
        })
        .collect();
    assert_eq!(lines, vec![(4, "b"), (6, "mass"), (7, "dampr")]);
    assert!(error.0[1].notes[0].contains("replace"));
    assert!(error.0[2].notes[0].contains("'damper'"));
}

#[test]
fn bad_extension_files_are_refused() {
    let missing = Extension::load(&SourceFile::new(
        "r.ron",
        r#"Extension(id: "r", cause: "x", replace: ["damper"])"#,
    ))
    .unwrap_err();
    assert!(missing.first().message.contains("gives no new 'damper'"));
    let bad_id = Extension::load(&SourceFile::new(
        "i.ron",
        r#"Extension(id: "Big Id", cause: "x")"#,
    ))
    .unwrap_err();
    assert!(bad_id.first().message.contains("lower-case"));
    let unknown = Extension::load(&SourceFile::new(
        "u.ron",
        "Extension(id: \"u\", cause: \"x\",\n  elements: {\"s\": Spring(k: \"1\")})",
    ))
    .unwrap_err();
    assert_eq!(unknown.first().location.as_ref().unwrap().line, 2);
}

#[test]
fn two_extensions_merge_in_one_pass() {
    let other = r#"Extension(id: "air", cause: "air drag",
    parameters: {"c": (value: 0.5)},
    elements: {"air": R(resistance: "c")},
    bonds: [("v", "air")])"#;
    let extended = merge(
        &base(),
        &[extension("spring.ron", SPRING), extension("air.ron", other)],
    )
    .unwrap();
    let model = extended.load().unwrap();
    assert_eq!(model.name(), "msd+wall-spring+air");
    assert_eq!(model.elements().len(), 6);
    assert_eq!(extended.file.name(), "models/msd.ron+wall-spring+air");
}
