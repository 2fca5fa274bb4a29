//! Diagnostics as Python exceptions: `BondGraphError` with `.diagnostics`.
//!
//! The libraries report problems as data ([`Diagnostics`]); here they become one Python
//! exception whose message is the rendering the command line prints (a rustc-style block
//! with the offending line), and whose `diagnostics` attribute lists every problem as a
//! [`PyDiagnostic`] (file, line, column, element, message), so that a notebook can show the
//! message and a program can act on the fields.
//!
//! Nothing may unwind across the FFI boundary: [`guard`] runs each call of the bindings
//! and turns a panic (a bug, never expected) into a `BondGraphError` instead of a
//! `PanicException`, which `except Exception` would not catch.

use std::panic::{AssertUnwindSafe, catch_unwind};

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyList;

pyo3::create_exception!(
    bondgraph,
    BondGraphError,
    PyException,
    "A model, scenario, experiment or data file that cannot be used, or a computation that \
     cannot go on. `str(error)` is what the command line prints; `error.diagnostics` lists \
     each problem with its file, line, column, element and message."
);

/// One problem, as Python sees it.
#[pyclass(name = "Diagnostic", module = "bondgraph", frozen, get_all)]
#[derive(Clone, Debug)]
pub struct PyDiagnostic {
    /// What kind of problem (`"UnknownElement"`, `"Syntax"`, ...).
    pub kind: String,
    /// One sentence, naming the element, bond or parameter concerned.
    pub message: String,
    /// The file the problem is in, if it has a place.
    pub file: Option<String>,
    /// 1-based line, if the problem has a place.
    pub line: Option<usize>,
    /// 1-based column (in characters), if the problem has a place.
    pub column: Option<usize>,
    /// The element, parameter or input concerned, if any.
    pub element: Option<String>,
    /// Further explanations or suggested fixes.
    pub notes: Vec<String>,
}

#[pymethods]
impl PyDiagnostic {
    fn __repr__(&self) -> String {
        let place = match (&self.file, self.line, self.column) {
            (Some(file), Some(line), Some(column)) => format!("{file}:{line}:{column}: "),
            (Some(file), _, _) => format!("{file}: "),
            _ => String::new(),
        };
        format!("<Diagnostic {place}{}>", self.message)
    }
}

impl From<&Diagnostic> for PyDiagnostic {
    fn from(diagnostic: &Diagnostic) -> Self {
        let location = diagnostic.location.as_ref();
        Self {
            kind: format!("{:?}", diagnostic.kind),
            message: diagnostic.message.clone(),
            file: location.map(|l| l.file.clone()),
            line: location.map(|l| l.line),
            column: location.map(|l| l.column),
            element: diagnostic.element.clone(),
            notes: diagnostic.notes.clone(),
        }
    }
}

pub use bondgraph_view::Failure;

/// A [`Failure`] raised in Python.
pub trait IntoPyErr {
    /// The exception: the rendered diagnostics as message, the fields as `.diagnostics`.
    fn into_pyerr(self, py: Python<'_>) -> PyErr;
}

impl IntoPyErr for Failure {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        let text = self
            .diagnostics
            .iter()
            .map(|diagnostic| {
                let source = diagnostic.location.as_ref().and_then(|location| {
                    self.sources
                        .iter()
                        .find(|s| s.name() == location.file)
                        .map(|s| s.as_ref())
                });
                bondgraph_view::diagnostics::render(diagnostic, source)
            })
            .collect::<Vec<_>>()
            .join("\n");
        let error = BondGraphError::new_err(text);
        let list: Vec<PyDiagnostic> = self.diagnostics.iter().map(PyDiagnostic::from).collect();
        let attached =
            PyList::new(py, list).and_then(|list| error.value(py).setattr("diagnostics", list));
        match attached {
            Ok(()) => error,
            Err(other) => other,
        }
    }
}

/// Runs `call` with the GIL released, catching any panic: its result, or a
/// `BondGraphError` for a failure or a panic.
pub fn guard<T: Send>(
    py: Python<'_>,
    call: impl FnOnce() -> Result<T, Failure> + Send,
) -> PyResult<T> {
    let outcome = py.detach(|| catch_unwind(AssertUnwindSafe(call)));
    match outcome {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(failure)) => Err(failure.into_pyerr(py)),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(Failure::message(
                DiagnosticKind::Simulation,
                format!("internal error (a bug in bondgraph, please report it): {what}"),
            )
            .into_pyerr(py))
        }
    }
}
