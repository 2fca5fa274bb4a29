//! Measured data against models: experiments, calibration, residuals, candidate extensions,
//! selection, for any model.
//!
//! A model derived from first principles is only as good as its agreement with the system it
//! describes. This crate is where the two meet: it reads measurements (the conditions that
//! were set and what was observed, in the columns an experiment file names), calibrates a
//! model's parameters on them, computes residuals by regime and by condition, tries candidate
//! extensions (small bond-graph fragments with a physical cause) that could explain what the
//! model gets wrong, and selects among them on held-out data, saying when the data cannot
//! tell candidates apart. It knows nothing of any particular system: a study uses it as any
//! other program does.
//!
//! - [`experiment`]: the experiment file (which columns set which inputs, what is observed,
//!   what an empty cell removes, what is refitted);
//! - [`data`]: the CSV reader (which refuses bad rows and says where they are) and writer;
//! - [`budget`]: the work each prediction and each fit may do, and the trials that ran out;
//! - [`predict`]: a model prepared once for an experiment, predicting rows as steady states
//!   or, for a time series, along a simulated run;
//! - [`calibrate`]: bounded least squares for piecewise-smooth steady states, and [`global`]:
//!   the search over the faces where friction thresholds tie, around it;
//! - [`calibration`]: a model calibrated on data, with residuals by regime and condition;
//! - [`folds`] and [`probes`]: held-out folds (for a time series, whole runs or contiguous
//!   blocks of one, every run simulated whole), and conditions (or, along a run, times) that
//!   separate two models;
//! - [`noise`]: where the noise level comes from (declared, pure error of replicated
//!   conditions, or a model's residual), and the lack-of-fit test it allows;
//! - [`discover`]: which candidate extension explains the misfit;
//! - [`weights`]: several observed columns in one fit, each in levels of its noise;
//! - [`synthetic`]: data made from a model with known values, for tests.
//!
//! # Example
//!
//! A mass dragged through a damper by a constant force settles at `v = F/b`; three steady
//! rows measured at `b = 4 N·s/m` calibrate `b` back from a start of 1:
//!
//! ```
//! use bondgraph_core::source::SourceFile;
//! use bondgraph_fit::{calibration::calibrate, data, discover::Settings, experiment::Experiment};
//!
//! let model = SourceFile::new("drag.ron", r#"Model(
//!     name: "drag",
//!     parameters: {
//!         "m": (value: 1.0, unit: "kg"),
//!         "b": (value: 1.0, unit: "N*s/m", bounds: (0.1, 100.0)),
//!     },
//!     inputs: { "F": (unit: "N") },
//!     elements: { "pull": Se(effort: "F"), "v": One, "mass": I(inertance: "m"),
//!                 "damper": R(resistance: "b") },
//!     bonds: [("pull", "v"), ("v", "mass"), ("v", "damper")],
//! )"#);
//! let experiment = Experiment::from_source(&SourceFile::new("experiment.ron", r#"Experiment(
//!     kind: Steady,
//!     conditions: [("F_N", "F", 1.0)],
//!     observed: [("v_m_s", "flow:mass", 1.0)],
//!     fitted: ["b"],
//! )"#)).unwrap();
//! let dataset = data::read("rows.csv", "F_N,v_m_s\n1,0.25\n2,0.5\n3,0.75\n", &experiment).unwrap();
//!
//! let calibration = calibrate(&model, &experiment, &dataset, &Settings::default()).unwrap();
//! let b = calibration.params["b"].value;
//! assert!((b - 4.0).abs() < 1e-9, "b = {b}");
//! ```

pub mod budget;
pub mod calibrate;
pub mod calibration;
pub mod data;
pub mod discover;
pub mod experiment;
pub mod folds;
pub mod global;
pub mod noise;
pub mod predict;
pub mod probes;
pub mod stats;
pub mod synthetic;
pub mod weights;
