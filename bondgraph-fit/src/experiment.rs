//! How measured data meets a model: the experiment file, as data.
//!
//! A CSV of measurements says "with these conditions set, this was observed". To predict a
//! row, a program must know which model input each condition column sets and in which units,
//! which model output each observed column measures, which elements an empty cell removes
//! from the model, where each run starts and what a calibration refits. That knowledge belongs
//! to the model, not to the program, so it lives in a small RON file beside the model
//! (`experiment.ron`), in the form `DESIGN.md` fixes:
//!
//! ```
//! use bondgraph_fit::experiment::{Experiment, Kind};
//!
//! let text = r#"Experiment(
//!     kind: Steady,
//!     conditions: [("u_V", "u", 1.0), ("tau_mNm", "tau_load", 0.001)],
//!     observed: [("w_rad_s", "flow:shaft", 1.0)],
//!     fitted: ["R_a", "b_m"],
//! )"#;
//! let experiment = Experiment::parse("motor/experiment.ron", text).unwrap();
//! assert_eq!(experiment.kind, Kind::Steady);
//! assert_eq!(experiment.conditions[1].factor, 0.001);
//! assert_eq!(experiment.observed[0].output, "flow:shaft");
//!
//! // A mistake is reported at its line and field.
//! let error = Experiment::parse("e.ron", "Experiment(\n  kind: Steady,\n  conditons: [],\n)")
//!     .unwrap_err();
//! assert!(error.to_string().starts_with("e.ron:3:"), "{error}");
//! assert!(error.to_string().contains("conditons"), "{error}");
//! ```
//!
//! Every later problem with what the file names (an input the model does not have, a removal
//! that leaves the model invalid) is reported at the entry that names it: the experiment keeps
//! its [`SourceFile`] for that ([`Experiment::locate`]).

use std::sync::Arc;

use bondgraph_core::diagnostics::Diagnostics;
use bondgraph_core::source::{Location, SourceFile, Span};
use bondgraph_core::{Diagnostic, DiagnosticKind};
use serde::Deserialize;

/// What each row (or each file) of the data is.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub enum Kind {
    /// Each row is the steady state reached from `initial_mode`, every storage element empty,
    /// with the row's conditions held constant.
    Steady,
    /// Each CSV file is one run of `scenario` (a scenario file, relative to the experiment
    /// file), sampled at the times of the column `time.0` (`time.1` seconds per unit).
    TimeSeries {
        /// The scenario file that gives every input the data does not.
        scenario: String,
        /// The time column and its factor to seconds.
        time: (String, f64),
    },
}

/// A condition column: the model input it sets, `input = factor * cell` in SI units.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(from = "(String, String, f64)")]
pub struct Condition {
    /// The CSV column.
    pub column: String,
    /// The model input.
    pub input: String,
    /// SI units per unit of the column.
    pub factor: f64,
}

impl From<(String, String, f64)> for Condition {
    fn from((column, input, factor): (String, String, f64)) -> Self {
        Self {
            column,
            input,
            factor,
        }
    }
}

/// An observed column: the model output it measures, `output = factor * cell` in SI units.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(from = "(String, String, f64)")]
pub struct Observed {
    /// The CSV column.
    pub column: String,
    /// The model output (`flow:ELEMENT`, `effort:ELEMENT`, `across:BRANCH`, ...).
    pub output: String,
    /// SI units per unit of the column.
    pub factor: f64,
}

impl From<(String, String, f64)> for Observed {
    fn from((column, output, factor): (String, String, f64)) -> Self {
        Self {
            column,
            output,
            factor,
        }
    }
}

/// A removal: a row whose cell in `column` is empty is simulated without `elements`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(from = "(String, Vec<String>)")]
pub struct Absent {
    /// The CSV column.
    pub column: String,
    /// The elements (or branches) removed, with every bond that touches them.
    pub elements: Vec<String>,
}

impl From<(String, Vec<String>)> for Absent {
    fn from((column, elements): (String, Vec<String>)) -> Self {
        Self { column, elements }
    }
}

