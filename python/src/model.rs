//! A loaded model (bond graph or linear graph) and the commands on it: `check`, `modes`,
//! `equations`, `graph`, `explain`, `analyze`, `compare`, `simulate`.
//!
//! Each method calls the `bondgraph` library function its command calls (`check::summary`,
//! `derive::derive`, `graph::render`, ...) and returns the document or text the command
//! prints, so that the bindings and the command line cannot disagree; the Python layer
//! (`bondgraph/__init__.py`) turns the documents into objects with numpy arrays.

use std::sync::Arc;

use bondgraph_core::equations::{Layout, Variables};
use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_view::{check, compare, derive, explain_bg, graph, parse_mode};
use pyo3::prelude::*;

use crate::error::{Failure, IntoPyErr, guard};
use crate::results::{
    PyAnalysis, PyComparison, PyEquations, PyTrajectory, bad_choice, explain_format, graph_format,
};

/// A checked model and the file it came from.
#[pyclass(name = "NativeModel", module = "bondgraph._native", frozen)]
pub struct PyModel {
    model: Model,
    source: Arc<SourceFile>,
}

/// Reads `path` as text (with the command line's size limit and UTF-8 check).
pub fn read_source(path: &str) -> Result<Arc<SourceFile>, Failure> {
    bondgraph_view::read_source(std::path::Path::new(path))
}

/// `energy` or `coenergy` as `--states` takes them; `None`: the model's own.
fn variables(states: Option<&str>) -> Result<Option<Variables>, Failure> {
    match states {
        None => Ok(None),
        Some("energy") => Ok(Some(Variables::Energy)),
        Some("coenergy") => Ok(Some(Variables::CoEnergy)),
        Some(other) => Err(bad_choice("states", other, &["energy", "coenergy"])),
    }
}

fn layout(matrices: Option<&str>) -> Result<Option<Layout>, Failure> {
    match matrices {
        None | Some("auto") => Ok(None),
        Some("dense") => Ok(Some(Layout::Dense)),
        Some("sparse") => Ok(Some(Layout::Sparse)),
        Some(other) => Err(bad_choice("matrices", other, &["auto", "dense", "sparse"])),
    }
}

impl PyModel {
    fn from_source(source: Arc<SourceFile>) -> Result<Self, Failure> {
        let model = bondgraph_ron::model::load_source(&source)
            .map_err(|d| Failure::with_sources(d, &[&source]))?;
        Ok(Self { model, source })
    }

    fn compare_with(
        &self,
        answer: Arc<SourceFile>,
        mode: Option<&str>,
    ) -> Result<PyComparison, Failure> {
        let compared = compare::check(&self.model, &self.source, &answer, mode)?;
        Ok(PyComparison {
            json: compared.json,
            text: compared.text,
            agrees: compared.agrees,
        })
    }
}

#[pymethods]
impl PyModel {
    /// Reads and checks the model file at `path`.
    #[staticmethod]
    fn load(py: Python<'_>, path: String) -> PyResult<Self> {
        guard(py, || Self::from_source(read_source(&path)?))
    }

    /// Checks the model in `text`; `name` is the file name its diagnostics give.
    #[staticmethod]
    fn loads(py: Python<'_>, text: String, name: String) -> PyResult<Self> {
        guard(py, || Self::from_source(SourceFile::new(name, text)))
    }

    /// The file name.
    #[getter]
    fn file(&self) -> String {
        self.source.name().to_string()
    }

    /// The model's name.
    #[getter]
    fn name(&self) -> String {
        self.model.name().to_string()
    }

    /// The model file's text.
    #[getter]
    fn text(&self) -> String {
        self.source.text().to_string()
    }

    /// Whether the model is a linear graph.
    #[getter]
    fn is_linear_graph(&self) -> bool {
        self.model.linear_graph().is_some()
    }

    /// Whether some law makes the model nonlinear.
    #[getter]
    fn is_nonlinear(&self) -> bool {
        self.model.is_nonlinear()
    }

    /// `bondgraph check`: the one-line summary.
    fn check(&self, py: Python<'_>) -> PyResult<String> {
        guard(py, || check::summary(&self.model, &self.source))
    }

    /// `bondgraph modes --format json`.
    #[pyo3(signature = (states=None))]
    fn modes(&self, py: Python<'_>, states: Option<String>) -> PyResult<String> {
        guard(py, || {
            check::modes(
                &self.model,
                &self.source,
                variables(states.as_deref())?,
                true,
            )
        })
    }

