//! Predicting rows of measured data: a model prepared once for an experiment, then asked for
//! the steady state of each row with changing parameter values.
//!
//! An experiment's `absent` entries make several variants of one model (for each set of
//! empty columns, the model without their elements). Each variant is validated once, and its
//! simulator keeps every mode it has derived between predictions, so a calibration that
//! tries thousands of parameter values derives nothing twice. A time series' rows are
//! predicted along a simulated run of each file (`timeseries`); both kinds give a
//! [`Prediction`] per row.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_core::source::SourceFile;
use bondgraph_core::{Diagnostic, DiagnosticKind, diagnostics::Diagnostics};
use bondgraph_ron::model::edit::{self, Edit};
use bondgraph_solver::steady::continuation::{Anchor, continue_branch, continue_steady};
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, SharedForms, Simulator};

use crate::budget::{Budget, Failure, Trials};
use crate::data::Measurement;
use crate::experiment::{Experiment, ExperimentError};

mod prediction;
mod row_failure;
mod timeseries;

pub use prediction::{Prediction, describe};
use row_failure::{RowFailure, check_friction_levels};
use timeseries::{Drive, RunSetup, predict_run};

/// Removals combined into variants, at most: 2^6 models to validate.
const MAX_ABSENT: usize = 6;

/// One model variant: the model without the elements of some `absent` entries.
struct Variant {
    model: Model,
    /// For each condition, the model input it sets (`None`: its column is empty here).
    inputs: Vec<Option<usize>>,
    /// Each observed column's output, and whether the column measures its time integral
    /// (`integral:flow:outlet`, a volume drained since the run started).
    outputs: Vec<(OutputSpec, bool)>,
    initial: Mode,
    /// The modes' forms its evaluators' simulators derive, shared among them.
    forms: Arc<SharedForms>,
}

/// A model prepared to predict an experiment's rows, one variant per combination of empty
/// `absent` columns.
///
/// A `Predictor` owns the models; [`Predictor::evaluator`] makes an [`Evaluator`], which keeps
/// the simulators between predictions and takes new parameter values without deriving
/// anything again: what a calibration needs.
pub struct Predictor {
    experiment: Experiment,
    /// Indexed by the mask of empty `absent` columns.
    variants: Vec<Variant>,
    /// Where each `absent` entry's column is among the experiment's condition columns.
    absent_columns: Vec<usize>,
    settings: SteadySettings,
    /// For a time series: the scenario's signals and start.
    drive: Option<Drive>,
}

impl Predictor {
    /// Prepares `model` (read from `source`) for `experiment`.
    ///
    /// # Errors
    /// Located diagnostics when the experiment names inputs, outputs, modes or elements the
    /// model does not have, or a removal leaves the model invalid (pointing at the `absent`
    /// entry, with the model's own diagnostics after it).
    pub fn new(
        model: Model,
        source: &Arc<SourceFile>,
        experiment: &Experiment,
    ) -> Result<Self, ExperimentError> {
        if experiment.absent.len() > MAX_ABSENT {
            return Err(experiment
                .error(
                    DiagnosticKind::InvalidValue,
                    "absent",
                    &experiment.absent[MAX_ABSENT].column,
                    format!(
                        "experiment: {} `absent` entries; at most {MAX_ABSENT} can be combined",
                        experiment.absent.len()
                    ),
                )
                .into());
        }
        let columns = experiment.condition_columns();
        let absent_columns = experiment
            .absent
            .iter()
            .map(|a| {
                columns
                    .iter()
                    .position(|c| *c == a.column)
                    .expect("absent columns are condition columns")
            })
            .collect();
        let mut variants = Vec::new();
        for mask in 0..1usize << experiment.absent.len() {
            let removed: Vec<usize> = (0..experiment.absent.len())
                .filter(|j| mask & (1 << j) != 0)
                .collect();
            let variant_model = if removed.is_empty() {
                model.clone()
            } else {
                reduced(&model, source, experiment, &removed)?
            };
            let empty: Vec<&str> = removed
                .iter()
                .map(|&j| experiment.absent[j].column.as_str())
                .collect();
            variants.push(Variant::new(variant_model, experiment, &empty)?);
        }
        Ok(Self {
            experiment: experiment.clone(),
            variants,
            absent_columns,
            // Predictions need where each row settles, not the events on the way.
            settings: SteadySettings {
                events: false,
                ..SteadySettings::default()
            },
            drive: Drive::load(experiment, source)?,
        })
    }