/// The serde form of the file.
#[derive(Deserialize)]
#[serde(rename = "Experiment", deny_unknown_fields)]
struct Raw {
    kind: Kind,
    conditions: Vec<Condition>,
    #[serde(default)]
    absent: Vec<Absent>,
    observed: Vec<Observed>,
    #[serde(default)]
    initial_mode: Option<String>,
    #[serde(default)]
    fitted: Vec<String>,
    #[serde(default)]
    fitted_when_present: Vec<(String, Vec<String>)>,
    #[serde(default)]
    regimes: Vec<(String, String)>,
    #[serde(default)]
    noise: Option<DeclaredNoise>,
}

/// The `noise` field as written: one standard deviation (one observed column), or one per
/// observed column, in file order.
#[derive(Deserialize)]
#[serde(untagged)]
enum DeclaredNoise {
    One(f64),
    PerColumn(Vec<f64>),
}

/// How the rows of a CSV become simulations of a model, and what is compared.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// Steady states or time series.
    pub kind: Kind,
    /// The condition columns, in file order.
    pub conditions: Vec<Condition>,
    /// The removals an empty cell makes.
    pub absent: Vec<Absent>,
    /// The observed columns.
    pub observed: Vec<Observed>,
    /// The mode every run starts in (assignments to removed elements are dropped); the
    /// model's initial mode when not given.
    pub initial_mode: Option<String>,
    /// The parameters a calibration refits (with the bounds in the model file).
    pub fitted: Vec<String>,
    /// Parameters refitted too when the column has values in the data.
    pub fitted_when_present: Vec<(String, Vec<String>)>,
    /// Operating regimes, named physically, each by the switching elements' modes that define
    /// it: the first whose every assignment holds in the mode a row settles in names it.
    pub regimes: Vec<(String, String)>,
    /// The measurement's known noise (standard deviation) of each observed column, in its
    /// units and in the order of `observed` (`noise: 0.05` for one column, `noise: [2.0,
    /// 1.0]` for two); empty when the file declares none.
    pub noise: Vec<f64>,
    source: Arc<SourceFile>,
}

/// Why an experiment cannot be used: located diagnostics (the experiment file's, and the
/// model's where a removal breaks it), or a data row the model cannot evaluate.
#[derive(Clone, Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExperimentError {
    /// The experiment file or what it names, located in the files concerned.
    #[error("{0}")]
    Diagnostics(Diagnostics),
    /// A row of the data the model cannot predict.
    #[error("{file}:{row}: {cells}: {reason}")]
    Row {
        /// The data file.
        file: String,
        /// Its line.
        row: usize,
        /// The row's condition cells, `column = value`.
        cells: String,
        /// Why (a simulation that does not settle, a friction law violated).
        reason: String,
    },
}

impl From<Diagnostics> for ExperimentError {
    fn from(diagnostics: Diagnostics) -> Self {
        Self::Diagnostics(diagnostics)
    }
}

impl From<Diagnostic> for ExperimentError {
    fn from(diagnostic: Diagnostic) -> Self {
        Self::Diagnostics(diagnostic.into())
    }
}

impl Experiment {
    /// Reads an experiment from RON text, naming `name` in errors.
    ///
    /// # Errors
    /// Syntax errors and unknown or missing fields at their line and column; a column named
    /// twice, a factor that is zero or not finite, a noise that is not positive, and a
    /// `fitted_when_present` or `absent` column that names no condition, at the entry.
    pub fn parse(name: &str, text: &str) -> Result<Self, ExperimentError> {
        Self::from_source(&SourceFile::new(name, text))
    }

