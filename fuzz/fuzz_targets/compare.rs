//! A student's answer file checked against a fixed model (the mass-spring-damper), as
//! `bondgraph compare` does: a verdict, or diagnostics pointing into the answer, never a
//! panic or a hang (answers hold matrices of expressions the comparison expands and ranks).
#![no_main]

use std::sync::{Arc, OnceLock};

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_view::compare::check;
use libfuzzer_sys::fuzz_target;

fn base() -> &'static (Model, Arc<SourceFile>) {
    static BASE: OnceLock<(Model, Arc<SourceFile>)> = OnceLock::new();
    BASE.get_or_init(|| {
        let source = SourceFile::new(
            "models/examples/mass_spring_damper.ron",
            include_str!("../../models/examples/mass_spring_damper.ron"),
        );
        let model = bondgraph_ron::model::load_source(&source).expect("the example loads");
        (model, source)
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let (model, source) = base();
    let answer = SourceFile::new("answer.ron", text);
    let _ = check(model, source, &answer, None);
});
