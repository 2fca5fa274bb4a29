//! Model (and scenario) file text to a [`ModelSpec`] and its [`SourceMap`], or one diagnostic.
//!
//! ron reports an error as a code and a position phrased for programmers; users need the
//! element named and the token underlined, so each error becomes one [`Diagnostic`] worded
//! in the model's own terms (`parse/diagnose.rs`).
//!
//! Scenario files are RON of the same shape (a struct of fields whose sections are maps
//! of named entries or lists), so [`parse_file`] reads them with the same machinery and
//! [`FileKind`] supplies the few words that differ (`scenario`, `Scenario(...)`).
//!
//! ron stops at the first error, so a file that does not parse gives exactly one
//! diagnostic; checks of the parsed model, which can report many, come later.

use serde::de::DeserializeOwned;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics};
use bondgraph_core::source::{SourceFile, Span};

use crate::source_map::skip_trivia;
use bondgraph_core::model::ModelSpec;
use bondgraph_core::model::source_map::SourceMap;

mod diagnose;
use diagnose::diagnose;

/// Which kind of file is read: the words diagnostics use for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileKind {
    /// A model file, `Model(...)`.
    Model,
    /// A scenario file, `Scenario(...)`.
    Scenario,
    /// A model extension, `Extension(...)`.
    Extension,
    /// A linear-graph model file, `LinearGraph(...)`.
    LinearGraph,
}

impl FileKind {
    /// What messages call the file's top-level value: "model", "scenario".
    pub fn noun(self) -> &'static str {
        match self {
            FileKind::Model => "model",
            FileKind::Scenario => "scenario",
            FileKind::Extension => "extension",
            FileKind::LinearGraph => "linear graph",
        }
    }

    /// The optional struct name around the top-level value: "Model", "Scenario".
    pub fn struct_name(self) -> &'static str {
        match self {
            FileKind::Model => "Model",
            FileKind::Scenario => "Scenario",
            FileKind::Extension => "Extension",
            FileKind::LinearGraph => "LinearGraph",
        }
    }
}

/// Parses a model file into its raw model and the spans of its parts.
///
/// An empty (or blank, or comments-only) file gives an [`DiagnosticKind::EmptyModel`]
/// diagnostic; text that is not a model gives one diagnostic of kind `Syntax`,
/// `UnknownField`, `UnknownElementKind`, `MissingField` or `WrongType`, located at the
/// offending token and naming the element, parameter, input or bond it is in.
///
/// The source map normally covers every entry and bond of the raw model, one for one; if
/// the scanner cannot read a text that ron accepted, it covers what it could read.
pub fn parse_model(file: &SourceFile) -> Result<(ModelSpec, SourceMap), Diagnostics> {
    parse_file(file, FileKind::Model)
}

/// Parses a file of `kind` into `T` (read with [`ron_options`])
/// and the spans of its parts, as [`parse_model`] does for models: an empty file, or text
/// that is not a `T`, gives one located diagnostic.
pub fn parse_file<T: DeserializeOwned>(
    file: &SourceFile,
    kind: FileKind,
) -> Result<(T, SourceMap), Diagnostics> {
    let text = file.text();
    if skip_trivia(text, 0) == Ok(text.len()) {
        let diagnostic_kind = match kind {
            FileKind::Model | FileKind::LinearGraph => DiagnosticKind::EmptyModel,
            FileKind::Scenario | FileKind::Extension => DiagnosticKind::Syntax,
        };
        return Err(Diagnostic::new(
            diagnostic_kind,
            format!("the file is empty; expected a {}(...)", kind.struct_name()),
        )
        .at(file, Span::new(0, 0))
        .into());
    }
    match ron_options().from_str::<T>(text) {
        Ok(value) => {
            let map = crate::source_map::scan(text)
                .unwrap_or_else(|| crate::source_map::scan_partial(text));
            Ok((value, map))
        }
        Err(error) => Err(diagnose(file, &error, kind).into()),
    }
}

/// The ron options every file is read with: optional fields written without `Some(...)`.
pub fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A valid model; tests replace one line of it to make one mistake.
    const MODEL: &str = r#"// A mass on a spring, pushed.
