//! Models against measured data and the main job: `calibrate`, `discover`, `reproduce`.
//!
//! The same steps as the command line, by the same code (the `bondgraph` library's
//! `calibrate::inputs`, `discover::library` and `reproduce::reproduce_all`): the experiment
//! beside the model (or the one given), the data files joined, every extension of the
//! library checked against the base model; the result is the command's JSON document.

use std::path::{Path, PathBuf};

use bondgraph::calibrate::inputs;
use bondgraph::discover::{discover_failure, library};
use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_fit::calibration;
use bondgraph_fit::discover::Settings;
use pyo3::prelude::*;

use crate::error::{Failure, guard};
use crate::model::json;

/// The data files, at least one.
fn data_paths(command: &str, data: &[String]) -> Result<Vec<PathBuf>, Failure> {
    if data.is_empty() {
        return Err(Failure::message(
            DiagnosticKind::Io,
            format!("{command} needs at least one data file"),
        ));
    }
    Ok(data.iter().map(PathBuf::from).collect())
}

fn run_calibrate(
    model: &str,
    data: &[String],
    experiment: Option<&str>,
) -> Result<String, Failure> {
    let data = data_paths("calibrate", data)?;
    let (base, experiment_source, experiment, dataset) =
        inputs(Path::new(model), experiment.map(Path::new), &data)?;
    let result = calibration::calibrate(&base, &experiment, &dataset, &Settings::default())
        .map_err(|e| discover_failure(e, &[&experiment_source, &base]))?;
    json(&result)
}

fn run_discover(
    model: &str,
    data: &[String],
    experiment: Option<&str>,
    extensions: Option<&str>,
) -> Result<String, Failure> {
    let data = data_paths("discover", data)?;
    let (base, experiment_source, experiment, dataset) =
        inputs(Path::new(model), experiment.map(Path::new), &data)?;
    let folder = Path::new(model).parent().unwrap_or(Path::new("."));
    let extensions = extensions.map_or_else(|| folder.join("extensions"), PathBuf::from);
    let candidates = library(&base, &extensions)?;
    let discovery = bondgraph_fit::discover::discover(
        &base,
        &experiment,
        &dataset,
        &candidates,
        &Settings::default(),
    )
    .map_err(|e| discover_failure(e, &[&experiment_source, &base]))?;
    json(&discovery)
}

/// `bondgraph calibrate --format json`.
#[pyfunction]
#[pyo3(signature = (model, data, experiment=None))]
pub fn calibrate(
    py: Python<'_>,
    model: String,
    data: Vec<String>,
    experiment: Option<String>,
) -> PyResult<String> {
    guard(py, || run_calibrate(&model, &data, experiment.as_deref()))
}

/// `bondgraph discover --format json`.
#[pyfunction]
#[pyo3(signature = (model, data, experiment=None, extensions=None))]
pub fn discover(
    py: Python<'_>,
    model: String,
    data: Vec<String>,
    experiment: Option<String>,
    extensions: Option<String>,
) -> PyResult<String> {
    guard(py, || {
        run_discover(&model, &data, experiment.as_deref(), extensions.as_deref())
    })
}

/// `bondgraph reproduce --format json` (the bundled flagship; nothing is written).
#[pyfunction]
pub fn reproduce(py: Python<'_>) -> PyResult<String> {
    guard(py, || {
        json(&bondgraph::reproduce::reproduce_all()?.document)
    })
}
