//! How a row of measured data becomes a simulation: the experimental protocol, as data.
//!
//! A measurement says "at this pressure, channel speed and catheter speed, the tip settled at
//! this velocity". To predict it, a model must know which of its inputs those conditions set,
//! in which units, which output is the tip velocity, what "no catheter in the lumen" means for
//! its structure, and where each run starts. That knowledge belongs to the model, not to the
//! program, so it lives in a small RON file next to the model (for the flagship,
//! `models/eversion/experiment.ron`):
//!
//! ```ron
//! Experiment(
//!     pressure: "P_s",                 // the model input set by P_s_kPa (in Pa)
//!     channel_velocity: "v_ac",        // set by v_ac_mm_s (in m/s)
//!     catheter_velocity: "v_ct_des",   // set by v_ct_mm_s (in m/s)
//!     tip_velocity: "flow:pressure",   // the output compared with v_ge_mm_s
//!     without_catheter: ["rubbing", "fr_ct", "catheter", "ct", "servo_force", "servo", "servo_command"],
//!     initial_mode: "fr_ge=stuck,k=taut,fr_ct=stuck",
//! )
//! ```
//!
//! Each row is predicted as the steady state reached from rest (every storage element empty)
//! in `initial_mode`, with the row's conditions held constant: the experiments set the
//! pressure, then moved the channel at constant speed and filmed the tip once steady.

use std::sync::Arc;

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::linear::Var;
use bondgraph_core::model::edit::{self, Edit};
use bondgraph_core::model::{self, ElementKind, Model};
use bondgraph_core::modes::Mode;
use bondgraph_core::source::SourceFile;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Simulator};
use serde::Deserialize;

use crate::data::Measurement;

/// The experimental protocol of a model.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Experiment", deny_unknown_fields)]
pub struct Experiment {
    /// The model input set by the supply pressure.
    pub pressure: String,
    /// The model input set by the active-channel velocity.
    pub channel_velocity: String,
    /// The model input set by the catheter velocity.
    pub catheter_velocity: String,
    /// The output compared with the measured tip velocity (`flow:pressure`).
    pub tip_velocity: String,
    /// The elements removed when a row has no catheter.
    pub without_catheter: Vec<String>,
    /// The mode every run starts in; assignments to removed elements are dropped.
    pub initial_mode: String,
    /// The parameters a calibration refits on any data (the ones the model's authors
    /// estimated from measurements rather than measured directly).
    #[serde(default)]
    pub fitted: Vec<String>,
    /// The parameters refitted in addition when the data has catheter rows.
    #[serde(default)]
    pub fitted_with_catheter: Vec<String>,
    /// Operating regimes, named physically, each by the switching elements' modes that
    /// define it (`("static", "fr_ge=stuck")`): the first whose every assignment holds in
    /// the mode a row settles in names the row's regime.
    #[serde(default)]
    pub regimes: Vec<(String, String)>,
}

impl Experiment {
    /// The physical name of the regime a row that settled in `mode` is in, or the mode
    /// itself when no regime matches.
    pub fn regime(&self, mode: &str) -> String {
        let assignments: Vec<&str> = mode.split(',').map(str::trim).collect();
        self.regimes
            .iter()
            .find(|(_, pattern)| {
                pattern
                    .split(',')
                    .map(str::trim)
                    .all(|part| assignments.contains(&part))
            })
            .map_or_else(|| mode.to_string(), |(name, _)| name.clone())
    }
}

/// Why a prediction failed.
#[derive(Clone, Debug)]
pub struct ExperimentError(pub String);

impl std::fmt::Display for ExperimentError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ExperimentError {}

impl Experiment {
    /// Reads an experiment description from RON text, naming `name` in errors.
    ///
    /// # Errors
    /// Syntax errors and unknown or missing fields, with the line and column.
    pub fn parse(name: &str, text: &str) -> Result<Self, ExperimentError> {
        ron::Options::default().from_str(text).map_err(|e| {
            ExperimentError(format!(
                "{name}:{}:{}: {}",
                e.span.start.line, e.span.start.col, e.code
            ))
        })
    }
}

