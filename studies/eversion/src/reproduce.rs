//! The main job: the flagship against the paper, side by side.
//!
//! The paper reports, for each experiment of its Tables III and VI, the measured tip velocity
//! and its own simulated one, and describes the events of its Fig. 6. This module predicts the
//! same from the two models of `models/eversion/` (the flagship `robot.ron`, and `paper.ron`,
//! the structure of the paper's printed equations), computes the errors against the
//! measurements, checks that removing the parasitic tip mass changes no table cell, and
//! works out, with numbers, where the paper's own simulated column departs from what its
//! Table IV parameters give. Everything reported is computed here; the narrative in
//! [`Reproduction::report`] only arranges the numbers.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_ron::model::reduction;
use bondgraph_solver::parasitic::{self, Parasitic};
use bondgraph_solver::{Simulator, Trajectory};
use serde::Serialize;

use bondgraph_fit::data::{self, Dataset, Measurement};
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::predict::Predictor;

use crate::columns::{self, catheter, channel, pressure, tip};

/// A named text: a file's name and contents (the binary embeds them).
#[derive(Clone, Copy, Debug)]
pub struct Named<'a> {
    /// The file's name, for messages.
    pub name: &'a str,
    /// Its contents.
    pub text: &'a str,
}

/// Everything the main job reads.
#[derive(Clone, Copy, Debug)]
pub struct Bundle<'a> {
    /// The flagship model.
    pub robot: Named<'a>,
    /// The paper's structure.
    pub paper: Named<'a>,
    /// The experimental protocol.
    pub experiment: Named<'a>,
    /// Table III, measured.
    pub table3: Named<'a>,
    /// Table III, the paper's simulated column.
    pub table3_sim: Named<'a>,
    /// Table VI, measured.
    pub table6: Named<'a>,
    /// Table VI, the paper's simulated column.
    pub table6_sim: Named<'a>,
    /// The Fig. 6 scenario.
    pub fig6: Named<'a>,
}

/// One experiment with every value side by side (mm/s, kPa), the `reproduce` JSON row.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct TableRow {
    /// Tank pressure, kPa.
    pub P_s_kPa: f64,
    /// Active-channel velocity, mm/s.
    pub v_ac_mm_s: f64,
    /// Catheter velocity, mm/s (`None`: no catheter).
    pub v_ct_mm_s: Option<f64>,
    /// Measured tip velocity.
    pub exp_mm_s: f64,
    /// The paper's simulated tip velocity.
    pub paper_sim_mm_s: f64,
    /// The flagship's prediction.
    pub model_mm_s: f64,
    /// The paper's structure's prediction.
    pub paper_model_mm_s: f64,
}

/// Root-mean-square errors against the measurements, mm/s.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Errors {
    /// Which table (and columns).
    pub table: String,
    /// Number of experiments.
    pub cells: usize,
    /// The flagship against the measurements.
    pub model_mm_s: f64,
    /// The paper's structure against the measurements.
    pub paper_model_mm_s: f64,
    /// The paper's own simulation against the measurements.
    pub paper_sim_mm_s: f64,
}

/// The parasitic-storage check: the flagship without its tip mass, on every cell.
#[derive(Clone, Debug)]
pub struct ReductionCheck {
    /// What was found parasitic and removed.
    pub removed: Vec<Parasitic>,
    /// The largest difference over all table cells between the full and reduced models, mm/s.
    pub largest_difference_mm_s: f64,
    /// The number of cells compared.
    pub cells: usize,
}

/// A straight line `v = slope (P_s - onset)` through simulated cells, and what it implies.
#[derive(Clone, Debug, PartialEq)]
pub struct PressureLine {
    /// The cells it goes through (`(P_s kPa, v mm/s)`).
    pub cells: Vec<(f64, f64)>,
    /// Its slope, mm/s per kPa.
    pub slope: f64,
    /// The pressure where it reaches zero, kPa.
    pub onset_kpa: f64,
    /// The largest distance of a cell from the line, mm/s.
    pub largest_residual: f64,
    /// The viscous coefficient that slope implies, `b = A/slope`, N·s/m.
    pub implied_b: f64,
    /// The Coulomb force that onset implies, `F_C = A P_onset`, N.
    pub implied_coulomb: f64,
}

