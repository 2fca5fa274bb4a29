//! Whole-crate tests of the solver on real model files, against closed-form solutions.

mod stick_slip;
mod support;
