//! Measured data, read from and written to CSV, against the columns an experiment names.
//!
//! Calibration, residuals and model selection all start from a table of measurements: the
//! conditions that were set and what was observed. This module is the single place where such
//! a table enters the program, so it is where typos must be caught: a wrong number that slipped
//! through would be fitted like any other, and nothing downstream could tell it from physics.
//! Every error names the file, the line and the column.
//!
//! # Format
//!
//! The contract of `DESIGN.md`: CSV with a header row naming the columns the experiment
//! ([`Experiment`]) names: its condition columns, its `absent` columns, its observed columns,
//! and for a time series its time column. Columns may come in any order (they are found by
//! name); whitespace around names and values is ignored; a UTF-8 byte-order mark and blank
//! lines are skipped. Lines may end with `\n`, `\r\n` or a lone `\r`; messages give the
//! file's own line numbers. An `absent` column may be left out of the header altogether (every
//! row then has it empty). Other columns (signals a rig records that the experiment does not
//! compare, annotations) are not read: [`Dataset::ignored`] lists them, for a note.
//!
//! What is refused, and why:
//!
//! - **A column the experiment names differently only in letter case** (`tau_mnm` for
//!   `tau_mNm`) when the header lacks the experiment's spelling: an `absent` column is
//!   optional, so a misspelt one would otherwise be ignored and every row silently read as
//!   "removed".
//! - **Comment lines** (`#`): the contract has none; provenance goes in a README beside the data.
//! - **Rows with too few or too many fields**, empty values outside `absent` columns,
//!   non-numbers, non-finite numbers (`NaN`, `inf`), and numbers whose value in SI units
//!   (the experiment's factor times the cell) is not finite (`1.797e308` kPa).
//!
//! ```
//! use bondgraph_fit::data;
//! use bondgraph_fit::experiment::Experiment;
//!
//! let experiment = Experiment::parse("e.ron", r#"Experiment(
//!     kind: Steady,
//!     conditions: [("u_V", "u", 1.0)],
//!     observed: [("w_rad_s", "flow:shaft", 1.0)],
//! )"#).unwrap();
//! let dataset = data::read("d.csv", "w_rad_s,u_V\n10.5,12\n", &experiment).unwrap();
//! assert_eq!(dataset.rows[0].conditions, [Some(12.0)]);
//! assert_eq!(dataset.rows[0].observed, [10.5]);
//! let error = data::read("d.csv", "u_V,w_rad_s\n12,fast\n", &experiment).unwrap_err();
//! assert_eq!(error.to_string(), "d.csv:2: column `w_rad_s`: `fast` is not a number");
//! ```

use std::fmt;
use std::io::Read;
use std::path::Path;
use std::sync::Arc;

use bondgraph_core::limits::{MAX_CELL_BYTES, MAX_DATA_FILE_BYTES, MAX_DATA_ROWS};

use crate::experiment::Experiment;

/// One measurement: the conditions that were set and what was observed.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// One cell per condition column of the experiment
    /// ([`Experiment::condition_columns`]), in the column's units; `None` for an empty
    /// `absent` cell.
    pub conditions: Vec<Option<f64>>,
    /// One value per observed column, in the column's units.
    pub observed: Vec<f64>,
    /// The time column's value (a time series' sample), in its units.
    pub time: Option<f64>,
    /// Line of the file this row was read from, 1-based (the header is line 1 in a file
    /// without leading blank lines), for messages that point back at the data.
    pub row: usize,
    /// The file it was read from, as named in messages.
    pub file: Arc<str>,
}

/// A table of measurements, named after the file it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// The name used in messages, normally the file name.
    pub name: String,
    /// The condition columns, as [`Measurement::conditions`] holds them.
    pub conditions: Vec<String>,
    /// The observed columns, as [`Measurement::observed`] holds them.
    pub observed: Vec<String>,
    /// The time column, for a time series.
    pub time: Option<String>,
    /// The measurements in file order.
    pub rows: Vec<Measurement>,
    /// Columns of the files that the experiment does not name, `(file, column)`: not read.
    pub ignored: Vec<(String, String)>,
}

impl Dataset {
    /// Joins datasets read against one experiment (several `--data` files), keeping where
    /// each row came from; named `a.csv + b.csv`.
    ///
    /// # Panics
    /// When `parts` is empty or their columns differ (they were read against different
    /// experiments).
    pub fn join(parts: Vec<Dataset>) -> Dataset {
        let mut parts = parts.into_iter();
        let mut joined = parts.next().expect("at least one dataset");
        for part in parts {
            assert_eq!(part.conditions, joined.conditions, "one experiment");
            joined.name = format!("{} + {}", joined.name, part.name);
            joined.rows.extend(part.rows);
            joined.ignored.extend(part.ignored);
        }
        joined
    }

