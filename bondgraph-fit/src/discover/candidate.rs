//! A candidate extension merged into the base model: what discovery fits beside it.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_ron::extension::{self, Extension};

use super::DiscoverError;

/// A candidate extension, merged into the base model.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The extension's id.
    pub id: String,
    /// Its physical cause.
    pub cause: String,
    /// What would show it directly.
    pub evidence: Option<String>,
    /// Its own parameters with bounds (the ones calibration fits), in file order.
    pub parameters: Vec<String>,
    /// The extended model file.
    pub source: Arc<SourceFile>,
    /// The extended model.
    pub model: Model,
}

impl Candidate {
    /// Merges `extension` into the model file `base`.
    ///
    /// # Errors
    /// Every problem of the merge or of the merged model, located in the file it came from.
    pub fn new(base: &Arc<SourceFile>, extension: &Extension) -> Result<Self, DiscoverError> {
        let extended = extension::merge(base, std::slice::from_ref(extension))?;
        let model = extended.load()?;
        let parameters = extension
            .raw
            .parameters
            .iter()
            .filter(|(_, p)| p.bounds.is_some())
            .map(|(name, _)| name.clone())
            .collect();
        Ok(Self {
            id: extension.raw.id.clone(),
            cause: extension.raw.cause.clone(),
            evidence: extension.raw.evidence.clone(),
            parameters,
            source: extended.file,
            model,
        })
    }
}
