//! Where the noise level comes from: the measurement's standard deviation that residuals,
//! trends and separations are judged against.
//!
//! In order of preference:
//!
//! 1. the experiment's declared `noise`;
//! 2. the **pure error** of replicated conditions (rows whose condition cells are all
//!    identical, empty cells included), when the replicates give at least
//!    [`MIN_PURE_ERROR_DOF`] degrees of freedom: it measures the scatter of repeated
//!    measurements and owes nothing to any model;
//! 3. the residual standard deviation `sqrt(SSE/(n - p))` of a fitted model, which also
//!    holds whatever that model gets wrong, and so overstates the noise of a model that
//!    misfits.
//!
//! An estimate of zero (replicates that repeat exactly, a model that fits every row exactly)
//! or with no degrees of freedom is no estimate: [`NoiseLevel::sd`] is then `None` and its
//! source says why, so that nothing is judged in noise levels of zero.
//!
//! With a noise level that does not come from the model itself (declared, or pure error),
//! the model's own misfit can be tested against it ([`lack_of_fit`]): the classic F-test of
//! lack of fit against pure error, or the chi-square of the residuals against a declared
//! standard deviation.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::data::Measurement;
use crate::stats;

/// The pure error's degrees of freedom needed before it is taken as the noise level: with
/// fewer, its estimate is too uncertain (with 2, its 95% interval spans a factor of 12).
pub const MIN_PURE_ERROR_DOF: usize = 3;

/// The scatter of replicated conditions in one observed column.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PureError {
    /// Its standard deviation, `sqrt(SS_pe/dof)`, in the observed column's units.
    pub sd: f64,
    /// Its degrees of freedom: over the replicated conditions, the rows less one each.
    pub dof: usize,
    /// How many conditions are replicated (measured more than once).
    pub groups: usize,
    /// The sum of squares about each condition's mean, `SS_pe`.
    #[serde(skip)]
    pub sum_of_squares: f64,
}

/// The pure error of observed column `column` over `rows`: the rows grouped by their
/// condition cells, compared exactly (an empty cell matches only an empty cell), and the
/// squares about each group's mean summed.
///
/// # Returns
/// `None` when no condition is measured twice.
///
/// # Complexity
/// `O(n log n)` comparisons of condition rows, for `n` rows.
pub fn pure_error(rows: &[Measurement], column: usize) -> Option<PureError> {
    // Cells keyed by their bits (with -0 read as 0), so that equal cells are one key.
    let key = |r: &Measurement| -> Vec<Option<u64>> {
        r.conditions
            .iter()
            .map(|c| c.map(|v| if v == 0.0 { 0u64 } else { v.to_bits() }))
            .collect()
    };
    let mut groups: BTreeMap<Vec<Option<u64>>, Vec<f64>> = BTreeMap::new();
    for row in rows {
        groups
            .entry(key(row))
            .or_default()
            .push(row.observed[column]);
    }
    let mut sum_of_squares = 0.0;
    let (mut dof, mut replicated) = (0, 0);
    for values in groups.values().filter(|v| v.len() > 1) {
        // About the first value, so that identical values give exactly zero.
        let shifted: Vec<f64> = values.iter().map(|y| y - values[0]).collect();
        let mean = shifted.iter().sum::<f64>() / values.len() as f64;
        sum_of_squares += shifted.iter().map(|d| (d - mean).powi(2)).sum::<f64>();
        dof += values.len() - 1;
        replicated += 1;
    }
    (replicated > 0).then(|| PureError {
        sd: (sum_of_squares / dof as f64).sqrt(),
        dof,
        groups: replicated,
        sum_of_squares,
    })
}

/// The root mean square of observed column `column` over `rows`: the scale of the
/// measured values ([`Residual::scale`]).
pub fn root_mean_square(rows: &[Measurement], column: usize) -> f64 {
    let n = rows.len().max(1) as f64;
    (rows.iter().map(|r| r.observed[column].powi(2)).sum::<f64>() / n).sqrt()
}

/// Where a noise level came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// The experiment's declared `noise`.
    Declared,
    /// The pure error of replicated conditions.
    PureError,
    /// A fitted model's residuals.
    Residual,
}

/// A noise level and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseLevel {
    /// The standard deviation, in the observed column's units; `None` when the data cannot
    /// estimate it (an estimate of zero, or no degrees of freedom).
    pub sd: Option<f64>,
    /// Where it came from.
    pub origin: Origin,
    /// Where it came from, as a phrase: `declared in the experiment`, `pure error of 4
    /// replicated conditions (9 dof)`, `residual of the base model (18 dof)`, or, with no
    /// estimate, `cannot be estimated: ...` and why.
    pub source: String,
    /// The replicates' scatter, when some condition is measured twice (whether or not it
    /// is the noise level).
    pub pure_error: Option<PureError>,
}

