//! Every diagnostic a user can meet, one model file each in `tests/fixtures/invalid/`.
//!
//! Each test checks the first diagnostic twice: through the library (its kind, the exact
//! line and column, the element it names, the text it underlines, its message) and through
//! the `bondgraph` program (exit code 1 rather than a panic's 101, and a rustc-style block
//! on stderr with `path:line:col`, the element's name, the offending line and a caret under
//! the column). Lines and columns are counted by hand from the fixture.

use std::process::Command;

use bondgraph_core::equations;
use bondgraph_core::laws;
use bondgraph_core::model;
use bondgraph_core::{Diagnostic, DiagnosticKind, Diagnostics};

use crate::support::{ron_files, root};

const DIR: &str = "tests/fixtures/invalid";

/// What a fixture's first diagnostic must be.
pub(crate) struct Expect {
    pub(crate) kind: DiagnosticKind,
    pub(crate) line: usize,
    pub(crate) column: usize,
    /// The element (or parameter, or input) it names, if any.
    pub(crate) element: Option<&'static str>,
    /// The text of the file its span covers.
    pub(crate) underlined: &'static str,
    pub(crate) message: &'static str,
}

/// Loads the fixture `name` and, if it loads, derives its equations; returns every
/// diagnostic of the first stage that fails, after checking the first against `expect`
/// through the library and through the program.
fn check(name: &str, expect: Expect) -> Diagnostics {
    check_file(&format!("{DIR}/{name}.ron"), expect)
}

/// [`check`] for the fixture at `path` (relative to the root).
pub(crate) fn check_file(path: &str, expect: Expect) -> Diagnostics {
    let path = path.to_string();
    let text = std::fs::read_to_string(root().join(&path)).expect("fixture exists");
    assert!(
        text.starts_with("//"),
        "{path}: start with a comment saying what is wrong"
    );
    let diagnostics = match bondgraph_ron::model::load_str(&path, &text) {
        Err(diagnostics) => diagnostics,
        Ok(model) => {
            let laws = laws::plain_laws(&model);
            match equations::derive(&model, &laws, &equations::Options::default()) {
                // In a linear graph's words, as the program prints them.
                Err(diagnostics) => model::linear_graph::reword(&model, diagnostics),
                Ok(_) => panic!("{path}: loads and derives without a diagnostic"),
            }
        }
    };
    let first = diagnostics.first();
    let location = first
        .location
        .as_ref()
        .expect("the diagnostic has a location");
    assert_eq!(first.kind, expect.kind, "{path}: kind of {first}");
    assert_eq!(location.file, path);
    assert_eq!(
        (location.line, location.column),
        (expect.line, expect.column),
        "{path}: line and column of {first}"
    );
    assert_eq!(first.element.as_deref(), expect.element, "{path}: element");
    assert_eq!(
        &text[location.span.start..location.span.end],
        expect.underlined,
        "{path}: underlined text"
    );
    assert_eq!(first.message, expect.message, "{path}: message");
    if let Some(element) = expect.element {
        assert!(
            first.message.contains(&format!("'{element}'")),
            "{path}: the message names '{element}'"
        );
    }

    for command in ["check", "equations"] {
        check_program(command, &path, &text, first);
    }
    diagnostics
}

