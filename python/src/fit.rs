//! Models against measured data and the main job: `calibrate`, `discover`, `reproduce`.
//!
//! The same library calls as the command line (`calibrate::calibrate`,
//! `discover::inputs(..).discover(..)`, the study's `main_job::reproduce_all`): the experiment beside
//! the model (or the one given), the data files joined, every extension of the library
//! checked against the base model; the result is the command's JSON document.

use std::path::{Path, PathBuf};

use bondgraph_view::{discover as command, json};
use pyo3::prelude::*;

use crate::error::guard;

fn paths(data: &[String]) -> Vec<PathBuf> {
    data.iter().map(PathBuf::from).collect()
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
    guard(py, || {
        let result = bondgraph_view::calibrate::calibrate(
            Path::new(&model),
            experiment.as_deref().map(Path::new),
            &paths(&data),
        )?;
        json(&result)
    })
}

/// `bondgraph discover --format json` (with `--out`: the report, the JSON, the extended
/// model and the residual plots written there too; `resamples` as `--resamples`).
#[pyfunction]
#[pyo3(signature = (model, data, experiment=None, extensions=None, out=None, resamples=None))]
pub fn discover(
    py: Python<'_>,
    model: String,
    data: Vec<String>,
    experiment: Option<String>,
    extensions: Option<String>,
    out: Option<String>,
    resamples: Option<usize>,
) -> PyResult<String> {
    guard(py, || {
        let inputs = command::inputs(
            Path::new(&model),
            &paths(&data),
            experiment.as_deref().map(Path::new),
            extensions.as_deref().map(Path::new),
        )?;
        let discovery = inputs.discover(resamples, &|| {})?;
        let text = json(&discovery)?;
        if let Some(out) = &out {
            command::write_outputs(Path::new(out), &discovery, &text)?;
        }
        Ok(text)
    })
}

/// `bondgraph reproduce --format json` (the bundled flagship; nothing is written).
#[pyfunction]
pub fn reproduce(py: Python<'_>) -> PyResult<String> {
    guard(py, || {
        let reproduced = bondgraph_eversion::main_job::reproduce_all(&|| {}).map_err(|e| {
            bondgraph_view::Failure::message(
                bondgraph_core::DiagnosticKind::Simulation,
                e.to_string(),
            )
        })?;
        json(&reproduced.document)
    })
}
