//! How a model built from parts is described to its reader: one line per use of a
//! sub-model (or sub-graph), shared by the bond-graph and linear-graph explanations so that
//! both say it the same way.

use bondgraph_core::model::Model;

/// One line per sub-model (or sub-graph) of `model`: its use, its part's name and file, and
/// what each port is (`describe` of the junction or node it is).
pub(crate) fn part_lines(model: &Model, describe: &dyn Fn(&str) -> String) -> Vec<String> {
    model
        .parts()
        .iter()
        .map(|part| {
            let ports: Vec<String> = part
                .ports
                .iter()
                .map(|(port, target)| format!("{}.{port} is {}", part.name, describe(target)))
                .collect();
            format!(
                "{}: '{}' from {}; {}",
                part.name,
                part.model,
                part.file,
                ports.join(", ")
            )
        })
        .collect()
}
