//! Every diagnostic of the linear-graph format, one file each in
//! `tests/fixtures/invalid_linear_graph/`, checked as `diagnostics.rs` checks bond-graph
//! files: kind, line and column (counted by hand from the fixture), the branch named, the
//! text underlined and the message, through the library and through the program.

use bondgraph_core::DiagnosticKind;

use crate::diagnostics::{Expect, check_file};

use crate::support::linear_graph_files;

const DIR: &str = "tests/fixtures/invalid_linear_graph";

fn check(name: &str, expect: Expect) -> bondgraph_core::Diagnostics {
    check_file(&format!("{DIR}/{name}.lg.ron"), expect)
}

#[test]
fn every_fixture_has_its_test() {
    let source = include_str!("linear_graph_diagnostics.rs");
    let fixtures = linear_graph_files(DIR);
    assert!(fixtures.len() >= 14, "fixtures found: {fixtures:?}");
    for path in fixtures {
        let name = path
            .rsplit('/')
            .next()
            .and_then(|f| f.strip_suffix(".lg.ron"))
            .expect("a .lg.ron file");
        assert!(
            source.contains(&format!("fn {name}() {{")) && source.contains(&format!("\"{name}\"")),
            "{path} has no test `fn {name}()`"
        );
    }
}

#[test]
fn undefined_node() {
    // Line 18: `        "damper": D(conductance: "b", from: "v2", to: "g"),`, "v2" at column 46.
    check(
        "undefined_node",
        Expect {
            kind: DiagnosticKind::UndefinedNode,
            line: 18,
            column: 46,
            element: Some("damper"),
            underlined: "v2",
            message: "branch 'damper' names node 'v2', which no other branch touches",
        },
    );
}

#[test]
fn dangling_node() {
    check(
        "dangling_node",
        Expect {
            kind: DiagnosticKind::DanglingNode,
            line: 17,
            column: 54,
            element: Some("spring"),
            underlined: "wall",
            message: "node 'wall' has only one branch, 'spring': no through variable can flow through it",
        },
    );
}

#[test]
fn across_source_loop() {
    check(
        "across_source_loop",
        Expect {
            kind: DiagnosticKind::AcrossSourceLoop,
            line: 17,
            column: 9,
            element: Some("second_drive"),
            underlined: "\"second_drive\"",
            message: "across sources 'drive', 'second_drive' form a loop through nodes 'v1' and 'g': their across variables would have to sum to zero",
        },
    );
}

#[test]
fn through_source_cut_set() {
    check(
        "through_source_cut_set",
        Expect {
            kind: DiagnosticKind::ThroughSourceCutSet,
            line: 15,
            column: 9,
            element: Some("push"),
            underlined: "\"push\"",
            message: "through sources 'push', 'pull' form a cut-set: they alone join node 'n' to the rest of the graph, so their through variables would have to sum to zero",
        },
    );
}

#[test]
fn two_port_missing_pair() {
    check(
        "two_port_missing_pair",
        Expect {
            kind: DiagnosticKind::MissingField,
            line: 17,
            column: 18,
            element: Some("lever"),
            underlined: "Transformer(ratio: \"2\", primary: (\"v1\", \"g\"))",
            message: "branch 'lever': missing field 'secondary'",
        },
    );
}

#[test]
fn pieces() {
    check(
        "pieces",
        Expect {
            kind: DiagnosticKind::Disconnected,
            line: 17,
            column: 9,
            element: Some("spring"),
            underlined: "\"spring\"",
            message: "the linear graph is in 2 pieces that no branch joins: {'force', 'mass'} and {'spring', 'damper'}",
        },
    );
}

#[test]
fn separate_systems() {
    check(
        "separate_systems",
        Expect {
            kind: DiagnosticKind::Disconnected,
            line: 17,
            column: 9,
            element: Some("other_mass"),
            underlined: "\"other_mass\"",
            message: "the linear graph is in 2 parts that meet only at the ground 'g': {'force', 'mass'} and {'other_mass', 'other_spring'}",
        },
    );
}

#[test]
fn branch_to_itself() {
    check(
        "branch_to_itself",
        Expect {
            kind: DiagnosticKind::SelfBond,
            line: 17,
            column: 56,
            element: Some("damper"),
            underlined: "v1",
            message: "branch 'damper' goes from node 'v1' to node 'v1': a branch joins two different nodes",
        },
    );
}

#[test]
fn inductance_and_stiffness() {
    check(
        "inductance_and_stiffness",
        Expect {
            kind: DiagnosticKind::ConflictingFields,
            line: 17,
            column: 40,
            element: Some("spring"),
            underlined: "stiffness",
            message: "branch 'spring' gives both inductance and stiffness; give one",
        },
    );
}

#[test]
fn zero_capacitance() {
    // The validator's check, worded for the branch: A-type capacitance, not inertance.
    check(
        "zero_capacitance",
        Expect {
            kind: DiagnosticKind::InvalidValue,
            line: 16,
            column: 33,
            element: Some("mass"),
            underlined: "m - 2",
            message: "branch 'mass': capacitance \"m - 2\" = 0 (with m = 2) must be positive",
        },
    );
}

#[test]
fn unknown_branch_kind() {
    check(
        "unknown_branch_kind",
        Expect {
            kind: DiagnosticKind::UnknownElementKind,
            line: 16,
            column: 17,
            element: Some("mass"),
            underlined: "Mass",
            message: "branch 'mass': unknown branch kind 'Mass'; expected one of A, T, D, AcrossSource, ThroughSource, Transformer, Gyrator, Friction, TensionOnly, Subgraph",
        },
    );
}

#[test]
fn unknown_symbol() {
    check(
        "unknown_symbol",
        Expect {
            kind: DiagnosticKind::UnknownSymbol,
            line: 17,
            column: 37,
            element: Some("damper"),
            underlined: "c",
            message: "branch 'damper': conductance \"2*c\" uses 'c', which is neither a parameter nor an input",
        },
    );
}

#[test]
fn ground_not_a_node() {
    let diagnostics = check(
        "ground_not_a_node",
        Expect {
            kind: DiagnosticKind::UndefinedNode,
            line: 13,
            column: 14,
            element: Some("g"),
            underlined: "g",
            message: "the ground 'g' is not a node of any branch",
        },
    );
    assert_eq!(
        diagnostics.first().notes,
        ["the branches' nodes are 'ground', 'v1'; the ground must be one of them"]
    );
}

#[test]
fn stuck_between_sources() {
    // A conflict of the mode, found by causality in the bond graph, reported at the branch.
    check(
        "stuck_between_sources",
        Expect {
            kind: DiagnosticKind::CausalConflict,
            line: 17,
            column: 9,
            element: Some("contact"),
            underlined: "\"contact\": Friction(breakaway: \"F_S\", coulomb: \"F_C\", from: \"v1\", to: \"v2\")",
            message: "causal conflict at branch 'contact': across source 'drive' and stuck friction contact 'contact' both impose its causality",
        },
    );
}
