//! `bondgraph analyze`: eigenvalues and time scales, the transfer function of one input and
//! one output, its poles, zeros and DC gain, the exact step response's metrics, and Bode and
//! step plots, of one linear mode (or a nonlinear mode's linearisation).
//!
//! The symbolic work is `bondgraph_core::analysis`, the numbers
//! `bondgraph_solver::analysis`; this module picks the channel, formats and plots.

use std::path::PathBuf;
use std::sync::Arc;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::analysis::{Analysis, Channel, TransferFunction};
use bondgraph_core::equations::nonlinear::OperatingPoint;
use bondgraph_core::equations::{self, StateEquations};
use bondgraph_core::linear::{LinearForm, Var};
use bondgraph_core::model::Model;
use bondgraph_core::modes;
use bondgraph_core::number;
use bondgraph_core::scenario::Record;
use bondgraph_core::source::SourceFile;
use bondgraph_core::symbolic::RatFunc;
use bondgraph_core::symbolic::Scaled;
use bondgraph_solver::analysis::{
    self as numbers, AnalysisError, Complex64, Scale, StepMetrics, StepSystem,
};
use serde_json::{Value, json};

use crate::{Failure, json as to_json, load, parse_mode, print, with_source, write_file};

/// What to analyse: the mode, the channel and, for a nonlinear model, the operating point.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// The mode (`fr=stuck,string=taut`); the initial mode if `None`.
    pub mode: Option<String>,
    /// The input of the transfer function; the first input if `None`.
    pub input: Option<String>,
    /// The output (a state name, `flow:ELEMENT`, ...); the first state if `None`.
    pub output: Option<String>,
    /// A nonlinear model's operating point, `NAME=VALUE,...`.
    pub at: Option<String>,
    /// Search the equilibrium (from `at`, or from all zeros) and linearise there.
    pub equilibrium: bool,
}

/// What `bondgraph analyze` was asked.
pub struct Args {
    /// The model file.
    pub model: PathBuf,
    /// The mode, channel and operating point.
    pub request: Request,
    /// JSON rather than text.
    pub json: bool,
    /// Where to write the Bode plot (SVG), if anywhere.
    pub bode: Option<PathBuf>,
    /// Where to write the step-response plot (SVG), if anywhere.
    pub step: Option<PathBuf>,
}

/// One mode analysed: its eigenvalues and, when it has a channel, the transfer function and
/// step response. [`Analyzed::json`] is the command's JSON document, [`Analyzed::text`] its text.
pub struct Analyzed {
    prepared: Prepared,
    analysis: Analysis,
    eigenvalues: Vec<Complex64>,
    transfer: Option<Transfer>,
    notes: Vec<String>,
}

/// The mode's equations, linearised if need be, and what was done to get them.
struct Prepared {
    equations: StateEquations,
    mode: String,
    /// The operating point of a linearisation, as text.
    linearised_at: Option<String>,
    notes: Vec<String>,
}

/// `bondgraph analyze`: the analysis printed, its plots written.
pub fn run(args: &Args) -> Result<(), Failure> {
    let (model, source) = load(&args.model)?;
    let analyzed = analyze(&model, &source, &args.request)?;
    if let Some(path) = &args.bode {
        write_file(path, &analyzed.bode_svg()?)?;
    }
    if let Some(path) = &args.step {
        write_file(path, &analyzed.step_svg()?)?;
    }
    let text = if args.json {
        to_json(&analyzed.json())?
    } else {
        analyzed.text()
    };
    print(&text);
    Ok(())
}

