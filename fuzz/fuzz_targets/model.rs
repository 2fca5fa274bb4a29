//! Model text to equations and modes: what `bondgraph check` and `modes` do. Any input
//! must give a model or diagnostics, never a panic, an abort or a hang.
#![no_main]

use bondgraph_core::equations::Options;
use bondgraph_core::{model, modes};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(model) = model::load_str("fuzz.ron", text) else {
        return;
    };
    let options = Options::default();
    if model.is_nonlinear() {
        let _ = modes::reachable_nonlinear(&model, &options);
    } else {
        let _ = modes::reachable(&model, &options);
    }
});
