//! The work a fit may do, and the trials that ran out of it.
//!
//! A fit tries thousands of parameter values, and some make a row's model do unbounded work:
//! a contact that sticks and slips forever, a fast electrical mode that makes event location
//! crawl, a tank that fills at a rate of rounding size. Each prediction of a row (or of a
//! recorded run) therefore has a budget of work, never of simulated seconds (how long a row
//! takes to settle is the model's own time scale, [`bondgraph_solver::steady`]), and each fit
//! a budget of evaluations. A trial that exceeds its budget is a failed trial: the search
//! treats its values as infeasible, and [`Trials`] counts it, by reason, with the range of
//! trial values where it happened, so that the report can say which values failed and why.

use std::collections::BTreeMap;
use std::fmt;

use serde::Serialize;

/// The work each prediction and each fit may do. Every limit is overridable (the CLI's
/// `--max-evaluations`, `--max-mode-changes`, `--max-steps`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Mode changes one steady row may take to settle. A steady state is reached after a
    /// handful (a contact that sticks then slides, a string that goes taut); trial values
    /// that make a row stick and slip hundreds of times describe a cycle, not a steady state.
    pub mode_changes: usize,
    /// Stretches one steady row's search may simulate (a mode's settling horizon, a window
    /// of a nonlinear mode, the way to a predicted crossing). A handful per mode visited
    /// settle any row that settles; the rest are cycles or runaway drifts.
    pub segments: usize,
    /// Integration steps and event-location samples one prediction (a steady row, or one
    /// recorded run of a time series) may take: a twentieth of the simulator's own limit for
    /// a whole simulation, well over what any row of the examples takes (a two-tank row
    /// about a thousand, a two-contact model's with linear modes under a hundred).
    pub steps: u64,
    /// Evaluations (a prediction of every row at one trial point) one search of a fit may
    /// make: a face's screening, or a local fit from one start. A fit runs several side by
    /// side, each with this budget to itself, so that what it finds does not depend on the
    /// threads. A 27-row fit of a two-contact model with eight candidates takes under
    /// 2,000 evaluations in all.
    pub evaluations: usize,
    /// How far, as a fraction of each fitted parameter's range (its bounds' width), trial
    /// values may be from those a steady row was last simulated at for that row's steady
    /// state to be continued from there by Newton's method instead of simulated again
    /// ([`bondgraph_solver::steady::continuation`]): where the row settled at a stable
    /// equilibrium of a mode without guards, never having left it. Ten of calibration's
    /// forward-difference steps
    /// (1e-5), so a Jacobian's differences and a descent's last steps continue. A row that
    /// settled where its path matters (a mode with guards, or one entered on the way) is
    /// continued only for a Jacobian's difference from the very values it was simulated at
    /// ([`crate::predict::Evaluator::predict_differenced`]). `0` turns both off.
    pub continuation: f64,
    /// The same for a refit on part of the rows (a fold, a resample), from the steady states
    /// of the fit on every row at its optimum, where the refit starts: a refit moves about a
    /// standard error from there, well within a hundredth of a range, and each of its
    /// training rows is then continued instead of simulated from its start at every trial.
    /// The rows a refit holds out, which score it, are simulated. `0` turns it off.
    pub refit_continuation: f64,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            mode_changes: 200,
            segments: 1_000,
            steps: bondgraph_core::limits::MAX_STEPS / 20,
            evaluations: 20_000,
            continuation: 1e-4,
            refit_continuation: 1e-2,
        }
    }
}

/// Why a trial prediction failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Failure {
    /// A row changed mode more often than [`Budget::mode_changes`].
    ModeChangeBudget,
    /// A row's search simulated more stretches than [`Budget::segments`].
    SegmentBudget,
    /// A prediction took more steps than [`Budget::steps`].
    StepBudget,
    /// A row has no steady state at these values (its motion grows or oscillates undamped).
    NotSteady,
    /// The values are outside those the model is consistent at (a breakaway force below
    /// its Coulomb force).
    Inconsistent,
    /// The simulation failed, or a prediction is not finite.
    Simulation,
}

