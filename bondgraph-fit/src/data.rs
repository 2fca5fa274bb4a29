//! Measured steady-state tip velocities, read from and written to CSV.
//!
//! Calibration, residuals and model selection all start from a table of experiments: the
//! conditions that were set (supply pressure, active-channel speed, catheter speed) and the tip
//! velocity that was measured. This module is the single place where such a table enters the
//! program, so it is where typos must be caught: a wrong number that slipped through would be
//! fitted like any other, and nothing downstream could tell it from physics. Every error names
//! the file, the line and the column.
//!
//! # Format
//!
//! The contract of `DESIGN.md`: CSV with a header row naming the columns
//!
//! | column | meaning | required |
//! |---|---|---|
//! | `P_s_kPa` | supply pressure in the tank, relative to the lumen, kPa | yes |
//! | `v_ac_mm_s` | active-channel velocity, mm/s | yes |
//! | `v_ct_mm_s` | catheter velocity, mm/s; empty (or no such column) means no catheter in the lumen | no |
//! | `v_ge_mm_s` | measured steady-state tip velocity, mm/s | yes |
//!
//! Columns may come in any order (they are found by name); whitespace around names and values
//! is ignored; a UTF-8 byte-order mark and blank lines are skipped.
//!
//! What is refused, and why:
//!
//! - **Unknown columns.** The catheter column is optional, so a misspelt one (`v_ct_mm_S`)
//!   would otherwise be ignored and every row silently read as "no catheter". The price is that
//!   extra annotation columns are not allowed; keep them in another file.
//! - **Comment lines** (`#`): the contract has none; provenance goes in a README beside the data.
//! - **Rows with too few or too many fields**, empty required values, non-numbers, and
//!   non-finite numbers (`NaN`, `inf`).
//! - **Negative values where the robot cannot produce them**, as the likely sign of a typo:
//!   - `P_s_kPa < 0`: suction inverts the robot rather than growing it.
//!   - `v_ac_mm_s < 0`: a retracting channel is not a steady growth experiment.
//!   - `v_ge_mm_s < 0` unless `v_ct_mm_s < 0`: at steady state nothing pulls the tip back.
//!     Pressure pushes it forward, the inner structure (tension only) holds it at most to
//!     `v_ac/2 >= 0`, and friction only opposes motion. The exception is a withdrawing catheter,
//!     whose friction can drag the tip backwards. A static tip is `0`, and noise-free synthetic
//!     data must be clipped there as a camera would report it.
//!
//!   A negative catheter velocity is allowed: the catheter servo drives both ways, and a
//!   withdrawing catheter that brakes the tip is a meaningful experiment.
//!
//! Values above the kinematic limits (a tip faster than `v_ac/2`) are *not* refused: the
//! paper's own Table III has them, and deciding what they mean is the fit's job, not the
//! reader's.

use std::fmt;
use std::path::Path;

/// Column name of the supply pressure, kPa.
pub const PRESSURE_COLUMN: &str = "P_s_kPa";
/// Column name of the active-channel velocity, mm/s.
pub const CHANNEL_COLUMN: &str = "v_ac_mm_s";
/// Column name of the catheter velocity, mm/s (optional; empty means no catheter).
pub const CATHETER_COLUMN: &str = "v_ct_mm_s";
/// Column name of the measured tip velocity, mm/s.
pub const TIP_COLUMN: &str = "v_ge_mm_s";

/// Every column of the format, in the order [`write()`] writes them.
pub const COLUMNS: [&str; 4] = [PRESSURE_COLUMN, CHANNEL_COLUMN, CATHETER_COLUMN, TIP_COLUMN];

const NEGATIVE_PRESSURE: &str =
    "the supply pressure cannot be negative (suction inverts the robot rather than growing it)";
const NEGATIVE_CHANNEL: &str =
    "the active channel cannot run backwards in a growth experiment (that is retraction)";
const NEGATIVE_TIP: &str = "the tip cannot run backwards at steady state \
     unless a withdrawing catheter (negative v_ct_mm_s) drags it";

/// One experiment: the conditions that were set and the tip velocity that was measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// Supply pressure `P_s` in the tank, relative to the lumen, in kPa.
    pub pressure_kpa: f64,
    /// Active-channel velocity `v_ac` in mm/s.
    pub channel_velocity_mm_s: f64,
    /// Catheter velocity `v_ct` in mm/s, or `None` when no catheter is in the lumen. `Some(0.0)`
    /// is a catheter held still, which is not the same experiment: it adds friction.
    pub catheter_velocity_mm_s: Option<f64>,
    /// Measured steady-state tip velocity `v_ge` in mm/s.
    pub tip_velocity_mm_s: f64,
    /// Line of the file this row was read from, 1-based (the header is line 1 in a file
    /// without leading blank lines), for messages that point back at the data.
    pub row: usize,
}

