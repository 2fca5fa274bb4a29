//! The commands that do more than print one document: `simulate` (a trajectory, a plot,
//! the run's figures on standard error), `extend` (a merged model file) and `discover` (with
//! a progress bar on a terminal).

use std::path::{Path, PathBuf};

use bondgraph_view::{Failure, count, discover, json, print, read_source, simulate, write_file};

use crate::args::SimulateFormat;

/// `bondgraph simulate`.
pub(crate) fn simulate(
    model: &Path,
    scenario: &Path,
    format: SimulateFormat,
    out: Option<&Path>,
    plot: Option<&Path>,
    panels: &[String],
) -> Result<(), Failure> {
    let run = simulate::simulate(&read_source(model)?, &read_source(scenario)?)?;
    let text = match format {
        SimulateFormat::Csv => run.csv(),
        SimulateFormat::Json => json(&run.json())?,
    };
    match out {
        Some(path) => write_file(path, &text)?,
        None => print(&text),
    }
    if let Some(path) = plot {
        write_file(path, &run.plot(panels)?)?;
    }
    let trajectory = &run.trajectory;
    eprintln!(
        "simulated {} s of '{}' in {:.3} ms: {} events, {} modes, {} segments",
        trajectory.final_time,
        run.scenario.name,
        run.elapsed.as_secs_f64() * 1e3,
        trajectory.stats.events,
        trajectory.stats.modes,
        trajectory.stats.segments
    );
    if let Some(books) = &trajectory.energy {
        // The books bound their own rounding; past a millionth of their largest term the
        // terms of the powers have cancelled (a mode whose rates differ by more than
        // rounding can tell apart), and the figures are only that good.
        let share = books.error / books.scale();
        if share > 1e-6 {
            eprintln!(
                "warning: the energy books are uncertain to {:e} J, {share:.1e} of their largest \
                 term: the terms of the powers cancel below rounding",
                books.error
            );
        }
    }
    Ok(())
}

/// Merges extensions into a model, checks the result and prints or writes it.
pub(crate) fn extend(
    model: &Path,
    extensions: &[PathBuf],
    out: Option<&Path>,
) -> Result<(), Failure> {
    use bondgraph_ron::extension::{self, Extension};
    let base = read_source(model)?;
    let mut sources = vec![base.clone()];
    let mut fragments = Vec::new();
    for path in extensions {
        let source = read_source(path)?;
        sources.push(source.clone());
        let fragment = Extension::load(&source).map_err(|d| Failure {
            diagnostics: d,
            sources: sources.clone(),
        })?;
        fragments.push(fragment);
    }
    let failure = |diagnostics| Failure {
        diagnostics,
        sources: sources.clone(),
    };
    let extended = extension::merge(&base, &fragments).map_err(failure)?;
    let merged = extended.check().map_err(failure)?;
    match out {
        Some(path) => {
            write_file(path, extended.file.text())?;
            let parts = match &merged.linear_graph() {
                Some(graph) => format!(
                    "{}, {}",
                    count(graph.nodes.len(), "node"),
                    count(graph.branches.len(), "branch")
                ),
                None => format!(
                    "{}, {}",
                    count(merged.elements().len(), "element"),
                    count(merged.bonds().len(), "bond")
                ),
            };
            eprintln!(
                "{}: model '{}' written ({parts})",
                path.display(),
                merged.name(),
            );
        }
        None => print(extended.file.text()),
    }
    Ok(())
}

/// `bondgraph discover`: the search with a progress bar, then the report.
pub(crate) fn discover(args: &discover::Args) -> Result<(), Failure> {
    let inputs = discover::inputs(
        &args.model,
        &args.data,
        args.experiment.as_deref(),
        args.extensions.as_deref(),
    )?;
    let candidates = inputs.candidates.len();
    let started = std::time::Instant::now();
    let progress = progress_bar(candidates as u64 + 1);
    let discovery = inputs.discover_within(&args.budget, args.resamples, &|| progress.inc(1));
    progress.finish_and_clear();
    discover::report(args, &discovery?, candidates, started.elapsed())
}

/// A progress bar on standard error when it is a terminal (hidden otherwise, so that logs
/// and pipes stay clean): the models fitted and cross-validated so far.
pub(crate) fn progress_bar(models: u64) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(models);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} fitting and cross-validating: {pos}/{len} models [{elapsed}]",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}
