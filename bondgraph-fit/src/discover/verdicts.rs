//! What the data says of each candidate: untestable, aliased with the base, worse than the
//! base, significant (an F-test at a Bonferroni-corrected level), qualifying (significant,
//! a lower AICc and better held-out predictions), selected, or indistinguishable from the
//! selected.

use super::Candidate;
use super::alias::{aliased_with_base, no_effect, reproduced_by_base};
use super::fit::Assessment;
use crate::stats;

/// The verdict of a significant candidate some of whose predictions (of its fit, or of a
/// fold's rows held out) did not settle: a stick-slip cycle where the data hold still.
pub(super) const SIGNIFICANT_BUT_UNSETTLED: &str = "significant, a prediction did not settle";

/// The verdict of a candidate that fits worse than the base model it contains.
pub(super) const WORSE_THAN_THE_BASE: &str = "worse than the base";

/// Whether `candidate` predicts the rows held out better than `baseline`: a lower held-out
/// RMSE, or most of its held-out residuals smaller than the baseline's (the median of the
/// paired differences of their squares above zero).
///
/// Why both: the pooled RMSE lets one residual decide. A row near a threshold (a tip that
/// stands still just below its breakaway force) that a fold's refit puts on the other side
/// errs by the whole speed, tens of noise levels, and outweighs a gain the candidate makes on
/// every other row; the median of the paired differences is not moved by one row. Under no
/// effect a candidate's refits overfit, so most of its held-out residuals grow and the
/// median is not above zero; the F-test and AICc guard the rest.
fn predicts_held_out_better(candidate: &Assessment, baseline: &Assessment) -> bool {
    candidate.rmse_heldout() < baseline.rmse_heldout()
        || median_gain(&baseline.heldout_cells, &candidate.heldout_cells).is_some_and(|g| g > 0.0)
}

/// The median of `base[i] - candidate[i]` over the slots both scored (not `NaN`); `None` if
/// there are none.
fn median_gain(base: &[f64], candidate: &[f64]) -> Option<f64> {
    let mut gains: Vec<f64> = base
        .iter()
        .zip(candidate)
        .filter(|(b, c)| !b.is_nan() && !c.is_nan())
        .map(|(b, c)| b - c)
        .collect();
    if gains.is_empty() {
        return None;
    }
    gains.sort_by(f64::total_cmp);
    let middle = gains.len() / 2;
    Some(if gains.len().is_multiple_of(2) {
        0.5 * (gains[middle - 1] + gains[middle])
    } else {
        gains[middle]
    })
}

/// Each candidate's standing against the base model, by candidate index.
pub(super) struct Verdicts {
    /// Its own parameters move no prediction anywhere in their bounds.
    pub(super) untestable: Vec<bool>,
    /// The base parameters can mimic its effect.
    pub(super) aliased: Vec<bool>,
    /// It fits worse than the base model it contains.
    pub(super) worse: Vec<bool>,
    /// The F-test's p-value against the base.
    pub(super) p_values: Vec<f64>,
    /// The level each p-value is held to: alpha over the candidates tried.
    pub(super) level: f64,
    /// Significant, a lower AICc and better held-out predictions
    /// ([`predicts_held_out_better`]), every prediction settled.
    pub(super) qualifies: Vec<bool>,
    /// The qualifying candidate with the lowest held-out RMSE.
    pub(super) selected: Option<usize>,
    /// For a significant candidate that does not qualify, what it lacks, in words.
    pub(super) shortfall: Vec<Option<&'static str>>,
}