    /// `bondgraph equations`: its JSON, LaTeX and text.
    #[pyo3(signature = (mode=None, states=None, outputs=Vec::new(), at=None, equilibrium=false, matrices=None))]
    #[allow(clippy::too_many_arguments)]
    fn equations(
        &self,
        py: Python<'_>,
        mode: Option<String>,
        states: Option<String>,
        outputs: Vec<String>,
        at: Option<String>,
        equilibrium: bool,
        matrices: Option<String>,
    ) -> PyResult<PyEquations> {
        guard(py, || {
            let request = derive::Request {
                mode,
                variables: variables(states.as_deref())?,
                outputs,
                at,
                equilibrium,
                matrices: layout(matrices.as_deref())?,
            };
            let derived = derive::derive(&self.model, &self.source, &request)?;
            Ok(PyEquations {
                json: derived.json()?,
                latex: derived.latex_body(),
                latex_document: derived.latex(),
                text: derived.text(),
            })
        })
    }

    /// `bondgraph analyze`: eigenvalues, transfer function, step metrics and the plots.
    #[pyo3(signature = (mode=None, input=None, output=None, at=None, equilibrium=false))]
    fn analyze(
        &self,
        py: Python<'_>,
        mode: Option<String>,
        input: Option<String>,
        output: Option<String>,
        at: Option<String>,
        equilibrium: bool,
    ) -> PyResult<PyAnalysis> {
        let request = bondgraph_view::analyze::Request {
            mode,
            input,
            output,
            at,
            equilibrium,
        };
        guard(py, || {
            let analyzed = bondgraph_view::analyze::analyze(&self.model, &self.source, &request)?;
            let has_channel = analyzed.has_transfer_function();
            Ok(PyAnalysis {
                json: bondgraph_view::json(&analyzed.json())?,
                text: analyzed.text(),
                bode_svg: has_channel.then(|| analyzed.bode_svg()).transpose()?,
                step_svg: has_channel.then(|| analyzed.step_svg()).transpose()?,
            })
        })
    }

    /// `bondgraph graph --format FORMAT` (`text`, `dot` or `svg`): a bond graph with its
    /// causal strokes, or a linear graph with its normal tree.
    #[pyo3(signature = (mode=None, format="text".to_string()))]
    fn graph(&self, py: Python<'_>, mode: Option<String>, format: String) -> PyResult<String> {
        guard(py, || {
            let format = graph_format(&format)?;
            let mode = parse_mode(&self.model, mode.as_deref(), &self.source)?;
            graph::render(&self.model, &mode, &self.source, format)
        })
    }

    /// `bondgraph explain --format FORMAT` (`text` or `markdown`). Where the mode's
    /// equations cannot be derived, the `BondGraphError` says why and carries the
    /// explanation (as far as it got) in its `explanation` attribute.
    #[pyo3(signature = (mode=None, format="text".to_string()))]
    fn explain(&self, py: Python<'_>, mode: Option<String>, format: String) -> PyResult<String> {
        let explanation = guard(py, || {
            let format = explain_format(&format)?;
            let mode = parse_mode(&self.model, mode.as_deref(), &self.source)?;
            explain_bg::explain(&self.model, &mode, &self.source, format)
        })?;
        match explanation.underivable {
            None => Ok(explanation.text),
            Some(failure) => {
                let error = failure.into_pyerr(py);
                error
                    .value(py)
                    .setattr("explanation", explanation.text)
                    .map_or_else(Err, |()| Err(error))
            }
        }
    }

    /// `bondgraph compare` with the answer file at `path`.
    #[pyo3(signature = (path, mode=None))]
    fn compare_file(
        &self,
        py: Python<'_>,
        path: String,
        mode: Option<String>,
    ) -> PyResult<PyComparison> {
        guard(py, || {
            self.compare_with(read_source(&path)?, mode.as_deref())
        })
    }

    /// `bondgraph compare` with the answer in `text`; `name` is the file name its
    /// diagnostics give.
    #[pyo3(signature = (text, name, mode=None))]
    fn compare_text(
        &self,
        py: Python<'_>,
        text: String,
        name: String,
        mode: Option<String>,
    ) -> PyResult<PyComparison> {
        guard(py, || {
            self.compare_with(SourceFile::new(name, text), mode.as_deref())
        })
    }

    /// `bondgraph simulate` with the scenario file at `path`.
    fn simulate_file(&self, py: Python<'_>, path: String) -> PyResult<PyTrajectory> {
        guard(py, || {
            PyTrajectory::new(bondgraph_view::simulate::simulate(
                &self.source,
                &read_source(&path)?,
            )?)
        })
    }

    /// `bondgraph simulate` with the scenario in `text`; `name` is the file name its
    /// diagnostics give.
    fn simulate_text(&self, py: Python<'_>, text: String, name: String) -> PyResult<PyTrajectory> {
        guard(py, || {
            PyTrajectory::new(bondgraph_view::simulate::simulate(
                &self.source,
                &SourceFile::new(name, text),
            )?)
        })
    }
}
