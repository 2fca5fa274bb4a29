//! CSV text to measurements (`bondgraph_fit::data`): a dataset or an error naming the
//! row and column, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(dataset) = bondgraph_fit::data::read("fuzz.csv", text) {
        let _ = bondgraph_fit::data::validate(&dataset);
    }
});
