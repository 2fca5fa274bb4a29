//! Whole-crate tests of the fit crate on the bundled models and data.

mod reproduce;
mod support;
mod tables;
