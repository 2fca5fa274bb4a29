//! Reading model files: RON text to a raw model plus a map of where everything is.
pub mod raw;
pub mod source_map;
