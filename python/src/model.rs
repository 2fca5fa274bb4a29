//! A loaded model (bond graph or linear graph) and the commands on it: `check`, `modes`,
//! `equations`, `graph`, `simulate`.
//!
//! Each command runs the same library calls as the command line and returns the same JSON
//! document, built by the same code (`to_json` of the core's equations and modes, the
//! `bondgraph` library's trajectory JSON); the Python layer (`bondgraph/__init__.py`) turns
//! the documents into objects with numpy arrays. Text and LaTeX renderings come along for
//! the notebook's `repr`s.

use std::sync::Arc;

use bondgraph_core::diagnostics::{DiagnosticKind, Diagnostics};
use bondgraph_core::equations::nonlinear::{NonlinearOutput, OperatingPoint};
use bondgraph_core::equations::{self, Variables};
use bondgraph_core::model::{self, Model};
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::scenario::Record;
use bondgraph_core::source::SourceFile;
use bondgraph_core::{causality, laws, normal_tree};
use bondgraph_solver::Trajectory;
use pyo3::prelude::*;

use crate::error::{Failure, guard};

/// A checked model and the file it came from.
#[pyclass(name = "NativeModel", module = "bondgraph._native", frozen)]
pub struct PyModel {
    model: Model,
    source: Arc<SourceFile>,
}

/// The equations of one mode in the three forms the bindings show.
#[pyclass(
    name = "NativeEquations",
    module = "bondgraph._native",
    frozen,
    get_all
)]
pub struct PyEquations {
    /// The command line's `--format json` document.
    json: String,
    /// Its `--format latex` rendering.
    latex: String,
    /// The state equations as text.
    text: String,
}

/// One mode analysed (`bondgraph analyze`): its JSON document, its text and, when it has a
/// transfer function, its Bode and step plots.
#[pyclass(name = "NativeAnalysis", module = "bondgraph._native", frozen, get_all)]
pub struct PyAnalysis {
    /// The command line's `--format json` document.
    json: String,
    /// Its text.
    text: String,
    /// `--bode` (SVG), if there is a transfer function.
    bode_svg: Option<String>,
    /// `--step` (SVG), if there is a transfer function.
    step_svg: Option<String>,
}

/// A simulated trajectory: its arrays, its JSON document (without the samples, which the
/// arrays carry) and, on demand, its plot.
#[pyclass(name = "NativeTrajectory", module = "bondgraph._native", frozen)]
pub struct PyTrajectory {
    trajectory: Trajectory,
    document: String,
    title: String,
}

/// Reads `path` as text (with the command line's size limit and UTF-8 check).
pub fn read_source(path: &str) -> Result<Arc<SourceFile>, Failure> {
    bondgraph::read_source(std::path::Path::new(path))
}

pub use bondgraph::json;

fn variables(model: &Model, states: Option<&str>) -> Result<Variables, Failure> {
    match states {
        None => Ok(Variables::preferred(model)),
        Some("energy") => Ok(Variables::Energy),
        Some("coenergy") => Ok(Variables::CoEnergy),
        Some(other) => Err(Failure::message(
            DiagnosticKind::Syntax,
            format!("states must be \"energy\" or \"coenergy\", not {other:?}"),
        )),
    }
}

use bondgraph::count;

impl PyModel {
    fn from_source(source: Arc<SourceFile>) -> Result<Self, Failure> {
        let model =
            model::load_source(&source).map_err(|d| Failure::with_sources(d, &[&source]))?;
        Ok(Self { model, source })
    }

    fn fail(&self, diagnostics: Diagnostics) -> Failure {
        Failure::with_sources(diagnostics, &[&self.source])
    }

    fn mode(&self, spec: Option<&str>) -> Result<Mode, Failure> {
        match spec {
            Some(spec) => Mode::parse(&self.model, spec).map_err(|d| self.fail(d)),
            None => Ok(Mode::initial(&self.model)),
        }
    }

