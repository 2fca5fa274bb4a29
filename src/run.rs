//! The commands that do more than print one document: `simulate` (a trajectory, a plot,
//! the run's figures on standard error), `extend` (a merged model file), `discover` (with
//! a progress bar on a terminal) and `reproduce` (the main job's files and plots).

use std::path::{Path, PathBuf};

use bondgraph_core::DiagnosticKind;
use bondgraph_eversion::main_job::{self, Reproduced};
use bondgraph_view::{
    Failure, count, discover, json, plot, print, read_source, simulate, trajectory, write_file,
};

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
fn progress_bar(models: u64) -> indicatif::ProgressBar {
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

/// Runs the main job on the bundled files, writing nothing, with a progress bar on a terminal.
fn reproduce_all() -> Result<Reproduced, Failure> {
    let progress = progress_bar(main_job::DISCREPANCY_MODELS as u64);
    let reproduced = main_job::reproduce_all(&|| progress.inc(1))
        .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()));
    progress.finish_and_clear();
    reproduced
}

/// `bondgraph reproduce`: runs the main job and writes its results under `out`. What it
/// computes, and the flagship's files it is computed from, are the study's
/// ([`bondgraph_eversion::main_job`]).
pub(crate) fn reproduce(out: &Path, as_json: bool) -> Result<(), Failure> {
    let started = std::time::Instant::now();
    let reproduced = reproduce_all()?;
    let elapsed = started.elapsed();
    let text = json(&reproduced.document)?;
    let discovery = &reproduced.discovery;
    discover::write_outputs(&out.join("discrepancy"), discovery, &json(discovery)?)?;
    write_file(&out.join("report.md"), &reproduced.report())?;
    write_file(&out.join("reproduce.json"), &text)?;
    let mut written = vec!["report.md".to_string()];
    for (name, table) in reproduced.tables() {
        write_file(&out.join(name), &table)?;
        written.push(name.to_string());
    }
    for (stem, trajectory, title) in reproduced.fig6() {
        write_file(
            &out.join(format!("{stem}.csv")),
            &trajectory::to_csv(trajectory),
        )?;
        let svg = plot::plot_svg(trajectory, &title, &[]).map_err(|e| {
            Failure::message(DiagnosticKind::Io, format!("cannot plot {stem}: {e}"))
        })?;
        write_file(&out.join(format!("{stem}.svg")), &svg)?;
    }
    let stems = reproduced.fig6().map(|(stem, _, _)| stem);
    written.extend(stems.iter().map(|stem| format!("{stem}.svg")));
    written.extend(stems.iter().map(|stem| format!("{stem}.csv")));
    written.push("reproduce.json".to_string());
    if as_json {
        print(&text);
    } else {
        let report = out.join("report.md");
        print(&reproduced.summary(&report.display().to_string()));
        print(&format!(
            "\nwritten to {}/: {} ({:.0} ms)\n",
            out.display(),
            written.join(", "),
            elapsed.as_secs_f64() * 1e3
        ));
    }
    Ok(())
}
