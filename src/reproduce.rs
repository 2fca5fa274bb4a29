//! `bondgraph reproduce`: the main job, with the flagship's model and data built in.

use std::path::Path;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::model::extension::Extension;
use bondgraph_core::source::SourceFile;
use bondgraph_eversion::reproduce::{Bundle, Named, Reproduction, TableRow, reproduce};
use bondgraph_fit::data;
use bondgraph_fit::discover::{self, Candidate, Discovery, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_solver::Trajectory;
use serde_json::json;

use crate::{Failure, json, plot, print, trajectory, write_file};

/// The bundled files, as they are in the repository.
macro_rules! bundled {
    ($path:literal) => {
        Named {
            name: $path,
            text: include_str!(concat!("../", $path)),
        }
    };
}

/// The flagship's model, the paper's structure, the protocol, the data and the Fig. 6 scenario.
pub const BUNDLE: Bundle<'static> = Bundle {
    robot: bundled!("models/eversion/robot.ron"),
    paper: bundled!("models/eversion/paper.ron"),
    experiment: bundled!("models/eversion/experiment.ron"),
    table3: bundled!("models/eversion/data/table3.csv"),
    table3_sim: bundled!("models/eversion/data/table3_paper_sim.csv"),
    table6: bundled!("models/eversion/data/table6.csv"),
    table6_sim: bundled!("models/eversion/data/table6_paper_sim.csv"),
    fig6: bundled!("models/eversion/fig6.ron"),
};

/// The candidate extensions of the flagship, as they are in the repository.
const EXTENSIONS: [Named<'static>; 8] = [
    bundled!("models/eversion/extensions/ac-fluid-displacement.ron"),
    bundled!("models/eversion/extensions/ac-sheath-drag.ron"),
    bundled!("models/eversion/extensions/catheter-pressure-friction.ron"),
    bundled!("models/eversion/extensions/catheter-viscous-slip.ron"),
    bundled!("models/eversion/extensions/pressure-dependent-friction.ron"),
    bundled!("models/eversion/extensions/supply-flow-resistance.ron"),
    bundled!("models/eversion/extensions/supply-flow-saturation.ron"),
    bundled!("models/eversion/extensions/velocity-weakening-friction.ron"),
];

/// `discover` on Table III: what the flagship gets wrong there, and which extension explains it.
fn discrepancy() -> Result<Discovery, Failure> {
    let fail =
        |e: &dyn std::fmt::Display| Failure::message(DiagnosticKind::Simulation, e.to_string());
    let base = SourceFile::new(BUNDLE.robot.name, BUNDLE.robot.text);
    let experiment =
        Experiment::parse(BUNDLE.experiment.name, BUNDLE.experiment.text).map_err(|e| fail(&e))?;
    let table3 =
        data::read(BUNDLE.table3.name, BUNDLE.table3.text, &experiment).map_err(|e| fail(&e))?;
    let mut candidates = Vec::new();
    for named in EXTENSIONS {
        let extension =
            Extension::load(&SourceFile::new(named.name, named.text)).map_err(|e| fail(&e))?;
        candidates.push(Candidate::new(&base, &extension).map_err(|e| fail(&e))?);
    }
    let progress = crate::discover::progress_bar(candidates.len() as u64 + 1);
    let discovery = discover::discover_with_progress(
        &base,
        &experiment,
        &table3,
        &candidates,
        &Settings::default(),
        &|| progress.inc(1),
    )
    .map_err(|e| fail(&e));
    progress.finish_and_clear();
    discovery
}

/// The main job's results: the paper's tables and Fig. 6 reproduced, and what the refitted
/// model still gets wrong on Table III.
pub struct Reproduced {
    /// The tables, Fig. 6 and the reduction, as the study computes them.
    pub result: Reproduction,
    /// `discover` on Table III.
    pub discovery: Discovery,
    /// The command's JSON document (DESIGN.md's `reproduce` fields and more).
    pub document: serde_json::Value,
}

/// Runs the main job on the bundled files, writing nothing.
pub fn reproduce_all() -> Result<Reproduced, Failure> {
    let result = reproduce(&BUNDLE)
        .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()))?;
    let discovery = discrepancy()?;
    let mut document = to_json(&result);
    document["discrepancy"] = serde_json::to_value(&discovery)
        .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot write JSON: {e}")))?;
    Ok(Reproduced {
        result,
        discovery,
        document,
    })
}

