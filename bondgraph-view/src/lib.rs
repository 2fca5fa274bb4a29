//! What `bondgraph` shows: each command's document, for every front end.
//!
//! The `bondgraph` binary and the Python bindings (`python/`) print the same documents from
//! the same code: `check`, `modes`, `graph`, `equations` ([`derive`](mod@derive)), `simulate`,
//! [`analyze`], [`calibrate`], [`compare`], [`discover`] and `explain` each build their
//! result here as text, JSON, CSV or SVG, with the drawings ([`bg_svg`], [`lg_svg`]), plots
//! ([`plot`], [`residual_plot`]) and diagnostics rendered with a snippet of the file they
//! point into ([`diagnostics`]). Nothing here parses a command line or draws a progress bar:
//! the formats are plain enums ([`formats`]) that each front end maps its own options onto.
//!
//! ```
//! use bondgraph_core::model;
//! use bondgraph_core::modes::Mode;
//! use bondgraph_core::normal_tree;
//! use bondgraph_core::laws;
//!
//! let text = std::fs::read_to_string("../models/examples/rlc.lg.ron").unwrap();
//! let model = bondgraph_ron::model::load_str("rlc.lg.ron", &text).unwrap();
//! let graph = model.linear_graph().unwrap();
//! let mode = Mode::initial(&model);
//! let tree = normal_tree::of_mode(&model, &laws::for_mode(&model, &mode)).unwrap();
//! let svg = bondgraph_view::lg_svg::draw(&model, graph, &tree, &mode.spec(&model));
//! assert!(svg.starts_with("<svg"));
//! ```

pub mod analyze;
pub mod analyze_plot;
pub mod bg_svg;
pub mod calibrate;
pub mod check;
pub mod compare;
pub mod conventions;
pub mod derive;
pub mod diagnostics;
pub mod discover;
pub mod explain_bg;
pub mod explain_lg;
pub mod failure;
pub mod files;
pub mod formats;
pub mod graph;
pub mod lg_graph;
pub mod lg_svg;
pub mod measured;
pub mod output;
mod parts;
pub mod plot;
pub mod residual_plot;
pub mod simulate;
pub mod trajectory;
pub mod unit_label;

pub use failure::{Failure, with_source};
pub use files::{count, json, load, parse_mode, read_source, write_file};
pub use output::print;