/// Runs `bondgraph COMMAND path` and checks it fails cleanly and shows `first` as a
/// located block with a caret under its column.
fn check_program(command: &str, path: &str, text: &str, first: &Diagnostic) {
    let output = Command::new(env!("CARGO_BIN_EXE_bondgraph"))
        .args([command, path])
        .current_dir(root())
        .output()
        .expect("the program runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    let what = format!("bondgraph {command} {path}");
    assert_eq!(output.status.code(), Some(1), "{what}: exit code\n{stderr}");
    assert!(!stderr.contains("panicked"), "{what}: panicked\n{stderr}");
    assert!(output.stdout.is_empty(), "{what}: wrote to stdout");

    let location = first.location.as_ref().expect("located");
    let (line, column) = (location.line, location.column);
    let gutter = " ".repeat(line.to_string().len());
    assert!(
        stderr.starts_with(&format!("error: {}\n", first.message)),
        "{what}: message first\n{stderr}"
    );
    assert!(
        stderr.contains(&format!("{gutter}--> {path}:{line}:{column}\n")),
        "{what}: path:line:col\n{stderr}"
    );
    let source_line = text.lines().nth(line - 1).unwrap_or("");
    let snippet = format!("{line} | {source_line}");
    assert!(
        stderr.contains(snippet.trim_end()),
        "{what}: the offending line\n{stderr}"
    );
    let caret = format!("{gutter} | {}^", " ".repeat(column - 1));
    assert!(
        stderr.lines().any(|l| l.starts_with(&caret)),
        "{what}: a caret under column {column}\n{stderr}"
    );
    if let Some(element) = &first.element {
        assert!(
            stderr.contains(&format!("'{element}'")),
            "{what}: names '{element}'\n{stderr}"
        );
    }
}

/// The fixture names (file stems) in the fixtures directory.
fn fixtures() -> Vec<String> {
    ron_files(DIR)
        .iter()
        .map(|path| {
            path.rsplit('/')
                .next()
                .and_then(|file| file.strip_suffix(".ron"))
                .expect("a .ron file")
                .to_string()
        })
        .collect()
}

#[test]
fn every_fixture_has_its_test() {
    let source = include_str!("diagnostics.rs");
    let fixtures = fixtures();
    assert!(fixtures.len() >= 30, "fixtures found: {fixtures:?}");
    for name in fixtures {
        assert!(
            source.contains(&format!("fn {name}() {{")) && source.contains(&format!("\"{name}\"")),
            "{DIR}/{name}.ron has no test `fn {name}()` calling check(\"{name}\", ...)"
        );
    }
}

// RON syntax and shape.

#[test]
fn empty_file() {
    check(
        "empty_file",
        Expect {
            kind: DiagnosticKind::EmptyModel,
            line: 1,
            column: 1,
            element: None,
            underlined: "",
            message: "the file is empty; expected a Model(...)",
        },
    );
}

#[test]
fn syntax_error() {
    // The ',' belongs right after `I(inertance: "m")` on line 15.
    check(
        "syntax_error",
        Expect {
            kind: DiagnosticKind::Syntax,
            line: 15,
            column: 34,
            element: Some("mass"),
            underlined: "",
            message: "expected ',' or '}' after element 'mass', found \"spring\"",
        },
    );
}

#[test]
fn unknown_element_kind() {
    check(
        "unknown_element_kind",
        Expect {
            kind: DiagnosticKind::UnknownElementKind,
            line: 14,
            column: 17,
            element: Some("mass"),
            underlined: "Mass",
            message: "element 'mass': unknown element kind 'Mass'; expected one of Se, Sf, I, C, \
                      R, TF, GY, Friction, TensionOnly, FlowLimit, Submodel, Zero, One",
        },
    );
}

#[test]
fn unknown_field() {
    check(
        "unknown_field",
        Expect {
            kind: DiagnosticKind::UnknownField,
            line: 14,
            column: 19,
            element: Some("mass"),
            underlined: "mass",
            message: "element 'mass': unknown field 'mass'; expected one of 'inertance', 'flow', 'symbol'",
        },
    );
}

#[test]
fn missing_field() {
    check(
        "missing_field",
        Expect {
            kind: DiagnosticKind::MissingField,
            line: 15,
            column: 19,
            element: Some("damper"),
            underlined: "R()",
            message: "element 'damper': missing field 'resistance'",
        },
    );
}

#[test]
fn wrong_type() {
    check(
        "wrong_type",
        Expect {
            kind: DiagnosticKind::WrongType,
            line: 14,
            column: 32,
            element: Some("spring"),
            underlined: "200.0",
            message: "element 'spring': field 'stiffness' must be a string in double quotes, \
                      found '200.0'",
        },
    );
}

// Names.

#[test]
fn duplicate_element() {
    let d = check(
        "duplicate_element",
        Expect {
            kind: DiagnosticKind::DuplicateName,
            line: 17,
            column: 9,
            element: Some("spring"),
            underlined: "\"spring\"",
            message: "element 'spring' is defined twice",
        },
    );
    assert_eq!(d.first().notes, ["first defined on line 16"]);
}

#[test]
fn duplicate_parameter() {
    let d = check(
        "duplicate_parameter",
        Expect {
            kind: DiagnosticKind::DuplicateName,
            line: 7,
            column: 9,
            element: Some("k"),
            underlined: "\"k\"",
            message: "parameter 'k' is defined twice",
        },
    );
    assert_eq!(d.first().notes, ["first defined on line 6"]);
}

#[test]
fn duplicate_input() {
    let d = check(
        "duplicate_input",
        Expect {
            kind: DiagnosticKind::DuplicateName,
            line: 10,
            column: 9,
            element: Some("F"),
            underlined: "\"F\"",
            message: "input 'F' is defined twice",
        },
    );
    assert_eq!(d.first().notes, ["first defined on line 9"]);
}

#[test]
fn parameter_and_input() {
    let d = check(
        "parameter_and_input",
        Expect {
            kind: DiagnosticKind::DuplicateName,
            line: 11,
            column: 9,
            element: Some("F"),
            underlined: "\"F\"",
            message: "'F' is both a parameter and an input",
        },
    );
    assert_eq!(d.first().notes, ["first defined on line 8"]);
}

// Bonds and the graph.

#[test]
fn undefined_element() {
    let d = check(
        "undefined_element",
        Expect {
            kind: DiagnosticKind::UndefinedElement,
            line: 23,
            column: 21,
            element: Some("dampr"),
            underlined: "dampr",
            message: "bond v_mass -> dampr names 'dampr', which is not an element of the model",
        },
    );
    assert_eq!(d.first().notes, ["did you mean 'damper'?"]);
    // And so the damper is left without a bond.
    assert_eq!(d.0.len(), 2);
    assert_eq!(d.0[1].kind, DiagnosticKind::BondCount);
    assert_eq!(d.0[1].element.as_deref(), Some("damper"));
}

#[test]
fn self_bond() {
    check(
        "self_bond",
        Expect {
            kind: DiagnosticKind::SelfBond,
            line: 19,
            column: 9,
            element: Some("v_mass"),
            underlined: "(\"v_mass\", \"v_mass\")",
            message: "bond v_mass -> v_mass connects element 'v_mass' to itself",
        },
    );
}

#[test]
fn one_port_two_bonds() {
    check(
        "one_port_two_bonds",
        Expect {
            kind: DiagnosticKind::BondCount,
            line: 17,
            column: 9,
            element: Some("spring"),
            underlined: "\"spring\"",
            message: "compliance 'spring' has 2 bonds (lines 23, 24); a one-port takes exactly one",
        },
    );
}

#[test]
fn one_port_no_bond() {
    check(
        "one_port_no_bond",
        Expect {
            kind: DiagnosticKind::BondCount,
            line: 17,
            column: 9,
            element: Some("damper"),
            underlined: "\"damper\"",
            message: "resistor 'damper' has no bond; it needs exactly one",
        },
    );
}

#[test]
fn tf_three_bonds() {
    check(
        "tf_three_bonds",
        Expect {
            kind: DiagnosticKind::BondCount,
            line: 15,
            column: 9,
            element: Some("gear"),
            underlined: "\"gear\"",
            message: "transformer 'gear' has 3 bonds (lines 21, 22, 23); it takes exactly two, \
                      one in and one out",
        },
    );
}

#[test]
fn tf_both_bonds_in() {
    check(
        "tf_both_bonds_in",
        Expect {
            kind: DiagnosticKind::BondCount,
            line: 15,
            column: 9,
            element: Some("lever"),
            underlined: "\"lever\"",
            message: "transformer 'lever' has 2 bonds pointing in; power must flow through it: \
                      one bond in, one out",
        },
    );
}

#[test]
fn junction_one_bond() {
    check(
        "junction_one_bond",
        Expect {
            kind: DiagnosticKind::BondCount,
            line: 16,
            column: 9,
            element: Some("node"),
            underlined: "\"node\"",
            message: "0-junction 'node' has 1 bond; a junction joins two or more",
        },
    );
}

#[test]
fn empty_elements() {
    check(
        "empty_elements",
        Expect {
            kind: DiagnosticKind::EmptyModel,
            line: 7,
            column: 5,
            element: None,
            underlined: "elements",
            message: "model 'nothing_yet' has no elements",
        },
    );
}

#[test]
fn disconnected() {
    // Located at the first element of the second piece.
    check(
        "disconnected",
        Expect {
            kind: DiagnosticKind::Disconnected,
            line: 19,
            column: 9,
            element: Some("v2"),
            underlined: "\"v2\"",
            message: "the model is in 2 pieces that no bond joins: {'force', 'v1', 'mass1', \
                      'spring1'} and {'v2', 'mass2', 'spring2'}",
        },
    );
}

// Expressions.

#[test]
fn unknown_symbol() {
    let d = check(
        "unknown_symbol",
        Expect {
            kind: DiagnosticKind::UnknownSymbol,
            line: 18,
            column: 36,
            element: Some("damper"),
            underlined: "c",
            message: "element 'damper': resistance \"2*c\" uses 'c', which is neither a \
                      parameter nor an input",
        },
    );
    // No far-fetched "did you mean 'F'?" for a one-letter name.
    assert!(d.first().notes.is_empty(), "{:?}", d.first().notes);
}

#[test]
fn unparsable_expression() {
    check(
        "unparsable_expression",
        Expect {
            kind: DiagnosticKind::BadExpression,
            line: 16,
            column: 41,
            element: Some("tank"),
            underlined: ")",
            message: "element 'tank': cannot parse compliance \"A_t/(rho*)\": expected an \
                      operand after '*', found ')'",
        },
    );
}

#[test]
fn input_in_inertance() {
    check(
        "input_in_inertance",
        Expect {
            kind: DiagnosticKind::NotLinear,
            line: 16,
            column: 31,
            element: Some("mass"),
            underlined: "m + m_load",
            message: "element 'mass': inertance \"m + m_load\" depends on input 'm_load'; it \
                      may use parameters only",
        },
    );
}

#[test]
fn product_of_inputs() {
    check(
        "product_of_inputs",
        Expect {
            kind: DiagnosticKind::NotLinear,
            line: 16,
            column: 40,
            element: Some("relief"),
            underlined: "A*gain*P_s",
            message: "element 'relief': max_flow \"A*gain*P_s\": multiplies two inputs; \
                      max_flow must be linear in the inputs, with rational functions of the \
                      parameters as coefficients",
        },
    );
}

#[test]
fn compliance_and_stiffness() {
    check(
        "compliance_and_stiffness",
        Expect {
            kind: DiagnosticKind::ConflictingFields,
            line: 15,
            column: 9,
            element: Some("spring"),
            underlined: "\"spring\"",
            message: "compliance 'spring' gives both compliance and stiffness; give one",
        },
    );
}

#[test]
fn neither_compliance_nor_stiffness() {
    check(
        "neither_compliance_nor_stiffness",
        Expect {
            kind: DiagnosticKind::MissingField,
            line: 15,
            column: 9,
            element: Some("spring"),
            underlined: "\"spring\"",
            message: "compliance 'spring' needs a compliance or a stiffness",
        },
    );
}

// Values.

#[test]
fn zero_mass() {
    check(
        "zero_mass",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 14,
            column: 31,
            element: Some("mass"),
            underlined: "m",
            message: "element 'mass': inertance \"m\" = 0 (with m = 0) must be positive",
        },
    );
}