    fn check_summary(&self) -> Result<String, Failure> {
        let model = &self.model;
        let options = equations::Options::default();
        let (states, mode_count, initial_empty) = if model.is_nonlinear() {
            let reachable =
                modes::reachable_nonlinear(model, &options).map_err(|d| self.fail(d))?;
            let states = reachable
                .modes
                .first()
                .map_or(0, |m| m.equations.state_count());
            (states, reachable.modes.len(), reachable.initial.is_empty())
        } else {
            let reachable = modes::reachable(model, &options).map_err(|d| self.fail(d))?;
            let states = reachable
                .modes
                .first()
                .map_or(0, |m| m.equations.state_count());
            (states, reachable.modes.len(), reachable.initial.is_empty())
        };
        let (kind, parts) = match (&model.linear_graph, model.is_nonlinear()) {
            (Some(graph), _) => (
                "linear graph",
                [
                    (graph.nodes.len(), "node"),
                    (graph.branches.len(), "branch"),
                ],
            ),
            (None, nonlinear) => (
                if nonlinear {
                    "nonlinear model"
                } else {
                    "model"
                },
                [
                    (model.elements.len(), "element"),
                    (model.bonds.len(), "bond"),
                ],
            ),
        };
        let modes = if initial_empty {
            String::new()
        } else {
            format!(", {}", count(mode_count, "reachable mode"))
        };
        Ok(format!(
            "{}: ok: {kind} '{}' with {}, {}, {}, {} and {}{modes}",
            self.source.name(),
            model.name,
            count(parts[0].0, parts[0].1),
            count(parts[1].0, parts[1].1),
            count(model.parameters.len(), "parameter"),
            count(model.inputs.len(), "input"),
            count(states, "state"),
        ))
    }

    fn modes_json(&self, states: Option<&str>) -> Result<String, Failure> {
        let options = equations::Options {
            variables: variables(&self.model, states)?,
        };
        if self.model.is_nonlinear() {
            let reachable =
                modes::reachable_nonlinear(&self.model, &options).map_err(|d| self.fail(d))?;
            json(&reachable.to_json(&self.model))
        } else {
            let reachable = modes::reachable(&self.model, &options).map_err(|d| self.fail(d))?;
            json(&reachable.to_json(&self.model))
        }
    }

