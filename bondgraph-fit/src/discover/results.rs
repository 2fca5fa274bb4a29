//! What discovery finds, as values: the JSON document of `discover` is their serialisation.

use std::collections::BTreeMap;

use serde::{Serialize, Serializer};

use crate::noise::{LackOfFit, PureError};

/// One value per observed column, written as the value itself when there is one column (the
/// document of one column keeps its form) and as a list when there are several.
fn one_or_list<T: Serialize, S: Serializer>(values: &[T], s: S) -> Result<S::Ok, S::Error> {
    match values {
        [one] => one.serialize(s),
        several => several.serialize(s),
    }
}

/// [`one_or_list`] of an optional list.
fn option_one_or_list<T: Serialize, S: Serializer>(
    values: &Option<Vec<T>>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match values {
        None => s.serialize_none(),
        Some(values) => one_or_list(values, s),
    }
}

/// One observed column's scores, in its units (with several observed columns).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ColumnScore {
    /// The observed column.
    pub column: String,
    /// RMSE of the fit on all rows.
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
}

/// One observed column's residuals, in its units (with several observed columns).
#[derive(Clone, Debug, Serialize)]
pub struct ColumnResiduals {
    /// The observed column.
    pub column: String,
    /// Residuals of the baseline.
    pub residuals_before: Residuals,
    /// Residuals of the selected extension.
    pub residuals_after: Option<Residuals>,
}

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
    /// RMSE of the fit on all rows, in the observed column's units; with several observed
    /// columns, in noise levels (each column's residuals divided by its noise).
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
    /// The refitted parameters.
    pub params: BTreeMap<String, Estimate>,
    /// Predictions of every row made by its fit and its folds' refits: the search's cost.
    pub evaluations: usize,
    /// With several observed columns, each one's RMSEs in its units.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub columns: Vec<ColumnScore>,
}

/// One candidate's result.
#[derive(Clone, Debug, Serialize)]
pub struct Ranked {
    /// The extension's id.
    pub id: String,
    /// Every refitted parameter (the base's and its own).
    pub params: BTreeMap<String, Estimate>,
    /// RMSE of the fit on all rows, in the observed column's units (several columns: in
    /// noise levels).
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
    /// With several observed columns, each one's RMSEs in its units.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub columns: Vec<ColumnScore>,
    /// The corrected Akaike criterion against the baseline's (negative: better).
    pub score: f64,
    /// The F-test's p-value against the baseline.
    pub p_value: f64,
    /// Predictions of every row made by its fit and its folds' refits: the search's cost.
    pub evaluations: usize,
    /// What the data says of it: `selected`, `indistinguishable`, `qualifies`,
    /// `not significant`, `significant, no AICc gain`, `significant, no held-out gain`,
    /// `significant, a prediction did not settle`, `aliased with the base`, `no effect on
    /// this data` or `worse than the base` (its bounds keep it from containing the base
    /// model here).
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
    /// The measured value of each observed column (one: the value, several: a list).
    #[serde(serialize_with = "one_or_list")]
    pub measured: Vec<f64>,
    /// The refitted base model's.
    #[serde(serialize_with = "one_or_list")]
    pub baseline: Vec<f64>,
    /// The selected extended model's.
    #[serde(serialize_with = "option_one_or_list")]
    pub selected: Option<Vec<f64>>,
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
    /// The observed column's name (every RMSE and residual is in its units); with several
    /// observed columns, a list (each column's noise, RMSEs and residuals are in its units;
    /// the combined ones in noise levels).
    #[serde(serialize_with = "one_or_list")]
    pub observed: Vec<String>,
    /// The noise level of each observed column, in its units ([`crate::noise`]): the
    /// experiment's declared one, else the pure error of replicated conditions, else (one
    /// column) the best model's or (several, where it weighs the fit) the base model's
    /// residual standard deviation; `None` when the data cannot estimate it (replicates
    /// that repeat exactly, an exact fit), and then nothing is judged in noise levels.
    #[serde(serialize_with = "one_or_list")]
    pub noise: Vec<Option<f64>>,
    /// Where each `noise` came from: `declared in the experiment`, `pure error of N
    /// replicated conditions (D dof)`, `residual of the base model (D dof)`, `residual of
    /// 'ID' (D dof)`, or `cannot be estimated: ...` and why.
    #[serde(serialize_with = "one_or_list")]
    pub noise_source: Vec<String>,
    /// The scatter of replicated conditions of each column, when some condition is
    /// measured twice.
    #[serde(serialize_with = "one_or_list")]
    pub pure_error: Vec<Option<PureError>>,
    /// The base model's lack-of-fit test, when the noise level does not come from a model's
    /// residuals (declared, or pure error); with several columns, the chi-square of all
    /// columns' residuals in noise levels.
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
    /// Residuals of the baseline (several observed columns: every column's, in noise levels,
    /// pooled).
    pub residuals_before: Residuals,
    /// Residuals of the selected extension.
    pub residuals_after: Option<Residuals>,
    /// With several observed columns, each one's residuals in its units.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub columns: Vec<ColumnResiduals>,
    /// Every row.
    pub table: Vec<RowResult>,
    /// Trial predictions of the fits (the base model's, then each candidate's, folds
    /// included) that failed or ran out of their budget, by model and reason.
    pub failed_trials: Vec<crate::budget::FailedTrials>,
    /// How firm the selection is over resamples; `None` when resampling is turned off.
    pub stability: Option<super::Stability>,
    /// The selected extended model with its fitted values, as a model file.
    #[serde(skip)]
    pub extended_model: Option<String>,
}
