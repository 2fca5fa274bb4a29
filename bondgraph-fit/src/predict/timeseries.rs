//! Time series: each data file is one run of the experiment's scenario, compared with the
//! model at the file's sample times.
//!
//! An experiment of kind `TimeSeries(scenario, time)` names a scenario file (relative to the
//! experiment file) that says how a run starts and gives a signal to every input the data
//! does not measure. Every condition column is a measured input signal, piecewise linear
//! through the file's samples (what a data logger's record means between samples). The
//! model is simulated once per file through every sample time in order, with exact events,
//! and the observed outputs are read at those times: a calibration's residuals run along
//! time.
//!
//! The scenario's `duration`, `record` and `sample` are not used (the data's times decide),
//! and its `remove` and `parameters` edits are refused: a fitted run takes the model as the
//! model file and the experiment's `absent` entries make it, so that the fitted values mean
//! what the model file says.

use std::path::Path;
use std::sync::Arc;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_core::scenario::{Signal as ScenarioSignal, TableCursor};
use bondgraph_core::source::SourceFile;
use bondgraph_ron::read::read_text;
use bondgraph_solver::hybrid::Stepper;
use bondgraph_solver::{Signal, Simulator};

use super::prediction::{Prediction, describe};
use crate::data::Measurement;
use crate::experiment::{Experiment, ExperimentError, Kind};

/// What a time series' scenario gives every run.
#[derive(Debug)]
pub(crate) struct Drive {
    /// The scenario's signal of each model input, by input name.
    signals: Vec<(String, ScenarioSignal)>,
    /// The energy variable at time 0 of each storage element the scenario gives, by name.
    initial_state: Vec<(String, f64)>,
    /// The scenario's initial mode, as a mode spec.
    initial_mode: String,
}

impl Drive {
    /// The drive of a time-series experiment (`None` for a steady one), its scenario read
    /// against the model file `model`.
    ///
    /// # Errors
    /// The scenario file cannot be read or does not load against the model (its own
    /// diagnostics), or it edits the model; located at the experiment's `kind`.
    pub(crate) fn load(
        experiment: &Experiment,
        model: &Arc<SourceFile>,
    ) -> Result<Option<Self>, ExperimentError> {
        let Kind::TimeSeries { scenario, .. } = &experiment.kind else {
            return Ok(None);
        };
        let at_kind = |message: String| -> ExperimentError {
            experiment
                .error(DiagnosticKind::Io, "kind", scenario, message)
                .into()
        };
        let folder = Path::new(experiment.source().name())
            .parent()
            .unwrap_or(Path::new(""));
        let path = folder.join(scenario);
        let text = read_text(&path, "scenario file")
            .map_err(|e| at_kind(format!("experiment: the time series' scenario: {e}")))?;
        let file = SourceFile::new(path.display().to_string(), text);
        let measured: Vec<&str> = experiment
            .conditions
            .iter()
            .map(|c| c.input.as_str())
            .collect();
        let loaded = bondgraph_ron::scenario::load_measured(&file, model, &measured)?;
        let base = bondgraph_ron::model::load_source(model)?;
        let edited = loaded.model.values() != base.values()
            || loaded.model.element_ids().count() != base.element_ids().count();
        if edited {
            return Err(at_kind(format!(
                "experiment: scenario '{}' edits the model (`remove` or `parameters`); a fitted time series takes the model as its file gives it (set values in the model file, remove elements with the experiment's `absent`)",
                path.display()
            )));
        }
        Ok(Some(Self {
            signals: loaded
                .model
                .inputs()
                .iter()
                .zip(&loaded.inputs)
                .map(|(input, signal)| (input.name.clone(), signal.clone()))
                .collect(),
            initial_state: loaded
                .initial_state
                .iter()
                .map(|(id, value)| (loaded.model.element(*id).name.clone(), *value))
                .collect(),
            initial_mode: loaded.initial_mode.spec(&loaded.model),
        }))
    }
}

/// One run of a model variant, as the evaluator holds it.
pub(crate) struct RunSetup<'a> {
    pub model: &'a Model,
    /// For each condition, the model input it drives (`None`: its column is empty here).
    pub inputs: &'a [Option<usize>],
    /// The mode the experiment starts in (its `initial_mode`, or the model's).
    pub initial: &'a Mode,
}

