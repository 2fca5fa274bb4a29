//! What a prediction of one row is, and how a row is named in messages: shared by the steady
//! and the time-series predictions.

use crate::data::Measurement;
use crate::experiment::Experiment;

/// The prediction of one row.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    /// The predicted value of each observed column, in the column's units.
    pub observed: Vec<f64>,
    /// The mode the model settles in (`fr=slip+,k=slack`).
    pub mode: String,
}

/// `column = value, ...` of a row's condition cells, `column empty` for an empty one.
pub fn describe(experiment: &Experiment, row: &Measurement) -> String {
    experiment
        .condition_columns()
        .iter()
        .zip(&row.conditions)
        .map(|(column, value)| match value {
            Some(v) => format!("{column} = {v}"),
            None => format!("{column} empty"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}
