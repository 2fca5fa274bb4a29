//! The `bondgraph` library: what the command line prints, for other front ends.
//!
//! The `bondgraph` binary renders the libraries' results as text, JSON, CSV and SVG; the
//! modules here are the renderers and the commands' documents that another front end (the
//! Python bindings in `python/`) needs too, so that both print the same documents from the
//! same code: `check`, `modes`, `graph`, `equations` (`derive`), `simulate`, `analyze`,
//! `calibrate`, `compare`, `discover`, `explain` and `reproduce` each build their result
//! here, and the binary only parses arguments and prints.
//!
//! ```
//! use bondgraph_core::model;
//! use bondgraph_core::modes::Mode;
//! use bondgraph_core::normal_tree;
//! use bondgraph_core::laws;
//!
//! let text = std::fs::read_to_string("models/examples/rlc.lg.ron").unwrap();
//! let model = model::load_str("rlc.lg.ron", &text).unwrap();
//! let graph = model.linear_graph.as_ref().unwrap();
//! let mode = Mode::initial(&model);
//! let tree = normal_tree::of_mode(&model, &laws::for_mode(&model, &mode)).unwrap();
//! let svg = bondgraph::lg_svg::draw(&model, graph, &tree, &mode.spec(&model));
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
pub mod plot;
pub mod reproduce;
pub mod residual_plot;
pub mod simulate;
pub mod trajectory;

pub use failure::{Failure, with_source};
pub use files::{count, json, load, parse_mode, read_source, write_file};
pub use output::print;
