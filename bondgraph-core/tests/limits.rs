//! Inputs beyond the documented limits of `bondgraph_core::limits` are refused quickly with
//! a diagnostic at the expression, instead of exhausting memory.

use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_core::limits::{MAX_EXPRESSION_DEGREE, MAX_EXPRESSION_TERMS};
use bondgraph_core::model;

/// A mass-spring whose mass is `inertance`, written on line 4 of the file.
fn with_inertance(inertance: &str) -> String {
    format!(
        r#"Model(
    name: "big",
    parameters: {{ "m": (value: 1.0), "k": (value: 1.0), "b": (value: 1.0) }},
    elements: {{ "v": One, "mass": I(inertance: "{inertance}"), "spring": C(stiffness: "k") }},
    bonds: [("v", "mass"), ("v", "spring")],
)"#
    )
}

fn refusal(inertance: &str) -> (String, bondgraph_core::diagnostics::Diagnostic) {
    let error = model::load_str("big.ron", &with_inertance(inertance)).unwrap_err();
    let first = error.first().clone();
    (error.to_string(), first)
}

/// `(m+k+b)^300` has 45 451 terms of degree 300; it once took 3.9 GB and an abort.
#[test]
fn a_power_that_expands_too_far_is_refused_at_its_line() {
    let (text, diagnostic) = refusal("(m+k+b)^300");
    assert_eq!(diagnostic.kind, DiagnosticKind::TooLarge, "{text}");
    assert_eq!(diagnostic.element.as_deref(), Some("mass"));
    let location = diagnostic.location.expect("located");
    assert_eq!(location.line, 4, "{text}");
    assert!(text.contains("degree 300"), "{text}");
    assert!(text.contains(&MAX_EXPRESSION_DEGREE.to_string()), "{text}");
}

/// Within the degree limit but over the term limit: `(m+k+b+1)^12` has C(15, 3) = 455
/// terms, and its square (degree 24) C(27, 3) = 2925 terms, over the limit of 1000.
#[test]
fn a_product_with_too_many_terms_is_refused() {
    const { assert!(2925 > MAX_EXPRESSION_TERMS && 24 <= MAX_EXPRESSION_DEGREE) };
    let (text, diagnostic) = refusal("(m+k+b+1)^12*(m+k+b+1)^12");
    assert_eq!(diagnostic.kind, DiagnosticKind::TooLarge, "{text}");
    assert!(text.contains("2925 terms"), "{text}");
}

/// At the degree limit a power is kept: `(m+k+b)^32` has C(34, 2) = 561 terms; one more
/// degree is refused.
#[test]
fn powers_up_to_the_limit_are_kept() {
    assert_eq!(MAX_EXPRESSION_DEGREE, 32);
    let text = with_inertance("(m+k+b)^32");
    if let Err(e) = model::load_str("ok.ron", &text) {
        panic!("{e}");
    }
    let (text, diagnostic) = refusal("(m+k+b)^33");
    assert_eq!(diagnostic.kind, DiagnosticKind::TooLarge, "{text}");
}

/// In a nonlinear law the parameter-only part is exact algebra too, and bounded alike.
#[test]
fn a_nonlinear_law_with_a_huge_parameter_power_is_refused() {
    let text = with_inertance("m").replace(
        r#""spring": C(stiffness: "k")"#,
        r#""spring": C(effort: "(m+k+b)^300*sin(q_spring)")"#,
    );
    let error = model::load_str("big.ron", &text).unwrap_err();
    let diagnostic = error.first();
    assert!(error.to_string().contains("degree 300"), "{error}");
    assert_eq!(diagnostic.element.as_deref(), Some("spring"), "{error}");
}
