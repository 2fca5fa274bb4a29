//! The robot's measurement columns, as `models/eversion/experiment.ron` names them.
//!
//! | column | meaning |
//! |---|---|
//! | `P_s_kPa` | supply pressure in the tank, relative to the lumen, kPa |
//! | `v_ac_mm_s` | active-channel velocity, mm/s |
//! | `v_ct_mm_s` | catheter velocity, mm/s; empty means no catheter in the lumen |
//! | `v_ge_mm_s` | measured steady-state tip velocity, mm/s |
//!
//! A [`Measurement`] holds its condition cells in the experiment's order; this module is
//! the one place that knows which is which.

use std::sync::Arc;

use bondgraph_fit::data::Measurement;
use bondgraph_fit::experiment::Experiment;

/// The condition columns, in the order of the flagship's experiment file.
pub const CONDITIONS: [&str; 3] = ["P_s_kPa", "v_ac_mm_s", "v_ct_mm_s"];
/// The observed column.
pub const TIP: &str = "v_ge_mm_s";

/// Whether `experiment` has the flagship's columns in the flagship's order.
pub fn matches(experiment: &Experiment) -> bool {
    experiment.condition_columns() == CONDITIONS
        && experiment.observed.len() == 1
        && experiment.observed[0].column == TIP
}

/// Supply pressure, kPa.
pub fn pressure(row: &Measurement) -> f64 {
    row.conditions[0].unwrap_or(f64::NAN)
}

/// Active-channel velocity, mm/s.
pub fn channel(row: &Measurement) -> f64 {
    row.conditions[1].unwrap_or(f64::NAN)
}

/// Catheter velocity, mm/s, or `None` without a catheter.
pub fn catheter(row: &Measurement) -> Option<f64> {
    row.conditions[2]
}

/// Measured tip velocity, mm/s.
pub fn tip(row: &Measurement) -> f64 {
    row.observed[0]
}

/// A row of the flagship's experiment (line `row` of `file`).
pub fn row(
    file: &Arc<str>,
    row: usize,
    pressure_kpa: f64,
    channel_mm_s: f64,
    catheter_mm_s: Option<f64>,
    tip_mm_s: f64,
) -> Measurement {
    Measurement {
        conditions: vec![Some(pressure_kpa), Some(channel_mm_s), catheter_mm_s],
        observed: vec![tip_mm_s],
        time: None,
        row,
        file: file.clone(),
    }
}
