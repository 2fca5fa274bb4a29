//! Measured data against models: experiments, calibration, residuals, candidate extensions,
//! selection, for any model.
//!
//! A model derived from first principles is only as good as its agreement with the system it
//! describes. This crate is where the two meet: it reads measurements (the conditions that
//! were set and what was observed, in the columns an experiment file names), calibrates a
//! model's parameters on them, computes residuals by regime and by condition, tries candidate
//! extensions (small bond-graph fragments with a physical cause) that could explain what the
//! model gets wrong, and selects among them on held-out data, saying when the data cannot
//! tell candidates apart. It knows nothing of any particular system: the flagship study
//! in `studies/` uses it like any other user.
//!
//! - [`experiment`]: the experiment file (which columns set which inputs, what is observed,
//!   what an empty cell removes, what is refitted);
//! - [`data`]: the CSV reader (which refuses bad rows and says where they are) and writer;
//! - [`budget`]: the work each prediction and each fit may do, and the trials that ran out;
//! - [`predict`]: a model prepared once for an experiment, predicting rows as steady states
//!   or, for a time series, along a simulated run (`timeseries`);
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
mod timeseries;
pub mod weights;
