//! Python bindings of bondgraph: the extension module `bondgraph._native`.
//!
//! The Python package `bondgraph` (`python/bondgraph/`) is the API people use; this module
//! is its engine. Each function here runs the same library calls as a command of the
//! `bondgraph` program and returns the same JSON document as text, built by the same code,
//! so that the bindings and the command line cannot disagree; the Python layer turns the
//! documents into objects and numpy arrays. Every failure is a `BondGraphError` carrying the
//! diagnostics (`error`), and no panic crosses into the interpreter.
//!
//! Built by maturin (`pip install ./python`), which sets `PYO3_BUILD_EXTENSION_MODULE` so
//! that the module does not link libpython; a plain `cargo build` of the workspace links it
//! and checks that everything compiles. The tests are Python's: `python/tests/`.

mod error;
mod fit;
mod model;
mod results;

use pyo3::prelude::*;

/// The allocator the `bondgraph` program runs with: a fit allocates in its inner loop, and
/// the system's allocator cost a fifth of its time there. Only the engine's own memory goes
/// through it; Python's objects keep Python's allocator.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The engine of the `bondgraph` Python package.
#[pymodule]
#[pyo3(name = "_native")]
fn bondgraph_native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add("BondGraphError", py.get_type::<error::BondGraphError>())?;
    module.add_class::<error::PyDiagnostic>()?;
    module.add_class::<model::PyModel>()?;
    module.add_class::<results::PyEquations>()?;
    module.add_class::<results::PyTrajectory>()?;
    module.add_class::<results::PyAnalysis>()?;
    module.add_class::<results::PyComparison>()?;
    module.add_function(wrap_pyfunction!(fit::calibrate, module)?)?;
    module.add_function(wrap_pyfunction!(fit::discover, module)?)?;
    module.add_function(wrap_pyfunction!(fit::reproduce, module)?)?;
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