/// One model variant ready to predict rows: the model and its simulator's setup.
struct Variant {
    model: Model,
    pressure: usize,
    channel: usize,
    catheter: Option<usize>,
    output: OutputSpec,
    initial: Mode,
}

/// A model prepared to predict measurements: the model as is for rows with a catheter, and
/// without the catheter's elements for rows without one.
///
/// A `Predictor` owns the models; [`Predictor::evaluator`] makes an [`Evaluator`], which keeps
/// the simulators (and so every mode derived symbolically) between predictions and takes new
/// parameter values without deriving anything again: what a calibration needs.
pub struct Predictor {
    with_catheter: Variant,
    without_catheter: Option<Variant>,
    settings: SteadySettings,
}

/// The prediction of one row.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    /// The steady tip velocity, mm/s.
    pub tip_velocity_mm_s: f64,
    /// The mode the model settles in (`fr_ge=slip+,k=slack`).
    pub mode: String,
}

impl Predictor {
    /// Prepares `model` (read from `source`) for `experiment`: the model as is for rows with a
    /// catheter, and without the catheter's elements for rows without one.
    ///
    /// # Errors
    /// When the experiment names inputs, outputs or elements the model does not have, or the
    /// model without its catheter is not valid.
    pub fn new(
        model: Model,
        source: &Arc<SourceFile>,
        experiment: &Experiment,
    ) -> Result<Self, ExperimentError> {
        let without = if experiment.without_catheter.is_empty() {
            None
        } else {
            let edit = Edit {
                remove: experiment.without_catheter.clone(),
                parameters: Vec::new(),
            };
            let edited = edit::apply(source, &edit).map_err(|d| ExperimentError(d.to_string()))?;
            let reduced =
                model::load_source(&edited).map_err(|d| ExperimentError(d.to_string()))?;
            Some(Variant::new(
                with_values(reduced, &model),
                experiment,
                false,
            )?)
        };
        Ok(Self {
            with_catheter: Variant::new(model, experiment, true)?,
            without_catheter: without,
            settings: SteadySettings::default(),
        })
    }

    /// The model used for rows with a catheter.
    pub fn model(&self) -> &Model {
        &self.with_catheter.model
    }

    /// Sets parameter values (by name) in every variant; the structure and so the symbolic
    /// equations do not change. (An [`Evaluator`] does the same without touching the models.)
    ///
    /// # Errors
    /// When a name is not a parameter of the model.
    pub fn set_parameters(&mut self, values: &[(String, f64)]) -> Result<(), ExperimentError> {
        for variant in
            std::iter::once(&mut self.with_catheter).chain(self.without_catheter.as_mut())
        {
            for (name, value) in values {
                let index = variant.parameter_index(name)?;
                variant.model.values[index] = *value;
                if let Some(parameter) = variant
                    .model
                    .parameters
                    .iter_mut()
                    .find(|p| &p.name == name)
                {
                    parameter.value = *value;
                }
            }
        }
        Ok(())
    }

    /// The predicted steady tip velocity of each row, in mm/s.
    ///
    /// # Errors
    /// When a simulation fails or does not settle.
    pub fn predict(&self, rows: &[Measurement]) -> Result<Vec<f64>, ExperimentError> {
        Ok(self
            .evaluator(&[])?
            .predict(rows)?
            .into_iter()
            .map(|p| p.tip_velocity_mm_s)
            .collect())
    }

