//! `bondgraph calibrate`: fit an experiment's parameters to measured data.

use std::path::{Path, PathBuf};

use bondgraph_core::DiagnosticKind;
use bondgraph_core::source::SourceFile;
use bondgraph_fit::budget::Budget;
use bondgraph_fit::calibration::{self, Calibration};
use bondgraph_fit::data;
use bondgraph_fit::discover::Settings;
use bondgraph_fit::experiment::Experiment;

use crate::discover::{discover_failure, experiment_failure};
use crate::{Failure, json, print, read_source};

/// The command line of `calibrate`.
pub struct Args {
    /// The model file.
    pub model: PathBuf,
    /// The measured data files, joined.
    pub data: Vec<PathBuf>,
    /// The experiment file; `experiment.ron` beside the model if `None`.
    pub experiment: Option<PathBuf>,
    /// JSON rather than text.
    pub json: bool,
    /// The work each prediction and the fit may do.
    pub budget: Budget,
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
        bondgraph_core::read::read_text(&experiment_path, "the experiment file").map_err(|e| {
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

/// Fits the experiment's parameters of `model` (its experiment given, or `experiment.ron`
/// beside it) to the `data` files, joined.
///
/// # Errors
/// A failure naming the file, line and column of what cannot be read, or why the fit
/// cannot be made.
pub fn calibrate(
    model: &Path,
    experiment: Option<&Path>,
    data: &[PathBuf],
) -> Result<Calibration, Failure> {
    calibrate_within(model, experiment, data, &Budget::default())
}

/// [`calibrate`] within `budget`.
///
/// # Errors
/// As [`calibrate`].
pub fn calibrate_within(
    model: &Path,
    experiment: Option<&Path>,
    data: &[PathBuf],
    budget: &Budget,
) -> Result<Calibration, Failure> {
    let (base, experiment_source, experiment, dataset) = inputs(model, experiment, data)?;
    let settings = Settings {
        budget: *budget,
        ..Settings::default()
    };
    calibration::calibrate(&base, &experiment, &dataset, &settings)
        .map_err(|e| discover_failure(e, &[&experiment_source, &base]))
}

/// Runs `calibrate`.
pub fn run(args: &Args) -> Result<(), Failure> {
    let result = calibrate_within(
        &args.model,
        args.experiment.as_deref(),
        &args.data,
        &args.budget,
    )?;
    if args.json {
        print(&json(&result)?);
    } else {
        print(&result.summary());
    }
    Ok(())
}