/// What the numbers say, for the report.
#[derive(Clone, Debug)]
pub struct Findings {
    /// Table IV's own line in the pressure-driven region (slope `A/b`, onset `F_C/A`).
    pub table4_line: (f64, f64),
    /// The line through the paper's simulated pressure-driven cells of Table III.
    pub paper_sim_line: Option<PressureLine>,
    /// Cells of Table III where the paper's simulation and the flagship differ by more than
    /// 0.05 mm/s: `(P_s, v_ac, paper sim, model)`.
    pub table3_disagreements: Vec<(f64, f64, f64, f64)>,
    /// The same for Table VI: `(v_ct, paper sim, model)`.
    pub table6_disagreements: Vec<(f64, f64, f64)>,
    /// Table IV's parameters.
    pub parameters: Table4,
}

/// The flagship's values of the parameters the paper estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table4 {
    /// Face area, m².
    pub area: f64,
    /// Breakaway force at the nozzle, N.
    pub breakaway: f64,
    /// Coulomb force at the nozzle, N.
    pub coulomb: f64,
    /// Viscous coefficient, N·s/m.
    pub viscous: f64,
}

/// Fig. 6 run by both models.
#[derive(Clone, Debug)]
pub struct Fig6 {
    /// The flagship's trajectory.
    pub robot: Trajectory,
    /// The paper's structure's trajectory.
    pub paper: Trajectory,
}

/// Everything `bondgraph reproduce` reports.
#[derive(Clone, Debug)]
pub struct Reproduction {
    /// Table III, side by side.
    pub table3: Vec<TableRow>,
    /// Table VI, side by side.
    pub table6: Vec<TableRow>,
    /// Errors against the measurements.
    pub errors: Vec<Errors>,
    /// Fig. 6.
    pub fig6: Fig6,
    /// The parasitic-storage check.
    pub reduction: ReductionCheck,
    /// What the numbers say.
    pub findings: Findings,
}