    /// An evaluator whose [`Evaluator::set`] takes values of the parameters `names`, in order.
    ///
    /// # Errors
    /// When a name is not a parameter of the model.
    pub fn evaluator(&self, names: &[String]) -> Result<Evaluator<'_>, ExperimentError> {
        let slots = |variant: &Variant| {
            names
                .iter()
                .map(|name| variant.parameter_index(name))
                .collect::<Result<Vec<_>, _>>()
        };
        let with = Session::new(&self.with_catheter, slots(&self.with_catheter)?);
        let without = match &self.without_catheter {
            Some(variant) => Some(Session::new(variant, slots(variant)?)),
            None => None,
        };
        Ok(Evaluator {
            sessions: [Some(with), without],
            settings: self.settings,
        })
    }
}

/// Predicts rows with changing parameter values, keeping every mode derived so far.
pub struct Evaluator<'p> {
    /// With the catheter, and without it.
    sessions: [Option<Session<'p>>; 2],
    settings: SteadySettings,
}

/// One variant's simulator and where the evaluator's parameters sit in its values.
struct Session<'p> {
    variant: &'p Variant,
    simulator: Simulator<'p>,
    slots: Vec<usize>,
    values: Vec<f64>,
}

impl<'p> Session<'p> {
    fn new(variant: &'p Variant, slots: Vec<usize>) -> Self {
        let outputs = vec![Output {
            name: "tip".into(),
            spec: variant.output.clone(),
            integral: false,
        }];
        Self {
            variant,
            simulator: Simulator::new(&variant.model, outputs),
            slots,
            values: variant.model.values.clone(),
        }
    }
}

