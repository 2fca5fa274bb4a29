//! `bondgraph simulate`: a model driven by a scenario, and its trajectory as CSV, JSON or a
//! plot.
//!
//! Here rather than in the binary so that the Python bindings return and plot exactly what
//! the command line writes (the same axis labels, the same panels).

use std::sync::Arc;
use std::time::Duration;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::scenario::Scenario;
use bondgraph_core::source::SourceFile;
use bondgraph_solver::Trajectory;

use crate::{Failure, plot, trajectory};

/// A scenario run: the scenario as loaded (the model with its edits) and the trajectory.
pub struct Simulated {
    /// The scenario, its model edited as it says.
    pub scenario: Scenario,
    /// The run.
    pub trajectory: Trajectory,
    /// The solver's wall time (the loading excluded).
    pub elapsed: Duration,
}

/// Loads the scenario in `scenario` against the model in `model` and runs it.
///
/// # Errors
/// A failure pointing into either file for a scenario that does not fit the model, or the
/// solver's message when the run cannot go on.
pub fn simulate(model: &Arc<SourceFile>, scenario: &Arc<SourceFile>) -> Result<Simulated, Failure> {
    let loaded = bondgraph_ron::scenario::load(scenario, model)
        .map_err(|d| Failure::with_sources(d, &[model, scenario]))?;
    let started = std::time::Instant::now();
    let trajectory = bondgraph_solver::scenario::run(&loaded, false)
        .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()))?;
    Ok(Simulated {
        elapsed: started.elapsed(),
        scenario: loaded,
        trajectory,
    })
}

impl Simulated {
    /// `--format json`: the whole trajectory, samples included.
    pub fn json(&self) -> serde_json::Value {
        trajectory::to_json(
            &self.trajectory,
            self.scenario.model.name(),
            &self.scenario.name,
        )
    }

    /// `--format csv`.
    pub fn csv(&self) -> String {
        trajectory::to_csv(&self.trajectory)
    }

    /// The plot's title: `MODEL: scenario NAME`.
    pub fn title(&self) -> String {
        format!(
            "{}: scenario {}",
            self.scenario.model.name(),
            self.scenario.name
        )
    }

    /// `--plot` with `--panel` for each of `panels` (each `out1,out2`; none: one panel per
    /// output): the outputs against time, the modes shaded, each axis saying what its
    /// output is and its unit where the model's units tell them.
    ///
    /// # Errors
    /// A failure naming a panel's unknown output, or when there is nothing to plot.
    pub fn plot(&self, panels: &[String]) -> Result<String, Failure> {
        let panels = plot::panels(&self.trajectory, panels)
            .map_err(|e| Failure::message(DiagnosticKind::BadOutput, e))?;
        let mut labelled = self.trajectory.clone();
        for name in &mut labelled.output_names {
            if let Some(record) = self.scenario.record.iter().find(|r| r.name() == *name) {
                *name = crate::unit_label::axis_label(&self.scenario.model, record);
            }
        }
        plot::plot_svg(&labelled, &self.title(), &panels)
            .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot plot: {e}")))
    }
}