/// Why the main job failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReproduceError {
    /// A bundled model or scenario that does not load: core's located diagnostics.
    #[error("{0}")]
    Model(#[from] bondgraph_core::diagnostics::Diagnostics),
    /// The experiment does not fit a model, or a row cannot be predicted.
    #[error("{0}")]
    Experiment(#[from] bondgraph_fit::experiment::ExperimentError),
    /// A bundled data file that does not read.
    #[error("{0}")]
    Data(#[from] bondgraph_fit::data::DataError),
    /// A simulation that fails.
    #[error("{0}")]
    Simulation(String),
    /// The bundled files do not fit together.
    #[error("{0}")]
    Bundle(String),
}

fn error(e: impl std::fmt::Display) -> ReproduceError {
    ReproduceError::Simulation(e.to_string())
}

/// Runs the main job.
///
/// # Errors
/// When a bundled file does not read, or a simulation fails.
pub fn reproduce(bundle: &Bundle<'_>) -> Result<Reproduction, ReproduceError> {
    let load = |named: Named<'_>| -> Result<(Model, Arc<SourceFile>), ReproduceError> {
        let source = SourceFile::new(named.name, named.text);
        Ok((bondgraph_ron::model::load_source(&source)?, source))
    };
    let experiment = Experiment::parse(bundle.experiment.name, bundle.experiment.text)?;
    if !columns::matches(&experiment) {
        return Err(ReproduceError::Bundle(format!(
            "{}: the main job needs the columns {:?} and `{}`",
            bundle.experiment.name,
            columns::CONDITIONS,
            columns::TIP
        )));
    }
    let read = |named: Named<'_>| data::read(named.name, named.text, &experiment);
    let (robot, robot_source) = load(bundle.robot)?;
    let (paper, paper_source) = load(bundle.paper)?;
    let robot_predictor = Predictor::new(robot.clone(), &robot_source, &experiment)?;
    let paper_predictor = Predictor::new(paper, &paper_source, &experiment)?;

    let table = |exp: &Dataset, sim: &Dataset| -> Result<Vec<TableRow>, ReproduceError> {
        let model = robot_predictor.predict(&exp.rows)?;
        let structure = paper_predictor.predict(&exp.rows)?;
        exp.rows
            .iter()
            .enumerate()
            .map(|(i, row)| {
                let simulated = matching(sim, row).ok_or_else(|| {
                    ReproduceError::Bundle(format!(
                        "{}: no simulated value for row {}",
                        sim.name, row.row
                    ))
                })?;
                Ok(TableRow {
                    P_s_kPa: pressure(row),
                    v_ac_mm_s: channel(row),
                    v_ct_mm_s: catheter(row),
                    exp_mm_s: tip(row),
                    paper_sim_mm_s: simulated,
                    model_mm_s: model[i][0],
                    paper_model_mm_s: structure[i][0],
                })
            })
            .collect()
    };
    let table3 = table(&read(bundle.table3)?, &read(bundle.table3_sim)?)?;
    let table6 = table(&read(bundle.table6)?, &read(bundle.table6_sim)?)?;

    let mut errors = vec![
        errors_of("Table III", &table3),
        errors_of("Table VI", &table6),
    ];
    for v_ac in [5.8, 8.7, 11.6] {
        let column: Vec<TableRow> = table3
            .iter()
            .filter(|r| r.v_ac_mm_s == v_ac)
            .cloned()
            .collect();
        if !column.is_empty() {
            errors.push(errors_of(
                &format!("Table III, v_ac = {v_ac} mm/s"),
                &column,
            ));
        }
    }

    let fig6 = Fig6 {
        robot: run_fig6(bundle, bundle.robot)?,
        paper: run_fig6(bundle, bundle.paper)?,
    };
    let reduction = reduction_check(&robot, &robot_source, &experiment, bundle, &table3, &table6)?;
    let findings = findings(&robot, &table3, &table6);
    Ok(Reproduction {
        table3,
        table6,
        errors,
        fig6,
        reduction,
        findings,
    })
}

/// The paper's simulated value for the conditions of `row`.
fn matching(sim: &Dataset, row: &Measurement) -> Option<f64> {
    sim.rows
        .iter()
        .find(|s| s.conditions == row.conditions)
        .map(tip)
}

fn rmse(pairs: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (sum, count) = pairs.fold((0.0, 0usize), |(s, n), (a, b)| {
        (s + (a - b) * (a - b), n + 1)
    });
    if count == 0 {
        f64::NAN
    } else {
        (sum / count as f64).sqrt()
    }
}

fn errors_of(table: &str, rows: &[TableRow]) -> Errors {
    Errors {
        table: table.to_string(),
        cells: rows.len(),
        model_mm_s: rmse(rows.iter().map(|r| (r.model_mm_s, r.exp_mm_s))),
        paper_model_mm_s: rmse(rows.iter().map(|r| (r.paper_model_mm_s, r.exp_mm_s))),
        paper_sim_mm_s: rmse(rows.iter().map(|r| (r.paper_sim_mm_s, r.exp_mm_s))),
    }
}

fn run_fig6(bundle: &Bundle<'_>, model: Named<'_>) -> Result<Trajectory, ReproduceError> {
    let scenario_source = SourceFile::new(bundle.fig6.name, bundle.fig6.text);
    let model_source = SourceFile::new(model.name, model.text);
    let loaded = bondgraph_ron::scenario::load(&scenario_source, &model_source)?;
    bondgraph_solver::scenario::run(&loaded, false).map_err(error)
}

fn reduction_check(
    robot: &Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    bundle: &Bundle<'_>,
    table3: &[TableRow],
    table6: &[TableRow],
) -> Result<ReductionCheck, ReproduceError> {
    let mut simulator = Simulator::new(robot, Vec::new());
    let removed = parasitic::find(&mut simulator, 1e6).map_err(error)?;
    let names: Vec<String> = removed.iter().map(|p| p.element.clone()).collect();
    if names.is_empty() {
        return Ok(ReductionCheck {
            removed,
            largest_difference_mm_s: 0.0,
            cells: 0,
        });
    }
    let reduced = reduction::without_storage(robot, source, &names)?;
    let predictor = Predictor::new(reduced.model, &reduced.source, experiment)?;
    let mut largest: f64 = 0.0;
    let mut cells = 0;
    for (named, rows) in [(bundle.table3, table3), (bundle.table6, table6)] {
        let dataset = data::read(named.name, named.text, experiment)?;
        let predicted = predictor.predict(&dataset.rows)?;
        for (p, row) in predicted.iter().zip(rows) {
            largest = largest.max((p[0] - row.model_mm_s).abs());
            cells += 1;
        }
    }
    Ok(ReductionCheck {
        removed,
        largest_difference_mm_s: largest,
        cells,
    })
}

fn parameter(model: &Model, name: &str) -> f64 {
    model
        .parameters()
        .iter()
        .find(|p| p.name == name)
        .map_or(f64::NAN, |p| p.value)
}

/// Least-squares line `v = s P + c` through points.
fn line(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    if sxx == 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, my - slope * mx))
}