    /// The model used for rows with every column filled.
    pub fn model(&self) -> &Model {
        &self.variants[0].model
    }

    /// The experiment.
    pub fn experiment(&self) -> &Experiment {
        &self.experiment
    }

    /// Sets parameter values (by name) in every variant; the structure and so the symbolic
    /// equations do not change. (An [`Evaluator`] does the same without touching the models.)
    ///
    /// # Errors
    /// When a name is not a parameter of the model.
    pub fn set_parameters(&mut self, values: &[(String, f64)]) -> Result<(), ExperimentError> {
        for variant in &mut self.variants {
            for (name, value) in values {
                parameter_index(&variant.model, name)?;
                let symbol = variant
                    .model
                    .symbols()
                    .get(name)
                    .expect("a parameter's symbol");
                variant.model.set_value(symbol, *value);
            }
        }
        Ok(())
    }

    /// The predicted observed values of each row (one per observed column), in the columns'
    /// units.
    ///
    /// # Errors
    /// When a simulation fails or does not settle, naming the row.
    pub fn predict(&self, rows: &[Measurement]) -> Result<Vec<Vec<f64>>, ExperimentError> {
        Ok(self
            .evaluator(&[])?
            .predict(rows)?
            .into_iter()
            .map(|p| p.observed)
            .collect())
    }

    /// An evaluator whose [`Evaluator::set`] takes values of the parameters `names`, in order.
    ///
    /// # Errors
    /// When a name is not a parameter of the model.
    pub fn evaluator(&self, names: &[String]) -> Result<Evaluator<'_>, ExperimentError> {
        let sessions = self
            .variants
            .iter()
            .map(|variant| {
                let slots = names
                    .iter()
                    .map(|name| parameter_index(&variant.model, name))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Session::new(variant, slots, &Budget::default()))
            })
            .collect::<Result<Vec<_>, ExperimentError>>()?;
        let budget = Budget::default();
        Ok(Evaluator {
            predictor: self,
            sessions,
            settings: steady_settings(self.settings, &budget),
            budget,
            names: names.to_vec(),
            values: Vec::new(),
            trials: Arc::new(Mutex::new(Trials::default())),
            differenced_from: None,
            continued_rows: 0,
        })
    }

    /// Whether some row's model (the variant its empty `absent` columns make) uses the
    /// parameter `name` in a law. One that only removed elements use changes no prediction.
    pub fn uses_parameter(&self, name: &str, rows: &[Measurement]) -> bool {
        let masks: std::collections::BTreeSet<usize> = rows.iter().map(|r| self.mask(r)).collect();
        masks.into_iter().any(|mask| {
            let model = &self.variants[mask].model;
            model
                .parameters()
                .iter()
                .find(|p| p.name == name)
                .is_some_and(|p| model.parameters_in_use().contains(&p.symbol))
        })
    }

    /// The variant a row is predicted by: the mask of its empty `absent` columns.
    fn mask(&self, row: &Measurement) -> usize {
        self.absent_columns
            .iter()
            .enumerate()
            .filter(|(_, c)| row.conditions[**c].is_none())
            .fold(0, |mask, (j, _)| mask | (1 << j))
    }
}

