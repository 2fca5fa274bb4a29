//! Reading model files and writing results, with failures that name the file.
//!
//! Every command reads its inputs through these (so that the size limit and the UTF-8
//! check of `bondgraph_ron::read` apply everywhere) and writes its files through
//! [`write_file`] (which creates missing folders, as `--out` promises).

use std::path::Path;
use std::sync::Arc;

use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_core::model::{ElementKind, Model};
use bondgraph_core::modes;
use bondgraph_core::source::SourceFile;

use crate::failure::{Failure, with_source};

/// Reads a file into a [`SourceFile`].
pub fn read_source(path: &Path) -> Result<Arc<SourceFile>, Failure> {
    let name = path.display().to_string();
    let text = bondgraph_ron::read::read_text(path, "")
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
/// ([`bondgraph_ron::model::load_source`]).
pub fn load(path: &Path) -> Result<(Model, Arc<SourceFile>), Failure> {
    let name = path.display().to_string();
    let text = bondgraph_ron::read::read_text(path, "model file")
        .map_err(|message| Failure::message(DiagnosticKind::Io, message))?;
    let source = SourceFile::new(name, text);
    let model = bondgraph_ron::model::load_source(&source).map_err(|d| with_source(d, &source))?;
    Ok((model, source))
}

/// The mode given (`fr=stuck,string=taut`), or the model's initial mode, as the model has
/// it at its values: a contact whose Stribeck velocity is zero there has no creeping range,
/// so its initial `creep±` is `slip±` and a mode given with it creeping is refused.
pub fn parse_mode(
    model: &Model,
    spec: Option<&str>,
    source: &Arc<SourceFile>,
) -> Result<modes::Mode, Failure> {
    let Some(spec) = spec else {
        return Ok(modes::Mode::initial(model).at_values(model, model.values()));
    };
    let mode = modes::Mode::parse(model, spec).map_err(|d| with_source(d, source))?;
    for &(id, element_mode) in mode.assignments() {
        if let ElementKind::Friction(contact) = &model.element(id).kind
            && contact.mode_at(element_mode, model.values()) != element_mode
        {
            let stribeck = contact.stribeck.as_ref().map_or("", |s| s.text.as_str());
            return Err(Failure::message(
                DiagnosticKind::BadMode,
                format!(
                    "mode '{spec}': contact '{}' cannot be {}: its Stribeck velocity \"{stribeck}\" is 0, which leaves no creeping range (it slips as a Karnopp contact)",
                    model.element(id).name,
                    element_mode.name()
                ),
            ));
        }
    }
    Ok(mode)
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
