//! Readers of bondgraph's RON files: models, linear graphs, scenarios, extensions, answers.
//!
//! Every file a user writes comes in here and leaves as a checked `bondgraph-core` value:
//! raw text never goes further in. Each reader collects every problem it can find, each a
//! diagnostic that names the file, line, column and element.
//!
//! - [`model`]: model files (bond graphs and linear graphs) to a checked
//!   [`Model`](bondgraph_core::model::Model), and [`model::edit`], variants of a model file;
//! - [`scenario`]: how a model is driven in a simulation;
//! - [`extension`]: fragments with a physical cause, merged into a model file;
//! - [`answer`]: a student's state equations, to compare with a derivation;
//! - [`source_map`]: where each entry, field and item of a file is;
//! - [`read`]: a file's text, bounded in size, with invalid UTF-8 located.
//!
//! # Example
//!
//! ```
//! use bondgraph_core::source::SourceFile;
//! use bondgraph_ron::{model, scenario};
//!
//! let model = SourceFile::new("msd.ron", r#"Model(
//!     name: "mass_spring_damper",
//!     parameters: { "m": (value: 2.0, unit: "kg"), "k": (value: 200.0, unit: "N/m") },
//!     inputs: { "F": (unit: "N") },
//!     elements: { "force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
//!                 "spring": C(stiffness: "k") },
//!     bonds: [("force", "v"), ("v", "mass"), ("v", "spring")],
//! )"#);
//! let checked = bondgraph_ron::model::load_source(&model).unwrap();
//! assert_eq!(checked.elements().len(), 4);
//!
//! let file = SourceFile::new("step.ron", r#"Scenario(
//!     name: "step", inputs: { "F": Constant(1.0) },
//!     duration: 0.5, record: ["effort:spring", "flow:sprung"],
//! )"#);
//! let error = scenario::load(&file, &model).unwrap_err();
//! assert_eq!(error.first().location.as_ref().unwrap().line, 3);
//! assert!(error.first().message.contains("sprung"), "{}", error.first());
//! ```

pub mod answer;
pub mod extension;
pub mod model;
pub mod read;
pub mod scenario;
pub mod source_map;
