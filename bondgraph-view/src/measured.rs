//! What `calibrate` and `discover` both take: a model, its experiment and its measured data,
//! read and checked, and their libraries' errors as failures located in those files.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data;
use bondgraph_fit::discover::DiscoverError;
use bondgraph_fit::experiment::{Experiment, ExperimentError};

use crate::{Failure, read_source};

fn fail(kind: DiagnosticKind, message: impl std::fmt::Display) -> Failure {
    Failure::message(kind, message.to_string())
}

/// Reads the model, its experiment (given, or `experiment.ron` beside the model) and the
/// data files (at least one), read against the experiment and joined.
///
/// # Errors
/// A failure naming the file, line and column of what cannot be read.
pub fn inputs(
    model: &Path,
    experiment: Option<&Path>,
    data: &[PathBuf],
) -> Result<
    (
        std::sync::Arc<SourceFile>,
        std::sync::Arc<SourceFile>,
        Experiment,
        data::Dataset,
    ),
    Failure,
> {
    if data.is_empty() {
        return Err(Failure::message(
            DiagnosticKind::Io,
            "no data file given: at least one is needed",
        ));
    }
    let base = read_source(model)?;
    let folder = model.parent().unwrap_or(Path::new("."));
    let experiment_path =
        experiment.map_or_else(|| folder.join("experiment.ron"), Path::to_path_buf);
    // Within the size limit of every input file, with invalid UTF-8 located.
    let text =
        bondgraph_ron::read::read_text(&experiment_path, "the experiment file").map_err(|e| {
            Failure::message(
                DiagnosticKind::Io,
                format!("{e} (give one with --experiment)"),
            )
        })?;
    let experiment_source = SourceFile::new(experiment_path.display().to_string(), text);
    let experiment = Experiment::from_source(&experiment_source)
        .map_err(|e| experiment_failure(e, &[&experiment_source, &base]))?;
    let mut parts = Vec::new();
    for path in data {
        parts.push(
            data::read_file(path, &experiment)
                .map_err(|e| Failure::message(DiagnosticKind::Syntax, e.to_string()))?,
        );
    }
    let dataset = data::Dataset::join(parts);
    // Columns a rig records that the experiment does not compare are not an error.
    for note in dataset.notes() {
        eprintln!("note: {note}");
    }
    Ok((base, experiment_source, experiment, dataset))
}

/// An experiment's error as located diagnostics, rendered with the lines of `sources`.
pub fn experiment_failure(error: ExperimentError, sources: &[&Arc<SourceFile>]) -> Failure {
    match error {
        ExperimentError::Diagnostics(diagnostics) => Failure {
            diagnostics,
            sources: sources.iter().map(|s| Arc::clone(s)).collect(),
        },
        other => fail(DiagnosticKind::Simulation, other),
    }
}

/// A discovery's (or calibration's) error, its diagnostics located where they point.
pub fn discover_failure(error: DiscoverError, sources: &[&Arc<SourceFile>]) -> Failure {
    let located = |diagnostics| Failure {
        diagnostics,
        sources: sources.iter().map(|s| Arc::clone(s)).collect(),
    };
    match error {
        DiscoverError::Model(diagnostics) => located(diagnostics),
        DiscoverError::Fitted(diagnostics) => located(diagnostics),
        DiscoverError::Experiment(error) => experiment_failure(error, sources),
        other => fail(DiagnosticKind::Simulation, other),
    }
}