/// The model without the elements of the `absent` entries `removed`, with the values of
/// `model` (which a calibration may have changed from the file's).
fn reduced(
    model: &Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    removed: &[usize],
) -> Result<Model, ExperimentError> {
    let mut remove: Vec<String> = Vec::new();
    for &j in removed {
        for name in &experiment.absent[j].elements {
            if !remove.contains(name) {
                remove.push(name.clone());
            }
        }
    }
    let columns: Vec<&str> = removed
        .iter()
        .map(|&j| experiment.absent[j].column.as_str())
        .collect();
    // The entry to blame: the last removal combined (each single one is tried first).
    let blamed = &experiment.absent[*removed.last().expect("something removed")];
    let located = |diagnostics: Diagnostics, edited: Option<&edit::Edited>| {
        let what = if columns.len() == 1 {
            format!("a row with an empty `{}`", columns[0])
        } else {
            format!("a row with `{}` empty", columns.join("`, `"))
        };
        let mut all = vec![experiment.error(
            DiagnosticKind::UnknownName,
            "absent",
            &blamed.column,
            format!(
                "experiment: the `absent` entry for `{}` removes {} from model '{}', and {what} cannot be simulated: {}",
                blamed.column,
                remove
                    .iter()
                    .map(|n| format!("'{n}'"))
                    .collect::<Vec<_>>()
                    .join(", "),
                model.name(),
                diagnostics.first().message
            ),
        )];
        all.extend(diagnostics.0.into_iter().map(|d| match edited {
            Some(edited) => edited.relocate(d, source),
            None => d,
        }));
        ExperimentError::Diagnostics(Diagnostics(all))
    };
    let edit = Edit {
        remove: remove.clone(),
        parameters: Vec::new(),
    };
    let edited = edit::apply_traced(source, &edit).map_err(|d| located(d, None))?;
    let mut reduced =
        bondgraph_ron::model::load_source(&edited.file).map_err(|d| located(d, Some(&edited)))?;
    for original in model.parameters() {
        if let Some(symbol) = reduced.symbols().get(&original.name) {
            reduced.set_value(symbol, original.value);
        }
    }
    Ok(reduced)
}

/// `settings` limited to `budget`'s work per steady row.
fn steady_settings(settings: SteadySettings, budget: &Budget) -> SteadySettings {
    SteadySettings {
        max_mode_changes: budget.mode_changes,
        max_segments: budget.segments,
        ..settings
    }
}

/// Predicts rows with changing parameter values, keeping every mode derived so far.
pub struct Evaluator<'p> {
    predictor: &'p Predictor,
    /// One per variant.
    sessions: Vec<Session<'p>>,
    settings: SteadySettings,
    budget: Budget,
    /// The parameters [`Evaluator::set`] takes, and their values last set.
    names: Vec<String>,
    values: Vec<f64>,
    /// The trial predictions of this evaluator and its forks ([`Evaluator::predict_all`]).
    trials: Arc<Mutex<Trials>>,
    /// While predicting a finite difference ([`Evaluator::predict_differenced`]): the values
    /// (of the parameters named) it is taken from.
    differenced_from: Option<Vec<f64>>,
    /// Steady rows of the trial under way continued from a kept steady state
    /// ([`Trials::continued_rows`]).
    continued_rows: usize,
}

/// One variant's simulator and where the evaluator's parameters sit in its values.
struct Session<'p> {
    variant: &'p Variant,
    simulator: Simulator<'p>,
    slots: Vec<usize>,
    /// Each slot's parameter range (its bounds' width; its value's magnitude without
    /// bounds), which [`Budget::continuation`] is a fraction of.
    ranges: Vec<f64>,
    values: Vec<f64>,
    /// Per row (file and line), the last steady state simulated that can be continued.
    anchors: RowAnchors,
}

/// A steady state that can be continued, with the parameter values (all of the model's) it
/// was simulated at, and whether it was seeded from the fit on every row
/// ([`Evaluator::seed`]: [`Budget::refit_continuation`] applies) or simulated here
/// ([`Budget::continuation`]).
#[derive(Clone, Debug)]
struct RowAnchor {
    at: Vec<f64>,
    anchor: Anchor,
    seeded: bool,
}

/// Per row (file and line), a steady state that can be continued.
type RowAnchors = HashMap<(Arc<str>, usize), RowAnchor>;

/// The steady states an evaluator simulated that can be continued, one set per variant: what
/// a refit on part of the rows ([`Evaluator::seed`]) starts from where the whole fit ended.
#[derive(Clone, Debug, Default)]
pub struct Anchors(Vec<RowAnchors>);