#[test]
fn negative_mass() {
    check(
        "negative_mass",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 14,
            column: 31,
            element: Some("mass"),
            underlined: "m",
            message: "element 'mass': inertance \"m\" = -2 (with m = -2) must be positive",
        },
    );
}

#[test]
fn huge_mass() {
    // The parameter is reported where its value is written, then the mass that uses it.
    let d = check(
        "huge_mass",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 6,
            column: 22,
            element: Some("m"),
            underlined: "1e400",
            message: "parameter 'm' has value 1e400, which is too large for a 64-bit \
                      floating-point number",
        },
    );
    assert_eq!(d.0.len(), 2);
    let mass = &d.0[1];
    assert_eq!(mass.kind, DiagnosticKind::InvalidValue);
    assert_eq!(mass.element.as_deref(), Some("mass"));
    assert_eq!(
        mass.location.as_ref().map(|l| (l.line, l.column)),
        Some((15, 31))
    );
    assert_eq!(
        mass.message,
        "element 'mass': inertance \"m\" = inf (with m = inf) must be finite"
    );
}

#[test]
fn mass_divided_by_zero() {
    check(
        "mass_divided_by_zero",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 14,
            column: 33,
            element: Some("mass"),
            underlined: "0",
            message: "element 'mass': inertance \"m/0\": divides by zero",
        },
    );
}

