//! What the data says of each candidate: untestable, aliased with the base, worse than the
//! base, significant (an F-test at a Bonferroni-corrected level), qualifying (significant,
//! a lower AICc and a lower held-out RMSE), selected, or indistinguishable from the selected.

use super::Candidate;
use super::alias::{aliased_with_base, no_effect, reproduced_by_base};
use super::fit::Assessment;
use crate::stats;

/// The verdict of a candidate that fits worse than the base model it contains.
pub(super) const WORSE_THAN_THE_BASE: &str = "worse than the base";

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
    /// Significant, a lower AICc and a lower held-out RMSE, every prediction settled.
    pub(super) qualifies: Vec<bool>,
    /// The qualifying candidate with the lowest held-out RMSE.
    pub(super) selected: Option<usize>,
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
                    && assessed[i].rmse_heldout() < baseline.rmse_heldout()
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
        } else {
            "not significant"
        }
    }
}