/// The mode's equations as analysed: a linear mode's own, or a nonlinear mode's
/// linearisation at the operating point given (or at the equilibrium found from it, or from
/// zero), with notes on how the point was reached.
fn prepare(
    model: &Model,
    source: &Arc<SourceFile>,
    args: &Request,
    mode: &bondgraph_core::mode::Mode,
) -> Result<Prepared, Failure> {
    let options = equations::Options {
        variables: equations::Variables::preferred(model),
    };
    let mut notes = Vec::new();
    Ok(if model.is_nonlinear() {
        let derived =
            modes::derive_nonlinear(model, mode, &options).map_err(|d| with_source(d, source))?;
        let eq = &derived.equations;
        let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
        let given = match &args.at {
            Some(text) => Some(
                OperatingPoint::parse(&names, &eq.inputs, text)
                    .map_err(|d| with_source(d, source))?,
            ),
            None => None,
        };
        let point = match given {
            Some(point) if !args.equilibrium => point,
            given => {
                let start = given
                    .clone()
                    .unwrap_or_else(|| OperatingPoint::zero(names.len(), eq.inputs.len()));
                if given.is_none() {
                    notes.push(
                    "nonlinear model without --at: linearised at the equilibrium found from all states and inputs 0"
                        .to_string(),
                );
                }
                let found = bondgraph_solver::equilibrium::find(eq, &start).map_err(|e| {
                Failure::message(
                    DiagnosticKind::Simulation,
                    format!(
                        "{e}; give an operating point with --at NAME=VALUE,... (and --equilibrium to start the search there)"
                    ),
                )
            })?;
                notes.push(format!(
                    "equilibrium: f = 0 to {:e} after {} Newton iterations",
                    found.residual, found.iterations
                ));
                found.point
            }
        };
        Prepared {
            linearised_at: Some(eq.point_text(&point)),
            equations: eq.linearise(&point),
            mode: mode.spec(model),
            notes,
        }
    } else {
        if args.equilibrium {
            return Err(Failure::message(
                DiagnosticKind::NotLinear,
                "--equilibrium is for nonlinear models; a linear mode's matrices do not depend on the operating point",
            ));
        }
        let derived = modes::derive(model, mode, &options).map_err(|d| with_source(d, source))?;
        if let Some(at) = &args.at {
            let names: Vec<String> = derived
                .equations
                .states
                .iter()
                .map(|s| s.name.clone())
                .collect();
            OperatingPoint::parse(&names, &derived.equations.inputs, at)
                .map_err(|d| with_source(d, source))?;
            notes.push("a linear mode's matrices do not depend on --at".to_string());
        }
        Prepared {
            equations: derived.equations,
            mode: mode.spec(model),
            linearised_at: None,
            notes,
        }
    })
}

