//! How firm a selection is: the selection rule rerun on resamples of the data, and how often
//! each candidate (or nothing) comes out selected.
//!
//! **The design: complementary half-samples.** Each resample splits the data's units at
//! random into two halves; the models are refitted on one half and scored on the other, and
//! the pair gives two resamples (fit on A, score on B; fit on B, score on A). A unit is a row
//! of steady data; for a time series it is a run (data file) when there are at least twice
//! [`Settings::folds`] runs, otherwise a contiguous block of a run (each run cut into
//! blocks, every run still simulated whole so that no block cuts the measured inputs that
//! drive it, as the folds do). Subsampling without replacement is chosen over a case
//! bootstrap: a bootstrap draws rows with replacement, and its duplicated rows are read by the
//! pure-error estimate as replicates and weigh twice in a fit, so it understates the noise
//! and overstates every effect; half-samples keep every row once, keep the replicates that
//! are there, and leave a natural held-out half. Subsampling is valid under weaker
//! conditions than the bootstrap (Politis & Romano, "Large sample confidence regions based on
//! subsamples under minimal assumptions", Ann. Statist. 22, 1994); half-samples are the
//! subsample of stability selection (Meinshausen & Bühlmann, "Stability selection", J. R.
//! Statist. Soc. B 72, 2010), and complementary pairs are Shah & Samworth's ("Variable
//! selection with error control: another look at stability selection", J. R. Statist. Soc.
//! B 75, 2013).
//!
//! **The rule on a half** is the full procedure's ([`super::verdicts`]): an F-test at the
//! same Bonferroni level, a lower AICc, and a lower held-out RMSE, here on the other half.
//! What a half does not redo is the global search: each model is refitted locally from where
//! the full data's search ended (the base model from each of its basins, a candidate from its
//! own optimum and from the half's base fit with its own parameters at their no-effect
//! values), as a fold refits; candidates with no effect on the whole data have none on a half
//! and are left out. A half has half the rows, so its tests have less power: a selection
//! that holds in most halves is firm, while nothing selected in most halves says that no
//! effect shows in half the data, not that there is none.
//!
//! **Firm** means selected in at least [`FIRM_FRACTION`] of the resamples (4 in 5; stability
//! selection's thresholds lie between 0.6 and 0.9, and a selection that a fifth of the halves
//! overturn is one the data only just carry). The verdict is `firm` (the selected candidate
//! in that many resamples), `firm among indistinguishable` (it or a candidate the data cannot
//! tell from it, which the report lists), `consistently null` (nothing selected, and nothing
//! in that many resamples), `unstable` (fewer), or `not assessed` (and why).
//!
//! **Cost.** Resamples run side by side and their cost is counted in row predictions (the
//! evaluations of each fit times the rows it simulates). By default ([`Resampling::count`]
//! `None`) they cost no more than the search itself: the first pair runs, and then as many
//! more pairs as three quarters of the search's cost (its fits' and folds' evaluations
//! times the rows; see `SEARCH_SHARE`) pay for at the pair's cost, up to
//! [`DEFAULT_RESAMPLES`] in all; when that is fewer than
//! [`MIN_DEFAULT_RESAMPLES`], none, and the report says what they would cost and how to
//! ask for them. The seed is fixed
//! ([`DEFAULT_SEED`]), so the same data give the same report.

use std::collections::BTreeMap;

use bondgraph_core::model::Model;
use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;
use rand::seq::SliceRandom;
use rayon::prelude::*;
use serde::Serialize;

use super::fit::{Assessment, active_only, fit_best, fitted_parameters, limit_to_budget};
use super::procedure::Models;
use super::verdicts::Verdicts;
use super::{Candidate, DiscoverError, Settings};
use crate::data::Measurement;
use crate::experiment::Experiment;
use crate::global::{self, Search};
use crate::predict::Anchors;
use crate::predict::Predictor;

