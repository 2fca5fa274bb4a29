//! Whole-crate tests of the fit crate on the bundled models and data.

mod global_fits;
mod hidden;
mod paper;
mod reproduce;
mod stability;
mod stalls;
mod support;
mod tables;
