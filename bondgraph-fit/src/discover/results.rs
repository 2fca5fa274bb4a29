//! What discovery finds, as values: the JSON document of `discover` is their serialisation.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::noise::{LackOfFit, PureError};

/// A parameter's fitted value and how well the data determines it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Estimate {
    /// The fitted value.
    pub value: f64,
    /// Its standard error, where the Jacobian determines it.
    pub std_error: Option<f64>,
    /// For a threshold, the interval of values that fit equally well.
    pub interval: Option<(f64, f64)>,
    /// Whether the fit ended on a bound.
    pub at_bound: bool,
}

/// The base model's scores.
#[derive(Clone, Debug, Serialize)]
pub struct Baseline {
    /// RMSE of the fit on all rows, in the observed column's units.
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
    /// The refitted parameters.
    pub params: BTreeMap<String, Estimate>,
    /// Predictions of every row made by its fit and its folds' refits: the search's cost.
    pub evaluations: usize,
}

/// One candidate's result.
#[derive(Clone, Debug, Serialize)]
pub struct Ranked {
    /// The extension's id.
    pub id: String,
    /// Every refitted parameter (the base's and its own).
    pub params: BTreeMap<String, Estimate>,
    /// RMSE of the fit on all rows, in the observed column's units.
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
    /// The corrected Akaike criterion against the baseline's (negative: better).
    pub score: f64,
    /// The F-test's p-value against the baseline.
    pub p_value: f64,
    /// Predictions of every row made by its fit and its folds' refits: the search's cost.
    pub evaluations: usize,
    /// What the data says of it: `selected`, `indistinguishable`, `qualifies`,
    /// `not significant`, `aliased with the base`, `no effect on this data` or
    /// `worse than the base` (its bounds keep it from containing the base model here).
    pub verdict: String,
}

/// Residuals of one regime.
#[derive(Clone, Debug, Serialize)]
pub struct RegimeResiduals {
    /// The regime's physical name.
    pub regime: String,
    /// Rows in it.
    pub rows: usize,
    /// Mean residual (model minus measured), in the observed column's units.
    pub mean: f64,
    /// Root-mean-square residual.
    pub rmse: f64,
    /// Whether the mean stands out of the noise (beyond three standard errors).
    pub stands_out: bool,
}

/// The trend of the residuals along one condition column (or a time series' time column).
#[derive(Clone, Debug, Serialize)]
pub struct FactorTrend {
    /// The condition column, or the time column.
    pub condition: String,
    /// The regime the trend is taken in (`all` for every row).
    pub regime: String,
    /// Residual change per unit of the condition (observed units per unit).
    pub slope: f64,
    /// Its standard error.
    pub std_error: f64,
    /// Whether it stands out of the noise (|slope| > 3 standard errors).
    pub stands_out: bool,
}

/// Residuals by regime and by factor.
#[derive(Clone, Debug, Serialize)]
pub struct Residuals {
    /// By operating regime.
    pub by_regime: Vec<RegimeResiduals>,
    /// Along each condition column and, for a time series, along its time column (a trend
    /// in time), over all rows and within each regime with enough rows.
    pub by_condition: Vec<FactorTrend>,
}

/// One row with its predictions.
#[derive(Clone, Debug, Serialize)]
pub struct RowResult {
    /// A time series' sample time, in the time column's units.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The condition cells, by column (`None`: empty).
    pub conditions: BTreeMap<String, Option<f64>>,
    /// The measured value.
    pub measured: f64,
    /// The refitted base model's.
    pub baseline: f64,
    /// The selected extended model's.
    pub selected: Option<f64>,
    /// The regime the base model settles in.
    pub regime: String,
}

/// A measurement that would tell two candidates apart.
#[derive(Clone, Debug, Serialize)]
pub struct Separation {
    /// The candidate the selected one (or the baseline) is confused with.
    pub id: String,
    /// What to measure.
    pub measurement: String,
}

/// Held-out RMSE before and after the extension.
#[derive(Clone, Debug, Serialize)]
pub struct Gain {
    /// The baseline's.
    pub rmse_heldout_before: f64,
    /// The selected extension's (the baseline's when nothing is selected).
    pub rmse_heldout_after: f64,
}

/// Everything `discover` finds.
#[derive(Clone, Debug, Serialize)]
pub struct Discovery {
    /// The data's name.
    pub data: String,
    /// Rows used.
    pub rows: usize,
    /// The observed column's name (every RMSE and residual is in its units).
    pub observed: String,
    /// The noise level, in the observed column's units ([`crate::noise`]): the experiment's
    /// declared one, else the pure error of replicated conditions, else the best model's
    /// residual standard deviation; `None` when the data cannot estimate it (replicates
    /// that repeat exactly, an exact fit), and then nothing is judged in noise levels.
    pub noise: Option<f64>,
    /// Where `noise` came from: `declared in the experiment`, `pure error of N replicated
    /// conditions (D dof)`, `residual of the base model (D dof)`, `residual of 'ID' (D
    /// dof)`, or `cannot be estimated: ...` and why.
    pub noise_source: String,
    /// The scatter of replicated conditions, when some condition is measured twice.
    pub pure_error: Option<PureError>,
    /// The base model's lack-of-fit test, when the noise level does not come from a model's
    /// residuals (declared, or pure error).
    pub lack_of_fit: Option<LackOfFit>,
    /// The base model.
    pub baseline: Baseline,
    /// Candidates, best held-out RMSE first.
    pub ranking: Vec<Ranked>,
    /// The selected extension, or `None` when none gains beyond the noise.
    pub selected: Option<String>,
    /// Its physical cause.
    pub cause: Option<String>,
    /// Candidates the data cannot tell apart from the selected one (or from the baseline).
    pub indistinguishable: Vec<String>,
    /// For each of them, what would separate it.
    pub separation: Vec<Separation>,
    /// Candidates with no effect on this data.
    pub untestable: Vec<String>,
    /// The gain.
    pub gain: Gain,
    /// Residuals of the baseline.
    pub residuals_before: Residuals,
    /// Residuals of the selected extension.
    pub residuals_after: Option<Residuals>,
    /// Every row.
    pub table: Vec<RowResult>,
    /// How firm the selection is over resamples; `None` when resampling is turned off.
    pub stability: Option<super::Stability>,
    /// The selected extended model with its fitted values, as a model file.
    #[serde(skip)]
    pub extended_model: Option<String>,
}
