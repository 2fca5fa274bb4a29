//! What a model gets wrong on measured data, which candidate extension explains it, and the
//! gain on held-out data.
//!
//! The procedure, for a base model, its experiment, the data and a library of candidate
//! extensions:
//!
//! 1. **Baseline**: refit the parameters the experiment names as fitted (and those of
//!    `fitted_when_present` whose column has values) and score the model on held-out data:
//!    leave one level out of a condition column with three or more levels (fit on some
//!    settings of a condition, predict the others; [`crate::folds`] says which), and k-fold (k = 5, rows dealt
//!    round-robin in the order of the conditions). A time series is held out along time:
//!    one run (data file) at a time, or with one run, k contiguous blocks of it; a fold fits
//!    its training samples' residuals and scores its held-out ones, each time simulating
//!    the whole run, so that no held-out block cuts the measured inputs that drive it.
//! 2. **Residuals** of the baseline by operating regime (named by the mode each row settles
//!    in, or a sample is in) and along each condition column (in a time series, a measured
//!    input signal) and the time column, with the trend and whether it stands out of the
//!    noise.
//! 3. **Candidates**: each extension merged into the base model, refitted with the base's
//!    fitted parameters and its own, and scored the same way. A candidate whose parameters
//!    move no prediction anywhere in their bounds is untestable on this data (an effect of
//!    an element that every row removes); one whose effect the base parameters can mimic
//!    exactly (its Jacobian columns lie in the span of theirs, or its fit, with its own
//!    parameters away from their no-effect values, predicts every row as the base's does) is
//!    aliased with the base.
//! 4. **Selection**: a candidate qualifies when its gain is beyond the noise — an F-test of
//!    its sum of squares against the baseline's at level 0.01 divided by the number of
//!    candidates tried (Bonferroni), a lower corrected Akaike criterion, and better
//!    held-out predictions: a lower held-out RMSE, or most held-out residuals smaller than
//!    the baseline's (one row near a threshold, put on its other side by a fold's refit,
//!    cannot veto a gain on every other row). The qualifying candidate with the lowest
//!    held-out RMSE is selected; if none qualifies, `selected` is `null`.
//! 5. **Indistinguishable** candidates: those that also qualify and fit the data no worse
//!    than the selected one beyond the noise (or, when nothing is selected, those aliased
//!    with the base), each with the measurement that would separate them: a condition where
//!    the two fitted models' predictions differ by more than three noise levels, searched
//!    over a grid of conditions wider than the data's (for a time series: the time along the
//!    recorded run where they differ most), or, when no such observation separates them,
//!    what the extension's file says would show its effect directly.
//! 6. **Stability** of the selection: the selection rule rerun on complementary half-samples
//!    of the data (rows, or runs or blocks of a time series), and how often each candidate or
//!    nothing is selected ([`Stability`]; the design in `stability.rs`).
//!
//! The noise level all of this is judged against is the experiment's declared one, else the
//! pure error of replicated conditions (steady data: a run's samples are not replicates),
//! else the best model's residual ([`crate::noise`]);
//! with a level that does not come from a model, the base model's lack of fit is tested too.
//!
//! Several observed columns are compared together, each in levels of its own noise
//! ([`crate::weights`]: declared, pure error, or the residual of the base model fitted with
//! each column weighed by its spread): every fit, test and score above runs on the sum of all
//! columns' squares in noise levels (a chi-square), and the report gives each column's RMSEs
//! and residuals in its units beside the combined ones.

mod alias;
mod candidate;
mod cross_validation;
mod fit;
mod procedure;
mod residuals;
mod results;
mod separation;
mod stability;
mod summary;
mod verdicts;

pub use candidate::Candidate;
pub use fit::fitted_names;
pub(crate) use fit::{fit_best, fitted_parameters, limit_to_budget};
pub use procedure::{discover, discover_with_progress};
pub(crate) use residuals::residuals;
pub use results::{
    Baseline, ColumnResiduals, ColumnScore, Discovery, Estimate, FactorTrend, Gain, Ranked,
    RegimeResiduals, Residuals, RowResult, Separation,
};
pub use stability::{
    Cost, DEFAULT_RESAMPLES, DEFAULT_SEED, FIRM_FRACTION, MIN_DEFAULT_RESAMPLES, Resampling,
    Stability, half_samples,
};
pub use summary::{estimate_text, write_residuals};

use bondgraph_core::diagnostics::Diagnostics;

use crate::budget::Budget;
use crate::calibrate::{self, CalibrationError};
use crate::experiment::ExperimentError;
use crate::global::Search;

/// How `discover` tests.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// The family-wise significance level of the F-tests, shared among the candidates.
    pub alpha: f64,
    /// Folds of the k-fold cross-validation.
    pub folds: usize,
    /// The calibration's settings.
    pub calibration: calibrate::Settings,
    /// How widely each model's first fit searches (folds refit locally from it).
    pub search: Search,
    /// The work each prediction and each fit may do.
    pub budget: Budget,
    /// The resamples that say how firm the selection is ([`Stability`]).
    pub resampling: Resampling,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            alpha: 0.01,
            folds: 5,
            calibration: calibrate::Settings::default(),
            search: Search::GLOBAL,
            budget: Budget::default(),
            resampling: Resampling::default(),
        }
    }
}

/// Why a calibration or a discovery failed.
#[derive(Clone, Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DiscoverError {
    /// A model, an extension or an edit that does not load: core's located diagnostics.
    #[error("{0}")]
    Model(#[from] Diagnostics),
    /// The experiment does not fit the model, or a row cannot be predicted.
    #[error("{0}")]
    Experiment(#[from] ExperimentError),
    /// The least-squares search could not start.
    #[error("{data}: {error}")]
    Calibration {
        /// The data's name.
        data: String,
        /// Why.
        error: CalibrationError,
    },
    /// A row whose residual the least-squares search cannot form at the starting values: a
    /// prediction that is not finite, or a residual whose square overflows (a cell such as
    /// `1.797e308`).
    #[error("{file}:{row}: {reason}")]
    Unfittable {
        /// The data file.
        file: String,
        /// Its line.
        row: usize,
        /// The column whose value the model cannot work with, where that is determinable:
        /// the observed column for a measured value too large, the largest condition cell
        /// for a prediction that overflows.
        column: Option<String>,
        /// That column's cell.
        value: Option<f64>,
        /// Why, naming the column and its cell.
        reason: String,
    },
    /// Too few rows to fit and hold some out.
    #[error("{data}: {rows} rows; discovery needs at least {needed} to fit and hold some out")]
    TooFewRows {
        /// The data's name.
        data: String,
        /// Rows it has.
        rows: usize,
        /// Rows needed.
        needed: usize,
    },
    /// A fitted parameter that is not in the model, or has no bounds.
    #[error("{0}")]
    Fitted(Diagnostics),
}
