//! What the commands (and the Python bindings) fail with: the libraries' diagnostics plus
//! the files they point into, so that the edge that renders them (the command line's
//! stderr, a Python exception) can show each problem with its line.
//!
//! The libraries keep their own typed errors; this is the one type they are turned into
//! at the edge, shared by the binary and the bindings so that both say the same thing.

use std::sync::Arc;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics};
use bondgraph_core::source::SourceFile;

/// A failure to report: diagnostics, and the sources they point into when there are some.
#[derive(Debug)]
pub struct Failure {
    /// The problems, each with its place when it has one.
    pub diagnostics: Diagnostics,
    /// The files the diagnostics may point into.
    pub sources: Vec<Arc<SourceFile>>,
}

impl From<Diagnostics> for Failure {
    fn from(diagnostics: Diagnostics) -> Self {
        Self {
            diagnostics,
            sources: Vec::new(),
        }
    }
}

impl Failure {
    /// A failure with a plain message (no file to point into).
    pub fn message(kind: DiagnosticKind, message: impl Into<String>) -> Self {
        Self::from(Diagnostics::from(Diagnostic::new(kind, message)))
    }

    /// Diagnostics that point into `sources`.
    pub fn with_sources(diagnostics: Diagnostics, sources: &[&Arc<SourceFile>]) -> Self {
        let mut sources: Vec<Arc<SourceFile>> = sources.iter().map(|s| Arc::clone(s)).collect();
        // A diagnostic inside a sub-model's file points into a file no command opened:
        // read it, so that the problem is shown with its line like any other.
        for diagnostic in &diagnostics.0 {
            let Some(location) = &diagnostic.location else {
                continue;
            };
            if location.is_in_code() || sources.iter().any(|s| s.name() == location.file) {
                continue;
            }
            let path = std::path::Path::new(&location.file);
            if let Ok(text) = bondgraph_ron::read::read_text(path, "") {
                sources.push(SourceFile::new(location.file.clone(), text));
            }
        }
        Self {
            diagnostics,
            sources,
        }
    }
}

/// Diagnostics that point into one source.
pub fn with_source(diagnostics: Diagnostics, source: &Arc<SourceFile>) -> Failure {
    Failure::with_sources(diagnostics, &[source])
}