#[test]
fn zero_stiffness() {
    check(
        "zero_stiffness",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 15,
            column: 33,
            element: Some("spring"),
            underlined: "k",
            message: "element 'spring': stiffness \"k\" = 0 (with k = 0) must be positive",
        },
    );
}

#[test]
fn negative_stiffness() {
    check(
        "negative_stiffness",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 15,
            column: 33,
            element: Some("spring"),
            underlined: "k",
            message: "element 'spring': stiffness \"k\" = -200 (with k = -200) must be positive",
        },
    );
}

#[test]
fn zero_compliance() {
    check(
        "zero_compliance",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 16,
            column: 34,
            element: Some("spring"),
            underlined: "0",
            message: "element 'spring': compliance \"0\" = 0 must be positive",
        },
    );
}

#[test]
fn negative_compliance() {
    check(
        "negative_compliance",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 16,
            column: 34,
            element: Some("spring"),
            underlined: "1/k - 1/100",
            message: "element 'spring': compliance \"1/k - 1/100\" = -0.005 (with k = 200) \
                      must be positive",
        },
    );
}

#[test]
fn infinite_compliance() {
    check(
        "infinite_compliance",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 16,
            column: 34,
            element: Some("spring"),
            underlined: "1/k",
            message: "element 'spring': compliance \"1/k\" = inf (with k = 0) must be finite",
        },
    );
}

