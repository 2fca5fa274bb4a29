//! `bondgraph discover`: a model against measured data, and the candidate extensions.

use std::path::{Path, PathBuf};

use bondgraph_core::DiagnosticKind;
use bondgraph_ron::extension::{self, Extension};
use std::sync::Arc;

use bondgraph_core::source::SourceFile;
use bondgraph_fit::discover::{self, Candidate, Discovery, Settings};

use crate::measured::discover_failure;
use crate::{Failure, json, print, read_source, residual_plot, write_file};

/// The command line of `discover`.
pub struct Args {
    /// The model file.
    pub model: PathBuf,
    /// The measured data files, joined.
    pub data: Vec<PathBuf>,
    /// The experiment file; `experiment.ron` beside the model if `None`.
    pub experiment: Option<PathBuf>,
    /// The folder of candidate extensions; `extensions/` beside the model if `None`.
    pub extensions: Option<PathBuf>,
    /// JSON rather than text.
    pub json: bool,
    /// A folder for the report, the JSON, the extended model and the residual plots.
    pub out: Option<PathBuf>,
    /// The work each prediction and each fit may do.
    pub budget: bondgraph_fit::budget::Budget,
    /// Resamples for the selection's stability: `Some(0)` none, `None` the default
    /// ([`discover::Resampling`]).
    pub resamples: Option<usize>,
}

fn fail(kind: DiagnosticKind, message: impl std::fmt::Display) -> Failure {
    Failure::message(kind, message.to_string())
}

/// Reads the library: every `*.ron` in `dir`, in name order.
pub fn library(base: &Arc<SourceFile>, dir: &Path) -> Result<Vec<Candidate>, Failure> {
    let entries = std::fs::read_dir(dir).map_err(|e| {
        fail(
            DiagnosticKind::Io,
            format!("cannot read the extensions folder '{}': {e}", dir.display()),
        )
    })?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    paths.sort();
    let mut candidates = Vec::new();
    for path in paths {
        let source = read_source(&path)?;
        let extension = Extension::load(&source).map_err(|d| Failure {
            diagnostics: d,
            sources: vec![source.clone()],
        })?;
        // Check the merge first, so that its problems are shown with the lines they point
        // at, in the base model or in the extension.
        extension::merge(base, std::slice::from_ref(&extension))
            .and_then(|extended| extended.load())
            .map_err(|d| Failure {
                diagnostics: d,
                sources: vec![base.clone(), source.clone()],
            })?;
        candidates.push(
            Candidate::new(base, &extension).map_err(|e| fail(DiagnosticKind::Simulation, e))?,
        );
    }
    Ok(candidates)
}

/// What `discover` works on: the base model, its experiment, the data joined and the
/// library of candidate extensions, all read and checked.
pub struct Inputs {
    base: Arc<SourceFile>,
    experiment_source: Arc<SourceFile>,
    experiment: bondgraph_fit::experiment::Experiment,
    dataset: bondgraph_fit::data::Dataset,
    /// The candidate extensions, in file-name order.
    pub candidates: Vec<Candidate>,
}

/// Reads `model`, its experiment (given, or `experiment.ron` beside it), the `data` files
/// (at least one) and the extensions in `extensions` (or `extensions/` beside the model).
///
/// # Errors
/// A failure naming the file, line and column of what cannot be read, or the extension
/// that does not merge with the model.
pub fn inputs(
    model: &Path,
    data: &[PathBuf],
    experiment: Option<&Path>,
    extensions: Option<&Path>,
) -> Result<Inputs, Failure> {
    let (base, experiment_source, experiment, dataset) =
        crate::measured::inputs(model, experiment, data)?;
    let folder = model.parent().unwrap_or(Path::new("."));
    let extensions = extensions.map_or_else(|| folder.join("extensions"), Path::to_path_buf);
    let candidates = library(&base, &extensions)?;
    Ok(Inputs {
        base,
        experiment_source,
        experiment,
        dataset,
        candidates,
    })
}

impl Inputs {
    /// Refits the base model and every candidate, cross-validates them and ranks them,
    /// calling `done` after each model; then reruns the selection on `resamples` resamples
    /// (`None`: the default, run when cheaper than the search; `Some(0)`: none).
    ///
    /// # Errors
    /// A failure located in the experiment or the model, or why the fits cannot be made.
    pub fn discover(
        &self,
        resamples: Option<usize>,
        done: &(dyn Fn() + Sync),
    ) -> Result<Discovery, Failure> {
        self.discover_within(&bondgraph_fit::budget::Budget::default(), resamples, done)
    }

    /// [`Inputs::discover`] within `budget`.
    ///
    /// # Errors
    /// As [`Inputs::discover`].
    pub fn discover_within(
        &self,
        budget: &bondgraph_fit::budget::Budget,
        resamples: Option<usize>,
        done: &(dyn Fn() + Sync),
    ) -> Result<Discovery, Failure> {
        let mut settings = Settings {
            budget: *budget,
            ..Settings::default()
        };
        settings.resampling.count = resamples;
        discover::discover_with_progress(
            &self.base,
            &self.experiment,
            &self.dataset,
            &self.candidates,
            &settings,
            done,
        )
        .map_err(|e| discover_failure(e, &[&self.experiment_source, &self.base]))
    }
}

/// Prints `discover`'s report (and writes it under `args.out`): the document of
/// `discovery`, made of `candidates` candidates in `elapsed`. The front end runs the search
/// ([`inputs`], [`Inputs::discover_within`]) with its own progress display.
pub fn report(
    args: &Args,
    discovery: &Discovery,
    candidates: usize,
    elapsed: std::time::Duration,
) -> Result<(), Failure> {
    let text = json(discovery)?;
    if let Some(out) = &args.out {
        write_outputs(out, discovery, &text)?;
    }
    if args.json {
        print(&text);
    } else {
        print(&discovery.summary());
        print(&format!(
            "\n{} candidates fitted and cross-validated in {:.2} s\n",
            candidates,
            elapsed.as_secs_f64()
        ));
        if let Some(out) = &args.out {
            print(&format!("written to {}/\n", out.display()));
        }
    }
    Ok(())
}

/// Writes the report, the JSON, the extended model and the residual plots.
pub fn write_outputs(out: &Path, discovery: &Discovery, json_text: &str) -> Result<(), Failure> {
    write_file(&out.join("discover.json"), json_text)?;
    write_file(&out.join("discover.txt"), &discovery.summary())?;
    if let (Some(id), Some(model)) = (&discovery.selected, &discovery.extended_model) {
        write_file(&out.join(format!("{id}.ron")), model)?;
    }
    let plot = |after: bool, column: usize| {
        let title = if after {
            format!(
                "Residuals with {}",
                discovery.selected.as_deref().unwrap_or("")
            )
        } else {
            "Residuals of the refitted base model".to_string()
        };
        let observed = (column, discovery.observed[column].as_str());
        residual_plot::residual_svg(&discovery.table, observed, &title, after)
            .map_err(|e| fail(DiagnosticKind::Io, format!("cannot plot residuals: {e}")))
    };
    // One observed column: `residuals_before.svg`; several: `residuals_before_COLUMN.svg`.
    for (k, column) in discovery.observed.iter().enumerate() {
        let suffix = if discovery.observed.len() == 1 {
            String::new()
        } else {
            format!("_{column}")
        };
        write_file(
            &out.join(format!("residuals_before{suffix}.svg")),
            &plot(false, k)?,
        )?;
        if discovery.selected.is_some() {
            write_file(
                &out.join(format!("residuals_after{suffix}.svg")),
                &plot(true, k)?,
            )?;
        }
    }
    Ok(())
}
