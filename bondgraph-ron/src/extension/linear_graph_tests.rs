//! Linear-graph fragments merged into linear graphs.

use super::*;

const GRAPH: &str = r#"// Two nodes joined by a bar, each to the ground by a film.
LinearGraph(
    name: "pair",
    parameters: {
        "C_1": (value: 2.0),
        "C_2": (value: 3.0),
        "R_12": (value: 1.0),
        "R_a": (value: 4.0),
    },
    inputs: { "P": () },
    ground: "g",
    branches: {
        "heater": ThroughSource(value: "P", from: "g", to: "T1"),
        "block_1": A(capacitance: "C_1", from: "T1", to: "g"),
        "block_2": A(capacitance: "C_2", from: "T2", to: "g"),
        "bar": D(resistance: "R_12", from: "T1", to: "T2"),
        "film": D(resistance: "R_a", from: "T2", to: "g"),
    },
)
"#;

const JOINT: &str = r#"Extension(
    id: "joint",
    cause: "a joint in series with the bar",
    parameters: { "R_c": (value: 0.5, bounds: (0.0, 10.0)) },
    branches: {
        "bar": D(resistance: "R_12", from: "T1", to: "contact"),
        "joint": D(resistance: "R_c", from: "contact", to: "T2"),
    },
    replace: ["bar"],
)
"#;

fn graph() -> Arc<SourceFile> {
    SourceFile::new("models/pair.lg.ron", GRAPH)
}

fn fragment(name: &str, text: &str) -> Extension {
    Extension::load(&SourceFile::new(name, text)).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_fragment_splits_a_branch_with_a_new_node() {
    let extended = merge(&graph(), &[fragment("joint.ron", JOINT)]).unwrap();
    let model = extended.check().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.name(), "pair+joint");
    let graph = model.linear_graph().expect("still a linear graph");
    let names: Vec<&str> = graph.branches.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(
        names,
        ["heater", "block_1", "block_2", "bar", "film", "joint"]
    );
    assert!(graph.node_named("contact").is_some());
    // The bar now ends at the new node, and the joint's R_c is a parameter with its bounds.
    let bar = &graph.branches[3];
    assert_eq!(graph.node(bar.edges[0].to).name, "contact");
    let r_c = model.parameters().iter().find(|p| p.name == "R_c").unwrap();
    assert_eq!(r_c.bounds, Some((0.0, 10.0)));
}

#[test]
fn a_bond_graph_fragment_is_refused_by_a_linear_graph_at_its_line() {
    let bonds = r#"Extension(
    id: "spring",
    cause: "a spring",
    elements: { "spring": C(stiffness: "1") },
    bonds: [("T1", "spring")],
)"#;
    let error = merge(&graph(), &[fragment("spring.ron", bonds)]).unwrap_err();
    let first = error.first();
    assert_eq!(
        first.message,
        "extension 'spring' is a bond-graph fragment (elements), and model 'pair' is a linear graph"
    );
    let at = first.location.as_ref().unwrap();
    assert_eq!((at.file.as_str(), at.line), ("spring.ron", 4));
    // And a linear-graph fragment is refused by a bond graph.
    let base = SourceFile::new("msd.ron", super::tests::BASE);
    let error = merge(&base, &[fragment("joint.ron", JOINT)]).unwrap_err();
    assert!(
        error
            .first()
            .message
            .contains("is a linear-graph fragment (branches)"),
        "{error}"
    );
}

#[test]
fn a_problem_of_a_new_branch_points_at_the_fragment() {
    let dangling = r#"Extension(
    id: "leak",
    cause: "a leak",
    branches: {
        "leak": D(conductance: "1", from: "T2", to: "T3"),
    },
)"#;
    let error = merge(&graph(), &[fragment("leak.ron", dangling)])
        .unwrap()
        .load()
        .unwrap_err();
    let first = error.first();
    assert_eq!(
        first.message,
        "branch 'leak' names node 'T3', which no other branch touches"
    );
    let at = first.location.as_ref().unwrap();
    assert_eq!((at.file.as_str(), at.line), ("leak.ron", 5));
    // A replaced branch the graph does not have, with a suggestion.
    let typo = JOINT
        .replace("[\"bar\"]", "[\"barr\"]")
        .replace("\"bar\":", "\"barr\":");
    let error = merge(&graph(), &[fragment("typo.ron", &typo)]).unwrap_err();
    assert_eq!(
        error.first().message,
        "extension 'joint' replaces branch 'barr', which model 'pair' does not have"
    );
    assert_eq!(error.first().notes, ["did you mean 'bar'?"]);
}