impl<'p> Session<'p> {
    fn new(variant: &'p Variant, slots: Vec<usize>, budget: &Budget) -> Self {
        let outputs = variant
            .outputs
            .iter()
            .enumerate()
            .map(|(k, (spec, integral))| Output {
                name: format!("observed{k}"),
                spec: spec.clone(),
                integral: *integral,
            })
            .collect();
        let settings = bondgraph_solver::Settings {
            max_steps: budget.steps,
            ..bondgraph_solver::Settings::default()
        };
        let model = &variant.model;
        let ranges = slots
            .iter()
            .map(|&slot| {
                let parameter = model.parameters().iter().find(|p| p.symbol.index() == slot);
                match parameter.and_then(|p| p.bounds) {
                    Some((low, high)) => high - low,
                    None => model.values()[slot].abs(),
                }
            })
            .collect();
        Self {
            variant,
            simulator: Simulator::new(model, outputs)
                .with_settings(settings)
                .with_shared_forms(Arc::clone(&variant.forms)),
            slots,
            ranges,
            values: model.values().to_vec(),
            anchors: HashMap::new(),
        }
    }

    /// Whether `at` (all of the model's parameter values) holds `from` (the evaluator's
    /// parameters) in the slots and the current values elsewhere.
    fn simulated_at(&self, at: &[f64], from: &[f64]) -> bool {
        at.len() == self.values.len()
            && self.values.iter().zip(at).enumerate().all(|(k, (v, a))| {
                match self.slots.iter().position(|&slot| slot == k) {
                    Some(j) => from[j] == *a,
                    None => v == a,
                }
            })
    }

    /// Whether `at` (all of the model's parameter values) is within `radius` of each slot's
    /// range of the current values, and equal to them elsewhere (an anchor seeded from
    /// another evaluator may have been simulated with other parameters fitted).
    fn near(&self, at: &[f64], radius: f64) -> bool {
        at.len() == self.values.len()
            && self.values.iter().zip(at).enumerate().all(|(k, (v, a))| {
                match self.slots.iter().position(|&slot| slot == k) {
                    Some(j) => (v - a).abs() <= radius * self.ranges[j],
                    None => v == a,
                }
            })
    }
}