/// Resamples run by default, when they cost less than the search ([`Resampling`]).
pub const DEFAULT_RESAMPLES: usize = 20;

/// The seed of the resamples' generator (Xoshiro256++), unless another is given.
pub const DEFAULT_SEED: u64 = 31;

/// The fraction of resamples in which a selection must recur to be called firm.
pub const FIRM_FRACTION: f64 = 0.8;

/// The fewest resamples run by default: fewer cannot tell 4 in 5 from chance, and when
/// even these cost more than the search, resampling waits to be asked for.
pub const MIN_DEFAULT_RESAMPLES: usize = 10;

/// The share of the search's row predictions the default resamples may take. The search's
/// count includes every screened point, many of them rejected at their first row that does
/// not settle, so it overstates its work: on Table III, resamples that took as many row
/// predictions as the search took 1.15 times its CPU time; at three quarters they take less.
const SEARCH_SHARE: (usize, usize) = (3, 4);

/// The fewest units (rows, runs or blocks) that give half-samples worth counting: with
/// fewer, every split is nearly the same.
const MIN_UNITS: usize = 4;

/// How `discover` resamples to say how firm its selection is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resampling {
    /// Resamples to run: `Some(0)` turns them off, `Some(n)` runs `n`, `None` runs
    /// [`DEFAULT_RESAMPLES`] when they cost less than the search itself.
    pub count: Option<usize>,
    /// The generator's seed.
    pub seed: u64,
}

impl Default for Resampling {
    fn default() -> Self {
        Self {
            count: None,
            seed: DEFAULT_SEED,
        }
    }
}

/// How firm the selection is, over resamples of the data.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Stability {
    /// Resamples run to the end (failed ones excluded); 0 when not assessed.
    pub resamples: usize,
    /// The generator's seed.
    pub seed: u64,
    /// What was resampled and how.
    pub design: String,
    /// The fraction of resamples a selection must recur in to be firm.
    pub threshold: f64,
    /// How many resamples selected each candidate, `null` for nothing selected.
    pub selected_counts: BTreeMap<String, usize>,
    /// Resamples whose fits failed (a model that could not be evaluated on a half).
    pub failed: usize,
    /// Why the first failed resample failed.
    pub failure: Option<String>,
    /// `firm`, `firm among indistinguishable`, `consistently null`, `unstable` or
    /// `not assessed`.
    pub verdict: String,
    /// The report's line.
    pub summary: String,
    /// The resamples' cost and the search's, in row predictions.
    pub cost: Cost,
}

/// Work in row predictions: each fit's evaluations times the rows it simulates.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
pub struct Cost {
    /// The resamples run.
    pub resamples: usize,
    /// The search and its cross-validation.
    pub search: usize,
}

