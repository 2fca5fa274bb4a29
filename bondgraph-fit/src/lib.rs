//! Measured data against bond-graph models.
//!
//! A model derived from first principles is only as good as its agreement with the robot it
//! describes. This crate is where the two meet: it reads measured steady states, calibrates a
//! model's parameters on them, computes residuals, tries candidate extensions (small bond-graph
//! fragments with a physical cause) that could explain what the model gets wrong, and selects
//! among them on held-out data, saying when the data cannot tell candidates apart.
//!
//! - [`data`]: the CSV format of measured data, its reader (which refuses bad rows and says
//!   where they are) and its writer (for synthetic data);
//! - [`experiment`]: the protocol that turns a row of data into a simulation, and the
//!   prediction of rows as steady states;
//! - [`reproduce`]: the main job, the flagship against the paper's tables and figure, and
//!   [`report`], its report.

pub mod calibrate;
pub mod data;
pub mod discover;
pub mod experiment;
pub mod report;
pub mod reproduce;
pub mod stats;
pub mod synthetic;
