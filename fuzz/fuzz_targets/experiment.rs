//! An experiment file and a CSV, checked against a fixed model (the geared motor) as
//! `calibrate` and `discover` read them: the experiment parsed and matched to the model's
//! inputs, outputs, modes and elements (removals included), then the CSV read against it.
//! Any input must give a dataset or an error naming the file, line and entry (or row and
//! column), never a panic.
//!
//! The input is the experiment's text, a line `---`, then the CSV's text (the seeds pair
//! each shipped experiment with a CSV of its folder).
#![no_main]

use std::sync::{Arc, OnceLock};

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::predict::Predictor;
use libfuzzer_sys::fuzz_target;

fn base() -> &'static (Model, Arc<SourceFile>) {
    static BASE: OnceLock<(Model, Arc<SourceFile>)> = OnceLock::new();
    BASE.get_or_init(|| {
        let source = SourceFile::new(
            "models/examples/geared_motor/geared_motor.ron",
            include_str!("../../models/examples/geared_motor/geared_motor.ron"),
        );
        let model = bondgraph_ron::model::load_source(&source).expect("the example loads");
        (model, source)
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let (experiment_text, csv) = text.split_once("\n---\n").unwrap_or((text, ""));
    let Ok(experiment) = Experiment::parse("experiment.ron", experiment_text) else {
        return;
    };
    let (model, source) = base();
    let _ = Predictor::new(model.clone(), source, &experiment);
    let _ = bondgraph_fit::data::read("data.csv", csv, &experiment);
});
