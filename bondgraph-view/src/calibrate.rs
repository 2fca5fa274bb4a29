//! `bondgraph calibrate`: fit an experiment's parameters to measured data.

use std::path::{Path, PathBuf};

use bondgraph_fit::budget::Budget;
use bondgraph_fit::calibration::{self, Calibration};
use bondgraph_fit::discover::Settings;

use crate::measured::{discover_failure, inputs};
use crate::{Failure, json, print};

/// The command line of `calibrate`.
pub struct Args {
    /// The model file.
    pub model: PathBuf,
    /// The measured data files, joined.
    pub data: Vec<PathBuf>,
    /// The experiment file; `experiment.ron` beside the model if `None`.
    pub experiment: Option<PathBuf>,
    /// JSON rather than text.
    pub json: bool,
    /// The work each prediction and the fit may do.
    pub budget: Budget,
}

/// Fits the experiment's parameters of `model` (its experiment given, or `experiment.ron`
/// beside it) to the `data` files, joined.
///
/// # Errors
/// A failure naming the file, line and column of what cannot be read, or why the fit
/// cannot be made.
pub fn calibrate(
    model: &Path,
    experiment: Option<&Path>,
    data: &[PathBuf],
) -> Result<Calibration, Failure> {
    calibrate_within(model, experiment, data, &Budget::default())
}

/// [`calibrate`] within `budget`.
///
/// # Errors
/// As [`calibrate`].
pub fn calibrate_within(
    model: &Path,
    experiment: Option<&Path>,
    data: &[PathBuf],
    budget: &Budget,
) -> Result<Calibration, Failure> {
    let (base, experiment_source, experiment, dataset) = inputs(model, experiment, data)?;
    let settings = Settings {
        budget: *budget,
        ..Settings::default()
    };
    calibration::calibrate(&base, &experiment, &dataset, &settings)
        .map_err(|e| discover_failure(e, &[&experiment_source, &base]))
}

/// Runs `calibrate`.
pub fn run(args: &Args) -> Result<(), Failure> {
    let result = calibrate_within(
        &args.model,
        args.experiment.as_deref(),
        &args.data,
        &args.budget,
    )?;
    if args.json {
        print(&json(&result)?);
    } else {
        print(&result.summary());
    }
    Ok(())
}