#[test]
fn negative_resistance() {
    check(
        "negative_resistance",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 16,
            column: 36,
            element: Some("resistor"),
            underlined: "R",
            message: "element 'resistor': resistance \"R\" = -10 (with R = -10) must be zero or \
                      positive",
        },
    );
}

// Found while deriving: the model loads, its causality or equations fail.

#[test]
fn two_flow_sources() {
    check(
        "two_flow_sources",
        Expect {
            kind: DiagnosticKind::CausalConflict,
            line: 15,
            column: 9,
            element: Some("v"),
            underlined: "\"v\"",
            message: "causal conflict at 1-junction 'v': its flow is imposed by both flow \
                      source 'shaker_a' and flow source 'shaker_b'",
        },
    );
}

#[test]
fn two_effort_sources() {
    check(
        "two_effort_sources",
        Expect {
            kind: DiagnosticKind::CausalConflict,
            line: 15,
            column: 9,
            element: Some("node"),
            underlined: "\"node\"",
            message: "causal conflict at 0-junction 'node': its effort is imposed by both \
                      effort source 'battery1' and effort source 'battery2'",
        },
    );
}

#[test]
fn zero_resistance_conductance() {
    // Both supplies give the loop its effort, so the wire must take its current from its
    // voltage: i = (V1 - V2)/R_w, with R_w = 0.
    let d = check(
        "zero_resistance_conductance",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 16,
            column: 9,
            element: Some("wire"),
            underlined: "\"wire\"",
            message: "resistor 'wire' must set its flow from its effort (conductance \
                      causality), but its resistance is zero",
        },
    );
    assert_eq!(
        d.first().notes,
        ["a zero resistance is a rigid connection: replace the resistor by a bond"]
    );
}