    /// A note for each file with columns the experiment does not name: `d.csv: column
    /// `T_amb` is not in the experiment; ignored`.
    pub fn notes(&self) -> Vec<String> {
        let mut notes: Vec<(String, Vec<&str>)> = Vec::new();
        for (file, column) in &self.ignored {
            match notes.iter_mut().find(|(f, _)| f == file) {
                Some((_, columns)) => columns.push(column),
                None => notes.push((file.clone(), vec![column])),
            }
        }
        notes
            .into_iter()
            .map(|(file, columns)| {
                let names = columns
                    .iter()
                    .map(|c| format!("`{c}`"))
                    .collect::<Vec<_>>()
                    .join(", ");
                let (noun, verb) = if columns.len() == 1 {
                    ("column", "is")
                } else {
                    ("columns", "are")
                };
                format!("{file}: {noun} {names} {verb} not in the experiment; ignored")
            })
            .collect()
    }
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
    /// The text is not well-formed CSV (e.g. an unbalanced quote).
    Malformed(String),
    /// A byte that is not UTF-8, at the error's line and this column (in characters).
    NotUtf8 {
        /// The column, from 1.
        column: usize,
        /// The byte.
        byte: u8,
    },
    /// Nothing at all, not even a header.
    Empty {
        /// The columns the experiment expects.
        expected: Vec<String>,
    },
    /// A header, but no measurements.
    NoRows,
    /// A line starting with `#`.
    Comment,
    /// A required column is not in the header.
    MissingColumn {
        /// The columns that the header does have.
        found: Vec<String>,
    },
    /// The header names a column that the experiment spells otherwise only in letter case,
    /// and lacks the experiment's spelling (a typo, not an extra column).
    UnknownColumn {
        /// The experiment's column this one differs from only in letter case, if any.
        did_you_mean: Option<String>,
        /// The experiment's columns.
        columns: Vec<String>,
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
    /// The file is larger than [`bondgraph_core::limits::MAX_DATA_FILE_BYTES`]; it was not
    /// read.
    TooLarge {
        /// The limit, in bytes.
        limit: u64,
    },
    /// More rows than [`bondgraph_core::limits::MAX_DATA_ROWS`]; the error's line is the
    /// first one past the limit.
    TooManyRows {
        /// The limit.
        limit: usize,
    },
    /// A cell longer than [`bondgraph_core::limits::MAX_CELL_BYTES`].
    CellTooLong {
        /// Its length, in bytes.
        length: usize,
        /// The limit.
        limit: usize,
    },
    /// A column name in the header longer than [`bondgraph_core::limits::MAX_CELL_BYTES`].
    NameTooLong {
        /// Its length, in bytes.
        length: usize,
        /// The limit.
        limit: usize,
    },
    /// A value whose SI value (the experiment's factor times it) is not finite.
    OutOfRange {
        /// The text found.
        text: String,
        /// The experiment's factor.
        factor: f64,
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
        if let DataErrorKind::NotUtf8 { column, .. } = self.kind {
            write!(f, ":{column}")?;
        }
        if let Some(column) = &self.column {
            write!(f, ": column `{column}`")?;
        }
        write!(f, ": {}", self.kind)
    }
}

impl std::error::Error for DataError {}

fn quoted(columns: &[String]) -> String {
    columns
        .iter()
        .map(|c| format!("`{c}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl fmt::Display for DataErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(error) => write!(f, "cannot read the file: {error}"),
            Self::Malformed(message) => write!(f, "malformed CSV: {message}"),
            Self::NotUtf8 { byte, .. } => write!(
                f,
                "byte {byte:#04x} is not valid UTF-8 (files must be UTF-8 text)"
            ),
            Self::Empty { expected } => write!(
                f,
                "the file is empty; expected the header `{}` and one row per measurement",
                expected.join(",")
            ),
            Self::NoRows => write!(f, "a header but no measurements after it"),
            Self::Comment => write!(
                f,
                "comment lines are not part of the format; put provenance in a README beside the data"
            ),
            Self::MissingColumn { found } => {
                write!(f, "required, but the header has only {}", quoted(found))
            }
            Self::UnknownColumn {
                did_you_mean,
                columns,
            } => {
                write!(f, "not a column of this experiment")?;
                if let Some(name) = did_you_mean {
                    write!(f, " (did you mean `{name}`?)")?;
                }
                write!(f, "; its columns are {}", quoted(columns))
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
            Self::TooLarge { limit } => write!(
                f,
                "the file is larger than the limit of {limit} bytes for a data file"
            ),
            Self::TooManyRows { limit } => write!(
                f,
                "more measurements than the limit of {limit} rows of a data file"
            ),
            Self::CellTooLong { length, limit } => {
                write!(f, "a cell of {length} bytes, over the limit of {limit}")
            }
            Self::NameTooLong { length, limit } => write!(
                f,
                "a column name of {length} bytes in the header, over the limit of {limit}"
            ),
            Self::OutOfRange { text, factor } => write!(
                f,
                "`{text}` times the experiment's factor {factor} is not a finite number in SI units"
            ),
        }
    }
}

/// What each column of the file is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// The `k`-th condition column, with its factor (1 for an `absent` column without one).
    Condition(usize, f64),
    /// The `k`-th observed column, with its factor.
    Observed(usize, f64),
    /// The time column.
    Time(f64),
    /// A column the experiment does not name: not read.
    Ignored,
}

/// Where each column is in the file's rows.
struct Layout {
    /// The role of each field of the header.
    roles: Vec<(String, Role, bool)>,
    conditions: usize,
    observed: usize,
    width: usize,
    names: Vec<String>,
}

/// The experiment's columns: `(name, role, may be empty)`.
fn columns(experiment: &Experiment) -> Vec<(String, Role, bool)> {
    let mut columns = Vec::new();
    for (k, column) in experiment.condition_columns().iter().enumerate() {
        let factor = experiment
            .conditions
            .iter()
            .find(|c| c.column == *column)
            .map_or(1.0, |c| c.factor);
        columns.push((
            column.to_string(),
            Role::Condition(k, factor),
            experiment.may_be_empty(column),
        ));
    }
    for (k, observed) in experiment.observed.iter().enumerate() {
        columns.push((
            observed.column.clone(),
            Role::Observed(k, observed.factor),
            false,
        ));
    }
    if let Some((time, factor)) = experiment.time() {
        columns.push((time.to_string(), Role::Time(factor), false));
    }
    columns
}

/// Reads a dataset from CSV text against `experiment`. `name` is used in messages (normally
/// the file name) and becomes the dataset's name.
///
/// # Errors
///
/// A [`DataError`] naming the line and column of the first problem found: see the module
/// documentation for what is refused.
pub fn read(name: &str, text: &str, experiment: &Experiment) -> Result<Dataset, DataError> {
    let expected = columns(experiment);
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(DataError::new(
            name,
            None,
            None,
            DataErrorKind::Empty {
                expected: expected.iter().map(|c| c.0.clone()).collect(),
            },
        ));
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
    let layout = layout(name, header_line, &header, &expected)?;
    let file: Arc<str> = Arc::from(name);

    let mut rows = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(error) => return Err(malformed(name, text, &error)),
        }
        let line = lines.of(&record);
        // A line of spaces is one empty field; a header of one column is read as such.
        if record.len() == 1 && record.get(0).is_some_and(str::is_empty) && layout.width > 1 {
            continue;
        }
        if rows.len() == MAX_DATA_ROWS {
            return Err(DataError::new(
                name,
                Some(line),
                None,
                DataErrorKind::TooManyRows {
                    limit: MAX_DATA_ROWS,
                },
            ));
        }
        rows.push(row(name, &file, line, &layout, &record)?);
    }
    if rows.is_empty() {
        return Err(DataError::new(
            name,
            Some(header_line),
            None,
            DataErrorKind::NoRows,
        ));
    }
    let ignored = layout
        .roles
        .iter()
        .filter(|(_, role, _)| *role == Role::Ignored)
        .map(|(column, _, _)| (name.to_owned(), column.clone()))
        .collect();
    Ok(Dataset {
        ignored,
        name: name.to_owned(),
        conditions: experiment
            .condition_columns()
            .iter()
            .map(|c| c.to_string())
            .collect(),
        observed: experiment
            .observed
            .iter()
            .map(|o| o.column.clone())
            .collect(),
        time: experiment.time().map(|(t, _)| t.to_string()),
        rows,
    })
}