    /// [`Experiment::parse`] of an already read file.
    ///
    /// # Errors
    /// As [`Experiment::parse`].
    pub fn from_source(source: &Arc<SourceFile>) -> Result<Self, ExperimentError> {
        // `initial_mode: "..."` and `noise: 0.1`, as DESIGN.md writes them, without `Some(...)`.
        let raw: Raw = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .from_str(source.text())
            .map_err(|e| {
                let (line, column) = (e.span.start.line, e.span.start.col);
                let offset = source.offset(line, column);
                Diagnostic::new(DiagnosticKind::Syntax, format!("experiment: {}", e.code))
                    .at(source, Span::new(offset, offset))
            })?;
        let experiment = Self {
            kind: raw.kind,
            conditions: raw.conditions,
            absent: raw.absent,
            observed: raw.observed,
            initial_mode: raw.initial_mode,
            fitted: raw.fitted,
            fitted_when_present: raw.fitted_when_present,
            regimes: raw.regimes,
            noise: match raw.noise {
                None => Vec::new(),
                Some(DeclaredNoise::One(sd)) => vec![sd],
                Some(DeclaredNoise::PerColumn(sds)) => sds,
            },
            source: source.clone(),
        };
        experiment.check()?;
        Ok(experiment)
    }

    /// The experiment file.
    pub fn source(&self) -> &Arc<SourceFile> {
        &self.source
    }

    /// Where the string `"value"` is written in the entry `field` of the file (the first
    /// occurrence after `field:`), or the field itself, or the file's start.
    pub fn locate(&self, field: &str, value: &str) -> Location {
        let text = self.source.text();
        let start = field_offset(text, field);
        let span = start
            .and_then(|at| {
                let quoted = format!("\"{value}\"");
                text[at..]
                    .find(&quoted)
                    .map(|k| Span::new(at + k, at + k + quoted.len()))
            })
            .or_else(|| start.map(|at| Span::new(at, at + field.len())))
            .unwrap_or(Span::new(0, 0));
        self.source.locate(span)
    }

    /// A diagnostic of `kind` pointing at `value` in `field`.
    pub fn error(
        &self,
        kind: DiagnosticKind,
        field: &str,
        value: &str,
        message: String,
    ) -> Diagnostic {
        Diagnostic::new(kind, message).at_location(self.locate(field, value))
    }

    /// Every column the experiment reads besides the observed ones (and the time): the
    /// condition columns, then the `absent` columns that set no input.
    pub fn condition_columns(&self) -> Vec<&str> {
        let mut columns: Vec<&str> = self.conditions.iter().map(|c| c.column.as_str()).collect();
        for absent in &self.absent {
            if !columns.contains(&absent.column.as_str()) {
                columns.push(&absent.column);
            }
        }
        columns
    }

    /// The declared noise (standard deviation) of observed column `k`, in its units.
    pub fn declared_noise(&self, k: usize) -> Option<f64> {
        self.noise.get(k).copied()
    }

    /// Whether an empty cell is allowed in `column` (it is an `absent` column).
    pub fn may_be_empty(&self, column: &str) -> bool {
        self.absent.iter().any(|a| a.column == column)
    }

    /// The time column and its factor to seconds, for a time series.
    pub fn time(&self) -> Option<(&str, f64)> {
        match &self.kind {
            Kind::Steady => None,
            Kind::TimeSeries { time, .. } => Some((time.0.as_str(), time.1)),
        }
    }

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

