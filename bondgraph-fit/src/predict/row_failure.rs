//! Why one row (or one run) has no prediction at a fit's trial values: the contact levels
//! judged before any simulation, and the failures a steady search reports, with their kind
//! for the count of failed trials.

use bondgraph_core::linear::Var;
use bondgraph_core::model::{ElementKind, Model};
use bondgraph_core::symbolic::RatFunc;
use bondgraph_solver::steady::{Exhausted, SteadyError};

use crate::budget::Failure;

/// A friction contact must break away at or above its Coulomb force, and neither may be
/// negative: parameter values a calibration tries can violate this where the model file's
/// values did not, and the contact then has no consistent mode. With `inputs` `None` (a
/// time series, whose inputs vary), a contact whose levels read an input is judged by their
/// difference where that reads none (both grow with a load alike).
pub(super) fn check_friction_levels(
    model: &Model,
    values: &[f64],
    inputs: Option<&[f64]>,
) -> Result<(), RowFailure> {
    let level = |form: &bondgraph_core::linear::LinearForm| -> Option<f64> {
        form.terms()
            .iter()
            .map(|(var, coefficient)| {
                let c = coefficient.eval(values);
                match var {
                    Var::Constant => Some(c),
                    Var::Input(i) => inputs.map(|u| c * u[*i as usize]),
                    _ => Some(0.0),
                }
            })
            .sum()
    };
    for id in model.element_ids() {
        let element = model.element(id);
        let ElementKind::Friction(friction) = &element.kind else {
            continue;
        };
        let contact = || element.name.clone();
        let coulomb = level(&friction.coulomb.value);
        if let Some(f_c) = coulomb
            && f_c < 0.0
        {
            return Err(RowFailure::NegativeCoulomb {
                contact: contact(),
                f_c,
            });
        }
        match (level(&friction.breakaway.value), coulomb) {
            (Some(f_s), Some(f_c)) if f_s < f_c => {
                return Err(RowFailure::FrictionLevels {
                    contact: contact(),
                    f_s,
                    f_c,
                });
            }
            (Some(_), Some(_)) => {}
            // A level reads an input the caller did not give: their difference may not.
            _ => {
                let mut gap = friction.breakaway.value.clone();
                gap.add_scaled(&friction.coulomb.value, &RatFunc::integer(-1));
                if let Some(gap) = level(&gap)
                    && gap < 0.0
                {
                    return Err(RowFailure::FrictionGap {
                        contact: contact(),
                        gap,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Why a row has no steady state, put into words only for a caller that reports it.
#[derive(Debug)]
pub(super) enum RowFailure {
    /// A contact's Coulomb force below zero.
    NegativeCoulomb { contact: String, f_c: f64 },
    /// A contact's breakaway force below its Coulomb force.
    FrictionLevels { contact: String, f_s: f64, f_c: f64 },
    /// A contact's breakaway force below its Coulomb force by `-gap` whatever the inputs
    /// its levels read.
    FrictionGap { contact: String, gap: f64 },
    /// The search failed or did not settle.
    Steady(bondgraph_solver::steady::SteadyError),
    /// This observed column's prediction is not a finite number.
    NotFinite(String),
}

impl RowFailure {
    /// The kind of failure, for the count of failed trials.
    pub(super) fn kind(&self) -> Failure {
        match self {
            RowFailure::Steady(SteadyError::NotSteady { exhausted, .. }) => match exhausted {
                Some(Exhausted::ModeChanges) => Failure::ModeChangeBudget,
                Some(Exhausted::Segments) => Failure::SegmentBudget,
                Some(Exhausted::Steps) => Failure::StepBudget,
                None => Failure::NotSteady,
            },
            RowFailure::NegativeCoulomb { .. }
            | RowFailure::FrictionLevels { .. }
            | RowFailure::FrictionGap { .. } => Failure::Inconsistent,
            RowFailure::Steady(SteadyError::Simulation(_)) | RowFailure::NotFinite(_) => {
                Failure::Simulation
            }
        }
    }
}

impl std::fmt::Display for RowFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            // The levels are in the contact's own units (a force, a torque): none is named.
            RowFailure::NegativeCoulomb { contact, f_c } => write!(
                f,
                "friction contact '{contact}': its Coulomb level {f_c} is negative (a contact needs 0 <= Coulomb <= breakaway)"
            ),
            RowFailure::FrictionLevels { contact, f_s, f_c } => write!(
                f,
                "friction contact '{contact}': its breakaway level {f_s} is below its Coulomb level {f_c} (a contact needs 0 <= Coulomb <= breakaway)"
            ),
            RowFailure::FrictionGap { contact, gap } => write!(
                f,
                "friction contact '{contact}': its breakaway level is below its Coulomb level by {} at any input (a contact needs 0 <= Coulomb <= breakaway)",
                -gap
            ),
            RowFailure::Steady(error) => write!(f, "{error}"),
            RowFailure::NotFinite(column) => {
                write!(f, "the predicted `{column}` is not a finite number")
            }
        }
    }
}
