//! Inputs beyond the documented limits of `bondgraph_core::limits` are refused quickly with
//! a diagnostic at the expression, instead of exhausting memory.

use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_core::limits::{MAX_EXPRESSION_DEGREE, MAX_EXPRESSION_TERMS};

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
    let error = bondgraph_ron::model::load_str("big.ron", &with_inertance(inertance)).unwrap_err();
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
    if let Err(e) = bondgraph_ron::model::load_str("ok.ron", &text) {
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
    let error = bondgraph_ron::model::load_str("big.ron", &text).unwrap_err();
    let diagnostic = error.first();
    assert!(error.to_string().contains("degree 300"), "{error}");
    assert_eq!(diagnostic.element.as_deref(), Some("spring"), "{error}");
}

/// A chain of `n` masses, each on a friction contact with the ground and tied to the next by
/// a spring, the first pushed by `F`: every contact has three modes, so `3^n` modes.
fn contact_chain(n: usize) -> String {
    let mut elements = vec![r#""push": Se(effort: "F")"#.to_string()];
    let mut bonds = vec![r#"("push", "v1")"#.to_string()];
    for i in 1..=n {
        elements.push(format!(
            r#""v{i}": One, "m{i}": I(inertance: "m"),
        "f{i}": Friction(breakaway: "F_S", coulomb: "F_C", initial: "stuck")"#
        ));
        bonds.push(format!(r#"("v{i}", "m{i}"), ("v{i}", "f{i}")"#));
        if i < n {
            elements.push(format!(r#""s{i}": Zero, "k{i}": C(stiffness: "k")"#));
            bonds.push(format!(
                r#"("v{i}", "s{i}"), ("s{i}", "v{}"), ("s{i}", "k{i}")"#,
                i + 1
            ));
        }
    }
    format!(
        r#"Model(
    name: "chain",
    parameters: {{ "m": (value: 1.0), "k": (value: 100.0), "F_S": (value: 10.0),
        "F_C": (value: 6.0) }},
    inputs: {{ "F": () }},
    elements: {{
        {},
    }},
    bonds: [{}],
)"#,
        elements.join(",\n        "),
        bonds.join(", ")
    )
}

/// Seven contacts have 3^7 = 2187 modes, over the limit of 1000 that `check` and `modes`
/// enumerate: refused at the first contact, with the count. (Fifteen would have 14 million,
/// each derived symbolically.) Six, 729 modes, are enumerated.
#[test]
fn a_model_with_too_many_modes_is_refused_at_its_switching_elements() {
    use bondgraph_core::equations::Options;
    use bondgraph_core::limits::MAX_MODES;
    use bondgraph_core::modes;
    let six = bondgraph_ron::model::load_str("chain.ron", &contact_chain(6))
        .unwrap_or_else(|e| panic!("{e}"));
    let reachable = modes::reachable(&six, &Options::default()).unwrap();
    assert_eq!(reachable.modes.len() + reachable.impossible.len(), 729);
    let seven = bondgraph_ron::model::load_str("chain.ron", &contact_chain(7))
        .unwrap_or_else(|e| panic!("{e}"));
    let error = match modes::reachable(&seven, &Options::default()) {
        Ok(reachable) => panic!("{} modes enumerated", reachable.modes.len()),
        Err(error) => error,
    };
    let text = error.to_string();
    let diagnostic = error.first();
    assert_eq!(diagnostic.kind, DiagnosticKind::TooLarge, "{text}");
    assert!(
        text.contains(&format!("more than {MAX_MODES} modes")) && text.contains("chain.ron:9:"),
        "{text}"
    );
}