/// Reads a dataset from a CSV file, named in messages and in the dataset by its path.
///
/// # Errors
///
/// As [`read`], and [`DataErrorKind::Io`] when the file cannot be read.
pub fn read_file(path: &Path, experiment: &Experiment) -> Result<Dataset, DataError> {
    let name = path.display().to_string();
    let io = |error| DataError::new(&name, None, None, DataErrorKind::Io(error));
    let too_large = || {
        DataError::new(
            &name,
            None,
            None,
            DataErrorKind::TooLarge {
                limit: MAX_DATA_FILE_BYTES,
            },
        )
    };
    let file = std::fs::File::open(path).map_err(io)?;
    // A regular file's length is known before it is read; a pipe's is not, so the read
    // itself stops one byte past the limit.
    if file.metadata().map_err(io)?.len() > MAX_DATA_FILE_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(MAX_DATA_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_DATA_FILE_BYTES {
        return Err(too_large());
    }
    let text = String::from_utf8(bytes).map_err(|error| {
        let valid = error.utf8_error().valid_up_to();
        let byte = error.as_bytes()[valid];
        let before = std::str::from_utf8(&error.as_bytes()[..valid]).unwrap_or_default();
        // Counted as records are (a lone `\r` ends a line), not as model files are.
        let line = Lines::new(before).at(before.len());
        let column = before
            .rsplit(['\n', '\r'])
            .next()
            .unwrap_or("")
            .chars()
            .count()
            + 1;
        DataError::new(
            &name,
            Some(line),
            None,
            DataErrorKind::NotUtf8 { column, byte },
        )
    })?;
    read(&name, &text, experiment)
}

/// Writes a dataset in the format [`read`] reads: the header (condition columns, observed
/// columns, then the time column), then one line per measurement, an empty field for `None`.
/// Numbers are written in the shortest form that reads back to the same `f64`, so
/// `read(write(d))` gives `d`'s values again (and its `row` numbers too, when they are the
/// consecutive lines of a file without blank lines).
pub fn write(dataset: &Dataset) -> String {
    let mut header: Vec<&str> = dataset.conditions.iter().map(String::as_str).collect();
    header.extend(dataset.observed.iter().map(String::as_str));
    header.extend(dataset.time.as_deref());
    let mut csv = CsvWriter::new(header);
    for measurement in &dataset.rows {
        let mut fields: Vec<String> = measurement
            .conditions
            .iter()
            .map(|v| v.map(|v| v.to_string()).unwrap_or_default())
            .collect();
        fields.extend(measurement.observed.iter().map(f64::to_string));
        if dataset.time.is_some() {
            fields.push(measurement.time.map(|t| t.to_string()).unwrap_or_default());
        }
        csv.row(fields);
    }
    csv.finish()
}

/// A CSV table being written: the one writer behind every CSV file the program writes (data
/// files, simulated trajectories, the study's tables), so that all of them quote alike.
///
/// Fields are separated by commas and lines end with `\n`. A field is quoted as RFC 4180 asks
/// (`"`, with inner quotes doubled) only when it holds a comma, a double quote or a line
/// break, so that a column named `effort:a,b` stays one column and every other field is
/// written as given. The caller formats the numbers.
#[derive(Debug)]
pub struct CsvWriter(csv::Writer<Vec<u8>>);

impl CsvWriter {
    /// A table whose first line is `header`.
    pub fn new<I, S>(header: I) -> Self
    where
        I: IntoIterator<Item = S>,
        S: AsRef<str>,
    {
        let writer = csv::WriterBuilder::new()
            .terminator(csv::Terminator::Any(b'\n'))
            .quote_style(csv::QuoteStyle::Necessary)
            // Rows are the caller's to keep as wide as the header; a short one is written
            // as it is rather than refused.
            .flexible(true)
            .from_writer(Vec::new());
        let mut table = Self(writer);
        table.row(header);
        table
    }

    /// Appends one line.
    pub fn row<I, S>(&mut self, fields: I)
    where
        I: IntoIterator<Item = S>,
        S: AsRef<str>,
    {
        let fields: Vec<S> = fields.into_iter().collect();
        self.0
            .write_record(fields.iter().map(|f| f.as_ref().as_bytes()))
            .expect("a flexible CSV writer into memory cannot fail");
    }

    /// The text written.
    pub fn finish(self) -> String {
        let bytes = self
            .0
            .into_inner()
            .expect("flushing into memory cannot fail");
        String::from_utf8(bytes).expect("every field written was UTF-8")
    }
}

/// Line numbers of records, counted from their byte offsets.
///
/// The `csv` crate's own line numbers are not usable for messages: a record's position is where
/// the previous record ended, before any skipped blank lines, and its line count does not
/// advance on `\r\n` line ends. So this counts the line ends itself, from the reported byte
/// offset past the blank lines (which contain only line-end characters) to the record. A line
/// ends where the reader ends records: at `\n`, `\r\n` or a lone `\r` (classic Mac files).
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
            let line_end = match self.text[position] {
                b'\n' => true,
                b'\r' => self.text.get(position + 1) != Some(&b'\n'),
                _ => false,
            };
            if line_end {
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

fn layout(
    name: &str,
    line: usize,
    header: &csv::StringRecord,
    expected: &[(String, Role, bool)],
) -> Result<Layout, DataError> {
    let error = |column: &str, kind| DataError::new(name, Some(line), Some(column), kind);
    if header.get(0).is_some_and(|first| first.starts_with('#')) {
        return Err(DataError::new(
            name,
            Some(line),
            None,
            DataErrorKind::Comment,
        ));
    }
    if let Some(long) = header.iter().find(|name| name.len() > MAX_CELL_BYTES) {
        return Err(DataError::new(
            name,
            Some(line),
            None,
            DataErrorKind::NameTooLong {
                length: long.len(),
                limit: MAX_CELL_BYTES,
            },
        ));
    }
    let names: Vec<String> = header.iter().map(str::to_owned).collect();
    let known: Vec<String> = expected.iter().map(|c| c.0.clone()).collect();
    let mut roles = Vec::new();
    for (index, column) in names.iter().enumerate() {
        if names[..index].contains(column) {
            return Err(error(column, DataErrorKind::DuplicateColumn));
        }
        let Some(found) = expected.iter().find(|c| &c.0 == column) else {
            // A column the header lacks, spelt otherwise only in letter case, is a typo, not
            // an extra column.
            if let Some(name) = known
                .iter()
                .find(|k| k.eq_ignore_ascii_case(column) && !names.contains(k))
            {
                return Err(error(
                    column,
                    DataErrorKind::UnknownColumn {
                        did_you_mean: Some(name.clone()),
                        columns: known.clone(),
                    },
                ));
            }
            roles.push((column.clone(), Role::Ignored, true));
            continue;
        };
        roles.push(found.clone());
    }
    for (column, _, optional) in expected {
        if !optional && !names.contains(column) {
            return Err(error(
                column,
                DataErrorKind::MissingColumn {
                    found: names.clone(),
                },
            ));
        }
    }
    let count = |f: fn(&Role) -> bool| expected.iter().filter(|c| f(&c.1)).count();
    Ok(Layout {
        roles,
        conditions: count(|r| matches!(r, Role::Condition(..))),
        observed: count(|r| matches!(r, Role::Observed(..))),
        width: names.len(),
        names,
    })
}

fn row(
    name: &str,
    file: &Arc<str>,
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
    let mut measurement = Measurement {
        conditions: vec![None; layout.conditions],
        observed: vec![f64::NAN; layout.observed],
        time: None,
        row: line,
        file: file.clone(),
    };
    for (index, (column, role, optional)) in layout.roles.iter().enumerate() {
        if *role == Role::Ignored {
            continue;
        }
        let text = record.get(index).unwrap_or_default();
        let column = Some(column.as_str());
        if text.len() > MAX_CELL_BYTES {
            return Err(error(
                column,
                DataErrorKind::CellTooLong {
                    length: text.len(),
                    limit: MAX_CELL_BYTES,
                },
            ));
        }
        let value = if text.is_empty() {
            if *optional {
                None
            } else {
                return Err(error(column, DataErrorKind::MissingValue));
            }
        } else {
            let value: f64 = text.parse().map_err(|_| {
                error(
                    column,
                    DataErrorKind::NotANumber {
                        text: text.to_owned(),
                    },
                )
            })?;
            if !value.is_finite() {
                return Err(error(
                    column,
                    DataErrorKind::NotFinite {
                        text: text.to_owned(),
                    },
                ));
            }
            let factor = match role {
                Role::Condition(_, f) | Role::Observed(_, f) | Role::Time(f) => *f,
                Role::Ignored => 1.0,
            };
            if !(value * factor).is_finite() {
                return Err(error(
                    column,
                    DataErrorKind::OutOfRange {
                        text: text.to_owned(),
                        factor,
                    },
                ));
            }
            Some(value)
        };
        match role {
            Role::Condition(k, _) => measurement.conditions[*k] = value,
            Role::Observed(k, _) => measurement.observed[*k] = value.expect("required"),
            Role::Time(_) => measurement.time = value,
            Role::Ignored => {}
        }
    }
    Ok(measurement)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motor whose load torque column may be empty (no load coupled).
    fn experiment() -> Experiment {
        Experiment::parse(
            "e.ron",
            r#"Experiment(
                kind: Steady,
                conditions: [("u_V", "u", 1.0), ("tau_mNm", "tau_load", 0.001)],
                absent: [("tau_mNm", ["load"])],
                observed: [("w_rad_s", "flow:shaft", 1.0)],
            )"#,
        )
        .unwrap()
    }

    fn read(name: &str, text: &str) -> Result<Dataset, DataError> {
        super::read(name, text, &experiment())
    }

    #[test]
    fn columns_in_any_order_with_whitespace_bom_crlf_and_blank_lines() {
        let text = "\u{feff} w_rad_s , u_V,tau_mNm\r\n\r\n 2.3 ,12,\"5.8\" \r\n   \r\n0,0,\r\n";
        let dataset = read("t.csv", text).expect("valid");
        let rows: Vec<_> = dataset
            .rows
            .iter()
            .map(|r| (r.conditions.clone(), r.observed.clone(), r.row))
            .collect();
        assert_eq!(
            rows,
            [
                (vec![Some(12.0), Some(5.8)], vec![2.3], 3),
                (vec![Some(0.0), None], vec![0.0], 5)
            ]
        );
        assert_eq!(dataset.conditions, ["u_V", "tau_mNm"]);
        assert_eq!(&*dataset.rows[0].file, "t.csv");
    }

    /// A byte that is not UTF-8 is located at its line and column (in characters), as in a
    /// model file; it once said only "stream did not contain valid UTF-8".
    #[test]
    fn a_byte_that_is_not_utf8_is_located() {
        let dir = std::env::temp_dir().join(format!("bondgraph-data-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("latin1.csv");
        // Line 3 is `6,\xb51,3`: the third character is a Latin-1 "µ".
        std::fs::write(&path, b"u_V,tau_mNm,w_rad_s\n12,,100.5\n6,\xb51,3\n").unwrap();
        let error = read_file(&path, &experiment()).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!(
                "{}:3:3: byte 0xb5 is not valid UTF-8 (files must be UTF-8 text)",
                path.display()
            )
        );
        // The same with the lone `\r` line ends of classic Mac files.
        std::fs::write(&path, b"u_V,tau_mNm,w_rad_s\r12,,100.5\r6,\xb51,3\r").unwrap();
        let error = read_file(&path, &experiment()).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!(
                "{}:3:3: byte 0xb5 is not valid UTF-8 (files must be UTF-8 text)",
                path.display()
            )
        );
    }

    #[test]
    fn an_absent_column_may_be_left_out() {
        let dataset = read("t.csv", "u_V,w_rad_s\n12,100\n").expect("valid");
        assert_eq!(dataset.rows[0].conditions, [Some(12.0), None]);
    }

    /// A column name holding a comma or a double quote is quoted (RFC 4180), so that the
    /// header still has one field per column; it was once written bare, which split
    /// `w,rad_s` into two columns.
    #[test]
    fn written_names_with_commas_and_quotes_are_quoted() {
        let dataset = Dataset {
            name: "t.csv".into(),
            conditions: vec!["u,V".into()],
            observed: vec!["w \"rad/s\"".into()],
            time: Some("t_s".into()),
            rows: vec![Measurement {
                conditions: vec![Some(12.0)],
                observed: vec![-0.5],
                time: None,
                file: Arc::from("t.csv"),
                row: 2,
            }],
            ignored: Vec::new(),
        };
        assert_eq!(
            write(&dataset),
            "\"u,V\",\"w \"\"rad/s\"\"\",t_s\n12,-0.5,\n"
        );
    }

    #[test]
    fn written_then_read_back_exactly() {
        let dataset = read(
            "t.csv",
            "u_V,tau_mNm,w_rad_s\n12,,100.5\n6,0.1,0.30000000000000004\n",
        )
        .expect("valid");
        let text = write(&dataset);
        assert_eq!(
            text,
            "u_V,tau_mNm,w_rad_s\n12,,100.5\n6,0.1,0.30000000000000004\n"
        );
        assert_eq!(read("t.csv", &text).unwrap(), dataset);
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

    const HEADER: &str = "u_V,tau_mNm,w_rad_s\n";

    fn row_error(rows: &str) -> (String, Option<usize>, Option<String>) {
        error(&format!("{HEADER}12,,100\n{rows}"))
    }

    #[test]
    fn empty_file_and_header_only() {
        let expected = "t.csv: the file is empty; expected the header `u_V,tau_mNm,w_rad_s` \
                        and one row per measurement";
        assert_eq!(error(" \n\n"), (expected.into(), None, None));
        assert_eq!(
            error(HEADER),
            (
                "t.csv:1: a header but no measurements after it".into(),
                Some(1),
                None
            )
        );
    }

    #[test]
    fn missing_unknown_and_duplicate_columns() {
        assert_eq!(
            error("u_V,tau_mNm\n12,\n"),
            (
                "t.csv:1: column `w_rad_s`: required, but the header has only `u_V`, `tau_mNm`"
                    .into(),
                Some(1),
                Some("w_rad_s".into())
            )
        );
        assert_eq!(
            error("u_V,tau_mnm,w_rad_s\n12,,100\n").0,
            "t.csv:1: column `tau_mnm`: not a column of this experiment (did you mean \
             `tau_mNm`?); its columns are `u_V`, `tau_mNm`, `w_rad_s`"
        );
        assert_eq!(
            error("u_V,w_rad_s,u_V\n12,100,12\n"),
            (
                "t.csv:1: column `u_V`: appears twice in the header".into(),
                Some(1),
                Some("u_V".into())
            )
        );
    }

    /// Item 3 of issue 31: a rig records more signals than an experiment compares; the
    /// columns the experiment does not name are not read, and a note names them.
    #[test]
    fn extra_columns_are_ignored_with_a_note() {
        let dataset = read(
            "t.csv",
            "T_amb_C,u_V,w_rad_s,i_A,tau_mNm\n21.5,12,100.5,x,\n21.6,6,50,,1\n",
        )
        .expect("extra columns are not an error");
        let rows: Vec<_> = dataset
            .rows
            .iter()
            .map(|r| (r.conditions.clone(), r.observed.clone()))
            .collect();
        assert_eq!(
            rows,
            [
                (vec![Some(12.0), None], vec![100.5]),
                (vec![Some(6.0), Some(1.0)], vec![50.0])
            ]
        );
        assert_eq!(
            dataset.notes(),
            ["t.csv: columns `T_amb_C`, `i_A` are not in the experiment; ignored"]
        );
        let joined = Dataset::join(vec![
            dataset,
            read("u.csv", "u_V,w_rad_s,pos\n1,2,3\n").unwrap(),
        ]);
        assert_eq!(
            joined.notes(),
            [
                "t.csv: columns `T_amb_C`, `i_A` are not in the experiment; ignored",
                "u.csv: column `pos` is not in the experiment; ignored"
            ]
        );
        assert!(
            read("t.csv", "u_V,w_rad_s\n1,2\n")
                .unwrap()
                .notes()
                .is_empty()
        );
    }

    #[test]
    fn comment_lines() {
        let message = "comment lines are not part of the format; put provenance in a README \
                       beside the data";
        assert_eq!(
            error(&format!("# runs\n{HEADER}12,,100\n")),
            (format!("t.csv:1: {message}"), Some(1), None)
        );
        assert_eq!(
            row_error("# repeated\n"),
            (format!("t.csv:3: {message}"), Some(3), None)
        );
    }

    #[test]
    fn rows_of_the_wrong_width() {
        assert_eq!(
            row_error("12,\n"),
            (
                "t.csv:3: column `w_rad_s`: missing: the row has 2 fields where the header has 3"
                    .into(),
                Some(3),
                Some("w_rad_s".into())
            )
        );
        assert_eq!(
            row_error("12,,100,\n").0,
            "t.csv:3: the row has 4 fields where the header has 3"
        );
    }

    #[test]
    fn bad_cells_name_their_row_and_column() {
        assert_eq!(
            row_error(",,100\n"),
            (
                "t.csv:3: column `u_V`: no value".into(),
                Some(3),
                Some("u_V".into())
            )
        );
        assert_eq!(
            row_error("12 V,,100\n").0,
            "t.csv:3: column `u_V`: `12 V` is not a number"
        );
        assert_eq!(
            row_error("12,,NaN\n").0,
            "t.csv:3: column `w_rad_s`: `NaN` is not a finite number"
        );
        assert_eq!(
            error(&format!("\n\r\n{HEADER}\n12,-inf,1\n")).0,
            "t.csv:5: column `tau_mNm`: `-inf` is not a finite number"
        );
    }

    /// The line of a bad cell is the file's own line, whatever ends its lines and however
    /// many blank lines come before: `\n`, `\r\n`, and the lone `\r` of classic Mac
    /// exports (which the reader splits records at, and once counted as no line at all).
    #[test]
    fn a_bad_cell_is_on_its_physical_line_whatever_ends_the_lines() {
        let lines = [
            "u_V,tau_mNm,w_rad_s",
            "12,,100",
            "",
            "12,,200",
            "  ",
            "",
            "12,,x",
            "",
        ];
        for end in ["\n", "\r\n", "\r"] {
            let (message, line, column) = error(&lines.join(end));
            assert_eq!(
                (line, column.as_deref()),
                (Some(7), Some("w_rad_s")),
                "{end:?}: {message}"
            );
        }
        // Blank lines before the header, and a quoted cell spanning two lines.
        assert_eq!(
            error("\r\n\r\nu_V,tau_mNm,w_rad_s\r\n\"12\r\n\",,1\r\n\r\n12,,x\r\n").1,
            Some(7)
        );
        assert_eq!(error("\r\ru_V,tau_mNm,w_rad_s\r12,,x\r").1, Some(4));
    }

    #[test]
    fn a_cell_too_large_for_si_units_names_its_row_and_column() {
        // 1.797e308 is a finite double, but in N m (times 0.001) it is fine, and as a
        // voltage factor 1 it is fine too: only a factor above 1 overflows.
        let experiment = Experiment::parse(
            "e.ron",
            r#"Experiment(kind: Steady, conditions: [("P_kPa", "P", 1000.0)],
                observed: [("y", "flow:x", 1.0)])"#,
        )
        .unwrap();
        let error = super::read("t.csv", "P_kPa,y\n120,1\n1.797e308,1\n", &experiment)
            .expect_err("overflows");
        assert_eq!(
            error.to_string(),
            "t.csv:3: column `P_kPa`: `1.797e308` times the experiment's factor 1000 is not a \
             finite number in SI units"
        );
        assert!(read("t.csv", &format!("{HEADER}1.797e308,1.797e308,1\n")).is_ok());
    }

    #[test]
    fn unreadable_file() {
        let error = read_file(Path::new("/nonexistent/d.csv"), &experiment()).expect_err("no file");
        assert!(matches!(error.kind(), DataErrorKind::Io(_)));
        assert!(
            error
                .to_string()
                .starts_with("/nonexistent/d.csv: cannot read the file: "),
            "{error}"
        );
    }

    /// Item 18 of the hardening issue: a file of more rows than the limit is refused at the
    /// first row past it, while reading, naming the limit.
    #[test]
    fn more_rows_than_the_limit_are_refused() {
        use bondgraph_core::limits::MAX_DATA_ROWS;
        let mut text = String::from(HEADER);
        for _ in 0..MAX_DATA_ROWS {
            text.push_str("1,,2\n");
        }
        assert_eq!(read("t.csv", &text).unwrap().rows.len(), MAX_DATA_ROWS);
        text.push_str("1,,2\n");
        let line = MAX_DATA_ROWS + 2;
        assert_eq!(
            error(&text),
            (
                format!(
                    "t.csv:{line}: more measurements than the limit of {MAX_DATA_ROWS} rows \
                     of a data file"
                ),
                Some(line),
                None
            )
        );
    }

    /// A cell (or a header name) longer than the limit is refused with its length, and not
    /// echoed whole.
    #[test]
    fn a_cell_longer_than_the_limit_is_refused() {
        use bondgraph_core::limits::MAX_CELL_BYTES;
        let long = "1".repeat(MAX_CELL_BYTES + 1);
        let (message, line, column) = row_error(&format!("{long},,100\n"));
        assert_eq!(
            message,
            format!(
                "t.csv:3: column `u_V`: a cell of {} bytes, over the limit of {MAX_CELL_BYTES}",
                MAX_CELL_BYTES + 1
            )
        );
        assert_eq!((line, column.as_deref()), (Some(3), Some("u_V")));
        let name = "x".repeat(100_000);
        let message = error(&format!("u_V,w_rad_s,{name}\n1,2,3\n")).0;
        assert_eq!(
            message,
            "t.csv:1: a column name of 100000 bytes in the header, over the limit of \
             256"
            .replace("256", &MAX_CELL_BYTES.to_string())
        );
        // At the limit, a cell is read (a number padded with zeros).
        let padded = format!("1.{}", "0".repeat(MAX_CELL_BYTES - 2));
        assert!(read("t.csv", &format!("{HEADER}{padded},,100\n")).is_ok());
    }

    /// A file larger than the limit is refused before it is read: this one is sparse, so it
    /// takes no room on the disk, and reading it would take the limit in memory.
    #[test]
    fn a_file_larger_than_the_limit_is_refused_unread() {
        use bondgraph_core::limits::MAX_DATA_FILE_BYTES;
        let dir = std::env::temp_dir().join(format!("bondgraph-data-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("huge.csv");
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(MAX_DATA_FILE_BYTES + 1).unwrap();
        let error = read_file(&path, &experiment()).expect_err("too large");
        assert!(
            matches!(error.kind(), DataErrorKind::TooLarge { limit } if *limit == MAX_DATA_FILE_BYTES),
            "{error}"
        );
        assert_eq!(
            error.to_string(),
            format!(
                "{}: the file is larger than the limit of {MAX_DATA_FILE_BYTES} bytes for a \
                 data file",
                path.display()
            )
        );
        std::fs::remove_file(&path).unwrap();
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            /// Whatever the text, reading returns a dataset or an error; it never panics.
            #[test]
            fn read_never_panics(text in "[-0-9a-zA-Z_.,#\"\\r\\n \t\u{feff}]{0,80}") {
                let _ = read("fuzz.csv", &text);
                let _ = read("fuzz.csv", &format!("{HEADER}{text}"));
            }

            /// Every dataset reads back from what `write` makes of it, exactly.
            #[test]
            fn write_then_read(
                cells in proptest::collection::vec(
                    (-1e3..1e3f64, proptest::option::of(-50.0..50.0f64), -1e4..1e4f64), 1..20)
            ) {
                let file: Arc<str> = Arc::from("synthetic");
                let rows = cells.iter().enumerate().map(|(i, (u, tau, w))| Measurement {
                    conditions: vec![Some(*u), *tau],
                    observed: vec![*w],
                    time: None,
                    row: i + 2,
                    file: file.clone(),
                }).collect();
                let dataset = Dataset {
                    name: "synthetic".into(),
                    conditions: vec!["u_V".into(), "tau_mNm".into()],
                    observed: vec!["w_rad_s".into()],
                    time: None,
                    rows,
                    ignored: Vec::new(),
                };
                let again = super::super::read("synthetic", &write(&dataset), &experiment());
                prop_assert_eq!(again.map_err(|e| e.to_string()), Ok(dataset));
            }
        }
    }
}