/// Every example with one line deleted, or one bond reversed: whatever the damage, the
/// library and the program answer with located diagnostics or equations, never a panic.
#[test]
fn damaged_examples_never_panic() {
    let mut damaged = Vec::new();
    for path in ron_files("models/examples") {
        let text = std::fs::read_to_string(root().join(&path)).expect("example");
        let lines: Vec<&str> = text.lines().collect();
        for i in 0..lines.len() {
            let mut without = lines.clone();
            let removed = without.remove(i);
            damaged.push((format!("{path} without line {}", i + 1), without.join("\n")));
            // A bond `("a", "b"),` reversed.
            if let Some(bond) = removed
                .trim()
                .strip_prefix("(\"")
                .and_then(|b| b.strip_suffix("\"),"))
                && let Some((from, to)) = bond.split_once("\", \"")
            {
                let reversed = removed.replace(bond, &format!("{to}\", \"{from}"));
                let mut with = lines.clone();
                with[i] = &reversed;
                damaged.push((
                    format!("{path} with line {} reversed", i + 1),
                    with.join("\n"),
                ));
            }
        }
    }
    let mut failures = 0;
    for (what, text) in &damaged {
        let result = bondgraph_ron::model::load_str("damaged.ron", text).and_then(|model| {
            let laws = laws::plain_laws(&model);
            equations::derive(&model, &laws, &equations::Options::default()).map(|_| ())
        });
        if let Err(diagnostics) = result {
            failures += 1;
            for d in diagnostics.iter() {
                assert!(!d.message.is_empty(), "{what}: empty message");
                let location = d.location.as_ref();
                let span = location.map(|l| l.span).unwrap_or_default();
                assert!(location.is_some(), "{what}: no location for {d}");
                assert!(
                    span.start <= span.end
                        && span.end <= text.len()
                        && text.is_char_boundary(span.start)
                        && text.is_char_boundary(span.end),
                    "{what}: span {span:?} of {d}"
                );
            }
        }
    }
    let reversed = damaged
        .iter()
        .filter(|(w, _)| w.contains("reversed"))
        .count();
    assert!(reversed >= 30, "{reversed} bonds reversed");
    assert!(failures > damaged.len() / 2, "most damage is noticed");

    // The program renders them all without panicking.
    let dir = std::env::temp_dir().join(format!("bondgraph-damaged-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    for (index, (what, text)) in damaged.iter().enumerate() {
        let file = dir.join(format!("{index}.ron"));
        std::fs::write(&file, text).expect("write");
        let output = Command::new(env!("CARGO_BIN_EXE_bondgraph"))
            .arg("equations")
            .arg(&file)
            .output()
            .expect("the program runs");
        let code = output.status.code();
        assert!(
            matches!(code, Some(0 | 1)),
            "{what}: exit {code:?}\n{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn value_outside_bounds() {
    check(
        "value_outside_bounds",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 6,
            column: 50,
            element: Some("k"),
            underlined: "(0.0, 100.0)",
            message: "parameter 'k' has value 200, outside its bounds (0, 100)",
        },
    );
}

#[test]
fn stribeck_drop_depends_on_input() {
    check(
        "stribeck_drop_depends_on_input",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 12,
            column: 41,
            element: Some("contact"),
            underlined: "F_S + F",
            message: "friction contact 'contact': with a Stribeck velocity, breakaway \"F_S + F\" and Coulomb \"F_C\" must differ by an amount that does not depend on inputs",
        },
    );
}

#[test]
fn negative_stribeck() {
    check(
        "negative_stribeck",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 12,
            column: 74,
            element: Some("contact"),
            underlined: "v_s",
            message: "element 'contact': stribeck \"v_s\" = -1 (with v_s = -1) must be zero or positive",
        },
    );
}

#[test]
fn flow_limit_unknown_mode() {
    check(
        "flow_limit_unknown_mode",
        Expect {
            kind: DiagnosticKind::BadMode,
            line: 11,
            column: 57,
            element: Some("limit"),
            underlined: "closed",
            message: "element 'limit': initial mode \"closed\" is not one of \"open\", \"limiting\"",
        },
    );
}