/// A table of measurements, named after the file it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// The name used in messages, normally the file name.
    pub name: String,
    /// The measurements in file order.
    pub rows: Vec<Measurement>,
}

/// Why a data file was refused, with where: the file, and the line and column when there is one.
///
/// Displays as `FILE:LINE: column `NAME`: what is wrong`.
#[derive(Debug)]
pub struct DataError {
    file: String,
    line: Option<usize>,
    column: Option<String>,
    kind: DataErrorKind,
}

/// What is wrong with a data file; see [`DataError`] for where.
#[derive(Debug)]
#[non_exhaustive]
pub enum DataErrorKind {
    /// The file could not be read.
    Io(std::io::Error),
    /// The text is not well-formed CSV (e.g. invalid UTF-8 or an unbalanced quote).
    Malformed(String),
    /// Nothing at all, not even a header.
    Empty,
    /// A header, but no measurements.
    NoRows,
    /// A line starting with `#`.
    Comment,
    /// A required column is not in the header.
    MissingColumn {
        /// The columns that the header does have.
        found: Vec<String>,
    },
    /// The header names a column that is not part of the format.
    UnknownColumn {
        /// The format's column this one differs from only in letter case, if any.
        did_you_mean: Option<&'static str>,
    },
    /// The header names a column twice.
    DuplicateColumn,
    /// A row with fewer fields than the header; the error's column is the first one missing.
    TooFewFields {
        /// Fields in the row.
        found: usize,
        /// Fields in the header.
        expected: usize,
    },
    /// A row with more fields than the header.
    TooManyFields {
        /// Fields in the row.
        found: usize,
        /// Fields in the header.
        expected: usize,
    },
    /// A required value is empty.
    MissingValue,
    /// A value that does not parse as a number.
    NotANumber {
        /// The text found.
        text: String,
    },
    /// A value that parses as `NaN` or an infinity.
    NotFinite {
        /// The text found.
        text: String,
    },
    /// A negative value where the robot cannot produce one.
    Negative {
        /// The value found.
        value: f64,
        /// Why this quantity cannot be negative.
        reason: &'static str,
    },
}

impl DataError {
    fn new(file: &str, line: Option<usize>, column: Option<&str>, kind: DataErrorKind) -> Self {
        Self {
            file: file.to_owned(),
            line,
            column: column.map(str::to_owned),
            kind,
        }
    }

    /// The file (as named to [`read`] or given to [`read_file`]).
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The 1-based line of the offending header or row, when the error has one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// The column at fault, when the error concerns one.
    pub fn column(&self) -> Option<&str> {
        self.column.as_deref()
    }

    /// What is wrong.
    pub fn kind(&self) -> &DataErrorKind {
        &self.kind
    }
}

impl fmt::Display for DataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(column) = &self.column {
            write!(f, ": column `{column}`")?;
        }
        write!(f, ": {}", self.kind)
    }
}

impl std::error::Error for DataError {}

impl fmt::Display for DataErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(error) => write!(f, "cannot read the file: {error}"),
            Self::Malformed(message) => write!(f, "malformed CSV: {message}"),
            Self::Empty => write!(
                f,
                "the file is empty; expected the header `{}` and one row per measurement",
                COLUMNS.join(",")
            ),
            Self::NoRows => write!(f, "a header but no measurements after it"),
            Self::Comment => write!(
                f,
                "comment lines are not part of the format; put provenance in a README beside the data"
            ),
            Self::MissingColumn { found } => {
                write!(f, "required, but the header has only ")?;
                let found: Vec<String> = found.iter().map(|c| format!("`{c}`")).collect();
                write!(f, "{}", found.join(", "))
            }
            Self::UnknownColumn { did_you_mean } => {
                write!(f, "not a column of this format")?;
                if let Some(name) = did_you_mean {
                    write!(f, " (did you mean `{name}`?)")?;
                }
                write!(
                    f,
                    "; the columns are `{PRESSURE_COLUMN}`, `{CHANNEL_COLUMN}`, \
                     `{CATHETER_COLUMN}` (optional) and `{TIP_COLUMN}`"
                )
            }
            Self::DuplicateColumn => write!(f, "appears twice in the header"),
            Self::TooFewFields { found, expected } => write!(
                f,
                "missing: the row has {found} fields where the header has {expected}"
            ),
            Self::TooManyFields { found, expected } => {
                write!(
                    f,
                    "the row has {found} fields where the header has {expected}"
                )
            }
            Self::MissingValue => write!(f, "no value"),
            Self::NotANumber { text } => write!(f, "`{text}` is not a number"),
            Self::NotFinite { text } => write!(f, "`{text}` is not a finite number"),
            Self::Negative { value, reason } => write!(f, "{value} is negative: {reason}"),
        }
    }
}

/// Where each column is in the file's rows.
struct Layout {
    pressure: usize,
    channel: usize,
    catheter: Option<usize>,
    tip: usize,
    width: usize,
    names: Vec<String>,
}