Model(
    name: "oscillator",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "k": (value: 50.0, unit: "N/m"),
    },
    inputs: { "F": (unit: "N") },
    elements: {
        "push": Se(effort: "F"),
        "j": One,
        "mass": I(inertance: "m"),
        "spring": C(stiffness: "k"),
    },
    bonds: [
        ("push", "j"),
        ("j", "mass"),
        ("j", "spring"),
    ],
)
"#;

    /// The model with `from` replaced by `to` (which must occur exactly once).
    fn with(from: &str, to: &str) -> String {
        assert_eq!(MODEL.matches(from).count(), 1, "{from:?}");
        MODEL.replace(from, to)
    }

    /// Parses `text` expecting one diagnostic; returns it with its line and column.
    fn diagnose(text: &str) -> (Diagnostic, usize, usize) {
        let file = SourceFile::new("models/test.ron", text);
        let diagnostics = match parse_model(&file) {
            Ok(_) => panic!("parsed:\n{text}"),
            Err(diagnostics) => diagnostics,
        };
        assert_eq!(diagnostics.0.len(), 1);
        let diagnostic = diagnostics.first().clone();
        let location = diagnostic.location.clone().expect("located");
        assert_eq!(location.file, "models/test.ron");
        (diagnostic, location.line, location.column)
    }

    /// The text a diagnostic's span covers.
    fn underlined(text: &str, diagnostic: &Diagnostic) -> String {
        let span = diagnostic
            .location
            .as_ref()
            .map(|l| l.span)
            .unwrap_or_default();
        text[span.start..span.end].to_string()
    }

    #[test]
    fn a_valid_model_parses_with_a_matching_source_map() {
        let file = SourceFile::new("m.ron", MODEL);
        let (model, map) = parse_model(&file).unwrap();
        assert_eq!(model.name, "oscillator");
        let keys: Vec<&str> = map.elements.iter().map(|e| e.key.as_str()).collect();
        let names: Vec<&str> = model.elements.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(keys, names);
        assert_eq!(map.bonds.len(), model.bonds.len());
        assert_eq!(map.parameters.len(), 2);
        let (line, column) = file.line_col(map.elements[2].key_span.start);
        assert_eq!((line, column), (12, 9));
    }

    #[test]
    fn unusual_but_valid_ron_still_gets_a_complete_source_map() {
        let text = r##"#![enable(implicit_some)]
            /* leading /* nested */ comment */ (
            name: r#"odd "name""#, description: Some("\u{e9}t\u{e9}"),
            parameters: {"a": (value: 1_000), "b": (value: -inf), "c": (value: +0.5e-3,),
                r"d": Parameter(value: 2, unit: None)},
            elements: {"x": r#Zero, "y": Se(effort: r#"a"#,), "y": C(stiffness: "b",
                compliance: Some("c"))},
            bonds: [Bond("x", "y",), ("y", r"x")],
        )"##;
        let file = SourceFile::new("m.ron", text);
        let (model, map) = parse_model(&file).unwrap();
        assert_eq!(map.parameters.len(), model.parameters.len());
        assert_eq!(map.elements.len(), model.elements.len());
        assert_eq!(map.bonds.len(), model.bonds.len());
        let keys: Vec<&str> = map.parameters.iter().map(|e| e.key.as_str()).collect();
        assert_eq!(keys, ["a", "b", "c", "d"]);
        let ends: Vec<&str> = map.bonds[1]
            .strings
            .iter()
            .map(|(n, _)| n.as_str())
            .collect();
        assert_eq!(ends, ["y", "x"]);
        assert_eq!(map.elements[0].kind.as_deref(), Some("Zero"));
    }

    #[test]
    fn empty_files() {
        for text in ["", "  \n\t\n", "// nothing here\n/* nor here */\n"] {
            let (d, line, column) = diagnose(text);
            assert_eq!(d.kind, DiagnosticKind::EmptyModel);
            assert_eq!(d.message, "the file is empty; expected a Model(...)");
            assert_eq!((line, column, d.element.as_deref()), (1, 1, None));
        }
    }

    #[test]
    fn unknown_field_in_an_element() {
        let text = with("I(inertance: \"m\")", "I(inertia: \"m\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(
            d.message,
            "element 'mass': unknown field 'inertia'; expected one of 'inertance', 'flow', 'symbol'"
        );
        assert_eq!((line, column), (12, 19));
        assert_eq!(d.element.as_deref(), Some("mass"));
        assert_eq!(underlined(&text, &d), "inertia");
    }

    #[test]
    fn unknown_field_in_a_parameter_and_in_the_model() {
        let text = with("unit: \"kg\"", "units: \"kg\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(
            d.message,
            "parameter 'm': unknown field 'units'; expected one of 'value', 'unit', 'description', 'bounds'"
        );
        assert_eq!((line, column), (5, 27));
        assert_eq!(d.element.as_deref(), Some("m"));

        let text = with(
            "    name: \"oscillator\",",
            "    name: \"oscillator\",\n    author: \"me\",",
        );
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(
            d.message,
            "unknown field 'author' in the model; expected one of 'name', 'description', \
             'parameters', 'inputs', 'elements', 'bonds', 'ports'"
        );
        assert_eq!((line, column, d.element.as_deref()), (4, 5, None));
    }

    #[test]
    fn another_tools_parts_field_is_told_how_parts_are_written_here() {
        let text = with(
            "    name: \"oscillator\",",
            "    name: \"oscillator\",\n    models: {},",
        );
        let (d, line, _) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(line, 4);
        assert_eq!(
            d.notes,
            [
                "a model built from parts uses each part as an element, \"front\": \
              Submodel(file: \"part.ron\"), and bonds to its ports, \"front.port\""
            ]
        );
    }

    #[test]
    fn unknown_element_kind() {
        let text = with("Se(effort: \"F\")", "Q(effort: \"F\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownElementKind);
        assert_eq!(
            d.message,
            "element 'push': unknown element kind 'Q'; expected one of Se, Sf, I, C, R, TF, GY, Friction, TensionOnly, FlowLimit, Submodel, Zero, One"
        );
        assert_eq!((line, column), (10, 17));
        assert_eq!(d.element.as_deref(), Some("push"));
        assert_eq!(underlined(&text, &d), "Q");
    }

    #[test]
    fn missing_fields() {
        let text = with("(value: 50.0, unit: \"N/m\")", "(unit: \"N/m\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::MissingField);
        assert_eq!(d.message, "parameter 'k': missing field 'value'");
        assert_eq!((line, column), (6, 14));
        assert_eq!(d.element.as_deref(), Some("k"));
        assert_eq!(underlined(&text, &d), "(unit: \"N/m\")");

        // An inertia may be given by its inertance or a nonlinear law, so which is missing
        // is the validator's to say, at the same place.
        let text = with("I(inertance: \"m\")", "I()");
        let error = crate::model::load_str("models/test.ron", &text).unwrap_err();
        let d = error.first();
        let location = d.location.clone().expect("located");
        assert_eq!(d.kind, DiagnosticKind::MissingField);
        assert_eq!(d.message, "element 'mass': missing field 'inertance'");
        assert_eq!(
            (location.line, location.column, d.element.as_deref()),
            (12, 17, Some("mass"))
        );

        let text = with("    name: \"oscillator\",\n", "");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::MissingField);
        assert_eq!(d.message, "missing field 'name' in the model");
        assert_eq!((line, column, d.element.as_deref()), (2, 1, None));
    }

    #[test]
    fn wrong_types() {
        let text = with("value: 2.0", "value: \"2.0\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "parameter 'm': field 'value' must be a number, found \"2.0\""
        );
        assert_eq!((line, column, d.element.as_deref()), (5, 22, Some("m")));

        let text = with("C(stiffness: \"k\")", "C(stiffness: k)");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "element 'spring': field 'stiffness' must be a string in double quotes, found 'k'"
        );
        assert_eq!(
            d.notes,
            ["strings are written in double quotes, as in \"k\""]
        );
        assert_eq!(
            (line, column, d.element.as_deref()),
            (13, 32, Some("spring"))
        );

        let text = with("inputs: { \"F\": (unit: \"N\") }", "inputs: [\"F\"]");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "field 'inputs' must be a map {\"name\": ..., ...}, found '['"
        );
        assert_eq!((line, column, d.element.as_deref()), (8, 13, None));

        let text = with("(\"j\", \"mass\")", "(\"j\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "bond 2: expected two element names (\"from\", \"to\"), found one"
        );
        assert_eq!((line, column, d.element.as_deref()), (17, 9, None));
        assert_eq!(underlined(&text, &d), "(\"j\")");

        let text = with("Model(", "Modle(");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "expected Model(...) or just (...) around the model, found 'Modle'"
        );
        assert_eq!((line, column), (2, 1));
    }

    #[test]
    fn syntax_errors_inside_an_element() {
        let text = with("I(inertance: \"m\")", "I(inertance: \"m\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'mass': expected a field name, found \"spring\""
        );
        // The next entry's key, on the line after.
        assert_eq!((line, column, d.element.as_deref()), (13, 9, Some("mass")));

        let text = with("I(inertance: \"m\"),", "I(inertance: \"m\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'mass': expected ',' or ')', found \"spring\""
        );
        assert_eq!((line, column, d.element.as_deref()), (13, 9, Some("mass")));

        // The string runs on to the next line's quote.
        let text = with("I(inertance: \"m\")", "I(inertance: \"m)");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'mass': expected ',' or ')', found 'spring'"
        );
        assert_eq!(
            d.notes,
            ["the string at line 12, column 30 runs on to line 13; is a closing '\"' missing?"]
        );
        assert_eq!((line, column, d.element.as_deref()), (13, 10, Some("mass")));

        let text = with("\"j\": One", "\"j\": One()");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'j': a One junction has no fields; write just One"
        );
        assert_eq!((line, column, d.element.as_deref()), (11, 17, Some("j")));

        let text = with("I(inertance: \"m\")", "I");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "element 'mass': expected '(' after I, found ','");
        assert_eq!((line, column, d.element.as_deref()), (12, 18, Some("mass")));
    }

    #[test]
    fn syntax_errors_outside_elements() {
        let text = format!("{MODEL}extra\n");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "unexpected 'extra' after the end of the model");
        assert_eq!((line, column, d.element.as_deref()), (21, 1, None));

        let text = MODEL.trim_end().trim_end_matches(')');
        let (d, line, column) = diagnose(text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "unexpected end of file; expected ')'");
        assert_eq!(d.notes, ["the '(' at line 2, column 6 is never closed"]);
        assert_eq!((line, column, d.element.as_deref()), (20, 1, None));

        let text = with(
            "\"m\": (value: 2.0, unit: \"kg\"),\n",
            "\"m\": (value: 2.0, unit: \"kg\")\n",
        );
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "expected ',' or '}' after parameter 'm', found \"k\""
        );
        // Where the ',' belongs: right after the entry.
        assert_eq!((line, column, d.element.as_deref()), (5, 38, Some("m")));
        assert!(underlined(&text, &d).is_empty());

        let text = with("(\"push\", \"j\"),", "(\"push\", \"j\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "expected ',' or ']' after bond 1 ('push' -> 'j'), found '('"
        );
        assert_eq!((line, column, d.element.as_deref()), (16, 22, None));

        let text = with("// A mass", "/* A mass");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "unclosed block comment: no closing '*/'");
        assert_eq!((line, column), (1, 1));
    }

    #[test]
    fn syntax_errors_in_bonds() {
        let text = with("(\"j\", \"spring\")", "(\"j\", \"spring)");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "bond 3: unterminated string: no closing '\"'");
        assert_eq!((line, column, d.element.as_deref()), (18, 15, None));

        let text = with("(\"j\", \"spring\")", "(\"j\", \"spring\", \"mass\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "bond 3: a bond names exactly two elements (\"from\", \"to\"), \
             found another item \"mass\""
        );
        assert_eq!((line, column, d.element.as_deref()), (18, 25, None));
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let text = with("\"mass\": I(inertance", "\"mäßé\": I(inertia");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(d.element.as_deref(), Some("mäßé"));
        assert_eq!((line, column), (12, 19));
        assert_eq!(underlined(&text, &d), "inertia");
    }

    /// Checks the contract for any text: no panic, and an error is one located diagnostic
    /// whose span lies on character boundaries inside the text.
    fn check_any(text: &str) {
        let file = SourceFile::new("fuzz.ron", text);
        if let Err(diagnostics) = parse_model(&file) {
            assert_eq!(diagnostics.0.len(), 1);
            let location = diagnostics.first().location.clone().expect("located");
            let span = location.span;
            assert!(span.start <= span.end && span.end <= text.len(), "{span:?}");
            assert!(text.is_char_boundary(span.start) && text.is_char_boundary(span.end));
            assert!(!diagnostics.first().message.is_empty());
        }
    }

    proptest::proptest! {
        #[test]
        fn any_ron_like_text_gives_a_located_diagnostic_or_a_model(
            text in "[ (){}\\[\\]:,\"'#!/*\\\\a-zA-Z0-9_.+\\-\né€]{0,120}"
        ) {
            check_any(&text);
        }

        #[test]
        fn any_damaged_model_gives_a_located_diagnostic_or_a_model(
            cut in 0..MODEL.len(),
            len in 0_usize..12,
            insert in "[ (){}\\[\\]:,\"'#/*a-z0-9é]{0,3}",
        ) {
            let mut text = MODEL.to_string();
            let start = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
            let end = (start + len..=text.len())
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(text.len());
            text.replace_range(start..end, &insert);
            check_any(&text);
            check_any(&text[..start]);
        }
    }

    #[test]
    fn hostile_nesting_is_an_error_not_a_crash() {
        let deep = format!(
            "(name: \"x\", description: {}1{})",
            "[".repeat(50_000),
            "]".repeat(50_000)
        );
        check_any(&deep);
        let open = format!("(name: \"x\", elements: {{\"a\": {}", "(".repeat(50_000));
        check_any(&open);
        let comments = format!("{}(name: \"x\")", "/*".repeat(10_000));
        check_any(&comments);
    }
}