/// Analyses one mode of `model` (read from `source`, which its diagnostics point into).
pub fn analyze(
    model: &Model,
    source: &Arc<SourceFile>,
    args: &Request,
) -> Result<Analyzed, Failure> {
    let mode = parse_mode(model, args.mode.as_deref(), source)?;
    let prepared = prepare(model, source, args, &mode)?;
    let eq = &prepared.equations;

    // The channel: which input, which output.
    let mut notes = prepared.notes.clone();
    let input =
        match &args.input {
            Some(name) => Some(eq.inputs.iter().position(|i| i == name.trim()).ok_or_else(
                || {
                    Failure::message(
                        DiagnosticKind::UnknownName,
                        format!(
                            "--input '{name}' is not an input of '{}'; its inputs: {}",
                            eq.model,
                            list_or_none(&eq.inputs)
                        ),
                    )
                },
            )?),
            None if eq.inputs.is_empty() => {
                notes.push("the model has no inputs: no transfer function".to_string());
                None
            }
            None => {
                if eq.inputs.len() > 1 {
                    notes.push(format!(
                        "no --input: the first input, {} (the others: {})",
                        eq.inputs[0],
                        eq.inputs[1..].join(", ")
                    ));
                }
                Some(0)
            }
        };
    let output: Option<(String, LinearForm, bool)> = match &args.output {
        Some(spec) => Some(match eq.state_named(spec.trim()) {
            Some(k) => (
                spec.trim().to_string(),
                LinearForm::var(Var::State(k as u32)),
                false,
            ),
            None => {
                let (record, spec) =
                    Record::parse_output(model, spec).map_err(|d| with_source(d, source))?;
                let row = eq.output(&spec).row;
                (record.name(), row, matches!(record, Record::Integral(_)))
            }
        }),
        None if eq.state_count() == 0 => {
            if input.is_some() {
                notes.push(
                    "no states and no --output: give --output (effort:ELEMENT, flow:ELEMENT, ...) for a transfer function"
                        .to_string(),
                );
            }
            None
        }
        None => {
            let name = eq.states[0].name.clone();
            if input.is_some() {
                notes.push(format!("no --output: the first state, {name}"));
            }
            Some((name, LinearForm::var(Var::State(0)), false))
        }
    };

    let analysis = Analysis::new(eq);
    let a = dense(&eq.a(), eq);
    refuse_non_finite(&prepared, &a, |i, j| {
        format!(
            "A[{i}][{j}], the coefficient of {} in d{}/dt,",
            eq.states[j].name, eq.states[i].name
        )
    })?;
    let eigenvalues = numbers::polished(
        &numbers::eigenvalues_of(&a).map_err(numbers_failure)?,
        &analysis.characteristic_scaled(),
    );
    let channel = match (input, &output) {
        (Some(i), Some((name, row, integral))) => Some((
            eq.inputs[i].clone(),
            name.clone(),
            Channel::new(eq, i, row, *integral),
        )),
        _ => None,
    };
    let transfer = match channel.as_ref() {
        Some((input, output, channel)) => {
            let tf = analysis.transfer(channel);
            let mut transfer = Transfer::new(
                &prepared,
                &analysis,
                &eigenvalues,
                input,
                output,
                channel,
                tf,
            )?;
            transfer.units = ChannelUnits::of(model, eq, input, output);
            if let Err(error) = &transfer.metrics {
                notes.push(format!(
                    "no step response: its closed form is not finite in double precision ({error})"
                ));
            }
            Some(transfer)
        }
        None => None,
    };
    let analysis_eigen = eigenvalues;
    Ok(Analyzed {
        prepared,
        analysis,
        eigenvalues: analysis_eigen,
        transfer,
        notes,
    })
}

impl Analyzed {
    fn report(&self) -> Report<'_> {
        Report {
            prepared: &self.prepared,
            analysis: &self.analysis,
            eigenvalues: &self.eigenvalues,
            transfer: self.transfer.as_ref(),
            notes: &self.notes,
        }
    }

    /// The command's JSON document (DESIGN.md's `analyze` fields and more).
    pub fn json(&self) -> Value {
        self.report().to_json()
    }

    /// The command's text.
    pub fn text(&self) -> String {
        self.report().to_text()
    }

    /// Whether the mode has a transfer function (an input and an output to relate).
    pub fn has_transfer_function(&self) -> bool {
        self.transfer.is_some()
    }

    /// The Bode plot of the transfer function (SVG).
    pub fn bode_svg(&self) -> Result<String, Failure> {
        let Some(t) = &self.transfer else {
            return Err(no_channel("--bode"));
        };
        let mut singular = t.poles.clone();
        singular.extend(&t.zeros);
        let points = numbers::bode_scaled(&t.numerator_scaled, &t.denominator_scaled, &singular);
        let title = format!(
            "{}: {} from {}",
            self.prepared.equations.model, t.output, t.input
        );
        crate::analyze_plot::bode_svg(&points, &title, &t.units.magnitude_label())
            .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot plot: {e}")))
    }

    /// The exact step response of the transfer function's channel (SVG).
    pub fn step_svg(&self) -> Result<String, Failure> {
        let Some(t) = &self.transfer else {
            return Err(no_channel("--step"));
        };
        step_plot(&self.prepared.equations, t)
    }
}