impl<'p> Evaluator<'p> {
    /// A new evaluator of the same parameters with the same limits, to predict alongside
    /// this one (on another thread): it derives its modes afresh, and counts its trials
    /// with this one's.
    pub fn fork(&self) -> Evaluator<'p> {
        Evaluator {
            predictor: self.predictor,
            sessions: self
                .sessions
                .iter()
                .map(|s| {
                    let mut fork = Session::new(s.variant, s.slots.clone(), &self.budget);
                    fork.anchors.clone_from(&s.anchors);
                    fork
                })
                .collect(),
            settings: self.settings,
            budget: self.budget,
            names: self.names.clone(),
            values: self.values.clone(),
            trials: Arc::clone(&self.trials),
            differenced_from: None,
            continued_rows: 0,
        }
    }

    /// The steady states simulated so far that can be continued.
    pub fn anchors(&self) -> Anchors {
        Anchors(self.sessions.iter().map(|s| s.anchors.clone()).collect())
    }

    /// Starts `rows` from `anchors`, taken from an evaluator of the same model and experiment
    /// at the optimum of a fit on every row, for a refit on part of them: a row whose anchor
    /// is within [`Budget::refit_continuation`] of the values set is continued from it
    /// instead of simulated from its start. This evaluator's forks start from them too. Seed
    /// only the rows the refit fits: the rows it holds out score it, and are simulated.
    pub fn seed(&mut self, anchors: &Anchors, rows: &[Measurement]) {
        for (session, seeded) in self.sessions.iter_mut().zip(&anchors.0) {
            for row in rows {
                let key = (Arc::clone(&row.file), row.row);
                if let Some(anchor) = seeded.get(&key) {
                    session.anchors.entry(key).or_insert_with(|| RowAnchor {
                        seeded: true,
                        ..anchor.clone()
                    });
                }
            }
        }
    }

    /// Limits each prediction to `budget`'s work ([`Budget`]); the parameter values set
    /// stay, the modes derived so far do not.
    pub fn set_budget(&mut self, budget: &Budget) {
        self.budget = *budget;
        self.settings = steady_settings(self.settings, budget);
        for session in &mut self.sessions {
            let values = session.values.clone();
            *session = Session::new(session.variant, session.slots.clone(), budget);
            session.values = values;
            session
                .simulator
                .set_parameter_values(&session.values)
                .expect("values indexed like the model's");
        }
    }

    /// The budget each prediction has.
    pub fn budget(&self) -> &Budget {
        &self.budget
    }

    /// The trial predictions made so far ([`Evaluator::predict_all`]) by this evaluator and
    /// its forks, and those that failed.
    pub fn trials(&self) -> Trials {
        self.trials
            .lock()
            .expect("no thread panicked holding it")
            .clone()
    }

    /// Marks that a fit with this evaluator stopped at its budget of evaluations.
    pub(crate) fn spent_evaluations(&self) {
        self.trials
            .lock()
            .expect("no thread panicked holding it")
            .evaluation_budget_spent = true;
    }

    /// Sets the values of the evaluator's parameters (in the order they were named).
    ///
    /// # Panics
    /// When `values` does not have one value per parameter named.
    pub fn set(&mut self, values: &[f64]) {
        self.values = values.to_vec();
        for session in &mut self.sessions {
            assert_eq!(values.len(), session.slots.len(), "one value per parameter");
            for (&slot, &value) in session.slots.iter().zip(values) {
                session.values[slot] = value;
            }
            session
                .simulator
                .set_parameter_values(&session.values)
                .expect("values indexed like the model's");
        }
    }

    /// The predicted steady state of each row.
    ///
    /// # Errors
    /// When a simulation fails or does not settle, naming the row.
    pub fn predict(&mut self, rows: &[Measurement]) -> Result<Vec<Prediction>, ExperimentError> {
        self.predict_each(rows).into_iter().collect()
    }

    /// The experiment the rows are read against.
    pub fn experiment(&self) -> &Experiment {
        self.predictor.experiment()
    }

    /// The predicted steady state of each row, or why that row has none (a simulation that
    /// does not settle, as in a stick-slip cycle), row by row.
    pub fn predict_each(
        &mut self,
        rows: &[Measurement],
    ) -> Vec<Result<Prediction, ExperimentError>> {
        if let Some(drive) = &self.predictor.drive {
            return self.predict_runs(drive, rows);
        }
        rows.iter()
            .map(|row| {
                self.predict_steady(row)
                    .map_err(|failure| self.located(row, failure))
            })
            .collect()
    }

    /// Every row's prediction, or `None` as soon as one row has none: what a fit's trial
    /// values need, which are rejected whole. Each call is a trial ([`Evaluator::trials`]):
    /// a failed one is counted with its reason and the first failed row in words.
    pub fn predict_all(&mut self, rows: &[Measurement]) -> Option<Vec<Prediction>> {
        let outcome: Result<Vec<Prediction>, (Failure, String)> =
            if let Some(drive) = &self.predictor.drive {
                match self.inconsistent_runs(rows) {
                    Some(error) => Err((Failure::Inconsistent, error.to_string())),
                    None => self
                        .predict_runs(drive, rows)
                        .into_iter()
                        .map(|p| p.map_err(|e| (Failure::Simulation, e.to_string())))
                        .collect(),
                }
            } else {
                rows.iter()
                    .map(|row| {
                        self.predict_steady(row).map_err(|failure| {
                            let reason = failure.kind();
                            (reason, self.located(row, failure).to_string())
                        })
                    })
                    .collect()
            };
        let (predictions, failure) = match outcome {
            Ok(predictions) => (Some(predictions), None),
            Err(failure) => (None, Some(failure)),
        };
        self.record_trial(failure);
        predictions
    }

    /// [`Evaluator::predict_all`] at the values set, a finite-difference step from `from`
    /// (values of the same parameters) where every row was last predicted: a steady row that
    /// settled at a path-dependent equilibrium there (a mode with guards, or one entered on the
    /// way) is continued on that branch ([`continue_branch`]) instead of simulated again, so
    /// that the difference is the slope on the branch, not a switch within the step.
    pub fn predict_differenced(
        &mut self,
        rows: &[Measurement],
        from: &[f64],
    ) -> Option<Vec<Prediction>> {
        self.differenced_from = Some(from.to_vec());
        let predictions = self.predict_all(rows);
        self.differenced_from = None;
        predictions
    }

    /// Predicts `rows` as [`Evaluator::predict_all`] does, handing each prediction to
    /// `enough` (with its row's position) in the order `order` gives, and stopping once
    /// `enough` says the rest are not needed; false when a row cannot be predicted. Steady
    /// rows are predicted one at a time in that order, so a stop saves the rest; a time
    /// series run by run, each whole, in the order of their first row in `order`, its rows
    /// in that order, so a stop saves the runs after it.
    pub fn predict_until(
        &mut self,
        rows: &[Measurement],
        order: &[usize],
        mut enough: impl FnMut(usize, &Prediction) -> bool,
    ) -> bool {
        if self.predictor.drive.is_some() {
            return self.predict_runs_until(rows, order, enough);
        }
        let mut failure = None;
        for &i in order {
            match self.predict_steady(&rows[i]) {
                Ok(prediction) => {
                    if enough(i, &prediction) {
                        break;
                    }
                }
                Err(error) => {
                    let reason = error.kind();
                    failure = Some((reason, self.located(&rows[i], error).to_string()));
                    break;
                }
            }
        }
        self.record_trial(failure)
    }

    /// Counts a trial at the current values ([`Evaluator::trials`]), failed with `failure`
    /// (its reason and the failed row in words) or not; whether it succeeded.
    fn record_trial(&mut self, failure: Option<(Failure, String)>) -> bool {
        let failed = failure.is_some();
        let mut trials = self.trials.lock().expect("no thread panicked holding it");
        trials.record(&self.names, &self.values, failure);
        trials.continued_rows += std::mem::take(&mut self.continued_rows);
        !failed
    }

    /// A row's failure, located at the row.
    fn located(&self, row: &Measurement, failure: RowFailure) -> ExperimentError {
        ExperimentError::Row {
            file: row.file.to_string(),
            row: row.row,
            cells: describe(&self.predictor.experiment, row),
            reason: failure.to_string(),
        }
    }

    /// One row's steady state.
    fn predict_steady(&mut self, row: &Measurement) -> Result<Prediction, RowFailure> {
        let experiment = &self.predictor.experiment;
        let session = &mut self.sessions[self.predictor.mask(row)];
        let variant = session.variant;
        let mut inputs = vec![0.0; variant.model.inputs().len()];
        for (k, condition) in experiment.conditions.iter().enumerate() {
            if let (Some(input), Some(cell)) = (variant.inputs[k], row.conditions[k]) {
                inputs[input] = condition.factor * cell;
            }
        }
        check_friction_levels(&variant.model, &session.values, Some(&inputs))?;
        let key = (Arc::clone(&row.file), row.row);
        let continued = match session.anchors.get(&key) {
            Some(RowAnchor { at, anchor, .. }) if anchor.path_dependent => {
                let from = self.differenced_from.as_deref();
                let here = from.is_some_and(|from| session.simulated_at(at, from));
                (self.budget.continuation > 0.0 && anchor.inputs == inputs && here)
                    .then(|| continue_branch(&mut session.simulator, anchor, &self.settings))
                    .flatten()
            }
            Some(RowAnchor { at, anchor, seeded }) => {
                let radius = if *seeded {
                    self.budget.refit_continuation
                } else {
                    self.budget.continuation
                };
                (radius > 0.0 && anchor.inputs == inputs && session.near(at, radius))
                    .then(|| continue_steady(&mut session.simulator, anchor, &self.settings))
                    .flatten()
            }
            None => None,
        };
        let steady = match continued {
            Some(steady) => {
                self.continued_rows += 1;
                steady
            }
            None => {
                let storage = session.simulator.storage().len();
                let steady = steady_state(
                    &mut session.simulator,
                    &inputs,
                    variant.initial.clone(),
                    vec![0.0; storage],
                    &self.settings,
                )
                .map_err(RowFailure::Steady)?;
                match &steady.anchor {
                    Some(anchor) => {
                        let at = session.values.clone();
                        session.anchors.insert(
                            key,
                            RowAnchor {
                                at,
                                anchor: anchor.clone(),
                                seeded: false,
                            },
                        );
                    }
                    None => {
                        session.anchors.remove(&key);
                    }
                }
                steady
            }
        };
        let observed: Vec<f64> = steady
            .outputs
            .iter()
            .zip(&experiment.observed)
            .map(|(y, o)| y / o.factor)
            .collect();
        if let Some(k) = observed.iter().position(|v| !v.is_finite()) {
            return Err(RowFailure::NotFinite(experiment.observed[k].column.clone()));
        }
        Ok(Prediction {
            observed,
            mode: steady.mode,
        })
    }

    /// A time series' runs: each stretch of consecutive rows from one file with the same
    /// empty `absent` columns is one simulation through its sample times.
    fn runs(&self, rows: &[Measurement]) -> Vec<std::ops::Range<usize>> {
        let mut runs = Vec::new();
        let mut start = 0;
        while start < rows.len() {
            let mask = self.predictor.mask(&rows[start]);
            let end = (start..rows.len())
                .find(|&k| {
                    rows[k].file != rows[start].file || self.predictor.mask(&rows[k]) != mask
                })
                .unwrap_or(rows.len());
            runs.push(start..end);
            start = end;
        }
        runs
    }

    /// The predictions of one run of a time series (`rows`, as [`Evaluator::runs`] gives
    /// them).
    fn predict_run(
        &mut self,
        drive: &Drive,
        rows: &[Measurement],
    ) -> Vec<Result<Prediction, ExperimentError>> {
        let session = &mut self.sessions[self.predictor.mask(&rows[0])];
        let variant = session.variant;
        let setup = RunSetup {
            model: &variant.model,
            inputs: &variant.inputs,
            initial: &variant.initial,
        };
        predict_run(
            drive,
            &self.predictor.experiment,
            &mut session.simulator,
            &setup,
            rows,
        )
    }

    /// A time series' rows, run by run.
    fn predict_runs(
        &mut self,
        drive: &Drive,
        rows: &[Measurement],
    ) -> Vec<Result<Prediction, ExperimentError>> {
        let mut predictions = Vec::with_capacity(rows.len());
        for run in self.runs(rows) {
            match self.inconsistent_run(&rows[run.clone()]) {
                Some(error) => predictions.extend(run.map(|_| Err(error.clone()))),
                None => predictions.extend(self.predict_run(drive, &rows[run])),
            }
        }
        predictions
    }

    /// Whether the values make a contact inconsistent in some run of a time series
    /// (its breakaway force below its Coulomb force, or a negative Coulomb force): the
    /// first such run's failure, located at its first row.
    fn inconsistent_runs(&self, rows: &[Measurement]) -> Option<ExperimentError> {
        self.runs(rows)
            .into_iter()
            .find_map(|run| self.inconsistent_run(&rows[run]))
    }

    /// Whether the values make a contact inconsistent in a run of a time series, found
    /// before simulating it: the simulation would otherwise run to the first breakaway
    /// and stop there with `no mode is consistent`. Levels that read an input vary along
    /// the run and are left to the simulation to judge.
    fn inconsistent_run(&self, run: &[Measurement]) -> Option<ExperimentError> {
        let session = &self.sessions[self.predictor.mask(run.first()?)];
        check_friction_levels(&session.variant.model, &session.values, None)
            .err()
            .map(|failure| self.located(&run[0], failure))
    }

    /// [`Evaluator::predict_until`] on a time series.
    fn predict_runs_until(
        &mut self,
        rows: &[Measurement],
        order: &[usize],
        mut enough: impl FnMut(usize, &Prediction) -> bool,
    ) -> bool {
        let predictor = self.predictor;
        let drive = predictor.drive.as_ref().expect("a time series");
        let runs = self.runs(rows);
        let run_of = |i: usize| runs.partition_point(|run| run.end <= i);
        // The runs in the order of their first row in `order`, and each run's rows so.
        let mut run_order: Vec<usize> = Vec::with_capacity(runs.len());
        let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); runs.len()];
        for &i in order {
            let run = run_of(i);
            if rows_of[run].is_empty() {
                run_order.push(run);
            }
            rows_of[run].push(i);
        }
        let mut failure = None;
        'runs: for run in run_order {
            let start = runs[run].start;
            if let Some(error) = self.inconsistent_run(&rows[runs[run].clone()]) {
                failure = Some((Failure::Inconsistent, error.to_string()));
                break 'runs;
            }
            let predictions = self.predict_run(drive, &rows[runs[run].clone()]);
            for &i in &rows_of[run] {
                match &predictions[i - start] {
                    Ok(prediction) => {
                        if enough(i, prediction) {
                            break 'runs;
                        }
                    }
                    Err(error) => {
                        failure = Some((Failure::Simulation, error.to_string()));
                        break 'runs;
                    }
                }
            }
        }
        self.record_trial(failure)
    }
}

