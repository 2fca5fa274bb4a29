//! Models for unit tests, written as model files: read with `ron` straight into a
//! [`ModelSpec`](crate::model::ModelSpec) and built by the [`Builder`](crate::model::Builder),
//! so they carry no locations (the reader, with its source map, is `bondgraph-ron`'s, and
//! tests of located diagnostics live in the integration tests).

use crate::model::{Builder, Model, ModelSpec};

/// The bond-graph model in `text` (a `Model(...)` file), checked.
pub(crate) fn model(text: &str) -> Model {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let spec: ModelSpec = options.from_str(text).unwrap_or_else(|e| panic!("{e}"));
    Builder::from(spec)
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}
