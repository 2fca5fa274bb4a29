//! Whole-crate tests of the fit crate on models of the repository other than the flagship
//! (which has its own study, `studies/eversion`).

mod base_refit;
mod calibration;
mod columns;
mod discover;
mod experiments;
mod motor;
mod motor_hidden;
mod noise;
