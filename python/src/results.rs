//! What the model's commands return to Python: each holds the command line's document (JSON
//! text, or the text it prints) and the renderings a notebook shows; the Python layer
//! (`bondgraph/__init__.py`) turns them into objects with numpy arrays.

use bondgraph_core::DiagnosticKind;
use bondgraph_view::simulate::Simulated;
use pyo3::prelude::*;

use crate::error::{Failure, guard};

/// The equations of one mode in the forms the bindings show.
#[pyclass(
    name = "NativeEquations",
    module = "bondgraph._native",
    frozen,
    get_all
)]
pub struct PyEquations {
    /// The command line's `--format json` document.
    pub json: String,
    /// The equations in LaTeX, what a notebook renders.
    pub latex: String,
    /// `--format latex`: the same after a comment saying what the matrices need.
    pub latex_document: String,
    /// The text `bondgraph equations` prints.
    pub text: String,
}

/// One mode analysed (`bondgraph analyze`): its JSON document, its text and, when it has a
/// transfer function, its Bode and step plots.
#[pyclass(name = "NativeAnalysis", module = "bondgraph._native", frozen, get_all)]
pub struct PyAnalysis {
    /// The command line's `--format json` document.
    pub json: String,
    /// Its text.
    pub text: String,
    /// `--bode` (SVG), if there is a transfer function.
    pub bode_svg: Option<String>,
    /// `--step` (SVG), if there is a transfer function.
    pub step_svg: Option<String>,
}

/// A student's answer checked (`bondgraph compare`).
#[pyclass(
    name = "NativeComparison",
    module = "bondgraph._native",
    frozen,
    get_all
)]
pub struct PyComparison {
    /// The command line's `--format json` document.
    pub json: String,
    /// The verdict and its notes as the command prints them.
    pub text: String,
    /// Equal, or equal up to a change of state variables (the command's exit code 0).
    pub agrees: bool,
}

/// A simulated trajectory: its arrays, its JSON document (without the samples, which the
/// arrays carry), its CSV and, on demand, its plot.
#[pyclass(name = "NativeTrajectory", module = "bondgraph._native", frozen)]
pub struct PyTrajectory {
    run: Simulated,
    document: String,
}

impl PyTrajectory {
    /// The run, with its document made once.
    pub fn new(run: Simulated) -> Result<Self, Failure> {
        let mut document = run.json();
        if let Some(object) = document.as_object_mut() {
            object.remove("samples");
        }
        Ok(Self {
            document: bondgraph_view::json(&document)?,
            run,
        })
    }
}

#[pymethods]
impl PyTrajectory {
    /// The JSON document of `simulate --format json`, without `samples`.
    #[getter]
    fn document(&self) -> String {
        self.document.clone()
    }

    /// The sample times, in seconds.
    #[getter]
    fn times(&self) -> Vec<f64> {
        self.run.trajectory.times.clone()
    }

    /// The outputs, row-major: output `j` of sample `k` at `k * len(outputs) + j`.
    #[getter]
    fn values(&self) -> Vec<f64> {
        self.run.trajectory.values.clone()
    }

    /// The mode at each sample, as an index into the document's `modes`.
    #[getter]
    fn sample_modes(&self) -> Vec<usize> {
        self.run.trajectory.sample_modes.clone()
    }

    /// `simulate --format csv`.
    fn csv(&self) -> String {
        self.run.csv()
    }

    /// `simulate --plot` with a `--panel` for each of `panels`, as SVG.
    #[pyo3(signature = (panels=Vec::new()))]
    fn plot_svg(&self, py: Python<'_>, panels: Vec<String>) -> PyResult<String> {
        guard(py, || self.run.plot(&panels))
    }
}

/// `text` or `markdown`, as `bondgraph explain --format` takes it.
pub fn explain_format(format: &str) -> Result<bondgraph_view::explain_bg::ExplainFormat, Failure> {
    use bondgraph_view::explain_bg::ExplainFormat;
    match format {
        "text" => Ok(ExplainFormat::Text),
        "markdown" => Ok(ExplainFormat::Markdown),
        other => Err(bad_choice("format", other, &["text", "markdown"])),
    }
}

/// `text`, `dot` or `svg`, as `bondgraph graph --format` takes it.
pub fn graph_format(format: &str) -> Result<bondgraph_view::graph::GraphFormat, Failure> {
    use bondgraph_view::graph::GraphFormat;
    match format {
        "text" => Ok(GraphFormat::Text),
        "dot" => Ok(GraphFormat::Dot),
        "svg" => Ok(GraphFormat::Svg),
        other => Err(bad_choice("format", other, &["text", "dot", "svg"])),
    }
}

/// An argument that is none of `choices`.
pub fn bad_choice(argument: &str, given: &str, choices: &[&str]) -> Failure {
    let choices: Vec<String> = choices.iter().map(|c| format!("{c:?}")).collect();
    Failure::message(
        DiagnosticKind::InvalidValue,
        format!("{argument} must be {}, not {given:?}", choices.join(" or ")),
    )
}