impl Verdicts {
    /// Judges every candidate's assessment against the base model's, at family-wise level
    /// `alpha`.
    pub(super) fn judge(
        candidates: &[Candidate],
        assessed: &[Assessment],
        baseline: &Assessment,
        alpha: f64,
    ) -> Self {
        let p0 = baseline.names.len();
        let n = baseline.predictions.len() as f64;
        let untestable: Vec<bool> = candidates
            .iter()
            .zip(assessed)
            .map(|(c, a)| no_effect(c, a))
            .collect();
        let aliased = candidates
            .iter()
            .zip(assessed)
            .map(|(c, a)| {
                aliased_with_base(&a.fit, p0, c.parameters.len())
                    || reproduced_by_base(c, a, baseline)
            })
            .collect();
        // A candidate contains the base model at its own parameters' no-effect values, and
        // its search starts there, so it cannot fit worse; if it does, those values are not
        // without effect on these rows (a flow ceiling whose highest value is below speeds
        // the data reach), and the candidate is not the base model extended here.
        let worse = assessed
            .iter()
            .map(|a| a.fit.sse > baseline.fit.sse * (1.0 + 1e-6))
            .collect();
        let tried = untestable.iter().filter(|u| !**u).count().max(1);
        let level = alpha / tried as f64;
        let p_values: Vec<f64> = assessed
            .iter()
            .map(|a| {
                let k = (a.names.len() - p0) as f64;
                let dof = n - a.names.len() as f64;
                if k == 0.0 || dof <= 0.0 || a.fit.sse >= baseline.fit.sse {
                    return 1.0;
                }
                let f = ((baseline.fit.sse - a.fit.sse) / k) / (a.fit.sse.max(1e-300) / dof);
                stats::f_survival(f, k, dof)
            })
            .collect();
        let qualifies: Vec<bool> = (0..candidates.len())
            .map(|i| {
                !untestable[i]
                    && assessed[i].unsettled == 0
                    && p_values[i] < level
                    && assessed[i].aicc() < baseline.aicc()
                    && predicts_held_out_better(&assessed[i], baseline)
            })
            .collect();
        let shortfall = (0..candidates.len())
            .map(|i| {
                let significant = !untestable[i] && p_values[i] < level;
                if !significant || qualifies[i] {
                    None
                } else if assessed[i].unsettled > 0 {
                    Some(SIGNIFICANT_BUT_UNSETTLED)
                } else if assessed[i].aicc() >= baseline.aicc() {
                    Some("significant, no AICc gain")
                } else {
                    Some("significant, no held-out gain")
                }
            })
            .collect();
        let selected = (0..candidates.len())
            .filter(|&i| qualifies[i])
            .min_by(|&a, &b| {
                assessed[a]
                    .rmse_heldout()
                    .total_cmp(&assessed[b].rmse_heldout())
            });
        Self {
            untestable,
            aliased,
            worse,
            p_values,
            level,
            qualifies,
            selected,
            shortfall,
        }
    }

    /// The candidates the data cannot tell apart from the selected one: those that also
    /// explain the effect (their F-test passes) and fit no worse beyond the `noise` (without
    /// a noise level, only a fit at least as good); when nothing is selected, those aliased
    /// with the base. Held-out scores are left out here, since they measure extrapolation,
    /// in which aliased models can differ by the luck of a fold.
    pub(super) fn indistinguishable(
        &self,
        assessed: &[Assessment],
        noise: Option<f64>,
    ) -> Vec<usize> {
        let candidates = 0..self.untestable.len();
        match self.selected {
            Some(s) => candidates
                .filter(|&i| {
                    i != s
                        && !self.untestable[i]
                        && self.p_values[i] < self.level
                        && assessed[i].fit.sse - assessed[s].fit.sse
                            <= 4.0 * noise.map_or(0.0, |sd| sd * sd)
                })
                .collect(),
            None => candidates
                .filter(|&i| self.aliased[i] && !self.untestable[i])
                .collect(),
        }
    }

    /// Candidate `i`'s verdict in words.
    pub(super) fn word(&self, i: usize, indistinguishable: &[usize]) -> &'static str {
        if Some(i) == self.selected {
            "selected"
        } else if indistinguishable.contains(&i) {
            "indistinguishable"
        } else if self.untestable[i] {
            "no effect on this data"
        } else if self.aliased[i] {
            "aliased with the base"
        } else if self.qualifies[i] {
            "qualifies"
        } else if self.worse[i] {
            WORSE_THAN_THE_BASE
        } else if let Some(shortfall) = self.shortfall[i] {
            shortfall
        } else {
            "not significant"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::median_gain;

    #[test]
    fn one_residual_across_a_threshold_does_not_outweigh_a_gain_on_every_other_row() {
        // Squared held-out errors: the candidate halves four of five, and one row that a
        // fold put on the other side of a threshold errs by ten times the noise.
        let base = [1.0, 1.0, 1.0, 1.0, 1.0];
        let candidate = [0.5, 0.5, 0.5, 0.5, 100.0];
        assert!(candidate.iter().sum::<f64>() > base.iter().sum::<f64>());
        assert_eq!(median_gain(&base, &candidate), Some(0.5));
        // Slots only one model scored are left out; an even count takes the mean of the two
        // middle gains: gains -0.1, 0.2, 0.3, 0.4 give 0.25.
        let base = [1.0, 1.0, f64::NAN, 1.0, 1.0, 2.0];
        let candidate = [1.1, 0.8, 0.1, 0.7, 0.6, f64::NAN];
        assert!((median_gain(&base, &candidate).unwrap() - 0.25).abs() < 1e-15);
        // A refit that overfits: most residuals grow a little, one shrinks a lot.
        let candidate = [1.1, 1.2, f64::NAN, 0.1, 1.05, 2.0];
        assert!(median_gain(&base, &candidate).unwrap() < 0.0);
        assert_eq!(median_gain(&[f64::NAN], &[1.0]), None);
    }
}