/// Reads a dataset from CSV text. `name` is used in messages (normally the file name) and
/// becomes the dataset's name.
///
/// # Errors
///
/// A [`DataError`] naming the line and column of the first problem found: see the module
/// documentation for what is refused.
pub fn read(name: &str, text: &str) -> Result<Dataset, DataError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(DataError::new(name, None, None, DataErrorKind::Empty));
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut lines = Lines::new(text);
    let header = reader
        .headers()
        .map_err(|error| malformed(name, text, &error))?
        .clone();
    let header_line = lines.of(&header);
    let layout = layout(name, header_line, &header)?;

    let mut rows = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(error) => return Err(malformed(name, text, &error)),
        }
        let line = lines.of(&record);
        // A line of spaces is one empty field; the header always has more than one column.
        if record.len() == 1 && record.get(0).is_some_and(str::is_empty) {
            continue;
        }
        let measurement = row(name, line, &layout, &record)?;
        check(name, &measurement)?;
        rows.push(measurement);
    }
    if rows.is_empty() {
        return Err(DataError::new(
            name,
            Some(header_line),
            None,
            DataErrorKind::NoRows,
        ));
    }
    Ok(Dataset {
        name: name.to_owned(),
        rows,
    })
}

/// Reads a dataset from a CSV file, named in messages and in the dataset by its path.
///
/// # Errors
///
/// As [`read`], and [`DataErrorKind::Io`] when the file cannot be read.
pub fn read_file(path: &Path) -> Result<Dataset, DataError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|error| DataError::new(&name, None, None, DataErrorKind::Io(error)))?;
    read(&name, &text)
}

/// Checks a dataset built in code (e.g. synthetic data) against the rules [`read`] enforces on
/// values, so that what [`write()`] writes of it can be read back. Errors name the dataset and
/// each measurement's `row`.
///
/// # Errors
///
/// The first non-finite or impossibly negative value, or [`DataErrorKind::NoRows`] for an
/// empty dataset.
pub fn validate(dataset: &Dataset) -> Result<(), DataError> {
    if dataset.rows.is_empty() {
        return Err(DataError::new(
            &dataset.name,
            None,
            None,
            DataErrorKind::NoRows,
        ));
    }
    for measurement in &dataset.rows {
        let values = [
            (PRESSURE_COLUMN, Some(measurement.pressure_kpa)),
            (CHANNEL_COLUMN, Some(measurement.channel_velocity_mm_s)),
            (CATHETER_COLUMN, measurement.catheter_velocity_mm_s),
            (TIP_COLUMN, Some(measurement.tip_velocity_mm_s)),
        ];
        for (column, value) in values {
            if let Some(value) = value.filter(|value| !value.is_finite()) {
                return Err(DataError::new(
                    &dataset.name,
                    Some(measurement.row),
                    Some(column),
                    DataErrorKind::NotFinite {
                        text: value.to_string(),
                    },
                ));
            }
        }
        check(&dataset.name, measurement)?;
    }
    Ok(())
}

/// Writes a dataset in the format [`read`] reads: the header of all four columns, then one line
/// per measurement, an empty catheter field for `None`. Numbers are written in the shortest
/// form that reads back to the same `f64`, so `read(write(d))` gives `d`'s values again (and
/// its `row` numbers too, when they are the consecutive lines of a file without blank lines).
/// Nothing is checked here; use [`validate`] first for data built in code.
pub fn write(dataset: &Dataset) -> String {
    let mut text = COLUMNS.join(",");
    text.push('\n');
    for measurement in &dataset.rows {
        let catheter = measurement
            .catheter_velocity_mm_s
            .map(|v| v.to_string())
            .unwrap_or_default();
        text.push_str(&format!(
            "{},{},{},{}\n",
            measurement.pressure_kpa,
            measurement.channel_velocity_mm_s,
            catheter,
            measurement.tip_velocity_mm_s
        ));
    }
    text
}

/// Line numbers of records, counted from their byte offsets.
///
/// The `csv` crate's own line numbers are not usable for messages: a record's position is where
/// the previous record ended, before any skipped blank lines, and its line count does not
/// advance on `\r\n` line ends. So this counts the newlines itself, from the reported byte
/// offset past the blank lines (which contain only line-end characters) to the record.
struct Lines<'a> {
    text: &'a [u8],
    offset: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            text: text.as_bytes(),
            offset: 0,
            line: 1,
        }
    }

    /// The 1-based line on which the record at this byte offset starts. Offsets must not
    /// decrease from one call to the next (records are read in order); if one does, counting
    /// restarts from the top.
    fn at(&mut self, byte: usize) -> usize {
        if byte < self.offset {
            (self.offset, self.line) = (0, 1);
        }
        let mut position = self.offset;
        while position < self.text.len()
            && (position < byte || matches!(self.text[position], b'\r' | b'\n'))
        {
            if self.text[position] == b'\n' {
                self.line += 1;
            }
            position += 1;
        }
        self.offset = position;
        self.line
    }

    fn of(&mut self, record: &csv::StringRecord) -> usize {
        let byte = record
            .position()
            .and_then(|position| usize::try_from(position.byte()).ok())
            .unwrap_or(self.offset);
        self.at(byte)
    }
}

