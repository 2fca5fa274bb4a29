//! The geared motor of `models/examples/geared_motor/`, as the fit crate's tests load it:
//! its model file, an experiment beside it, and its three-candidate extension library.

use std::path::PathBuf;
use std::sync::Arc;

use bondgraph_core::source::SourceFile;
use bondgraph_fit::discover::Candidate;
use bondgraph_fit::experiment::Experiment;
use bondgraph_ron::extension::Extension;

/// A repository file by its path from the root, named by its absolute path (so that a
/// time series' experiment finds its scenario beside it).
pub fn file(relative: &str) -> Arc<SourceFile> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    SourceFile::new(
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    )
}

/// The motor's model file.
pub fn motor() -> Arc<SourceFile> {
    file("models/examples/geared_motor/geared_motor.ron")
}

/// One of the motor's experiment files (`experiment.ron`, `experiment_step.ron`).
pub fn experiment(name: &str) -> Experiment {
    Experiment::from_source(&file(&format!("models/examples/geared_motor/{name}"))).unwrap()
}

/// The motor's extension library, merged into it.
pub fn library() -> Vec<Candidate> {
    let base = motor();
    [
        "brake-loaded-bearings",
        "brush-voltage-drop",
        "shaft-windage",
    ]
    .iter()
    .map(|id| {
        let source = file(&format!("models/examples/geared_motor/extensions/{id}.ron"));
        Candidate::new(&base, &Extension::load(&source).unwrap()).unwrap()
    })
    .collect()
}