impl Failure {
    /// What happened, for a sentence "N of M trial predictions ...".
    pub fn phrase(self, budget: &Budget) -> String {
        match self {
            Failure::ModeChangeBudget => format!(
                "stopped at the budget of {} mode changes per row (a cycle, such as stick-slip, \
                 not a steady state)",
                budget.mode_changes
            ),
            Failure::SegmentBudget => format!(
                "stopped at the budget of {} simulated stretches per row (the state still moved)",
                budget.segments
            ),
            Failure::StepBudget => format!(
                "stopped at the budget of {} steps per prediction",
                budget.steps
            ),
            Failure::NotSteady => "had no steady state".to_string(),
            Failure::Inconsistent => {
                "were outside the values the model is consistent at".to_string()
            }
            Failure::Simulation => "could not be simulated".to_string(),
        }
    }
}

/// The failed trials of one kind.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FailedKind {
    /// How many trial predictions failed so.
    pub count: usize,
    /// The interval of each fitted parameter's trial values among them, by name.
    pub values: BTreeMap<String, (f64, f64)>,
    /// The first one's row and reason, in words.
    pub first: String,
}

/// A fit's trial predictions: how many were made, and those that failed, by reason.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Trials {
    /// Trial predictions made (each predicts every row at one trial point).
    pub trials: usize,
    /// The failed ones, by reason.
    pub failed: BTreeMap<Failure, FailedKind>,
    /// The interval of each fitted parameter's trial values over every trial, by name.
    pub tried: BTreeMap<String, (f64, f64)>,
    /// Whether a fit stopped at its budget of evaluations.
    pub evaluation_budget_spent: bool,
    /// Steady rows predicted by continuing a steady state simulated before (near the values
    /// it was simulated at, or on its branch for a finite difference from them) instead of
    /// simulating them again ([`Budget::continuation`]).
    pub continued_rows: usize,
}

fn widen(intervals: &mut BTreeMap<String, (f64, f64)>, names: &[String], values: &[f64]) {
    for (name, &value) in names.iter().zip(values) {
        let interval = intervals.entry(name.clone()).or_insert((value, value));
        interval.0 = interval.0.min(value);
        interval.1 = interval.1.max(value);
    }
}

impl Trials {
    /// Counts a trial at `values` (of the parameters `names`), failed for `failure` if any.
    pub fn record(&mut self, names: &[String], values: &[f64], failure: Option<(Failure, String)>) {
        self.trials += 1;
        widen(&mut self.tried, names, values);
        if let Some((failure, first)) = failure {
            let kind = self.failed.entry(failure).or_insert_with(|| FailedKind {
                count: 0,
                values: BTreeMap::new(),
                first,
            });
            kind.count += 1;
            widen(&mut kind.values, names, values);
        }
    }

    /// Adds `other`'s counts to these.
    pub fn merge(&mut self, other: &Trials) {
        self.trials += other.trials;
        self.continued_rows += other.continued_rows;
        self.evaluation_budget_spent |= other.evaluation_budget_spent;
        for (name, &(low, high)) in &other.tried {
            widen(&mut self.tried, std::slice::from_ref(name), &[low]);
            widen(&mut self.tried, std::slice::from_ref(name), &[high]);
        }
        for (&failure, kind) in &other.failed {
            match self.failed.get_mut(&failure) {
                Some(mine) => {
                    mine.count += kind.count;
                    for (name, &(low, high)) in &kind.values {
                        widen(&mut mine.values, std::slice::from_ref(name), &[low]);
                        widen(&mut mine.values, std::slice::from_ref(name), &[high]);
                    }
                }
                None => {
                    self.failed.insert(failure, kind.clone());
                }
            }
        }
    }

    /// Failed trials, or a fit stopped at its evaluation budget: what a report mentions.
    pub fn any_failed(&self) -> bool {
        !self.failed.is_empty() || self.evaluation_budget_spent
    }
}

/// The failed trials of one model's fits, as a report lists them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FailedTrials {
    /// The model: `base` or a candidate's id (a calibration: the model's name).
    pub model: String,
    /// Trial predictions made in its fits (and its folds' refits).
    pub trials: usize,
    /// Why some failed.
    pub reason: Failure,
    /// How many.
    pub count: usize,
    /// The interval of each fitted parameter's trial values among the failed ones.
    pub values: BTreeMap<String, (f64, f64)>,
    /// The first failure's row and reason.
    pub first: String,
    /// The sentence the text report prints.
    pub text: String,
}