fn malformed(name: &str, text: &str, error: &csv::Error) -> DataError {
    let line = error
        .position()
        .and_then(|position| usize::try_from(position.byte()).ok())
        .map(|byte| Lines::new(text).at(byte));
    let message = match error.kind() {
        csv::ErrorKind::Utf8 { err, .. } => format!("invalid UTF-8 in field {}", err.field() + 1),
        _ => error.to_string(),
    };
    DataError::new(name, line, None, DataErrorKind::Malformed(message))
}

fn layout(name: &str, line: usize, header: &csv::StringRecord) -> Result<Layout, DataError> {
    let error = |column: &str, kind| DataError::new(name, Some(line), Some(column), kind);
    if header.get(0).is_some_and(|first| first.starts_with('#')) {
        return Err(DataError::new(
            name,
            Some(line),
            None,
            DataErrorKind::Comment,
        ));
    }
    let names: Vec<String> = header.iter().map(str::to_owned).collect();
    for (index, column) in names.iter().enumerate() {
        if names[..index].contains(column) {
            return Err(error(column, DataErrorKind::DuplicateColumn));
        }
        if !COLUMNS.contains(&column.as_str()) {
            let did_you_mean = COLUMNS
                .iter()
                .find(|known| known.eq_ignore_ascii_case(column))
                .copied();
            return Err(error(column, DataErrorKind::UnknownColumn { did_you_mean }));
        }
    }
    let position = |column: &str| names.iter().position(|name| name == column);
    let required = |column: &'static str| {
        position(column).ok_or_else(|| {
            error(
                column,
                DataErrorKind::MissingColumn {
                    found: names.clone(),
                },
            )
        })
    };
    Ok(Layout {
        pressure: required(PRESSURE_COLUMN)?,
        channel: required(CHANNEL_COLUMN)?,
        catheter: position(CATHETER_COLUMN),
        tip: required(TIP_COLUMN)?,
        width: names.len(),
        names,
    })
}

fn row(
    name: &str,
    line: usize,
    layout: &Layout,
    record: &csv::StringRecord,
) -> Result<Measurement, DataError> {
    let error = |column: Option<&str>, kind| DataError::new(name, Some(line), column, kind);
    if record.get(0).is_some_and(|first| first.starts_with('#')) {
        return Err(error(None, DataErrorKind::Comment));
    }
    let (found, expected) = (record.len(), layout.width);
    if found < expected {
        let missing = layout.names.get(found).map(String::as_str);
        return Err(error(
            missing,
            DataErrorKind::TooFewFields { found, expected },
        ));
    }
    if found > expected {
        return Err(error(
            None,
            DataErrorKind::TooManyFields { found, expected },
        ));
    }
    let optional = |index: usize, column: &str| -> Result<Option<f64>, DataError> {
        let text = record.get(index).unwrap_or_default();
        if text.is_empty() {
            return Ok(None);
        }
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(Some(value)),
            Ok(_) => Err(error(
                Some(column),
                DataErrorKind::NotFinite {
                    text: text.to_owned(),
                },
            )),
            Err(_) => Err(error(
                Some(column),
                DataErrorKind::NotANumber {
                    text: text.to_owned(),
                },
            )),
        }
    };
    let required = |index: usize, column: &str| -> Result<f64, DataError> {
        optional(index, column)?.ok_or_else(|| error(Some(column), DataErrorKind::MissingValue))
    };
    Ok(Measurement {
        pressure_kpa: required(layout.pressure, PRESSURE_COLUMN)?,
        channel_velocity_mm_s: required(layout.channel, CHANNEL_COLUMN)?,
        catheter_velocity_mm_s: match layout.catheter {
            Some(index) => optional(index, CATHETER_COLUMN)?,
            None => None,
        },
        tip_velocity_mm_s: required(layout.tip, TIP_COLUMN)?,
        row: line,
    })
}

