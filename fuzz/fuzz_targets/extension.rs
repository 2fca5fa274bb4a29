//! Extension text merged into a fixed base model (the flagship robot), then checked as
//! `bondgraph extend` checks it (the merged model loaded and every reachable mode derived):
//! diagnostics pointing into the extension, or a model, never a panic.
#![no_main]

use std::sync::{Arc, OnceLock};

use bondgraph_core::source::SourceFile;
use bondgraph_ron::extension::{Extension, merge};
use libfuzzer_sys::fuzz_target;

fn base() -> &'static Arc<SourceFile> {
    static BASE: OnceLock<Arc<SourceFile>> = OnceLock::new();
    BASE.get_or_init(|| {
        SourceFile::new(
            "models/eversion/robot.ron",
            include_str!("../../models/eversion/robot.ron"),
        )
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let source = SourceFile::new("fuzz.ron", text);
    let Ok(extension) = Extension::load(&source) else {
        return;
    };
    if let Ok(extended) = merge(base(), &[extension]) {
        let _ = extended.check();
    }
});
