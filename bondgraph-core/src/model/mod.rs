//! Reading model files: RON text to a raw model plus a map of where everything is.
//!
//! Parsing is split so that each part answers one question: [`raw`] is the file format as
//! serde reads it, [`source_map`] records where each entry and bond is (serde keeps no
//! positions), and [`parse`] runs both and turns ron's errors into diagnostics that name
//! the element and point at the offending token.
pub mod parse;
pub mod raw;
pub mod source_map;
