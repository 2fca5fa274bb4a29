//! Snapshots of every pipeline stage of every textbook model (every mode of a switching
//! one), so that any change in what a user sees (the graph, the causal strokes, the
//! equations as text and LaTeX, the modes and guards) shows in review.
//!
//! The values in these files are checked independently in `examples.rs`; the snapshots guard
//! the presentation.

use bondgraph_core::equations::{Options, Variables};
use bondgraph_core::{causality, graph, laws, modes};

use crate::support::{load, ron_files};

#[test]
fn every_stage_of_every_example() {
    for file in ron_files("models/examples") {
        let model = load(&file);
        let name = model.name().to_string();
        insta::assert_snapshot!(format!("{name}__1_graph"), graph::describe(&model));
        let energy = Options {
            variables: Variables::Energy,
        };
        let coenergy = Options {
            variables: Variables::CoEnergy,
        };
        let reachable = modes::reachable(&model, &energy).expect("examples derive");
        if !reachable.initial.is_empty() {
            insta::assert_snapshot!(format!("{name}__0_modes"), reachable.to_text(&model));
        }
        for derived in &reachable.modes {
            let spec = derived.mode.spec(&model);
            // A plain model's only mode has no name of its own.
            let prefix = if spec.is_empty() {
                name.clone()
            } else {
                format!(
                    "{name}__{}",
                    spec.replace(['=', ','], "_")
                        .replace('+', "plus")
                        .replace('-', "minus")
                )
            };
            let laws = laws::for_mode(&model, &derived.mode);
            let causal = causality::assign(&model, &laws).expect("examples are causal");
            insta::assert_snapshot!(
                format!("{prefix}__2_causality"),
                graph::describe_causality(&model, &laws, &causal)
            );
            let co = modes::derive(&model, &derived.mode, &coenergy).expect("co-energy");
            insta::assert_snapshot!(
                format!("{prefix}__3_equations"),
                derived.equations.to_text()
            );
            insta::assert_snapshot!(
                format!("{prefix}__4_equations_coenergy"),
                co.equations.to_text()
            );
            insta::assert_snapshot!(format!("{prefix}__5_latex"), derived.equations.to_latex());
            insta::assert_snapshot!(
                format!("{prefix}__6_latex_coenergy"),
                co.equations.to_latex()
            );
        }
    }
}

/// Every mode of both eversion models, in text and LaTeX, energy and co-energy variables:
/// one snapshot per model and presentation, the modes one after another.
#[test]
fn every_mode_of_the_eversion_models() {
    for file in ["models/eversion/paper.ron", "models/eversion/robot.ron"] {
        let model = load(file);
        let name = model.name().to_string();
        let reachable = modes::reachable(
            &model,
            &Options {
                variables: Variables::Energy,
            },
        )
        .expect("eversion models derive");
        insta::assert_snapshot!(format!("{name}__0_modes"), reachable.to_text(&model));
        for (variables, suffix) in [(Variables::Energy, ""), (Variables::CoEnergy, "_coenergy")] {
            let options = Options { variables };
            let mut text = String::new();
            let mut latex = String::new();
            for mode in &reachable.modes {
                let derived = modes::derive(&model, &mode.mode, &options).expect("derives");
                let spec = mode.mode.spec(&model);
                text.push_str(&format!(
                    "=== mode {spec}\n{}\n",
                    derived.equations.to_text()
                ));
                latex.push_str(&format!(
                    "% mode {spec}\n{}\n",
                    derived.equations.to_latex()
                ));
            }
            insta::assert_snapshot!(format!("{name}__equations{suffix}"), text);
            insta::assert_snapshot!(format!("{name}__latex{suffix}"), latex);
        }
    }
}