    /// Checks what can be checked without the model.
    fn check(&self) -> Result<(), Diagnostics> {
        let mut problems = Vec::new();
        let mut seen: Vec<&str> = Vec::new();
        let columns = self
            .conditions
            .iter()
            .map(|c| ("conditions", c.column.as_str(), c.factor))
            .chain(
                self.observed
                    .iter()
                    .map(|o| ("observed", o.column.as_str(), o.factor)),
            )
            .chain(self.time().map(|(column, factor)| ("time", column, factor)));
        for (field, column, factor) in columns {
            if seen.contains(&column) {
                problems.push(self.error(
                    DiagnosticKind::DuplicateName,
                    field,
                    column,
                    format!("experiment: column `{column}` is named twice"),
                ));
            }
            seen.push(column);
            if !(factor.is_finite() && factor != 0.0) {
                problems.push(self.error(
                    DiagnosticKind::InvalidValue,
                    field,
                    column,
                    format!("experiment: the factor of column `{column}` is {factor}; it must be a finite, non-zero number of SI units per unit of the column"),
                ));
            }
        }
        if self.observed.is_empty() {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::MissingField,
                    "experiment: `observed` is empty; name at least one observed column",
                )
                .at_location(self.locate("observed", "")),
            );
        }
        let observed: Vec<&str> = self.observed.iter().map(|o| o.column.as_str()).collect();
        for absent in &self.absent {
            if observed.contains(&absent.column.as_str()) {
                problems.push(self.error(
                    DiagnosticKind::ConflictingFields,
                    "absent",
                    &absent.column,
                    format!(
                        "experiment: `absent` column `{}` is an observed column",
                        absent.column
                    ),
                ));
            }
        }
        let readable = self.condition_columns();
        for (column, _) in &self.fitted_when_present {
            if !readable.contains(&column.as_str()) {
                problems.push(self.error(
                    DiagnosticKind::UnknownName,
                    "fitted_when_present",
                    column,
                    format!("experiment: `fitted_when_present` names column `{column}`, which is neither a condition nor an `absent` column"),
                ));
            }
        }
        if !self.noise.is_empty() && self.noise.len() != self.observed.len() {
            problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "experiment: `noise` gives {} value{} for {} observed columns; give one \
                         standard deviation per observed column, in its units and in the order \
                         of `observed` (`noise: [{}]`)",
                        self.noise.len(),
                        if self.noise.len() == 1 { "" } else { "s" },
                        self.observed.len(),
                        vec!["SD"; self.observed.len()].join(", ")
                    ),
                )
                .at_location(self.locate("noise", "")),
            );
        }
        for (k, noise) in self.noise.iter().enumerate() {
            if !(noise.is_finite() && *noise > 0.0) {
                let column = self
                    .observed
                    .get(k)
                    .map_or(String::new(), |o| format!(" of `{}`", o.column));
                problems.push(
                    Diagnostic::new(
                        DiagnosticKind::InvalidValue,
                        format!(
                            "experiment: noise {noise}{column} must be a positive standard deviation"
                        ),
                    )
                    .at_location(self.locate("noise", "")),
                );
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(Diagnostics(problems))
        }
    }
}