/// Predicts the rows of one run (one data file, rows in file order) by simulating it
/// through their sample times.
pub(crate) fn predict_run(
    drive: &Drive,
    experiment: &Experiment,
    simulator: &mut Simulator<'_>,
    setup: &RunSetup<'_>,
    run: &[Measurement],
) -> Vec<Result<Prediction, ExperimentError>> {
    let located = |row: &Measurement, reason: String| ExperimentError::Row {
        file: row.file.to_string(),
        row: row.row,
        cells: describe(experiment, row),
        reason,
    };
    let factor = experiment.time().map_or(1.0, |(_, f)| f);
    let column = experiment.time().map_or("", |(c, _)| c);
    let times: Vec<f64> = run
        .iter()
        .map(|row| row.time.unwrap_or(f64::NAN) * factor)
        .collect();
    // Sample times must start at or after 0 and increase strictly: a measured signal is
    // piecewise linear through them, and the run passes through them in order.
    for (k, row) in run.iter().enumerate() {
        let bad = if times[k].is_nan() || times[k] < 0.0 {
            Some(format!("time `{column}` must be 0 or later"))
        } else if k > 0 && times[k] <= times[k - 1] {
            Some(format!(
                "time `{column}` must increase from row to row (the row before is at {} s)",
                times[k - 1]
            ))
        } else {
            None
        };
        if let Some(reason) = bad {
            let error = located(row, reason);
            return run.iter().map(|_| Err(error.clone())).collect();
        }
    }
    let model = setup.model;
    let mut signals: Vec<ScenarioSignal> = model
        .inputs()
        .iter()
        .map(|input| {
            drive
                .signals
                .iter()
                .find(|(name, _)| *name == input.name)
                .map_or(ScenarioSignal::Constant(0.0), |(_, s)| s.clone())
        })
        .collect();
    for (k, condition) in experiment.conditions.iter().enumerate() {
        if let Some(input) = setup.inputs[k] {
            let points = run
                .iter()
                .zip(&times)
                .filter_map(|(row, &t)| row.conditions[k].map(|cell| (t, condition.factor * cell)))
                .collect();
            signals[input] = ScenarioSignal::Table(points);
        }
    }
    let initial = if experiment.initial_mode.is_some() {
        setup.initial.clone()
    } else {
        // The scenario's start, keeping the assignments to elements this variant has.
        let spec: Vec<&str> = drive
            .initial_mode
            .split(',')
            .filter(|part| {
                part.split_once('=')
                    .is_some_and(|(name, _)| model.element_named(name.trim()).is_some())
            })
            .collect();
        Mode::parse(model, &spec.join(",")).unwrap_or_else(|_| setup.initial.clone())
    };
    let mut state = vec![0.0; simulator.storage().len()];
    for (name, value) in &drive.initial_state {
        if let Some(i) = model
            .element_named(name)
            .and_then(|id| simulator.storage().index(id))
        {
            state[i] = *value;
        }
    }
    let readers: Vec<Reader<'_>> = signals.iter().map(Reader::of).collect();
    let inputs: Vec<&dyn Signal> = readers.iter().map(|s| s as &dyn Signal).collect();
    let mut predictions = Vec::with_capacity(run.len());
    let mut stepper = match Stepper::new(simulator, &inputs, initial, state, None) {
        Ok(stepper) => stepper,
        Err(e) => {
            let error = located(&run[0], e.to_string());
            return run.iter().map(|_| Err(error.clone())).collect();
        }
    };
    for (row, &t) in run.iter().zip(&times) {
        while stepper.time() < t {
            if let Err(e) = stepper.advance(t) {
                let error = located(row, e.to_string());
                predictions.extend((predictions.len()..run.len()).map(|_| Err(error.clone())));
                return predictions;
            }
        }
        let observed: Vec<f64> = stepper
            .outputs()
            .iter()
            .zip(&experiment.observed)
            .map(|(y, o)| y / o.factor)
            .collect();
        predictions.push(match observed.iter().position(|v| !v.is_finite()) {
            Some(k) => Err(located(
                row,
                format!(
                    "the predicted `{}` is not a finite number",
                    experiment.observed[k].column
                ),
            )),
            None => Ok(Prediction {
                observed,
                mode: stepper.mode().spec.clone(),
            }),
        });
    }
    predictions
}

/// A run's input signal as the simulation reads it: a measured table through a cursor that
/// starts its search where the last read ended (the run reads every input at every sample,
/// in order), any other signal as it is.
enum Reader<'a> {
    Table(TableCursor<'a>),
    Other(&'a ScenarioSignal),
}

impl<'a> Reader<'a> {
    fn of(signal: &'a ScenarioSignal) -> Self {
        match signal {
            ScenarioSignal::Table(points) => Reader::Table(TableCursor::new(points)),
            other => Reader::Other(other),
        }
    }
}

impl Signal for Reader<'_> {
    fn value(&self, t: f64) -> f64 {
        match self {
            Reader::Table(cursor) => cursor.value(t),
            Reader::Other(signal) => signal.value(t),
        }
    }
    fn rate(&self, t: f64) -> f64 {
        match self {
            Reader::Table(cursor) => cursor.rate(t),
            Reader::Other(signal) => signal.rate(t),
        }
    }
    fn breakpoints(&self) -> Vec<f64> {
        match self {
            Reader::Table(cursor) => cursor.breakpoints(),
            Reader::Other(signal) => signal.breakpoints(),
        }
    }
}