/// A fitted model's residuals, the last resort for the noise level.
#[derive(Clone, Copy, Debug)]
pub struct Residual<'a> {
    /// Its sum of squares.
    pub sse: f64,
    /// Its degrees of freedom, rows less fitted parameters.
    pub dof: f64,
    /// The model, as a phrase: `the base model`, `'shaft-windage'`.
    pub model: &'a str,
    /// The size of the measured values (their root mean square): a residual standard
    /// deviation below [`ROUNDING`] times this is rounding, an exact fit.
    pub scale: f64,
}

/// Relative to the measured values, the residual standard deviation of an exact fit (a
/// least-squares fit of data with no scatter stops at rounding errors, not at zero).
pub const ROUNDING: f64 = 1e-10;

impl NoiseLevel {
    /// The noise level of a column: `declared`, else the pure error of `replicates` with at
    /// least [`MIN_PURE_ERROR_DOF`] degrees of freedom, else `residual`'s standard
    /// deviation.
    pub fn estimate(
        declared: Option<f64>,
        replicates: Option<PureError>,
        residual: Residual<'_>,
    ) -> Self {
        if let Some(sd) = declared {
            return Self {
                sd: Some(sd),
                origin: Origin::Declared,
                source: "declared in the experiment".to_string(),
                pure_error: replicates,
            };
        }
        if let Some(pe) = replicates.as_ref().filter(|p| p.dof >= MIN_PURE_ERROR_DOF) {
            let (sd, source) = if pe.sd > 0.0 && pe.sd.is_finite() {
                (
                    Some(pe.sd),
                    format!(
                        "pure error of {} replicated condition{} ({} dof)",
                        pe.groups,
                        plural(pe.groups),
                        pe.dof
                    ),
                )
            } else {
                (
                    None,
                    format!(
                        "cannot be estimated: the {} replicated condition{} repeat{} exactly \
                         (pure error {} on {} dof)",
                        pe.groups,
                        plural(pe.groups),
                        if pe.groups == 1 { "s" } else { "" },
                        pe.sd,
                        pe.dof
                    ),
                )
            };
            return Self {
                sd,
                origin: Origin::PureError,
                source,
                pure_error: replicates,
            };
        }
        let Residual {
            sse,
            dof,
            model,
            scale,
        } = residual;
        let sd = (sse / dof).sqrt();
        let (sd, source) = if dof.is_nan() || dof <= 0.0 {
            (
                None,
                format!("cannot be estimated: the residual of {model} has no degrees of freedom"),
            )
        } else if sd > ROUNDING * scale && sd.is_finite() {
            (
                Some(sd),
                format!("residual of {model} ({} dof)", dof_text(dof)),
            )
        } else {
            (
                None,
                format!(
                    "cannot be estimated: the residual of {model} is {} ({} dof)",
                    if sd.is_finite() {
                        format!("{sd:.1e}, rounding error: the fit is exact")
                    } else {
                        sd.to_string()
                    },
                    dof_text(dof)
                ),
            )
        };
        Self {
            sd,
            origin: Origin::Residual,
            source,
            pure_error: replicates,
        }
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// A test of a model's misfit against a noise level that does not come from its residuals.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LackOfFit {
    /// The test statistic: `F` or `chi-square`.
    pub statistic: f64,
    /// Its degrees of freedom: `[lack of fit, pure error]` for F, `[n - p]` for chi-square.
    pub dof: Vec<usize>,
    /// The probability of a statistic at least this large if the model is right.
    pub p_value: f64,
    /// Which test: `F (lack of fit against pure error)` or `chi-square (residuals against
    /// the declared noise)`.
    pub test: String,
}

/// The lack-of-fit test of a model with sum of squares `sse` on `rows` rows with `params`
/// fitted parameters, against `level`.
///
/// With pure error (`SS_pe` on `df_pe` dof), `F = ((SSE - SS_pe)/df_lof)/(SS_pe/df_pe)` with
/// `df_lof = (n - p) - df_pe`, on `(df_lof, df_pe)` dof; with a declared `σ`,
/// `SSE/σ²` on `n - p` dof, chi-square.
///
/// # Returns
/// `None` when the level is the model's own residual, is not estimated, or leaves no
/// degrees of freedom to the test (every distinct condition fitted exactly by `p`
/// parameters).
pub fn lack_of_fit(level: &NoiseLevel, sse: f64, rows: usize, params: usize) -> Option<LackOfFit> {
    let residual_dof = rows.checked_sub(params).filter(|d| *d > 0)?;
    let sd = level.sd?;
    match level.origin {
        Origin::Residual => None,
        Origin::Declared => {
            let statistic = sse / (sd * sd);
            Some(LackOfFit {
                statistic,
                dof: vec![residual_dof],
                p_value: stats::chi_square_survival(statistic, residual_dof as f64),
                test: "chi-square (residuals against the declared noise)".to_string(),
            })
        }
        Origin::PureError => {
            let pe = level.pure_error.as_ref()?;
            let lack_dof = residual_dof.checked_sub(pe.dof).filter(|d| *d > 0)?;
            // The group means fit the replicates best, so SSE >= SS_pe but for rounding.
            let lack = (sse - pe.sum_of_squares).max(0.0);
            let statistic = (lack / lack_dof as f64) / (pe.sum_of_squares / pe.dof as f64);
            Some(LackOfFit {
                statistic,
                dof: vec![lack_dof, pe.dof],
                p_value: stats::f_survival(statistic, lack_dof as f64, pe.dof as f64),
                test: "F (lack of fit against pure error)".to_string(),
            })
        }
    }
}

impl LackOfFit {
    /// The test as a sentence: `F = 3.210 on (5, 12) dof, p = 0.041: no misfit beyond the
    /// noise` (at level 0.01).
    pub fn text(&self) -> String {
        let dof = self
            .dof
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ");
        let name = if self.dof.len() == 2 {
            "F"
        } else {
            "chi-square"
        };
        let p = if self.p_value >= 1e-3 {
            format!("{:.3}", self.p_value)
        } else {
            format!("{:.1e}", self.p_value)
        };
        format!(
            "{name} = {:.3} on ({dof}) dof, p = {p}: {}",
            self.statistic,
            if self.p_value < 0.01 {
                "the model misfits beyond the noise"
            } else {
                "no misfit beyond the noise"
            }
        )
    }
}

/// Degrees of freedom as a reader wants them: whole when whole (`26`), else to a tenth
/// (`26.3`: a threshold parameter takes part of one).
fn dof_text(dof: f64) -> String {
    if dof.fract() == 0.0 {
        format!("{dof:.0}")
    } else {
        format!("{dof:.1}")
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;

    fn row(conditions: &[Option<f64>], y: f64) -> Measurement {
        Measurement {
            conditions: conditions.to_vec(),
            observed: vec![y],
            time: None,
            row: 2,
            file: Arc::from("hand.csv"),
        }
    }

    /// Groups {1, 2, 3} at (1, empty) and {5, 7} at (2, 0): SS = 2 + 2 = 4 on 2 + 1 = 3 dof;
    /// (1, 0) and (2, empty) once each, and -0 the same cell as 0.
    fn hand_made() -> Vec<Measurement> {
        vec![
            row(&[Some(1.0), None], 1.0),
            row(&[Some(2.0), Some(0.0)], 5.0),
            row(&[Some(1.0), None], 2.0),
            row(&[Some(1.0), Some(0.0)], 100.0),
            row(&[Some(1.0), None], 3.0),
            row(&[Some(2.0), Some(-0.0)], 7.0),
            row(&[Some(2.0), None], -50.0),
        ]
    }

    #[test]
    fn pure_error_of_a_hand_made_set() {
        let pe = pure_error(&hand_made(), 0).expect("replicates");
        assert_eq!((pe.dof, pe.groups), (3, 2));
        assert!((pe.sum_of_squares - 4.0).abs() < 1e-12);
        assert!((pe.sd - (4.0f64 / 3.0).sqrt()).abs() < 1e-12);
        let level = NoiseLevel::estimate(
            None,
            Some(pe),
            Residual {
                sse: 1e4,
                dof: 5.0,
                model: "the base model",
                scale: 1.0,
            },
        );
        assert_eq!(level.origin, Origin::PureError);
        assert_eq!(
            level.source,
            "pure error of 2 replicated conditions (3 dof)"
        );
        assert!(pure_error(&hand_made()[..2], 0).is_none());
    }

    #[test]
    fn the_declared_noise_comes_first_and_too_few_replicates_give_the_residual() {
        let rows = hand_made();
        let residual = Residual {
            sse: 18.0,
            dof: 2.0,
            model: "'shaft-windage'",
            scale: 1.0,
        };
        let declared = NoiseLevel::estimate(Some(0.5), pure_error(&rows, 0), residual);
        assert_eq!(
            (declared.sd, declared.source.as_str()),
            (Some(0.5), "declared in the experiment")
        );
        // Two dof of pure error (the group {1, 2, 3} alone) are too few: sqrt(18/2) = 3.
        let level = NoiseLevel::estimate(None, pure_error(&rows[..5], 0), residual);
        assert_eq!(level.sd, Some(3.0));
        assert_eq!(level.source, "residual of 'shaft-windage' (2 dof)");
        assert_eq!(super::dof_text(26.333333333333332), "26.3");
        assert_eq!(level.pure_error.map(|p| p.dof), Some(2));
    }

    #[test]
    fn identical_rows_or_an_exact_fit_give_no_noise_level() {
        let rows: Vec<Measurement> = (0..30).map(|_| row(&[Some(12.0), None], 10.6)).collect();
        let pe = pure_error(&rows, 0).unwrap();
        assert_eq!((pe.dof, pe.groups, pe.sd), (29, 1, 0.0));
        let residual = Residual {
            sse: 0.0,
            dof: 26.0,
            model: "the base model",
            scale: 1.0,
        };
        let level = NoiseLevel::estimate(None, Some(pe), residual);
        assert_eq!(level.sd, None);
        assert_eq!(
            level.source,
            "cannot be estimated: the 1 replicated condition repeats exactly (pure error 0 on 29 dof)"
        );
        assert_eq!(lack_of_fit(&level, 1.0, 30, 4), None);
        let exact = NoiseLevel::estimate(None, None, residual);
        assert_eq!(exact.sd, None);
        assert_eq!(
            exact.source,
            "cannot be estimated: the residual of the base model is 0.0e0, rounding error: \
             the fit is exact (26 dof)"
        );
        // At rounding level of the values: 1e-15 against values near 10.
        let rounding = NoiseLevel::estimate(
            None,
            None,
            Residual {
                sse: 26.0 * 1e-30,
                scale: 10.6,
                ..residual
            },
        );
        assert_eq!(rounding.sd, None);
        assert!(rounding.source.contains("is 1.0e-15, rounding error"));
    }

    #[test]
    fn lack_of_fit_against_pure_error_by_hand() {
        // The hand-made set: SS_pe = 4 on 3 dof. A model with p = 2 parameters and SSE = 24
        // on n = 7 rows: df_lof = (7 - 2) - 3 = 2, F = ((24 - 4)/2)/(4/3) = 7.5. For F(2, d2),
        // P(F > f) = (1 + 2f/d2)^(-d2/2) = (1 + 5)^(-1.5) = 0.068041.
        let rows = hand_made();
        let residual = Residual {
            sse: 24.0,
            dof: 5.0,
            model: "the base model",
            scale: 1.0,
        };
        let level = NoiseLevel::estimate(None, pure_error(&rows, 0), residual);
        let test = lack_of_fit(&level, 24.0, 7, 2).expect("a test");
        assert!((test.statistic - 7.5).abs() < 1e-12, "{test:?}");
        assert_eq!(test.dof, [2, 3]);
        assert!((test.p_value - 6f64.powf(-1.5)).abs() < 1e-10, "{test:?}");
        assert!(test.test.starts_with("F "));
        // With p = 4, no dof is left for lack of fit: no test.
        assert_eq!(lack_of_fit(&level, 24.0, 7, 4), None);
        // The residual's own level tests nothing.
        let own = NoiseLevel::estimate(None, None, residual);
        assert_eq!(lack_of_fit(&own, 24.0, 7, 2), None);
    }

    #[test]
    fn lack_of_fit_against_a_declared_noise_by_hand() {
        // SSE = 36 with σ = 2: chi-square 9 on 10 - 8 = 2 dof, P = e^(-9/2) = 0.011109.
        let residual = Residual {
            sse: 36.0,
            dof: 2.0,
            model: "the base model",
            scale: 1.0,
        };
        let level = NoiseLevel::estimate(Some(2.0), None, residual);
        let test = lack_of_fit(&level, 36.0, 10, 8).expect("a test");
        assert!((test.statistic - 9.0).abs() < 1e-12);
        assert_eq!(test.dof, [2]);
        assert!((test.p_value - (-4.5f64).exp()).abs() < 1e-12, "{test:?}");
        assert!(test.text().starts_with("chi-square = 9.000 on (2) dof"));
    }
}