/// The byte offset of `field:` written as a field name (not in a comment), if any.
fn field_offset(text: &str, field: &str) -> Option<usize> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or("");
        let mut from = 0;
        while let Some(k) = code[from..].find(field) {
            let at = from + k;
            let before = code[..at].chars().next_back();
            let after = code[at + field.len()..].trim_start();
            if !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '"')
                && after.starts_with(':')
            {
                return Some(offset + at);
            }
            from = at + field.len();
        }
        offset += line.len();
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOTOR: &str = r#"Experiment(
    kind: Steady,
    conditions: [("u_V", "u", 1.0), ("tau_mNm", "tau_load", 0.001)],
    absent: [("tau_mNm", ["load"])],
    observed: [("w_rad_s", "flow:shaft", 1.0)],
    fitted: ["R_a"],
    fitted_when_present: [("tau_mNm", ["b_load"])],
    noise: 0.05,
)"#;

    fn message(text: &str) -> String {
        Experiment::parse("e.ron", text).unwrap_err().to_string()
    }

    #[test]
    fn every_field_is_read() {
        let e = Experiment::parse("e.ron", MOTOR).unwrap();
        assert_eq!(e.condition_columns(), ["u_V", "tau_mNm"]);
        assert!(e.may_be_empty("tau_mNm") && !e.may_be_empty("u_V"));
        assert_eq!(e.absent[0].elements, ["load"]);
        assert_eq!(e.fitted_when_present[0].1, ["b_load"]);
        assert_eq!(e.noise, [0.05]);
        assert_eq!(e.declared_noise(0), Some(0.05));
        assert_eq!(e.initial_mode, None);
        assert_eq!(e.time(), None);
    }

    #[test]
    fn a_time_series_names_its_scenario_and_time_column() {
        let text = MOTOR.replace(
            "kind: Steady",
            r#"kind: TimeSeries(scenario: "step.ron", time: ("t_ms", 0.001))"#,
        );
        let e = Experiment::parse("e.ron", &text).unwrap();
        assert_eq!(e.time(), Some(("t_ms", 0.001)));
    }

    #[test]
    fn unknown_and_missing_fields_at_their_line() {
        let m = message(&MOTOR.replace("    fitted: [", "    fited: ["));
        assert!(m.starts_with("e.ron:6:5: error: experiment: "), "{m}");
        assert!(m.contains("fited"), "{m}");
        let m = message("Experiment(\n    kind: Steady,\n    conditions: [],\n)");
        assert!(m.contains("observed"), "{m}");
    }

    #[test]
    fn bad_entries_at_the_entry() {
        let m = message(&MOTOR.replace("\"tau_load\", 0.001", "\"tau_load\", 0.0"));
        assert_eq!(
            m,
            "e.ron:3:38: error: experiment: the factor of column `tau_mNm` is 0; it must be a \
             finite, non-zero number of SI units per unit of the column"
        );
        let m =
            message(&MOTOR.replace("(\"tau_mNm\", [\"b_load\"])", "(\"tau_Nm\", [\"b_load\"])"));
        assert!(
            m.starts_with(
                "e.ron:7:28: error: experiment: `fitted_when_present` names column `tau_Nm`"
            ),
            "{m}"
        );
        let m = message(&MOTOR.replace("noise: 0.05", "noise: -1.0"));
        assert!(
            m.starts_with("e.ron:8:5: error: experiment: noise -1"),
            "{m}"
        );
        let m = message(&MOTOR.replace("(\"w_rad_s\"", "(\"u_V\""));
        assert!(m.contains("column `u_V` is named twice"), "{m}");
    }

    /// Several observed columns declare one noise each, in the order of `observed`; a count
    /// that does not match, or a value that is not positive, is refused at `noise`.
    #[test]
    fn a_noise_per_observed_column() {
        let two = MOTOR.replace(
            r#"observed: [("w_rad_s", "flow:shaft", 1.0)],"#,
            r#"observed: [("w_rad_s", "flow:shaft", 1.0), ("i_A", "flow:armature", 1.0)],"#,
        );
        let e =
            Experiment::parse("e.ron", &two.replace("noise: 0.05", "noise: [0.05, 0.02]")).unwrap();
        assert_eq!(e.noise, [0.05, 0.02]);
        assert_eq!(e.declared_noise(1), Some(0.02));
        let m = message(&two);
        assert!(
            m.starts_with(
                "e.ron:8:5: error: experiment: `noise` gives 1 value for 2 observed columns; \
                 give one standard deviation per observed column"
            ),
            "{m}"
        );
        assert!(m.contains("(`noise: [SD, SD]`)"), "{m}");
        let m = message(&two.replace("noise: 0.05", "noise: [0.05, 0.0]"));
        assert!(
            m.starts_with(
                "e.ron:8:5: error: experiment: noise 0 of `i_A` must be a positive standard \
                 deviation"
            ),
            "{m}"
        );
    }

    #[test]
    fn field_names_in_comments_or_strings_are_not_fields() {
        let text = "// fitted: no\nExperiment(x: \"fitted: \", fitted: [])";
        assert_eq!(field_offset(text, "fitted"), Some(40));
    }

    #[test]
    fn regimes_by_the_first_matching_pattern() {
        let text = MOTOR.replace(
            "noise: 0.05,",
            r#"regimes: [("held", "fr=stuck"), ("moving", "")],"#,
        );
        let e = Experiment::parse("e.ron", &text).unwrap();
        assert_eq!(e.regime("fr=stuck,k=taut"), "held");
        assert_eq!(e.regime("fr=slip+"), "fr=slip+");
    }
}
