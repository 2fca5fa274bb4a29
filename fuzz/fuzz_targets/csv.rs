//! CSV text to measurements (`bondgraph_fit::data`) against a fixed experiment (the geared
//! motor's: two condition columns, one of them `absent`-able, one observed column): a
//! dataset or an error naming the row and column, never a panic.
#![no_main]

use std::sync::OnceLock;

use bondgraph_fit::experiment::Experiment;
use libfuzzer_sys::fuzz_target;

fn experiment() -> &'static Experiment {
    static EXPERIMENT: OnceLock<Experiment> = OnceLock::new();
    EXPERIMENT.get_or_init(|| {
        Experiment::parse(
            "models/examples/geared_motor/experiment.ron",
            include_str!("../../models/examples/geared_motor/experiment.ron"),
        )
        .expect("the geared motor's experiment parses")
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = bondgraph_fit::data::read("fuzz.csv", text, experiment());
});