/// The report's entries for one model's `trials`, made under `budget`: one per reason, then,
/// when a fit stopped at its budget of evaluations, one saying so.
pub fn failed_trials(model: &str, trials: &Trials, budget: &Budget) -> Vec<FailedTrials> {
    let mut entries: Vec<FailedTrials> = trials
        .failed
        .iter()
        .map(|(&reason, kind)| {
            let text = format!(
                "{}: {} of {} trial predictions {}, at {}; the first: {}",
                model,
                thousands(kind.count),
                thousands(trials.trials),
                reason.phrase(budget),
                Intervals(&kind.values, &trials.tried),
                kind.first
            );
            FailedTrials {
                model: model.to_string(),
                trials: trials.trials,
                reason,
                count: kind.count,
                values: kind.values.clone(),
                first: kind.first.clone(),
                text,
            }
        })
        .collect();
    if trials.evaluation_budget_spent {
        entries.push(FailedTrials {
            model: model.to_string(),
            trials: trials.trials,
            reason: Failure::Simulation,
            count: 0,
            values: BTreeMap::new(),
            first: String::new(),
            text: format!(
                "{model}: a fit's search stopped at its budget of {} evaluations \
                 (--max-evaluations); the fit's result is the best point found by then",
                thousands(budget.evaluations)
            ),
        });
    }
    entries
}

/// The report's paragraph on failed trials, if any.
pub fn write_failed_trials(s: &mut String, entries: &[FailedTrials]) {
    use std::fmt::Write;
    if entries.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\nfailed trials (the fits rejected these values; budgets: \
         --max-mode-changes, --max-segments, --max-steps, --max-evaluations):"
    );
    for entry in entries {
        let _ = writeln!(s, "  {}", entry.text);
    }
}

/// `2,431`.
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// `tau_S 0.01..0.05 (of 0.01..2), b 10..20 (of 5..40)`: the failed trials' values against
/// all trials'.
struct Intervals<'a>(
    &'a BTreeMap<String, (f64, f64)>,
    &'a BTreeMap<String, (f64, f64)>,
);

impl fmt::Display for Intervals<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return write!(f, "the model file's values");
        }
        let short = |v: f64| format!("{v:.3e}").parse::<f64>().unwrap_or(v);
        let parts: Vec<String> = self
            .0
            .iter()
            .map(|(name, &(low, high))| {
                let all = self.1.get(name).copied().unwrap_or((low, high));
                format!(
                    "{name} {}..{} (of {}..{})",
                    short(low),
                    short(high),
                    short(all.0),
                    short(all.1)
                )
            })
            .collect();
        write!(f, "{}", parts.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_trials_are_counted_by_reason_with_their_values() {
        let names = ["tau_S".to_string()];
        let mut trials = Trials::default();
        for k in 0..2431 {
            let value = 0.01 + 2.0 * k as f64 / 2430.0;
            let failure = (k < 12).then(|| {
                (
                    Failure::ModeChangeBudget,
                    format!("row {k}: no steady state"),
                )
            });
            trials.record(&names, &[value], failure);
        }
        let entries = failed_trials("base", &trials, &Budget::default());
        assert_eq!(entries.len(), 1);
        assert_eq!(entries[0].count, 12);
        assert_eq!(entries[0].trials, 2431);
        let (low, high) = entries[0].values["tau_S"];
        assert_eq!(low, 0.01);
        assert!((high - (0.01 + 22.0 / 2430.0)).abs() < 1e-15);
        assert!(
            entries[0].text.starts_with(
                "base: 12 of 2,431 trial predictions stopped at the budget of 200 mode changes"
            ),
            "{}",
            entries[0].text
        );
        assert!(
            entries[0]
                .text
                .contains("tau_S 0.01..0.01905 (of 0.01..2.01)")
        );
        assert!(
            entries[0]
                .text
                .ends_with("the first: row 0: no steady state")
        );
    }

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(1234567), "1,234,567");
    }
}
