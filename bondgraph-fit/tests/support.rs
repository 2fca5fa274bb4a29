//! Helpers shared by the fit crate's tests.

use std::path::PathBuf;
use std::sync::Arc;

use bondgraph_core::model::{self, Model};
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data::{self, Dataset};
use bondgraph_fit::experiment::{Experiment, Predictor};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A model and its source, by path relative to the root.
pub fn load(relative: &str) -> (Model, Arc<SourceFile>) {
    let text = std::fs::read_to_string(root().join(relative)).expect("model file");
    let source = SourceFile::new(relative, text);
    (model::load_source(&source).expect("valid model"), source)
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
    data::read_file(&root().join("models/eversion/data").join(name)).expect("valid data")
}

/// A predictor of a model file with the flagship's experiment.
pub fn predictor(relative: &str) -> Predictor {
    let (model, source) = load(relative);
    Predictor::new(model, &source, &experiment()).expect("predictor")
}