fn no_channel(flag: &str) -> Failure {
    Failure::message(
        DiagnosticKind::BadOutput,
        format!("{flag} needs a transfer function: an input, and states or --output"),
    )
}

fn list_or_none(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// A failure naming the first entry of `rows` that is not finite (`name(i, j)` says what the
/// entry is): a linearisation far from the origin can overflow where the model's own
/// coefficients, checked when it was derived, do not.
fn refuse_non_finite(
    prepared: &Prepared,
    rows: &[Vec<f64>],
    name: impl Fn(usize, usize) -> String,
) -> Result<(), Failure> {
    for (i, row) in rows.iter().enumerate() {
        if let Some(j) = row.iter().position(|x| !x.is_finite()) {
            let at = match &prepared.linearised_at {
                Some(point) => format!("linearised at {point}, "),
                None => String::new(),
            };
            return Err(Failure::message(
                DiagnosticKind::InvalidValue,
                format!(
                    "{at}{} is {}, which is not a finite double: no analysis",
                    name(i, j),
                    number::shortest(row[j])
                ),
            ));
        }
    }
    Ok(())
}

fn numbers_failure(error: numbers::AnalysisError) -> Failure {
    Failure::message(
        DiagnosticKind::Simulation,
        format!("analysis failed: {error}"),
    )
}

fn dense(m: &[Vec<RatFunc>], eq: &StateEquations) -> Vec<Vec<f64>> {
    m.iter()
        .map(|row| row.iter().map(|x| eq.evaluate(x)).collect())
        .collect()
}

/// One transfer function with its numbers.
struct Transfer {
    input: String,
    output: String,
    tf: TransferFunction,
    numerator_text: String,
    denominator_text: String,
    /// Monic coefficients, highest power first.
    numerator: Vec<f64>,
    denominator: Vec<f64>,
    /// The same in extended range, for the frequency response.
    numerator_scaled: Vec<Scaled>,
    denominator_scaled: Vec<Scaled>,
    poles: Vec<Complex64>,
    zeros: Vec<Complex64>,
    dc_gain: Option<f64>,
    dc_gain_text: Option<String>,
    system: StepSystem,
    /// The step response's metrics, or why its closed form could not be evaluated.
    metrics: Result<StepMetrics, AnalysisError>,
    units: ChannelUnits,
}

/// What the plots write on their axes: the output's quantity and unit, the input's unit.
#[derive(Default)]
struct ChannelUnits {
    /// The output's axis label: `effort:capacitor: voltage (V)`, or its name alone where
    /// the model's units do not tell.
    output_label: String,
    /// The output's unit.
    output: Option<String>,
    /// The input's unit, as the model file writes it.
    input: Option<String>,
}

impl ChannelUnits {
    /// The units of the channel from `input` to `output` (a state's name or an output as
    /// `--output` writes it), as `simulate --plot` labels its axes.
    fn of(model: &Model, eq: &StateEquations, input: &str, output: &str) -> Self {
        let record = match eq.state_named(output) {
            Some(k) => state_record(model, &eq.states[k]),
            None => Record::parse_output(model, output).ok().map(|(r, _)| r),
        };
        let quantity = record
            .as_ref()
            .and_then(|r| crate::unit_label::quantity(model, r));
        let output_label = match &quantity {
            Some((word, unit)) if word.is_empty() => format!("{output} ({unit})"),
            Some((word, unit)) => format!("{output}: {word} ({unit})"),
            None => output.to_string(),
        };
        ChannelUnits {
            output_label,
            output: quantity.map(|(_, unit)| unit),
            input: model
                .inputs()
                .iter()
                .find(|i| i.name == input)
                .and_then(|i| i.unit.clone()),
        }
    }

    /// The Bode magnitude's label: `magnitude (dB of (rad/s)/V)`, the decibels of the
    /// output's unit per the input's.
    fn magnitude_label(&self) -> String {
        let grouped = |unit: &str| {
            if unit.contains(['/', '*']) {
                format!("({unit})")
            } else {
                unit.to_string()
            }
        };
        match (&self.output, &self.input) {
            (Some(out), Some(input)) => {
                format!("magnitude (dB of {}/{})", grouped(out), grouped(input))
            }
            _ => "magnitude (dB)".to_string(),
        }
    }
}

/// What a state measures as a recorded output would: a momentum is the time integral of
/// its element's effort, a displacement of its flow; a co-energy state is the flow or the
/// effort itself.
fn state_record(model: &Model, state: &equations::StateVariable) -> Option<Record> {
    use bondgraph_core::equations::{OutputQuantity, OutputSpec, Quantity};
    let element = model.element_named(&state.element)?;
    let bond = *model.element(element).bonds.first()?;
    let spec = |quantity| OutputSpec {
        name: state.name.clone(),
        quantity,
        bond,
        negated: false,
    };
    Some(match state.quantity {
        Quantity::Momentum => Record::Integral(spec(OutputQuantity::Effort)),
        Quantity::Displacement => Record::Integral(spec(OutputQuantity::Flow)),
        Quantity::Velocity => Record::Output(spec(OutputQuantity::Flow)),
        Quantity::Force => Record::Output(spec(OutputQuantity::Effort)),
    })
}

impl Transfer {
    /// The transfer function `tf` of `channel` with its numbers: poles are the eigenvalues
    /// of `A` (and 0 for an integral output) that did not cancel, polished on the
    /// denominator; zeros the numerator's roots.
    fn new(
        prepared: &Prepared,
        analysis: &Analysis,
        eigenvalues: &[Complex64],
        input: &str,
        output: &str,
        channel: &Channel,
        tf: TransferFunction,
    ) -> Result<Self, Failure> {
        let eq = &prepared.equations;
        let symbols = analysis.symbols();
        let (numerator, denominator) = tf.monic_values(&eq.values);
        let (numerator_scaled, denominator_scaled) = tf.monic_scaled(&eq.values);
        let mut modes = eigenvalues.to_vec();
        if channel.integral {
            modes.push(Complex64::new(0.0, 0.0));
        }
        let poles = numbers::poles(
            &modes,
            &tf.cancelled_scaled(&eq.values),
            &denominator_scaled,
        );
        let zeros = numbers::roots_scaled(&numerator_scaled).map_err(numbers_failure)?;
        let (num_last, den_last) = (
            tf.numerator.last().cloned().unwrap_or_default(),
            tf.denominator.last().cloned().unwrap_or_default(),
        );
        let dc = (!den_last.is_zero()).then(|| num_last.checked_div(&den_last).unwrap_or_default());
        let column = |v: &[RatFunc]| -> Vec<f64> { v.iter().map(|x| eq.evaluate(x)).collect() };
        let system = StepSystem {
            a: dense(&eq.a(), eq),
            b: column(&channel.b),
            e: column(&channel.e),
            c: column(&channel.c),
            d: eq.evaluate(&channel.d),
            f: eq.evaluate(&channel.f),
            integral: channel.integral,
        };
        let inputs = [
            ("the input's column of B", &system.b),
            ("the input's column of E", &system.e),
            ("the output's row of C", &system.c),
            ("the output's D and F", &vec![system.d, system.f]),
        ];
        for (what, values) in inputs {
            refuse_non_finite(prepared, std::slice::from_ref(values), |_, j| {
                format!("entry {j} of {what}")
            })?;
        }
        let dc_gain = dc.as_ref().map(|g| g.eval(&eq.values));
        let metrics = numbers::step_metrics(&system, &poles, dc_gain);
        Ok(Transfer {
            input: input.to_string(),
            output: output.to_string(),
            numerator_text: tf.numerator_text(symbols),
            denominator_text: tf.denominator_text(symbols),
            tf,
            numerator,
            denominator,
            numerator_scaled,
            denominator_scaled,
            poles,
            zeros,
            dc_gain,
            dc_gain_text: dc.filter(|_| analysis.symbolic).map(|g| g.text(symbols)),
            system,
            metrics,
            units: ChannelUnits::default(),
        })
    }
}

/// The step plot.
fn step_plot(eq: &StateEquations, t: &Transfer) -> Result<String, Failure> {
    let metrics = t.metrics.as_ref().map_err(|error| {
        Failure::message(
            DiagnosticKind::Simulation,
            format!("--step: the step response's closed form is not finite in double precision ({error})"),
        )
    })?;
    let horizon = metrics.horizon;
    let times: Vec<f64> = (0..=1000).map(|i| horizon * i as f64 / 1000.0).collect();
    let values = t.system.response().at(&times);
    let points: Vec<(f64, f64)> = times.into_iter().zip(values).collect();
    let title = match &t.units.input {
        Some(unit) => format!(
            "{}: response to a step of 1 {unit} in {}",
            eq.model, t.input
        ),
        None => format!("{}: unit step in {}", eq.model, t.input),
    };
    crate::analyze_plot::step_svg(&points, metrics.final_value, &title, &t.units.output_label)
        .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot plot: {e}")))
}

struct Report<'a> {
    prepared: &'a Prepared,
    analysis: &'a Analysis,
    eigenvalues: &'a [Complex64],
    transfer: Option<&'a Transfer>,
    notes: &'a [String],
}

