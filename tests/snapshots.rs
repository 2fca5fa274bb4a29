//! Snapshots of every pipeline stage of every textbook model, so that any change in what a
//! user sees (the graph, the causal strokes, the equations as text and LaTeX) shows in review.
//!
//! The values in these files are checked independently in `examples.rs`; the snapshots guard
//! the presentation.

use bondgraph_core::equations::Variables;
use bondgraph_core::{causality, graph, laws};

use crate::support::{derive, load, ron_files};

#[test]
fn every_stage_of_every_example() {
    for file in ron_files("models/examples") {
        let model = load(&file);
        let name = &model.name;
        let laws = laws::plain_laws(&model);
        let causal = causality::assign(&model, &laws).expect("examples are causal");

        insta::assert_snapshot!(format!("{name}__1_graph"), graph::describe(&model));
        insta::assert_snapshot!(
            format!("{name}__2_causality"),
            graph::describe_causality(&model, &laws, &causal)
        );
        let energy = derive(&model, Variables::Energy);
        let coenergy = derive(&model, Variables::CoEnergy);
        insta::assert_snapshot!(format!("{name}__3_equations"), energy.to_text());
        insta::assert_snapshot!(format!("{name}__4_equations_coenergy"), coenergy.to_text());
        insta::assert_snapshot!(format!("{name}__5_latex"), energy.to_latex());
        insta::assert_snapshot!(format!("{name}__6_latex_coenergy"), coenergy.to_latex());
    }
}
