//! Model text to `bondgraph analyze`'s report: poles, the first channel's transfer function,
//! its step and frequency responses, as text, JSON and the Bode plot's SVG. Any input must give
//! a report or a failure, never a panic, a hang, `NaN` read as an answer or an overflow.
//!
//! Nonlinear models go through the equilibrium search from all zeros, as the command does
//! without `--at`, so the search's budget is exercised too.
#![no_main]

use bondgraph_core::source::SourceFile;
use bondgraph_view::analyze::{Request, analyze};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let source = SourceFile::new("fuzz.ron", text);
    let Ok(model) = bondgraph_ron::model::load_source(&source) else {
        return;
    };
    let request = Request {
        mode: None,
        input: None,
        output: None,
        at: None,
        equilibrium: false,
    };
    if let Ok(analyzed) = analyze(&model, &source, &request) {
        let _ = analyzed.text();
        let _ = analyzed.json();
        let _ = analyzed.bode_svg();
    }
});