/// The data's units of resampling, each a list of row indices, and the design in words.
///
/// Steady data: every row. A time series: the runs (data files) when there are at least
/// `2 * folds` of them, else each run cut into contiguous blocks, about `2 * folds` in all.
pub fn units(
    experiment: &Experiment,
    rows: &[Measurement],
    folds: usize,
) -> (Vec<Vec<usize>>, String) {
    if experiment.time().is_none() {
        return (
            (0..rows.len()).map(|i| vec![i]).collect(),
            format!("complementary half-samples of the {} rows", rows.len()),
        );
    }
    let mut runs: Vec<Vec<usize>> = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if rows[run[0]].file == row.file => run.push(i),
            _ => runs.push(vec![i]),
        }
    }
    let wanted = 2 * folds.max(1);
    if runs.len() >= wanted {
        let design = format!("complementary half-samples of the {} runs", runs.len());
        return (runs, design);
    }
    let per_run = wanted.div_ceil(runs.len());
    let blocks: Vec<Vec<usize>> = runs
        .iter()
        .flat_map(|run| {
            let count = per_run.min(run.len());
            let (size, longer) = (run.len() / count, run.len() % count);
            let mut start = 0;
            (0..count)
                .map(|b| {
                    let end = start + size + usize::from(b < longer);
                    let block = run[start..end].to_vec();
                    start = end;
                    block
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let design = format!(
        "complementary half-samples of {} contiguous blocks of the {} run(s), each run \
         simulated whole",
        blocks.len(),
        runs.len()
    );
    (blocks, design)
}

/// `resamples` splits of `units` units into two halves (`units / 2` and the rest), each as
/// (fitted, held out), sorted: random partitions drawn from `seed`, each used both ways
/// (complementary pairs), the last one way only when `resamples` is odd.
pub fn half_samples(units: usize, resamples: usize, seed: u64) -> Vec<(Vec<usize>, Vec<usize>)> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut splits = Vec::with_capacity(resamples);
    while splits.len() < resamples {
        let mut order: Vec<usize> = (0..units).collect();
        order.shuffle(&mut rng);
        let (a, b) = order.split_at(units / 2);
        let (mut a, mut b) = (a.to_vec(), b.to_vec());
        a.sort_unstable();
        b.sort_unstable();
        splits.push((a.clone(), b.clone()));
        if splits.len() < resamples {
            splits.push((b, a));
        }
    }
    splits
}

/// The selection's stability: the selection rule rerun on resamples ([`Settings::resampling`])
/// of `models`' data, from the full fits (`baseline`, whose search found `base_basins`, and
/// `assessed`, judged by `verdicts`); `None` when resampling is turned off.
pub(super) fn assess(
    models: &Models<'_>,
    baseline: &Assessment,
    base_basins: &[Vec<f64>],
    assessed: &[Assessment],
    verdicts: &Verdicts,
    indistinguishable: &[usize],
) -> Option<Stability> {
    let settings = models.settings;
    let requested = settings.resampling.count;
    let count = requested.unwrap_or(DEFAULT_RESAMPLES);
    if count == 0 {
        return None;
    }
    let seed = settings.resampling.seed;
    let (units, design) = units(models.experiment, models.rows, settings.folds);
    let search_cost = (baseline.evaluations
        + assessed.iter().map(|a| a.evaluations).sum::<usize>())
        * models.rows.len();
    let selected = verdicts.selected.map(|s| models.candidates[s].id.clone());
    let group: Vec<String> = indistinguishable
        .iter()
        .map(|&i| models.candidates[i].id.clone())
        .collect();
    let report = Report {
        seed,
        design,
        selected,
        group,
        search_cost,
    };
    // Every model's parameters on the half, at most: a half with no more rows than that
    // leaves its largest model without a residual degree of freedom.
    let largest = assessed
        .iter()
        .map(|a| a.names.len())
        .chain([baseline.names.len()])
        .max()
        .unwrap_or(0);
    if units.len() < MIN_UNITS {
        let why = format!(
            "{} units to resample ({}); half-samples need at least {MIN_UNITS}",
            units.len(),
            report.design
        );
        return Some(report.not_assessed(why));
    }
    let smallest_half: usize = {
        let mut sizes: Vec<usize> = units.iter().map(Vec::len).collect();
        sizes.sort_unstable();
        sizes[..units.len() / 2].iter().sum()
    };
    if smallest_half < largest + 2 {
        return Some(report.not_assessed(format!(
            "a half-sample may keep {smallest_half} rows, and the largest model fits \
             {largest} parameters"
        )));
    }
    let base_starts = if base_basins.is_empty() {
        vec![baseline.fit.values.clone()]
    } else {
        base_basins.to_vec()
    };
    let context = match Context::new(models, baseline, &base_starts, assessed, verdicts, &units) {
        Ok(context) => context,
        Err(error) => return Some(report.not_assessed(error.to_string())),
    };
    let mut splits = half_samples(units.len(), count, seed);
    let run = |splits: &[(Vec<usize>, Vec<usize>)]| -> Vec<Result<Outcome, DiscoverError>> {
        splits
            .par_iter()
            .map(|(fitted, held_out)| context.resample(fitted, held_out))
            .collect()
    };
    let probe = splits.len().min(2);
    let mut outcomes = run(&splits[..probe]);
    if requested.is_none() {
        // As many pairs as cost no more than the search, up to the default number.
        let probe_cost: usize = outcomes.iter().flatten().map(|o| o.cost).sum();
        let affordable = (search_cost * SEARCH_SHARE.0 / SEARCH_SHARE.1 * probe)
            .checked_div(probe_cost)
            .map_or(count, |n| n / 2 * 2);
        if affordable < MIN_DEFAULT_RESAMPLES {
            let projected = probe_cost * MIN_DEFAULT_RESAMPLES / probe.max(1);
            return Some(report.not_assessed(format!(
                "{MIN_DEFAULT_RESAMPLES} resamples would take about {projected} row predictions, \
                 more than {}/{} of the search's {search_cost}; `--resamples N` runs them",
                SEARCH_SHARE.0, SEARCH_SHARE.1
            )));
        }
        splits.truncate(affordable.min(count));
    }
    outcomes.extend(run(&splits[probe..]));
    Some(
        report.tally(
            &outcomes,
            &models
                .candidates
                .iter()
                .map(|c| c.id.clone())
                .collect::<Vec<_>>(),
        ),
    )
}

/// What one resample selected, and its cost in row predictions.
struct Outcome {
    selected: Option<usize>,
    cost: usize,
}

/// What the report's line needs besides the counts.
struct Report {
    seed: u64,
    design: String,
    selected: Option<String>,
    group: Vec<String>,
    search_cost: usize,
}

impl Report {
    fn not_assessed(self, why: String) -> Stability {
        Stability {
            resamples: 0,
            seed: self.seed,
            summary: format!("stability: not assessed: {why}"),
            design: self.design,
            threshold: FIRM_FRACTION,
            selected_counts: BTreeMap::new(),
            failed: 0,
            failure: None,
            verdict: "not assessed".to_string(),
            cost: Cost {
                resamples: 0,
                search: self.search_cost,
            },
        }
    }

    /// The counts of `outcomes` (candidate indices into `ids`) and the verdict.
    fn tally(self, outcomes: &[Result<Outcome, DiscoverError>], ids: &[String]) -> Stability {
        let mut counts: BTreeMap<String, usize> = BTreeMap::new();
        let (mut failed, mut failure, mut cost) = (0, None, 0);
        for outcome in outcomes {
            match outcome {
                Ok(o) => {
                    let key = o.selected.map_or("null".to_string(), |s| ids[s].clone());
                    *counts.entry(key).or_default() += 1;
                    cost += o.cost;
                }
                Err(error) => {
                    failed += 1;
                    failure.get_or_insert_with(|| error.to_string());
                }
            }
        }
        let resamples = outcomes.len() - failed;
        let (verdict, mut summary) =
            verdict(&counts, resamples, self.selected.as_deref(), &self.group);
        summary.push_str(&format!(" ({}, seed {})", self.design, self.seed));
        if let Some(why) = &failure {
            summary.push_str(&format!("; {failed} resample(s) failed: {why}"));
        }
        Stability {
            resamples,
            seed: self.seed,
            design: self.design,
            threshold: FIRM_FRACTION,
            selected_counts: counts,
            failed,
            failure,
            verdict: verdict.to_string(),
            summary,
            cost: Cost {
                resamples: cost,
                search: self.search_cost,
            },
        }
    }
}

/// The verdict and the report's line, from how many of `resamples` selected each id
/// (`null`: nothing), given the full data's `selected` id and the ids indistinguishable
/// from it (`group`).
pub fn verdict(
    counts: &BTreeMap<String, usize>,
    resamples: usize,
    selected: Option<&str>,
    group: &[String],
) -> (&'static str, String) {
    if resamples == 0 {
        return (
            "not assessed",
            "stability: not assessed: every resample failed".to_string(),
        );
    }
    let needed = (FIRM_FRACTION * resamples as f64).ceil() as usize;
    let key = selected.unwrap_or("null");
    let held = counts.get(key).copied().unwrap_or(0);
    let name = |id: &str| {
        if id == "null" {
            "nothing".to_string()
        } else {
            format!("'{id}'")
        }
    };
    let mut others: Vec<(&String, &usize)> = counts.iter().filter(|(id, _)| *id != key).collect();
    others.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
    let others: Vec<String> = others
        .iter()
        .map(|(id, n)| format!("{} in {n}", name(id)))
        .collect();
    let with_group = held
        + group
            .iter()
            .map(|id| counts.get(id).copied().unwrap_or(0))
            .sum::<usize>();
    let (word, mut line) = match selected {
        Some(_) if held >= needed => (
            "firm",
            format!("stability: selected in {held} of {resamples} resamples, firm"),
        ),
        Some(id) if with_group >= needed => (
            "firm among indistinguishable",
            format!(
                "stability: '{id}' selected in {held} of {resamples} resamples, it or a \
                 candidate indistinguishable from it in {with_group}: firm that one of them \
                 is there, not which"
            ),
        ),
        Some(id) => (
            "unstable",
            format!(
                "stability: unstable: '{id}' selected in {held} of {resamples} resamples (firm \
                 needs {needed})"
            ),
        ),
        None if held >= needed => (
            "consistently null",
            format!(
                "stability: nothing selected in {held} of {resamples} resamples (a half has \
                 less power than the whole: no effect shows in most halves)"
            ),
        ),
        None => (
            "unstable",
            format!(
                "stability: unstable: nothing selected in {held} of {resamples} resamples \
                 (firm needs {needed})"
            ),
        ),
    };
    if !others.is_empty() {
        line.push_str(&format!("; {}", others.join(", ")));
    }
    if word == "unstable" && selected.is_some() && !group.is_empty() {
        line.push_str(&format!(
            "; it or a candidate indistinguishable from it in {with_group}"
        ));
    }
    (word, line)
}

/// A model prepared once for every resample.
struct Prepared<'a> {
    model: &'a Model,
    predictor: Predictor,
    /// Its fitted parameters on the whole data, their bounds, and the model file's values.
    names: Vec<String>,
    bounds: Vec<(f64, f64)>,
    /// Its own parameters' file values (their no-effect values), for a candidate.
    own_values: Vec<f64>,
    /// Its optimum on the whole data.
    optimum: Vec<f64>,
    /// The steady states of its fit on the whole data that can be continued.
    anchors: Anchors,
}

impl<'a> Prepared<'a> {
    fn new(
        model: &'a Model,
        source: &std::sync::Arc<bondgraph_core::source::SourceFile>,
        models: &Models<'_>,
        own: &[String],
        fitted: &Assessment,
    ) -> Result<Self, DiscoverError> {
        let (names, bounds, file_values) =
            fitted_parameters(model, models.experiment, models.rows, own)?;
        Ok(Self {
            model,
            predictor: Predictor::new(model.clone(), source, models.experiment)?,
            own_values: file_values[names.len() - own.len()..].to_vec(),
            names,
            bounds,
            optimum: fitted.fit.values.clone(),
            anchors: fitted.anchors.clone(),
        })
    }

    /// Refitted locally on `fitted` from `starts`, scored on `held_out`: its assessment
    /// on the half, and the cost in row predictions.
    fn refit(
        &self,
        fitted: &Half,
        held_out: &Half,
        starts: &[Vec<f64>],
        settings: &Settings,
    ) -> Result<(Assessment, usize), DiscoverError> {
        // A parameter no row of the half uses changes no prediction there: it keeps its
        // start, and its whole bounds fit as well.
        let idle: Vec<bool> = self
            .names
            .iter()
            .map(|n| !self.predictor.uses_parameter(n, &fitted.rows))
            .collect();
        let active = |values: &[f64]| active_only(values, &idle);
        let names = active_only(&self.names, &idle);
        let bounds = active_only(&self.bounds, &idle);
        let mut evaluator = self.predictor.evaluator(&names)?;
        limit_to_budget(&mut evaluator, settings);
        evaluator.seed(&self.anchors, &fitted.rows);
        let orderings = global::orderings(self.model, &names);
        let starts_active: Vec<Vec<f64>> = starts.iter().map(|s| active(s)).collect();
        let start_refs: Vec<&[f64]> = starts_active.iter().map(Vec::as_slice).collect();
        let fit = fit_best(
            &mut evaluator,
            &fitted.rows,
            Some(&fitted.kept),
            &start_refs,
            &bounds,
            (&orderings, &Search::LOCAL),
            settings,
        )?
        .fit;
        evaluator.set(&fit.values);
        let on_fitted = evaluator.predict_each(&fitted.rows);
        // Every observed column of each row (several are in their noise levels).
        let columns = self.predictor.experiment().observed.len();
        let predictions: Vec<f64> = fitted
            .kept
            .iter()
            .flat_map(|&i| {
                on_fitted[i]
                    .as_ref()
                    .map_or(vec![f64::NAN; columns], |p| p.observed.clone())
            })
            .collect();
        let on_held_out = evaluator.predict_each(&held_out.rows);
        let (mut heldout_sse, mut heldout_count, mut unsettled) = (0.0, 0, 0);
        let mut heldout_by_column = vec![0.0; columns];
        // One slot per residual of the half held out, the same for every model.
        let mut heldout_cells = vec![f64::NAN; held_out.kept.len() * columns];
        for (slot, &i) in held_out.kept.iter().enumerate() {
            match &on_held_out[i] {
                Ok(p) => {
                    for (k, (predicted, measured)) in p
                        .observed
                        .iter()
                        .zip(&held_out.rows[i].observed)
                        .enumerate()
                    {
                        let square = (predicted - measured).powi(2);
                        heldout_sse += square;
                        heldout_by_column[k] += square;
                        heldout_count += 1;
                        heldout_cells[slot * columns + k] = square;
                    }
                }
                Err(_) => unsettled += 1,
            }
        }
        unsettled += predictions.iter().filter(|p| p.is_nan()).count();
        let evaluations = fit.evaluations;
        let cost = (evaluations + 1) * fitted.rows.len() + held_out.rows.len();
        let fit = fit.with_idle(&idle, &starts[0], &self.bounds);
        Ok((
            Assessment {
                names: self.names.clone(),
                fit,
                predictions,
                modes: Vec::new(),
                heldout_sse,
                heldout_count,
                heldout_by_column,
                heldout_cells,
                unsettled,
                evaluations,
                trials: evaluator.trials(),
                anchors: Anchors::default(),
            },
            cost,
        ))
    }
}

/// The rows a half simulates and the positions among them of the rows it keeps
/// ([`crate::folds::simulated`]).
struct Half {
    rows: Vec<Measurement>,
    kept: Vec<usize>,
}

impl Half {
    fn new(
        experiment: &Experiment,
        rows: &[Measurement],
        units: &[Vec<usize>],
        chosen: &[usize],
    ) -> Self {
        let mut wanted: Vec<usize> = chosen
            .iter()
            .flat_map(|&u| units[u].iter().copied())
            .collect();
        wanted.sort_unstable();
        let simulated = crate::folds::simulated(experiment, rows, &wanted);
        Self {
            rows: simulated.rows.iter().map(|&i| rows[i].clone()).collect(),
            kept: simulated.kept,
        }
    }
}

/// Everything a resample shares: the models prepared, the candidates tested on the whole
/// data (those with some effect on it), and where the base model's fits start.
struct Context<'a> {
    models: &'a Models<'a>,
    units: &'a [Vec<usize>],
    base: Prepared<'a>,
    base_basins: &'a [Vec<f64>],
    /// Each tested candidate's index in the library, and the model prepared.
    tested: Vec<(usize, Prepared<'a>)>,
    /// The tested candidates, as the verdicts take them.
    library: Vec<Candidate>,
}

impl<'a> Context<'a> {
    fn new(
        models: &'a Models<'a>,
        baseline: &Assessment,
        base_basins: &'a [Vec<f64>],
        assessed: &[Assessment],
        verdicts: &Verdicts,
        units: &'a [Vec<usize>],
    ) -> Result<Self, DiscoverError> {
        let base = Prepared::new(models.base_model, models.base, models, &[], baseline)?;
        let mut tested = Vec::new();
        let mut library = Vec::new();
        for (i, candidate) in models.candidates.iter().enumerate() {
            if verdicts.untestable[i] {
                continue;
            }
            tested.push((
                i,
                Prepared::new(
                    &candidate.model,
                    &candidate.source,
                    models,
                    &candidate.parameters,
                    &assessed[i],
                )?,
            ));
            library.push(candidate.clone());
        }
        Ok(Self {
            models,
            units,
            base,
            base_basins,
            tested,
            library,
        })
    }

    /// Fits every model on the units `fitted`, scores it on `held_out`, and judges.
    fn resample(&self, fitted: &[usize], held_out: &[usize]) -> Result<Outcome, DiscoverError> {
        let (experiment, rows, settings) = (
            self.models.experiment,
            self.models.rows,
            self.models.settings,
        );
        let fitted = Half::new(experiment, rows, self.units, fitted);
        let held_out = Half::new(experiment, rows, self.units, held_out);
        let (baseline, base_cost) =
            self.base
                .refit(&fitted, &held_out, self.base_basins, settings)?;
        let assessed: Vec<(Assessment, usize)> = self
            .tested
            .par_iter()
            .map(|(_, candidate)| {
                // From its own optimum, and from the half's base fit with its own
                // parameters at their no-effect values (so it does no worse than the base).
                let contains_base: Vec<f64> = baseline
                    .fit
                    .values
                    .iter()
                    .chain(&candidate.own_values)
                    .copied()
                    .collect();
                candidate.refit(
                    &fitted,
                    &held_out,
                    &[candidate.optimum.clone(), contains_base],
                    settings,
                )
            })
            .collect::<Result<_, _>>()?;
        let cost = base_cost + assessed.iter().map(|a| a.1).sum::<usize>();
        let assessed: Vec<Assessment> = assessed.into_iter().map(|a| a.0).collect();
        let verdicts = Verdicts::judge(&self.library, &assessed, &baseline, settings.alpha);
        Ok(Outcome {
            selected: verdicts.selected.map(|j| self.tested[j].0),
            cost,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::{half_samples, units, verdict};
    use crate::data;
    use crate::experiment::Experiment;

    #[test]
    fn half_samples_split_every_unit_once_and_repeat_with_their_seed() {
        let splits = half_samples(27, 20, 31);
        assert_eq!(splits.len(), 20);
        for (k, (fitted, held_out)) in splits.iter().enumerate() {
            assert_eq!(fitted.len(), if k % 2 == 0 { 13 } else { 14 });
            assert_eq!(fitted.len() + held_out.len(), 27);
            let mut all: Vec<usize> = fitted.iter().chain(held_out).copied().collect();
            all.sort_unstable();
            assert_eq!(
                all,
                (0..27).collect::<Vec<_>>(),
                "every unit once, no duplicate"
            );
            assert!(fitted.windows(2).all(|w| w[0] < w[1]));
        }
        // Complementary pairs: the second of a pair is the first swapped.
        assert_eq!(splits[1].0, splits[0].1);
        assert_eq!(splits[1].1, splits[0].0);
        // The partitions differ from pair to pair.
        assert_ne!(splits[0].0, splits[2].0);
        assert_eq!(
            half_samples(27, 20, 31),
            splits,
            "the same seed, the same splits"
        );
        assert_ne!(half_samples(27, 20, 32), splits);
        // An odd count uses the last partition one way.
        let odd = half_samples(10, 5, 1);
        assert_eq!(odd.len(), 5);
        assert_eq!(odd[..4], half_samples(10, 4, 1)[..]);
    }

    #[test]
    fn a_run_is_resampled_in_contiguous_blocks_and_steady_rows_one_by_one() {
        let series = Experiment::parse(
            "e.ron",
            r#"Experiment(
    kind: TimeSeries(scenario: "s.ron", time: ("t_s", 1.0)),
    conditions: [("u_V", "u", 1.0)], observed: [("w", "flow:shaft", 1.0)])"#,
        )
        .unwrap();
        let text: String = std::iter::once("t_s,u_V,w\n".to_string())
            .chain((0..23).map(|i| format!("{i},1,0\n")))
            .collect();
        let rows = data::read("d.csv", &text, &series).unwrap().rows;
        let (blocks, design) = units(&series, &rows, 5);
        // 23 samples in 10 blocks: three of 3, seven of 2, in order.
        assert_eq!(blocks.len(), 10);
        assert_eq!(blocks[0], [0, 1, 2]);
        assert_eq!(blocks[3], [9, 10]);
        assert_eq!(blocks.concat(), (0..23).collect::<Vec<_>>());
        assert!(
            design.contains("10 contiguous blocks of the 1 run"),
            "{design}"
        );

        let steady = Experiment::parse(
            "e.ron",
            r#"Experiment(kind: Steady, conditions: [("u_V", "u", 1.0)], observed: [("w", "flow:shaft", 1.0)])"#,
        )
        .unwrap();
        let rows = data::read("d.csv", "u_V,w\n1,0\n2,0\n3,0\n", &steady)
            .unwrap()
            .rows;
        assert_eq!(units(&steady, &rows, 5).0, [[0], [1], [2]]);
    }

    #[test]
    fn a_selection_is_firm_when_four_resamples_in_five_repeat_it() {
        let counts = |pairs: &[(&str, usize)]| -> BTreeMap<String, usize> {
            pairs.iter().map(|(id, n)| (id.to_string(), *n)).collect()
        };
        let (word, line) = verdict(&counts(&[("a", 16), ("null", 4)]), 20, Some("a"), &[]);
        assert_eq!(word, "firm");
        assert_eq!(
            line,
            "stability: selected in 16 of 20 resamples, firm; nothing in 4"
        );
        let group = ["b".to_string()];
        let (word, line) = verdict(
            &counts(&[("a", 4), ("b", 3), ("null", 5)]),
            12,
            Some("a"),
            &group,
        );
        assert_eq!(word, "unstable");
        assert_eq!(
            line,
            "stability: unstable: 'a' selected in 4 of 12 resamples (firm needs 10); nothing \
             in 5, 'b' in 3; it or a candidate indistinguishable from it in 7"
        );
        let (word, line) = verdict(
            &counts(&[("a", 9), ("b", 8), ("null", 3)]),
            20,
            Some("a"),
            &group,
        );
        assert_eq!(word, "firm among indistinguishable");
        assert_eq!(
            line,
            "stability: 'a' selected in 9 of 20 resamples, it or a candidate indistinguishable \
             from it in 17: firm that one of them is there, not which; 'b' in 8, nothing in 3"
        );
        let (word, _) = verdict(&counts(&[("null", 19), ("a", 1)]), 20, None, &[]);
        assert_eq!(word, "consistently null");
        let (word, line) = verdict(&counts(&[("null", 9), ("a", 11)]), 20, None, &[]);
        assert_eq!(word, "unstable");
        assert_eq!(
            line,
            "stability: unstable: nothing selected in 9 of 20 resamples (firm needs 16); 'a' \
             in 11"
        );
    }
}
