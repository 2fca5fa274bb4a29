//! `bondgraph reproduce` as the study defines it: the flagship's files built in, the paper's
//! tables and Fig. 6 reproduced ([`crate::reproduce`]), `discover` on Table III with the
//! flagship's candidate extensions, and the JSON document and tables the command writes.
//!
//! The command's binary only writes what this module computes and draws its plots; every
//! fact of the robot and its paper (which files, which extensions, the events the paper
//! reports) is here.

use bondgraph_core::source::SourceFile;
use bondgraph_fit::data;
use bondgraph_fit::discover::{self, Candidate, Discovery, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_ron::extension::Extension;
use bondgraph_solver::Trajectory;
use serde_json::json;

use crate::reproduce::{Bundle, Named, ReproduceError, Reproduction, TableRow, reproduce};

/// The bundled files, as they are in the repository.
macro_rules! bundled {
    ($path:literal) => {
        Named {
            name: $path,
            text: include_str!(concat!("../../../", $path)),
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
pub const EXTENSIONS: [Named<'static>; 8] = [
    bundled!("models/eversion/extensions/ac-fluid-displacement.ron"),
    bundled!("models/eversion/extensions/ac-sheath-drag.ron"),
    bundled!("models/eversion/extensions/catheter-pressure-friction.ron"),
    bundled!("models/eversion/extensions/catheter-viscous-slip.ron"),
    bundled!("models/eversion/extensions/pressure-dependent-friction.ron"),
    bundled!("models/eversion/extensions/supply-flow-resistance.ron"),
    bundled!("models/eversion/extensions/supply-flow-saturation.ron"),
    bundled!("models/eversion/extensions/velocity-weakening-friction.ron"),
];

/// The events of Fig. 6 as the paper's text reports them: time (s) and what happens.
pub const PAPER_FIG6_EVENTS: [(f64, &str); 3] = [
    (0.06, "State 2 -> State 4"),
    (0.1, "State 3 briefly"),
    (0.106, "catheter breaks away, State 4"),
];

/// The Fig. 6 plot's title for the model file `name` (`robot`, `paper`).
fn fig6_title(name: &str) -> String {
    format!(
        "Fig. 6 scenario, {name}.ron: v_ac = 5.8 mm/s, P_s = min(1e6 t, 1.1e5) Pa, v_ct = 6.3 mm/s"
    )
}

/// The number of models `discover` fits on Table III: the base and each extension (for a
/// progress bar).
pub const DISCREPANCY_MODELS: usize = EXTENSIONS.len() + 1;

/// `discover` on Table III: what the flagship gets wrong there, and which extension explains
/// it; `done` is called as each model is fitted and cross-validated.
///
/// # Errors
/// When a bundled file does not load or the search fails.
pub fn discrepancy(done: &(dyn Fn() + Sync)) -> Result<Discovery, ReproduceError> {
    let fail = |e: &dyn std::fmt::Display| ReproduceError::Simulation(e.to_string());
    let base = SourceFile::new(BUNDLE.robot.name, BUNDLE.robot.text);
    let experiment = Experiment::parse(BUNDLE.experiment.name, BUNDLE.experiment.text)?;
    let table3 = data::read(BUNDLE.table3.name, BUNDLE.table3.text, &experiment)?;
    let mut candidates = Vec::new();
    for named in EXTENSIONS {
        let extension = Extension::load(&SourceFile::new(named.name, named.text))?;
        candidates.push(Candidate::new(&base, &extension).map_err(|e| fail(&e))?);
    }
    discover::discover_with_progress(
        &base,
        &experiment,
        &table3,
        &candidates,
        &Settings::default(),
        done,
    )
    .map_err(|e| fail(&e))
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

/// Runs the main job on the bundled files, writing nothing; `done` is called as each model of
/// [`discrepancy`] is fitted.
///
/// # Errors
/// As [`reproduce`] and [`discrepancy`].
pub fn reproduce_all(done: &(dyn Fn() + Sync)) -> Result<Reproduced, ReproduceError> {
    let result = reproduce(&BUNDLE)?;
    let discovery = discrepancy(done)?;
    let mut document = to_json(&result);
    document["discrepancy"] = serde_json::to_value(&discovery)
        .map_err(|e| ReproduceError::Simulation(format!("cannot write JSON: {e}")))?;
    Ok(Reproduced {
        result,
        discovery,
        document,
    })
}

impl Reproduced {
    /// The report (`report.md`): the study's, then what `discover` says of Table III.
    pub fn report(&self) -> String {
        format!(
            "{}\n## What the refitted model still gets wrong on Table III (`bondgraph discover`)\n\n\
             Residual plots: `discrepancy/residuals_before.svg` (and `residuals_after.svg` when an \
             extension is selected).\n\n```text\n{}```\n",
            self.result.report(),
            self.discovery.summary()
        )
    }

    /// The summary printed on a terminal, pointing at the report written to `report`.
    pub fn summary(&self, report: &str) -> String {
        format!(
            "{}\nTable III, nozzle friction refitted, candidate extensions tried: selected {} \
             (held-out RMSE {:.3} -> {:.3} mm/s); see {report}\n",
            self.result.summary(),
            self.discovery.selected.as_deref().unwrap_or("null"),
            self.discovery.gain.rmse_heldout_before,
            self.discovery.gain.rmse_heldout_after,
        )
    }

    /// The tables side by side as CSV files: name and contents.
    pub fn tables(&self) -> [(&'static str, String); 2] {
        [
            ("table3.csv", table_csv(&self.result.table3)),
            ("table6.csv", table_csv(&self.result.table6)),
        ]
    }

    /// Fig. 6's trajectories, to write and plot: file stem, trajectory, plot title.
    pub fn fig6(&self) -> [(&'static str, &Trajectory, String); 2] {
        [
            ("fig6_robot", &self.result.fig6.robot, fig6_title("robot")),
            ("fig6_paper", &self.result.fig6.paper, fig6_title("paper")),
        ]
    }
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
            "paper_reported": PAPER_FIG6_EVENTS
                .iter()
                .map(|(t, what)| json!({"t": t, "what": what}))
                .collect::<Vec<_>>(),
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

/// A table side by side as CSV: the columns of [`TableRow`].
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