/// The sign rules of the module documentation.
fn check(name: &str, measurement: &Measurement) -> Result<(), DataError> {
    let negative = |column: &str, value: f64, reason| {
        Err(DataError::new(
            name,
            Some(measurement.row),
            Some(column),
            DataErrorKind::Negative { value, reason },
        ))
    };
    if measurement.pressure_kpa < 0.0 {
        return negative(PRESSURE_COLUMN, measurement.pressure_kpa, NEGATIVE_PRESSURE);
    }
    if measurement.channel_velocity_mm_s < 0.0 {
        return negative(
            CHANNEL_COLUMN,
            measurement.channel_velocity_mm_s,
            NEGATIVE_CHANNEL,
        );
    }
    let withdrawing = measurement.catheter_velocity_mm_s.is_some_and(|v| v < 0.0);
    if measurement.tip_velocity_mm_s < 0.0 && !withdrawing {
        return negative(TIP_COLUMN, measurement.tip_velocity_mm_s, NEGATIVE_TIP);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn bundled(file: &str) -> Dataset {
        let path: PathBuf = [
            env!("CARGO_MANIFEST_DIR"),
            "..",
            "models",
            "eversion",
            "data",
            file,
        ]
        .iter()
        .collect();
        read_file(&path).unwrap_or_else(|error| panic!("{error}"))
    }

    /// Table III of the paper as printed: pressure [kPa], then v_ge [mm/s] Exp. and Sim. for
    /// v_ac1 = 5.8, v_ac2 = 8.7 and v_ac3 = 11.6 mm/s.
    const PAPER_TABLE_III: [[f64; 7]; 9] = [
        [110.0, 0.05, 0.0, 0.28, 0.0, 0.1, 0.0],
        [115.0, 0.25, 0.3, 0.2, 0.3, 1.0, 0.3],
        [120.0, 2.3, 1.1, 3.3, 1.1, 5.4, 1.1],
        [125.0, 2.7, 1.85, 4.0, 1.85, 5.1, 1.85],
        [130.0, 2.9, 2.6, 4.3, 2.6, 5.5, 2.6],
        [135.0, 2.9, 2.9, 4.4, 3.4, 5.6, 3.4],
        [140.0, 2.9, 2.9, 4.4, 4.15, 6.2, 4.15],
        [145.0, 3.1, 2.9, 4.5, 4.35, 5.8, 5.7],
        [150.0, 3.1, 2.9, 4.5, 4.35, 5.9, 5.7],
    ];
    const PAPER_CHANNEL_VELOCITIES: [f64; 3] = [5.8, 8.7, 11.6];

    /// Table VI of the paper as printed: catheter velocity, v_ge Exp., v_ge Sim. [mm/s], at
    /// P_s = 110 kPa and v_ac = 5.8 mm/s.
    const PAPER_TABLE_VI: [[f64; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [1.8, 0.9, 0.9],
        [2.9, 1.3, 1.45],
        [3.9, 1.8, 1.9],
        [4.8, 2.2, 2.35],
        [6.3, 2.8, 2.9],
    ];

    /// Table III in the file's order (by channel velocity, then pressure); `column` 1 is Exp.
    /// and 2 is Sim.
    fn check_table3(dataset: &Dataset, column: usize) {
        assert_eq!(dataset.rows.len(), 27);
        let mut rows = dataset.rows.iter();
        for (k, v_ac) in PAPER_CHANNEL_VELOCITIES.iter().enumerate() {
            for paper in &PAPER_TABLE_III {
                let row = rows.next().expect("27 rows");
                assert_eq!(row.pressure_kpa, paper[0], "{}:{}", dataset.name, row.row);
                assert_eq!(
                    row.channel_velocity_mm_s, *v_ac,
                    "{}:{}",
                    dataset.name, row.row
                );
                assert_eq!(
                    row.catheter_velocity_mm_s, None,
                    "{}:{}",
                    dataset.name, row.row
                );
                assert_eq!(
                    row.tip_velocity_mm_s,
                    paper[2 * k + column],
                    "{}:{}",
                    dataset.name,
                    row.row
                );
            }
        }
    }

    fn check_table6(dataset: &Dataset, column: usize) {
        assert_eq!(dataset.rows.len(), 6);
        for (row, paper) in dataset.rows.iter().zip(&PAPER_TABLE_VI) {
            assert_eq!(row.pressure_kpa, 110.0);
            assert_eq!(row.channel_velocity_mm_s, 5.8);
            assert_eq!(row.catheter_velocity_mm_s, Some(paper[0]));
            assert_eq!(
                row.tip_velocity_mm_s, paper[column],
                "{}:{}",
                dataset.name, row.row
            );
        }
    }

    #[test]
    fn bundled_files_match_the_paper() {
        check_table3(&bundled("table3.csv"), 1);
        check_table3(&bundled("table3_paper_sim.csv"), 2);
        check_table6(&bundled("table6.csv"), 1);
        check_table6(&bundled("table6_paper_sim.csv"), 2);
    }

    #[test]
    fn bundled_spot_values_and_lines() {
        let table3 = bundled("table3.csv");
        assert!(table3.name.ends_with("table3.csv"));
        let first = &table3.rows[0];
        assert_eq!(
            (
                first.pressure_kpa,
                first.channel_velocity_mm_s,
                first.tip_velocity_mm_s
            ),
            (110.0, 5.8, 0.05)
        );
        assert_eq!(first.row, 2);
        // v_ac3 = 11.6 mm/s at 140 kPa: the largest measured tip velocity, 6.2 mm/s.
        let row = table3
            .rows
            .iter()
            .find(|r| r.channel_velocity_mm_s == 11.6 && r.pressure_kpa == 140.0)
            .expect("row");
        assert_eq!(row.tip_velocity_mm_s, 6.2);
        assert_eq!(row.row, 26);

        let sim = bundled("table3_paper_sim.csv");
        assert_eq!(sim.rows[26].tip_velocity_mm_s, 5.7);
        assert_eq!(sim.rows[15].tip_velocity_mm_s, 4.15);

        let table6 = bundled("table6.csv");
        // A catheter held still is in the lumen: Some(0.0), not None.
        assert_eq!(table6.rows[0].catheter_velocity_mm_s, Some(0.0));
        assert_eq!(table6.rows[5].catheter_velocity_mm_s, Some(6.3));
        assert_eq!(table6.rows[5].tip_velocity_mm_s, 2.8);
        assert_eq!(
            bundled("table6_paper_sim.csv").rows[2].tip_velocity_mm_s,
            1.45
        );
    }

    #[test]
    fn bundled_files_round_trip() {
        for file in [
            "table3.csv",
            "table6.csv",
            "table3_paper_sim.csv",
            "table6_paper_sim.csv",
        ] {
            let dataset = bundled(file);
            let again = read(&dataset.name, &write(&dataset)).expect("reads back");
            assert_eq!(again, dataset, "{file}");
        }
    }

    #[test]
    fn write_format() {
        let dataset = Dataset {
            name: "synthetic".into(),
            rows: vec![
                Measurement {
                    pressure_kpa: 120.0,
                    channel_velocity_mm_s: 5.8,
                    catheter_velocity_mm_s: None,
                    tip_velocity_mm_s: 2.3,
                    row: 2,
                },
                Measurement {
                    pressure_kpa: 110.0,
                    channel_velocity_mm_s: 5.8,
                    catheter_velocity_mm_s: Some(-1.5),
                    tip_velocity_mm_s: 0.1 + 0.2,
                    row: 3,
                },
            ],
        };
        let text = write(&dataset);
        assert_eq!(
            text,
            "P_s_kPa,v_ac_mm_s,v_ct_mm_s,v_ge_mm_s\n\
             120,5.8,,2.3\n\
             110,5.8,-1.5,0.30000000000000004\n"
        );
        assert_eq!(validate(&dataset).map_err(|e| e.to_string()), Ok(()));
        assert_eq!(read("synthetic", &text).expect("reads back"), dataset);
    }

    #[test]
    fn columns_in_any_order_with_whitespace_bom_crlf_and_blank_lines() {
        let text = "\u{feff} v_ge_mm_s , P_s_kPa,v_ac_mm_s\r\n\r\n 2.3 ,120,\"5.8\" \r\n   \r\n0,110,5.8\r\n";
        let dataset = read("t.csv", text).expect("valid");
        let rows: Vec<_> = dataset
            .rows
            .iter()
            .map(|r| {
                (
                    r.pressure_kpa,
                    r.channel_velocity_mm_s,
                    r.catheter_velocity_mm_s,
                    r.tip_velocity_mm_s,
                    r.row,
                )
            })
            .collect();
        assert_eq!(
            rows,
            [(120.0, 5.8, None, 2.3, 3), (110.0, 5.8, None, 0.0, 5)]
        );
    }

    #[test]
    fn empty_catheter_field_is_no_catheter() {
        let dataset = read(
            "t.csv",
            "v_ct_mm_s,P_s_kPa,v_ac_mm_s,v_ge_mm_s\n,120,5.8,2.3\n1.8,110,5.8,0.9\n",
        )
        .expect("valid");
        assert_eq!(dataset.rows[0].catheter_velocity_mm_s, None);
        assert_eq!(dataset.rows[1].catheter_velocity_mm_s, Some(1.8));
    }

    #[test]
    fn a_withdrawing_catheter_may_drag_the_tip_backwards() {
        let dataset = read(
            "t.csv",
            "P_s_kPa,v_ac_mm_s,v_ct_mm_s,v_ge_mm_s\n110,5.8,-2,-1\n",
        )
        .expect("valid");
        assert_eq!(dataset.rows[0].tip_velocity_mm_s, -1.0);
    }

    /// The message of reading `text`, with the line and column the error reports.
    fn error(text: &str) -> (String, Option<usize>, Option<String>) {
        let error = read("t.csv", text).expect_err("must be refused");
        (
            error.to_string(),
            error.line(),
            error.column().map(str::to_owned),
        )
    }

    const HEADER: &str = "P_s_kPa,v_ac_mm_s,v_ct_mm_s,v_ge_mm_s\n";

    fn row_error(rows: &str) -> (String, Option<usize>, Option<String>) {
        error(&format!("{HEADER}120,5.8,,2.3\n{rows}"))
    }

    #[test]
    fn empty_file() {
        let expected = "t.csv: the file is empty; expected the header \
                        `P_s_kPa,v_ac_mm_s,v_ct_mm_s,v_ge_mm_s` and one row per measurement";
        assert_eq!(error(""), (expected.into(), None, None));
        assert_eq!(error(" \n\n"), (expected.into(), None, None));
    }

    #[test]
    fn header_only() {
        assert_eq!(
            error(HEADER),
            (
                "t.csv:1: a header but no measurements after it".into(),
                Some(1),
                None
            )
        );
        assert_eq!(
            error("P_s_kPa,v_ac_mm_s,v_ge_mm_s\n\n  \n"),
            (
                "t.csv:1: a header but no measurements after it".into(),
                Some(1),
                None
            )
        );
    }

    #[test]
    fn missing_column() {
        assert_eq!(
            error("P_s_kPa,v_ac_mm_s,v_ct_mm_s\n120,5.8,\n"),
            (
                "t.csv:1: column `v_ge_mm_s`: required, but the header has only \
                 `P_s_kPa`, `v_ac_mm_s`, `v_ct_mm_s`"
                    .into(),
                Some(1),
                Some("v_ge_mm_s".into())
            )
        );
    }

    #[test]
    fn unknown_column() {
        assert_eq!(
            error("P_s_kPa,v_ac_mm_s,v_ct_mm_S,v_ge_mm_s\n120,5.8,,2.3\n"),
            (
                "t.csv:1: column `v_ct_mm_S`: not a column of this format (did you mean \
                 `v_ct_mm_s`?); the columns are `P_s_kPa`, `v_ac_mm_s`, `v_ct_mm_s` (optional) \
                 and `v_ge_mm_s`"
                    .into(),
                Some(1),
                Some("v_ct_mm_S".into())
            )
        );
        assert_eq!(
            error("P_s_kPa,v_ac_mm_s,v_ge_mm_s,trial\n120,5.8,2.3,1\n").0,
            "t.csv:1: column `trial`: not a column of this format; the columns are `P_s_kPa`, \
             `v_ac_mm_s`, `v_ct_mm_s` (optional) and `v_ge_mm_s`"
        );
    }

    #[test]
    fn duplicate_column() {
        assert_eq!(
            error("P_s_kPa,v_ac_mm_s,v_ge_mm_s,P_s_kPa\n120,5.8,2.3,120\n"),
            (
                "t.csv:1: column `P_s_kPa`: appears twice in the header".into(),
                Some(1),
                Some("P_s_kPa".into())
            )
        );
    }

    #[test]
    fn comment_lines() {
        let message = "comment lines are not part of the format; put provenance in a README \
                       beside the data";
        assert_eq!(
            error(&format!("# Table III\n{HEADER}120,5.8,,2.3\n")),
            (format!("t.csv:1: {message}"), Some(1), None)
        );
        assert_eq!(
            row_error("# 125 kPa repeated\n"),
            (format!("t.csv:3: {message}"), Some(3), None)
        );
    }

    #[test]
    fn too_few_fields() {
        assert_eq!(
            row_error("125,5.8,\n"),
            (
                "t.csv:3: column `v_ge_mm_s`: missing: the row has 3 fields where the header \
                 has 4"
                    .into(),
                Some(3),
                Some("v_ge_mm_s".into())
            )
        );
    }

    #[test]
    fn too_many_fields() {
        assert_eq!(
            row_error("125,5.8,,2.7,\n"),
            (
                "t.csv:3: the row has 5 fields where the header has 4".into(),
                Some(3),
                None
            )
        );
    }

    #[test]
    fn missing_value() {
        assert_eq!(
            row_error("125,,,2.7\n"),
            (
                "t.csv:3: column `v_ac_mm_s`: no value".into(),
                Some(3),
                Some("v_ac_mm_s".into())
            )
        );
    }

    #[test]
    fn not_a_number() {
        assert_eq!(
            row_error("125,5.8,,2,7\n").0,
            "t.csv:3: the row has 5 fields where the header has 4"
        );
        assert_eq!(
            row_error("125 kPa,5.8,,2.7\n"),
            (
                "t.csv:3: column `P_s_kPa`: `125 kPa` is not a number".into(),
                Some(3),
                Some("P_s_kPa".into())
            )
        );
        assert_eq!(
            row_error("125,5.8,fast,2.7\n").0,
            "t.csv:3: column `v_ct_mm_s`: `fast` is not a number"
        );
    }

    #[test]
    fn not_finite() {
        assert_eq!(
            row_error("125,5.8,,NaN\n"),
            (
                "t.csv:3: column `v_ge_mm_s`: `NaN` is not a finite number".into(),
                Some(3),
                Some("v_ge_mm_s".into())
            )
        );
        assert_eq!(
            row_error("125,5.8,-inf,2.7\n").0,
            "t.csv:3: column `v_ct_mm_s`: `-inf` is not a finite number"
        );
    }

    #[test]
    fn negative_pressure() {
        assert_eq!(
            row_error("\n-125,5.8,,2.7\n"),
            (
                "t.csv:4: column `P_s_kPa`: -125 is negative: the supply pressure cannot be \
                 negative (suction inverts the robot rather than growing it)"
                    .into(),
                Some(4),
                Some("P_s_kPa".into())
            )
        );
    }

    #[test]
    fn lines_count_blank_lines_before_the_header() {
        assert_eq!(
            error(&format!("\n\r\n{HEADER}\n120,5.8,,x\n")).0,
            "t.csv:5: column `v_ge_mm_s`: `x` is not a number"
        );
    }

    #[test]
    fn negative_channel_velocity() {
        assert_eq!(
            row_error("125,-5.8,,2.7\n"),
            (
                "t.csv:3: column `v_ac_mm_s`: -5.8 is negative: the active channel cannot run \
                 backwards in a growth experiment (that is retraction)"
                    .into(),
                Some(3),
                Some("v_ac_mm_s".into())
            )
        );
    }

    #[test]
    fn negative_tip_velocity() {
        let expected = "t.csv:3: column `v_ge_mm_s`: -2.7 is negative: the tip cannot run \
                        backwards at steady state unless a withdrawing catheter (negative \
                        v_ct_mm_s) drags it";
        assert_eq!(
            row_error("125,5.8,,-2.7\n"),
            (expected.into(), Some(3), Some("v_ge_mm_s".into()))
        );
        assert_eq!(row_error("125,5.8,1.8,-2.7\n").0, expected);
        // A static tip is zero, of either sign.
        assert!(read("t.csv", &format!("{HEADER}110,5.8,,-0\n")).is_ok());
    }

    #[test]
    fn unreadable_file() {
        let error = read_file(Path::new("/nonexistent/table3.csv")).expect_err("no such file");
        assert!(matches!(error.kind(), DataErrorKind::Io(_)));
        assert!(
            error
                .to_string()
                .starts_with("/nonexistent/table3.csv: cannot read the file: "),
            "{error}"
        );
    }

    #[test]
    fn validate_synthetic_data() {
        let mut dataset = bundled("table6.csv");
        dataset.name = "synthetic".into();
        dataset.rows[3].tip_velocity_mm_s = f64::NAN;
        assert_eq!(
            validate(&dataset).map_err(|e| e.to_string()),
            Err("synthetic:5: column `v_ge_mm_s`: `NaN` is not a finite number".into())
        );
        dataset.rows[3].tip_velocity_mm_s = -0.05;
        assert_eq!(
            validate(&dataset).map_err(|e| e.to_string()),
            Err(
                "synthetic:5: column `v_ge_mm_s`: -0.05 is negative: the tip cannot run \
                 backwards at steady state unless a withdrawing catheter (negative v_ct_mm_s) \
                 drags it"
                    .into()
            )
        );
        dataset.rows.clear();
        assert_eq!(
            validate(&dataset).map_err(|e| e.to_string()),
            Err("synthetic: a header but no measurements after it".into())
        );
    }

    mod properties {
        use super::super::*;
        use proptest::prelude::*;

        fn measurement() -> impl Strategy<Value = Measurement> {
            (
                0.0..1e3f64,
                0.0..50.0f64,
                proptest::option::of(-50.0..50.0f64),
                0.0..50.0f64,
            )
                .prop_map(|(pressure, channel, catheter, tip)| Measurement {
                    pressure_kpa: pressure,
                    channel_velocity_mm_s: channel,
                    catheter_velocity_mm_s: catheter,
                    tip_velocity_mm_s: tip,
                    row: 0,
                })
        }

        proptest! {
            /// Whatever the text, reading returns a dataset or an error; it never panics.
            #[test]
            fn read_never_panics(text in "[-0-9a-zA-Z_.,#\"\\r\\n \t\u{feff}]{0,80}") {
                let _ = read("fuzz.csv", &text);
                let _ = read("fuzz.csv", &format!("{}\n{text}", COLUMNS.join(",")));
            }

            /// Every valid dataset reads back from what `write` makes of it, exactly.
            #[test]
            fn write_then_read(mut rows in proptest::collection::vec(measurement(), 1..20)) {
                for (index, row) in rows.iter_mut().enumerate() {
                    row.row = index + 2;
                }
                let dataset = Dataset { name: "synthetic".into(), rows };
                prop_assert!(validate(&dataset).is_ok());
                let again = read("synthetic", &write(&dataset));
                prop_assert_eq!(again.map_err(|e| e.to_string()), Ok(dataset));
            }
        }
    }
}
