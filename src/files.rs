//! Reading model files and writing results, with failures that name the file.
//!
//! Every command reads its inputs through these (so that the size limit and the UTF-8
//! check of `bondgraph_core::read` apply everywhere) and writes its files through
//! [`write_file`] (which creates missing folders, as `--out` promises).

use std::path::Path;
use std::sync::Arc;

use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_core::model::{self, Model};
use bondgraph_core::modes;
use bondgraph_core::source::SourceFile;

use crate::failure::{Failure, with_source};

/// Reads a file into a [`SourceFile`].
pub fn read_source(path: &Path) -> Result<Arc<SourceFile>, Failure> {
    let name = path.display().to_string();
    let text = bondgraph_core::read::read_text(path, "")
        .map_err(|message| Failure::message(DiagnosticKind::Io, message))?;
    Ok(SourceFile::new(name, text))
}

/// Writes `text` to `path`, creating its directory.
pub fn write_file(path: &Path, text: &str) -> Result<(), Failure> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| {
            Failure::message(
                DiagnosticKind::Io,
                format!("cannot create '{}': {e}", parent.display()),
            )
        })?;
    }
    std::fs::write(path, text).map_err(|e| {
        Failure::message(
            DiagnosticKind::Io,
            format!("cannot write '{}': {e}", path.display()),
        )
    })
}

/// Reads and validates a model file, a bond graph or a linear graph
/// ([`model::load_source`]).
pub fn load(path: &Path) -> Result<(Model, Arc<SourceFile>), Failure> {
    let name = path.display().to_string();
    let text = bondgraph_core::read::read_text(path, "model file")
        .map_err(|message| Failure::message(DiagnosticKind::Io, message))?;
    let source = SourceFile::new(name, text);
    let model = model::load_source(&source).map_err(|d| with_source(d, &source))?;
    Ok((model, source))
}

/// The mode given (`fr=stuck,string=taut`), or the model's initial mode.
pub fn parse_mode(
    model: &Model,
    spec: Option<&str>,
    source: &Arc<SourceFile>,
) -> Result<modes::Mode, Failure> {
    match spec {
        Some(spec) => modes::Mode::parse(model, spec).map_err(|d| with_source(d, source)),
        None => Ok(modes::Mode::initial(model)),
    }
}

/// A value as pretty JSON with a final newline, as the commands print it.
pub fn json(value: &impl serde::Serialize) -> Result<String, Failure> {
    serde_json::to_string_pretty(value)
        .map(|mut s| {
            s.push('\n');
            s
        })
        .map_err(|error| {
            Failure::message(DiagnosticKind::Io, format!("cannot write JSON: {error}"))
        })
}

/// `1 bond`, `2 bonds`, `3 branches`.
pub fn count(n: usize, noun: &str) -> String {
    let plural = match (n, noun.ends_with(['s', 'h'])) {
        (1, _) => "",
        (_, true) => "es",
        _ => "s",
    };
    format!("{n} {noun}{plural}")
}