fn findings(robot: &Model, table3: &[TableRow], table6: &[TableRow]) -> Findings {
    let parameters = Table4 {
        area: parameter(robot, "A"),
        breakaway: parameter(robot, "F_S_ge"),
        coulomb: parameter(robot, "F_C_ge"),
        viscous: parameter(robot, "b"),
    };
    // Table IV's line: v = (A P - F_C)/b, in mm/s per kPa and kPa.
    let table4_line = (
        parameters.area * 1e3 / parameters.viscous * 1e3,
        parameters.coulomb / parameters.area / 1e3,
    );
    // The paper's simulated cells that lie strictly between static and the channel's limit:
    // the pressure-driven region of its own simulation.
    let cells: Vec<(f64, f64)> = table3
        .iter()
        .filter(|r| r.paper_sim_mm_s > 0.0 && r.paper_sim_mm_s < r.v_ac_mm_s / 2.0 - 0.1)
        .map(|r| (r.P_s_kPa, r.paper_sim_mm_s))
        .collect();
    let paper_sim_line = line(&cells).map(|(slope, intercept)| {
        let largest_residual = cells
            .iter()
            .map(|(p, v)| (v - (slope * p + intercept)).abs())
            .fold(0.0, f64::max);
        let onset_kpa = -intercept / slope;
        PressureLine {
            cells: cells.clone(),
            slope,
            onset_kpa,
            largest_residual,
            implied_b: parameters.area * 1e3 / (slope * 1e-3),
            implied_coulomb: parameters.area * onset_kpa * 1e3,
        }
    });
    let table3_disagreements = table3
        .iter()
        .filter(|r| (r.paper_sim_mm_s - r.model_mm_s).abs() > 0.05)
        .map(|r| (r.P_s_kPa, r.v_ac_mm_s, r.paper_sim_mm_s, r.model_mm_s))
        .collect();
    let table6_disagreements = table6
        .iter()
        .filter(|r| (r.paper_sim_mm_s - r.model_mm_s).abs() > 0.05)
        .map(|r| {
            (
                r.v_ct_mm_s.unwrap_or(f64::NAN),
                r.paper_sim_mm_s,
                r.model_mm_s,
            )
        })
        .collect();
    Findings {
        table4_line,
        paper_sim_line,
        table3_disagreements,
        table6_disagreements,
        parameters,
    }
}
