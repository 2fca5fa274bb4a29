//! Scenario text against a fixed model (the belt with stick-slip friction) to a
//! simulation with its energy books: a trajectory or an error, never a panic or a hang.
#![no_main]

use std::sync::{Arc, OnceLock};

use bondgraph_core::source::SourceFile;
use libfuzzer_sys::fuzz_target;

fn model() -> &'static Arc<SourceFile> {
    static MODEL: OnceLock<Arc<SourceFile>> = OnceLock::new();
    MODEL.get_or_init(|| {
        SourceFile::new(
            "models/examples/belt_friction.ron",
            include_str!("../../models/examples/belt_friction.ron"),
        )
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let source = SourceFile::new("fuzz.ron", text);
    let Ok(scenario) = bondgraph_ron::scenario::load(&source, model()) else {
        return;
    };
    let _ = bondgraph_solver::scenario::run(&scenario, true);
});