/// A number with six significant digits, without trailing zeros: `0.5`, `1.23457e-7`.
fn g(x: f64) -> String {
    number::significant(x, 6)
}

/// Complex numbers with conjugate pairs joined: `-1 ± 9.94987i`.
fn complex_list(values: &[Complex64]) -> Vec<String> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < values.len() {
        let v = values[i];
        if v.im != 0.0
            && i + 1 < values.len()
            && (values[i + 1] - v.conj()).norm() <= 1e-9 * v.norm()
        {
            out.push(format!("{} ± {}i", g(v.re), g(v.im.abs())));
            i += 2;
        } else {
            out.push(if v.im == 0.0 {
                g(v.re)
            } else {
                format!(
                    "{} {} {}i",
                    g(v.re),
                    if v.im < 0.0 { "-" } else { "+" },
                    g(v.im.abs())
                )
            });
            i += 1;
        }
    }
    out
}

fn complex_json(values: &[Complex64]) -> Value {
    Value::Array(
        values
            .iter()
            .map(|v| json!({"re": v.re, "im": v.im}))
            .collect(),
    )
}

/// A fraction drawn over three lines.
fn fraction(prefix: &str, numerator: &str, denominator: &str) -> String {
    let width = numerator.chars().count().max(denominator.chars().count());
    let pad = |s: &str| {
        let left = (width - s.chars().count()) / 2;
        format!("{}{s}", " ".repeat(left))
    };
    let blank = " ".repeat(prefix.chars().count());
    format!(
        "{blank}{}\n{prefix}{}\n{blank}{}\n",
        pad(numerator).trim_end(),
        "-".repeat(width),
        pad(denominator).trim_end()
    )
}