    fn derive(
        &self,
        mode: Option<&str>,
        states: Option<&str>,
        outputs: &[String],
        at: Option<&str>,
    ) -> Result<PyEquations, Failure> {
        let model = &self.model;
        let mode = self.mode(mode)?;
        let options = equations::Options {
            variables: variables(model, states)?,
        };
        let spec = mode.spec(model);
        if model.is_nonlinear() {
            let derived =
                modes::derive_nonlinear(model, &mode, &options).map_err(|d| self.fail(d))?;
            let eq = &derived.equations;
            let outputs = outputs
                .iter()
                .map(|spec| {
                    Record::parse_output(model, spec).map(|(record, output)| NonlinearOutput {
                        integral: matches!(record, Record::Integral(_)),
                        name: record.name(),
                        ..eq.output(&output)
                    })
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(|d| self.fail(d))?;
            let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
            let point = at
                .map(|text| OperatingPoint::parse(&names, &eq.inputs, text))
                .transpose()
                .map_err(|d| self.fail(d))?;
            return Ok(PyEquations {
                json: json(&eq.to_json(&spec, &outputs, point.as_ref()))?,
                latex: eq.to_latex(),
                text: eq.to_text(point.as_ref()),
            });
        }
        let derived = modes::derive(model, &mode, &options).map_err(|d| self.fail(d))?;
        let eq = &derived.equations;
        if let Some(at) = at {
            // A linear mode's matrices do not depend on the point; the point is checked.
            let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
            OperatingPoint::parse(&names, &eq.inputs, at).map_err(|d| self.fail(d))?;
        }
        let outputs = outputs
            .iter()
            .map(|spec| {
                Record::parse_output(model, spec).map(|(record, spec)| {
                    let mut output = eq.output(&spec);
                    output.integral = matches!(record, Record::Integral(_));
                    output.name = record.name();
                    output
                })
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(|d| self.fail(d))?;
        Ok(PyEquations {
            json: json(&eq.to_json(&spec, &outputs))?,
            latex: eq.to_latex_with_outputs(&outputs),
            text: eq.to_text(),
        })
    }

    fn svg_of(&self, mode: Option<&str>) -> Result<Option<String>, Failure> {
        let model = &self.model;
        let mode = self.mode(mode)?;
        let laws = laws::for_mode(model, &mode);
        let Some(graph) = &model.linear_graph else {
            let causality = causality::assign(model, &laws).map_err(|d| self.fail(d))?;
            return Ok(Some(bondgraph::bg_svg::draw(model, &mode, &causality)));
        };
        causality::assign(model, &laws)
            .map_err(|d| self.fail(bondgraph_core::model::linear_graph::reword(model, d)))?;
        let tree = normal_tree::of_mode(model, &laws).ok_or_else(|| {
            Failure::message(
                DiagnosticKind::CausalConflict,
                "the mode has no normal tree",
            )
        })?;
        Ok(Some(bondgraph::lg_svg::draw(
            model,
            graph,
            &tree,
            &mode.spec(model),
        )))
    }

    fn dot_of(&self, mode: Option<&str>) -> Result<Option<String>, Failure> {
        let model = &self.model;
        if model.linear_graph.is_some() {
            return Ok(None);
        }
        let mode = self.mode(mode)?;
        let laws = laws::for_mode(model, &mode);
        let causality = causality::assign(model, &laws).map_err(|d| self.fail(d))?;
        Ok(Some(bondgraph_core::graph::to_dot(model, Some(&causality))))
    }

    fn run_scenario(&self, scenario: Arc<SourceFile>) -> Result<PyTrajectory, Failure> {
        let sources = [&self.source, &scenario];
        let loaded = bondgraph_core::scenario::load(&scenario, &self.source)
            .map_err(|d| Failure::with_sources(d, &sources))?;
        let trajectory = bondgraph_solver::scenario::run(&loaded, false)
            .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()))?;
        let mut document =
            bondgraph::trajectory::to_json(&trajectory, &loaded.model.name, &loaded.name);
        if let Some(object) = document.as_object_mut() {
            object.remove("samples");
        }
        Ok(PyTrajectory {
            title: format!("{}: scenario {}", loaded.model.name, loaded.name),
            document: json(&document)?,
            trajectory,
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
        self.model.name.clone()
    }

    /// The model file's text.
    #[getter]
    fn text(&self) -> String {
        self.source.text().to_string()
    }

    /// Whether the model is a linear graph.
    #[getter]
    fn is_linear_graph(&self) -> bool {
        self.model.linear_graph.is_some()
    }

    /// Whether some law makes the model nonlinear.
    #[getter]
    fn is_nonlinear(&self) -> bool {
        self.model.is_nonlinear()
    }

    /// `bondgraph check`: the one-line summary.
    fn check(&self, py: Python<'_>) -> PyResult<String> {
        guard(py, || self.check_summary())
    }

    /// `bondgraph modes --format json`.
    #[pyo3(signature = (states=None))]
    fn modes(&self, py: Python<'_>, states: Option<String>) -> PyResult<String> {
        guard(py, || self.modes_json(states.as_deref()))
    }

    /// `bondgraph equations --format json` (and its LaTeX and text).
    #[pyo3(signature = (mode=None, states=None, outputs=Vec::new(), at=None))]
    fn equations(
        &self,
        py: Python<'_>,
        mode: Option<String>,
        states: Option<String>,
        outputs: Vec<String>,
        at: Option<String>,
    ) -> PyResult<PyEquations> {
        guard(py, || {
            self.derive(mode.as_deref(), states.as_deref(), &outputs, at.as_deref())
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
        let request = bondgraph::analyze::Request {
            mode,
            input,
            output,
            at,
            equilibrium,
        };
        guard(py, || {
            let analyzed = bondgraph::analyze::analyze(&self.model, &self.source, &request)?;
            let has_channel = analyzed.has_transfer_function();
            Ok(PyAnalysis {
                json: json(&analyzed.json())?,
                text: analyzed.text(),
                bode_svg: has_channel.then(|| analyzed.bode_svg()).transpose()?,
                step_svg: has_channel.then(|| analyzed.step_svg()).transpose()?,
            })
        })
    }

    /// `bondgraph graph --format svg`: a bond graph with its causal strokes, or a linear graph
    /// with its normal tree.
    #[pyo3(signature = (mode=None))]
    fn graph_svg(&self, py: Python<'_>, mode: Option<String>) -> PyResult<Option<String>> {
        guard(py, || self.svg_of(mode.as_deref()))
    }

    /// `bondgraph graph --format dot` of a bond graph (`None` for a linear graph).
    #[pyo3(signature = (mode=None))]
    fn graph_dot(&self, py: Python<'_>, mode: Option<String>) -> PyResult<Option<String>> {
        guard(py, || self.dot_of(mode.as_deref()))
    }

    /// `bondgraph simulate` with the scenario file at `path`.
    fn simulate_file(&self, py: Python<'_>, path: String) -> PyResult<PyTrajectory> {
        guard(py, || self.run_scenario(read_source(&path)?))
    }

    /// `bondgraph simulate` with the scenario in `text`.
    fn simulate_text(&self, py: Python<'_>, text: String, name: String) -> PyResult<PyTrajectory> {
        guard(py, || self.run_scenario(SourceFile::new(name, text)))
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
        self.trajectory.times.clone()
    }

    /// The outputs, row-major: output `j` of sample `k` at `k * len(outputs) + j`.
    #[getter]
    fn values(&self) -> Vec<f64> {
        self.trajectory.values.clone()
    }

    /// The mode at each sample, as an index into the document's `modes`.
    #[getter]
    fn sample_modes(&self) -> Vec<usize> {
        self.trajectory.sample_modes.clone()
    }

    /// The recorded outputs against time, the modes shaded (`simulate --plot`), as SVG.
    fn plot_svg(&self, py: Python<'_>) -> PyResult<String> {
        guard(py, || {
            bondgraph::plot::plot_svg(&self.trajectory, &self.title, &[])
                .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot plot: {e}")))
        })
    }
}