impl Evaluator<'_> {
    /// Sets the values of the evaluator's parameters (in the order they were named).
    ///
    /// # Panics
    /// When `values` does not have one value per parameter named.
    pub fn set(&mut self, values: &[f64]) {
        for session in self.sessions.iter_mut().flatten() {
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

    /// The predicted steady state of each row, or why that row has none (a simulation that
    /// does not settle, as in a stick-slip cycle), row by row.
    pub fn predict_each(
        &mut self,
        rows: &[Measurement],
    ) -> Vec<Result<Prediction, ExperimentError>> {
        let mut predictions: Vec<Option<Result<Prediction, ExperimentError>>> =
            (0..rows.len()).map(|_| None).collect();
        for (k, with) in [(0, true), (1, false)] {
            let indices: Vec<usize> = (0..rows.len())
                .filter(|&i| rows[i].catheter_velocity_mm_s.is_some() == with)
                .collect();
            let Some(session) = self.sessions[k].as_mut() else {
                for i in indices {
                    predictions[i] = Some(Err(ExperimentError(
                        "rows without a catheter, but the experiment names no catheter elements to remove".into(),
                    )));
                }
                continue;
            };
            let variant = session.variant;
            let storage = session.simulator.storage().len();
            for i in indices {
                let row = &rows[i];
                let mut inputs = vec![0.0; variant.model.inputs.len()];
                inputs[variant.pressure] = row.pressure_kpa * 1e3;
                inputs[variant.channel] = row.channel_velocity_mm_s * 1e-3;
                if let (Some(k), Some(v)) = (variant.catheter, row.catheter_velocity_mm_s) {
                    inputs[k] = v * 1e-3;
                }
                let located = |e: String| {
                    ExperimentError(format!("row {} ({}): {e}", row.row, describe(row)))
                };
                let prediction = check_friction_levels(&variant.model, &session.values, &inputs)
                    .map_err(located)
                    .and_then(|()| {
                        steady_state(
                            &mut session.simulator,
                            &inputs,
                            variant.initial.clone(),
                            vec![0.0; storage],
                            &self.settings,
                        )
                        .map_err(|e| located(e.to_string()))
                    })
                    .map(|steady| Prediction {
                        tip_velocity_mm_s: steady.outputs[0] * 1e3,
                        mode: steady.mode,
                    });
                predictions[i] = Some(prediction);
            }
        }
        predictions
            .into_iter()
            .map(|p| p.expect("every row predicted"))
            .collect()
    }

    /// Gives up on rows that have not settled after `seconds` of simulated time (a
    /// calibration tries values where the model oscillates forever).
    pub fn set_max_time(&mut self, seconds: f64) {
        self.settings.max_time = seconds;
    }
}

/// A friction contact must break away at or above its Coulomb force, and neither may be
/// negative: parameter values a calibration tries can violate this where the model file's
/// values did not, and the contact then has no consistent mode.
fn check_friction_levels(model: &Model, values: &[f64], inputs: &[f64]) -> Result<(), String> {
    let level = |form: &bondgraph_core::linear::LinearForm| -> f64 {
        form.terms()
            .iter()
            .map(|(var, coefficient)| {
                let c = coefficient.eval(values);
                match var {
                    Var::Constant => c,
                    Var::Input(i) => c * inputs[*i as usize],
                    _ => 0.0,
                }
            })
            .sum()
    };
    for id in model.element_ids() {
        let element = model.element(id);
        if let ElementKind::Friction(friction) = &element.kind {
            let (f_s, f_c) = (
                level(&friction.breakaway.value),
                level(&friction.coulomb.value),
            );
            if f_c < 0.0 || f_s < f_c {
                return Err(format!(
                    "friction contact '{}': breakaway {f_s} N and Coulomb {f_c} N, but F_S >= F_C >= 0",
                    element.name
                ));
            }
        }
    }
    Ok(())
}

/// `reduced` with the parameter values of `original` (the edit keeps the file's values; a
/// calibrated model may have others).
fn with_values(mut reduced: Model, original: &Model) -> Model {
    for parameter in &mut reduced.parameters {
        if let Some(source) = original
            .parameters
            .iter()
            .find(|p| p.name == parameter.name)
        {
            parameter.value = source.value;
            reduced.values[parameter.symbol.index()] = source.value;
        }
    }
    reduced
}

fn describe(row: &Measurement) -> String {
    match row.catheter_velocity_mm_s {
        Some(v) => format!(
            "P_s = {} kPa, v_ac = {} mm/s, v_ct = {v} mm/s",
            row.pressure_kpa, row.channel_velocity_mm_s
        ),
        None => format!(
            "P_s = {} kPa, v_ac = {} mm/s, no catheter",
            row.pressure_kpa, row.channel_velocity_mm_s
        ),
    }
}

impl Variant {
    /// Where the parameter `name` sits in the model's values.
    fn parameter_index(&self, name: &str) -> Result<usize, ExperimentError> {
        self.model
            .parameters
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.symbol.index())
            .ok_or_else(|| {
                ExperimentError(format!(
                    "'{name}' is not a parameter of model '{}'",
                    self.model.name
                ))
            })
    }

    fn new(
        model: Model,
        experiment: &Experiment,
        with_catheter: bool,
    ) -> Result<Self, ExperimentError> {
        let input = |name: &str| {
            model.input_named(name).map(|i| i.index()).ok_or_else(|| {
                ExperimentError(format!(
                    "the experiment's input '{name}' is not an input of model '{}'",
                    model.name
                ))
            })
        };
        let pressure = input(&experiment.pressure)?;
        let channel = input(&experiment.channel_velocity)?;
        let catheter = if with_catheter {
            Some(input(&experiment.catheter_velocity)?)
        } else {
            None
        };
        let output = OutputSpec::parse(&model, &experiment.tip_velocity)
            .map_err(|d| ExperimentError(d.to_string()))?;
        // Keep the assignments to elements this variant has.
        let spec: Vec<&str> = experiment
            .initial_mode
            .split(',')
            .filter(|part| {
                part.split_once('=')
                    .is_some_and(|(name, _)| model.element_named(name.trim()).is_some())
            })
            .collect();
        let initial =
            Mode::parse(&model, &spec.join(",")).map_err(|d| ExperimentError(d.to_string()))?;
        Ok(Self {
            model,
            pressure,
            channel,
            catheter,
            output,
            initial,
        })
    }
}