fn numbers_list(values: &[f64]) -> String {
    format!(
        "[{}]",
        values.iter().map(|v| g(*v)).collect::<Vec<_>>().join(", ")
    )
}

impl Report<'_> {
    fn to_text(&self) -> String {
        let eq = &self.prepared.equations;
        let mut text = String::new();
        let states: Vec<&str> = eq.states.iter().map(|s| s.name.as_str()).collect();
        text.push_str(&format!(
            "model '{}': {} ({}) in {} variables, {} ({})\n",
            eq.model,
            crate::count(states.len(), "state"),
            if states.is_empty() {
                "none".to_string()
            } else {
                states.join(", ")
            },
            match eq.variables {
                equations::Variables::Energy => "energy",
                equations::Variables::CoEnergy => "co-energy",
            },
            crate::count(eq.inputs.len(), "input"),
            list_or_none(&eq.inputs)
        ));
        if !self.prepared.mode.is_empty() {
            text.push_str(&format!("mode {}\n", self.prepared.mode));
        }
        if let Some(point) = &self.prepared.linearised_at {
            text.push_str(&format!(
                "linearised at {point} (deviations from this point)\n"
            ));
        }
        for note in self.notes {
            text.push_str(&format!("note: {note}\n"));
        }
        text.push('\n');
        let values = self.analysis.characteristic_values();
        if self.analysis.symbolic {
            text.push_str(&format!(
                "characteristic polynomial: det(sI - A) = {}\n",
                self.analysis.characteristic_text()
            ));
        }
        text.push_str(&format!(
            "  coefficients (highest power first): {}\n",
            numbers_list(&values)
        ));
        text.push_str("\neigenvalues (1/s):\n");
        if self.eigenvalues.is_empty() {
            text.push_str("  none: no states in this mode\n");
        }
        let labels = complex_list(self.eigenvalues);
        let mut k = 0;
        for label in labels {
            let scale = Scale::of(self.eigenvalues[k]);
            k += if self.eigenvalues[k].im != 0.0 && label.contains('±') {
                2
            } else {
                1
            };
            text.push_str(&format!("  {label:<24} {}\n", scale_text(&scale)));
        }
        let Some(t) = self.transfer else {
            return text;
        };
        text.push_str(&format!(
            "\ntransfer function from {} to {}:\n",
            t.input, t.output
        ));
        if self.analysis.symbolic {
            text.push_str(&fraction(
                "  G(s) = ",
                &t.numerator_text,
                &t.denominator_text,
            ));
        } else {
            text.push_str(&format!(
                "  ({} states: coefficients with the parameter values, not printed symbolically)\n",
                eq.state_count()
            ));
        }
        if t.tf.cancelled > 0 {
            text.push_str(&format!(
                "  ({} cancelled between numerator and denominator: modes this output does not see or this input does not reach)\n",
                crate::count(t.tf.cancelled, "root")
            ));
        }
        text.push_str(&format!(
            "  numerator:   {}\n  denominator: {} (monic)\n",
            numbers_list(&t.numerator),
            numbers_list(&t.denominator)
        ));
        let or_none = |v: Vec<String>| {
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        text.push_str(&format!("  poles: {}\n", or_none(complex_list(&t.poles))));
        text.push_str(&format!("  zeros: {}\n", or_none(complex_list(&t.zeros))));
        match (t.dc_gain, &t.dc_gain_text) {
            (Some(v), Some(s)) if s != &g(v) => {
                text.push_str(&format!("  DC gain G(0) = {s} = {}\n", g(v)));
            }
            (Some(v), _) => text.push_str(&format!("  DC gain G(0) = {}\n", g(v))),
            (None, _) => text.push_str(
                "  DC gain: none (a pole at s = 0: the step response grows without bound)\n",
            ),
        }
        let Ok(m) = &t.metrics else {
            return text;
        };
        text.push_str(&format!(
            "\nstep response (unit step in {} at t = 0, from rest; exact closed form):\n",
            t.input
        ));
        if t.system.f != 0.0 {
            text.push_str(&format!(
                "  an impulse of weight {} in the output at t = 0 (the output's du/dt term)\n",
                g(t.system.f)
            ));
        }
        text.push_str(&format!("  initial value y(0+) = {}\n", g(m.initial_value)));
        match m.final_value {
            None => text
                .push_str("  no final value: the response does not settle (a pole with Re >= 0)\n"),
            Some(y) => {
                text.push_str(&format!("  final value   {}\n", g(y)));
                let opt = |x: Option<f64>, unit: &str| {
                    x.map_or("undefined (final value 0)".to_string(), |v| {
                        format!("{}{unit}", g(v))
                    })
                };
                text.push_str(&format!(
                    "  rise time     {} (10 % to 90 %)\n",
                    opt(m.rise_time, " s")
                ));
                text.push_str(&format!(
                    "  settling time {} (within 2 %)\n",
                    opt(m.settling_time, " s")
                ));
                text.push_str(&format!(
                    "  overshoot     {}\n",
                    opt(m.overshoot_percent, " %")
                ));
                if let (Some(tp), Some(yp)) = (m.peak_time, m.peak_value) {
                    text.push_str(&format!("  peak          {} at {} s\n", g(yp), g(tp)));
                }
            }
        }
        text
    }

    fn to_json(&self) -> Value {
        let eq = &self.prepared.equations;
        let scales: Vec<Value> = self
            .eigenvalues
            .iter()
            .map(|v| {
                let s = Scale::of(*v);
                json!({"re": v.re, "im": v.im, "time_constant": s.time_constant,
                       "natural_frequency": s.natural_frequency, "damping_ratio": s.damping_ratio})
            })
            .collect();
        let transfer = self.transfer.map(|t| {
            json!({
                "input": t.input,
                "output": t.output,
                "numerator": t.numerator,
                "denominator": t.denominator,
                "numerator_text": self.analysis.symbolic.then(|| t.numerator_text.clone()),
                "denominator_text": self.analysis.symbolic.then(|| t.denominator_text.clone()),
                "cancelled": t.tf.cancelled,
            })
        });
        let step = self
            .transfer
            .and_then(|t| t.metrics.as_ref().ok().map(|m| (t, m)));
        let step = step.map(|(t, m)| {
            json!({
                "initial_value": m.initial_value,
                "final_value": m.final_value,
                "rise_time": m.rise_time,
                "settling_time": m.settling_time,
                "overshoot_percent": m.overshoot_percent,
                "peak_time": m.peak_time,
                "peak_value": m.peak_value,
                "impulse_at_zero": t.system.f,
            })
        });
        json!({
            "model": eq.model,
            "mode": self.prepared.mode,
            "variables": eq.variables,
            "states": eq.states.iter().map(|s| s.name.clone()).collect::<Vec<_>>(),
            "inputs": eq.inputs,
            "linearised_at": self.prepared.linearised_at,
            "characteristic_polynomial": {
                "text": self.analysis.symbolic.then(|| self.analysis.characteristic_text()),
                "coefficients": self.analysis.characteristic_values(),
            },
            "eigenvalues": complex_json(self.eigenvalues),
            "eigen_scales": scales,
            "transfer_function": transfer,
            "poles": complex_json(self.transfer.map_or(&[][..], |t| &t.poles)),
            "zeros": complex_json(self.transfer.map_or(&[][..], |t| &t.zeros)),
            "dc_gain": self.transfer.and_then(|t| t.dc_gain),
            "dc_gain_text": self.transfer.and_then(|t| t.dc_gain_text.clone()),
            "step": step,
            "notes": self.notes,
        })
    }
}

fn scale_text(s: &Scale) -> String {
    let v = s.value;
    if v.norm() == 0.0 {
        return "integrator: no decay".to_string();
    }
    let mut parts = Vec::new();
    match (v.re < 0.0, s.time_constant) {
        (true, Some(tau)) => parts.push(format!("time constant {} s", g(tau))),
        (false, Some(tau)) => {
            parts.push(format!("unstable: grows with time constant {} s", g(tau)))
        }
        (_, None) => parts.push("undamped".to_string()),
    }
    if v.im != 0.0 {
        parts.push(format!(
            "natural frequency {} rad/s ({} Hz)",
            g(s.natural_frequency),
            g(s.natural_frequency / std::f64::consts::TAU)
        ));
        if let Some(z) = s.damping_ratio {
            parts.push(format!("damping ratio {}", g(z)));
        }
    }
    parts.join(", ")
}
