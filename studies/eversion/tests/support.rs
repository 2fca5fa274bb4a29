//! Helpers shared by the fit crate's tests.

use std::path::PathBuf;
use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data::{self, Dataset};
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::predict::Predictor;

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A model and its source, by path relative to the root.
pub fn load(relative: &str) -> (Model, Arc<SourceFile>) {
    let text = std::fs::read_to_string(root().join(relative)).expect("model file");
    let source = SourceFile::new(relative, text);
    (
        bondgraph_ron::model::load_source(&source).expect("valid model"),
        source,
    )
}

/// The flagship's experiment description.
pub fn experiment() -> Experiment {
    let path = "models/eversion/experiment.ron";
    Experiment::parse(
        path,
        &std::fs::read_to_string(root().join(path)).expect("file"),
    )
    .expect("valid experiment")
}

/// A bundled dataset.
pub fn dataset(name: &str) -> Dataset {
    data::read_file(
        &root().join("models/eversion/data").join(name),
        &experiment(),
    )
    .expect("valid data")
}

/// A predictor of a model file with the flagship's experiment.
pub fn predictor(relative: &str) -> Predictor {
    let (model, source) = load(relative);
    Predictor::new(model, &source, &experiment()).expect("predictor")
}

/// The main job's inputs, read from the repository.
pub struct Files(Vec<(String, String)>);

impl Files {
    /// Reads the bundled files.
    pub fn read() -> Self {
        Files(
            [
                "models/eversion/robot.ron",
                "models/eversion/paper.ron",
                "models/eversion/experiment.ron",
                "models/eversion/data/table3.csv",
                "models/eversion/data/table3_paper_sim.csv",
                "models/eversion/data/table6.csv",
                "models/eversion/data/table6_paper_sim.csv",
                "models/eversion/fig6.ron",
            ]
            .iter()
            .map(|p| {
                let text = std::fs::read_to_string(root().join(p)).expect("bundled file");
                (p.to_string(), text)
            })
            .collect(),
        )
    }

    /// The bundle the main job reads.
    pub fn bundle(&self) -> bondgraph_eversion::reproduce::Bundle<'_> {
        use bondgraph_eversion::reproduce::{Bundle, Named};
        let n = |i: usize| Named {
            name: &self.0[i].0,
            text: &self.0[i].1,
        };
        Bundle {
            robot: n(0),
            paper: n(1),
            experiment: n(2),
            table3: n(3),
            table3_sim: n(4),
            table6: n(5),
            table6_sim: n(6),
            fig6: n(7),
        }
    }
}
