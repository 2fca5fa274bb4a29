//! Models against measured data: `discover`.
//!
//! The same steps as `bondgraph discover`: the experiment beside the model (or the one
//! given), the data files joined, every extension of the library checked against the base
//! model and fitted; the result is the command's JSON document, the fit crate's
//! `Discovery` serialised.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_core::model::extension::{self, Extension};
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data;
use bondgraph_fit::discover::{Candidate, Settings};
use bondgraph_fit::experiment::Experiment;
use pyo3::prelude::*;

use crate::error::{Failure, guard};
use crate::model::{json, read_source};

fn fail(kind: DiagnosticKind, message: impl std::fmt::Display) -> Failure {
    Failure::message(kind, message.to_string())
}

/// Every `*.ron` in `dir`, in name order, checked against `base` and made a candidate.
fn library(base: &Arc<SourceFile>, dir: &Path) -> Result<Vec<Candidate>, Failure> {
    let entries = std::fs::read_dir(dir).map_err(|e| {
        fail(
            DiagnosticKind::Io,
            format!("cannot read the extensions folder '{}': {e}", dir.display()),
        )
    })?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    paths.sort();
    let mut candidates = Vec::new();
    for path in paths {
        let source = read_source(&path.display().to_string())?;
        let extension =
            Extension::load(&source).map_err(|d| Failure::with_sources(d, &[&source]))?;
        extension::merge(base, std::slice::from_ref(&extension))
            .and_then(|extended| extended.load())
            .map_err(|d| Failure::with_sources(d, &[base, &source]))?;
        candidates.push(
            Candidate::new(base, &extension).map_err(|e| fail(DiagnosticKind::Simulation, e))?,
        );
    }
    Ok(candidates)
}

fn run_discover(
    model: &str,
    data_files: &[String],
    experiment: Option<&str>,
    extensions: Option<&str>,
) -> Result<String, Failure> {
    let base = read_source(model)?;
    let folder = Path::new(model).parent().unwrap_or(Path::new("."));
    let experiment_path = experiment.map_or_else(|| folder.join("experiment.ron"), PathBuf::from);
    let experiment_text = std::fs::read_to_string(&experiment_path).map_err(|e| {
        fail(
            DiagnosticKind::Io,
            format!(
                "cannot read the experiment file '{}': {e}",
                experiment_path.display()
            ),
        )
    })?;
    let experiment_source = SourceFile::new(experiment_path.display().to_string(), experiment_text);
    let experiment =
        Experiment::from_source(&experiment_source).map_err(|e| fail(DiagnosticKind::Syntax, e))?;
    if data_files.is_empty() {
        return Err(fail(
            DiagnosticKind::Io,
            "discover needs at least one data file",
        ));
    }
    let mut parts = Vec::new();
    for path in data_files {
        parts.push(
            data::read_file(Path::new(path), &experiment)
                .map_err(|e| fail(DiagnosticKind::Syntax, e))?,
        );
    }
    let dataset = data::Dataset::join(parts);
    let extensions = extensions.map_or_else(|| folder.join("extensions"), PathBuf::from);
    let candidates = library(&base, &extensions)?;
    let discovery = bondgraph_fit::discover::discover(
        &base,
        &experiment,
        &dataset,
        &candidates,
        &Settings::default(),
    )
    .map_err(|e| fail(DiagnosticKind::Simulation, e))?;
    json(&discovery)
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