/// Runs the main job and writes its results under `out`.
pub fn run(out: &Path, as_json: bool) -> Result<(), Failure> {
    let started = std::time::Instant::now();
    let Reproduced {
        result,
        discovery,
        document,
    } = reproduce_all()?;
    let elapsed = started.elapsed();
    let text = json(&document)?;
    let report = format!(
        "{}\n## What the refitted model still gets wrong on Table III (`bondgraph discover`)\n\n\
         Residual plots: `discrepancy/residuals_before.svg` (and `residuals_after.svg` when an \
         extension is selected).\n\n```text\n{}```\n",
        result.report(),
        discovery.summary()
    );
    crate::discover::write_outputs(&out.join("discrepancy"), &discovery, &json(&discovery)?)?;
    write_file(&out.join("report.md"), &report)?;
    write_file(&out.join("reproduce.json"), &text)?;
    write_file(&out.join("table3.csv"), &table_csv(&result.table3))?;
    write_file(&out.join("table6.csv"), &table_csv(&result.table6))?;
    for (name, trajectory) in [("robot", &result.fig6.robot), ("paper", &result.fig6.paper)] {
        write_file(
            &out.join(format!("fig6_{name}.csv")),
            &trajectory::to_csv(trajectory),
        )?;
        let svg = plot::plot_svg(
            trajectory,
            &format!(
                "Fig. 6 scenario, {name}.ron: v_ac = 5.8 mm/s, P_s = min(1e6 t, 1.1e5) Pa, v_ct = 6.3 mm/s"
            ),
            &[],
        )
        .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot plot Fig. 6: {e}")))?;
        write_file(&out.join(format!("fig6_{name}.svg")), &svg)?;
    }
    if as_json {
        print(&text);
    } else {
        print(&result.summary());
        print(&format!(
            "\nTable III, nozzle friction refitted, candidate extensions tried: selected {} \
             (held-out RMSE {:.3} -> {:.3} mm/s); see {}\n",
            discovery.selected.as_deref().unwrap_or("null"),
            discovery.gain.rmse_heldout_before,
            discovery.gain.rmse_heldout_after,
            out.join("report.md").display()
        ));
        print(&format!(
            "\nwritten to {}/: report.md, table3.csv, table6.csv, fig6_robot.svg, fig6_paper.svg, \
             fig6_robot.csv, fig6_paper.csv, reproduce.json ({:.0} ms)\n",
            out.display(),
            elapsed.as_secs_f64() * 1e3
        ));
    }
    Ok(())
}

fn events(trajectory: &Trajectory) -> serde_json::Value {
    json!(trajectory
        .events
        .iter()
        .map(|e| json!({"t": e.t, "from": e.from, "to": e.to, "element": e.element, "reason": e.reason}))
        .collect::<Vec<_>>())
}

/// The `reproduce` JSON document (DESIGN.md's fields and more).
fn to_json(result: &Reproduction) -> serde_json::Value {
    json!({
        "table3": result.table3,
        "table6": result.table6,
        "errors": result.errors,
        "fig6": {
            "events": events(&result.fig6.robot),
            "paper_model_events": events(&result.fig6.paper),
            "paper_reported": [
                {"t": 0.06, "what": "State 2 -> State 4"},
                {"t": 0.1, "what": "State 3 briefly"},
                {"t": 0.106, "what": "catheter breaks away, State 4"},
            ],
        },
        "reduction": {
            "removed": result.reduction.removed.iter().map(|p| json!({
                "element": p.element,
                "time_constant_s": p.time_constant,
                "next_time_constant_s": p.next_time_constant,
                "ratio": p.ratio,
            })).collect::<Vec<_>>(),
            "cells": result.reduction.cells,
            "largest_difference_mm_s": result.reduction.largest_difference_mm_s,
        },
    })
}

fn table_csv(rows: &[TableRow]) -> String {
    let mut csv = data::CsvWriter::new([
        "P_s_kPa",
        "v_ac_mm_s",
        "v_ct_mm_s",
        "exp_mm_s",
        "paper_sim_mm_s",
        "model_mm_s",
        "paper_model_mm_s",
    ]);
    for r in rows {
        csv.row([
            r.P_s_kPa.to_string(),
            r.v_ac_mm_s.to_string(),
            r.v_ct_mm_s.map_or(String::new(), |v| v.to_string()),
            r.exp_mm_s.to_string(),
            r.paper_sim_mm_s.to_string(),
            r.model_mm_s.to_string(),
            r.paper_model_mm_s.to_string(),
        ]);
    }
    csv.finish()
}