/// Where the parameter `name` sits in the model's values.
fn parameter_index(model: &Model, name: &str) -> Result<usize, ExperimentError> {
    model
        .parameters()
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.symbol.index())
        .ok_or_else(|| {
            Diagnostic::new(
                DiagnosticKind::UnknownName,
                format!("'{name}' is not a parameter of model '{}'", model.name()),
            )
            .into()
        })
}

impl Variant {
    /// The variant `model` of `experiment` in which the columns `empty` are empty.
    fn new(model: Model, experiment: &Experiment, empty: &[&str]) -> Result<Self, ExperimentError> {
        let mut problems = Vec::new();
        let inputs = experiment
            .conditions
            .iter()
            .map(|condition| {
                if empty.contains(&condition.column.as_str()) {
                    return None;
                }
                let input = model.input_named(&condition.input).map(|i| i.index());
                if input.is_none() {
                    let inputs: Vec<String> =
                        model.inputs().iter().map(|i| format!("'{}'", i.name)).collect();
                    problems.push(
                        experiment
                            .error(
                                DiagnosticKind::UnknownName,
                                "conditions",
                                &condition.input,
                                format!(
                                    "experiment: column `{}` sets input '{}', which model '{}' does not have",
                                    condition.column, condition.input, model.name()
                                ),
                            )
                            .note(format!("its inputs are {}", inputs.join(", "))),
                    );
                }
                input
            })
            .collect();
        let outputs = experiment
            .observed
            .iter()
            .filter_map(|observed| {
                let (integral, text) = match observed.output.trim().strip_prefix("integral:") {
                    Some(rest) => (true, rest.trim()),
                    None => (false, observed.output.as_str()),
                };
                if integral && experiment.time().is_none() {
                    // A steady state's time integral grows without end, unless what is
                    // integrated settles at zero, and then it depends on the whole way there.
                    problems.push(experiment.error(
                        DiagnosticKind::BadOutput,
                        "observed",
                        &observed.output,
                        format!(
                            "experiment: column `{}` observes '{}', a time integral, which a \
                             steady row does not settle to (it grows while '{text}' is not zero); \
                             observe it in a time series (kind: TimeSeries), where it is the \
                             integral from the start of each run",
                            observed.column, observed.output
                        ),
                    ));
                    return None;
                }
                match OutputSpec::parse(&model, text) {
                    Ok(spec) => Some((spec, integral)),
                    Err(d) => {
                        problems.push(experiment.error(
                            DiagnosticKind::BadOutput,
                            "observed",
                            &observed.output,
                            format!(
                                "experiment: column `{}`: {}",
                                observed.column,
                                d.first().message
                            ),
                        ));
                        None
                    }
                }
            })
            .collect();
        // Keep the assignments to elements this variant has.
        let written = experiment.initial_mode.clone().unwrap_or_default();
        let spec: Vec<&str> = written
            .split(',')
            .filter(|part| {
                part.split_once('=')
                    .is_some_and(|(name, _)| model.element_named(name.trim()).is_some())
                    || (empty.is_empty() && !part.trim().is_empty())
            })
            .collect();
        let initial = match Mode::parse(&model, &spec.join(",")) {
            Ok(mode) => Some(mode),
            Err(d) => {
                problems.push(experiment.error(
                    DiagnosticKind::BadMode,
                    "initial_mode",
                    &written,
                    format!("experiment: initial_mode: {}", d.first().message),
                ));
                None
            }
        };
        if !problems.is_empty() {
            return Err(Diagnostics(problems).into());
        }
        Ok(Self {
            model,
            inputs,
            outputs,
            initial: initial.expect("no problems"),
            forms: Arc::default(),
        })
    }
}
