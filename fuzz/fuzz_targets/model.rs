//! Model text to equations and modes: what `bondgraph check`, `modes` and, for a linear
//! graph, `graph` do. Any input must give a model or diagnostics, never a panic, an abort or
//! a hang.
//!
//! Each input is read as the loader reads it (a bond graph or a linear graph, by its
//! top-level value) and also as the other kind of model file, so that mutations of bond
//! graphs reach the linear-graph reader and mutations of linear graphs the bond graph's.
#![no_main]

use std::sync::Arc;

use bondgraph_core::equations::Options;
use bondgraph_core::model::{Model, linear_graph, validate};
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::source::SourceFile;
use bondgraph_core::{causality, laws, normal_tree};
use bondgraph_ron::model::{Format, parse};
use libfuzzer_sys::fuzz_target;

/// The text as the other kind of model file than the one its top-level value names.
fn as_other_format(source: &Arc<SourceFile>) -> Option<Model> {
    match Format::of(source.text()) {
        Format::BondGraph => bondgraph_ron::model::linear_graph::load(source).ok(),
        Format::LinearGraph => {
            let (raw, map) = parse::parse_model(source).ok()?;
            validate::validate(source, raw, &map).ok()
        }
    }
}

/// `check` and `modes`, and for a linear graph the normal tree of its initial mode as
/// `graph` draws it.
fn exercise(model: &Model) {
    let options = Options::default();
    if model.is_nonlinear() {
        let _ = modes::reachable_nonlinear(model, &options);
    } else {
        let _ = modes::reachable(model, &options);
    }
    if model.linear_graph().is_some() {
        let laws = laws::for_mode(model, &Mode::initial(model));
        match causality::assign(model, &laws) {
            Ok(_) => {
                let _ = normal_tree::of_mode(model, &laws);
            }
            Err(diagnostics) => {
                let _ = linear_graph::reword(model, diagnostics);
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let source = SourceFile::new("fuzz.ron", text);
    if let Ok(model) = bondgraph_ron::model::load_source(&source) {
        exercise(&model);
    }
    if let Some(model) = as_other_format(&source) {
        exercise(&model);
    }
});
