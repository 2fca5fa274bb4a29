//! `bondgraph reproduce`: the main job. What it computes, and the flagship's files it is
//! computed from, are the study's ([`bondgraph_eversion::main_job`]); this writes the results
//! and draws the plots.

use std::path::Path;

use bondgraph_core::DiagnosticKind;
use bondgraph_eversion::main_job::{self, Reproduced};

use bondgraph_view::{Failure, discover, json, plot, print, trajectory, write_file};

/// Runs the main job on the bundled files, writing nothing, with a progress bar on a terminal.
pub(crate) fn reproduce_all() -> Result<Reproduced, Failure> {
    let progress = crate::run::progress_bar(main_job::DISCREPANCY_MODELS as u64);
    let reproduced = main_job::reproduce_all(&|| progress.inc(1))
        .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()));
    progress.finish_and_clear();
    reproduced
}

/// Runs the main job and writes its results under `out`.
pub(crate) fn run(out: &Path, as_json: bool) -> Result<(), Failure> {
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
