//! Parasitic storage: an inertia or compliance whose time constant is far below every other.
//!
//! A tip with an apparent mass of 5e-15 kg against a 1250 N·s/m damper has
//! a time constant of 4e-18 s, some fourteen orders of magnitude faster than anything else
//! in the model. Such storage makes the equations stiff without changing any result at the
//! time scales that matter; removing it (a massless tip whose velocity follows from a force
//! balance) is the classic singular-perturbation reduction. This module finds candidates
//! from the modes' eigen-structure; the reduction itself is a model edit
//! (`bondgraph_ron::model::reduction`), reported and optional.
//!
//! An element is parasitic when, in every reachable mode where it has a state of its own
//! (not merged with others) and the mode has other dynamics, it dominates the fastest
//! eigenvalue (largest participation factor `|V_ik (V⁻¹)_ki|`) and that eigenvalue is at least
//! `ratio` times faster than the next.

use bondgraph_core::equations::Options;
use bondgraph_core::modes;

use crate::hybrid::{SimError, Simulator};
use crate::propagate::Propagator;

/// A storage element found parasitic.
#[derive(Clone, Debug, PartialEq)]
pub struct Parasitic {
    /// The element.
    pub element: String,
    /// Its time constant (the inverse of the fastest eigenvalue it dominates), in seconds,
    /// at its slowest over the modes.
    pub time_constant: f64,
    /// The next time constant in that mode.
    pub next_time_constant: f64,
    /// How much faster it is, at least, over the modes.
    pub ratio: f64,
}

/// The parasitic storage elements of the simulator's model; `ratio` is the separation of
/// time scales required (1e6 is a reasonable default).
///
/// # Errors
/// When a reachable mode cannot be derived.
pub fn find(simulator: &mut Simulator<'_>, ratio: f64) -> Result<Vec<Parasitic>, SimError> {
    let model = simulator.model();
    let reachable = modes::reachable(model, &Options::default()).map_err(SimError::Derivation)?;
    // Per element: (flagged in every mode so far, weakest candidate).
    let mut verdicts: Vec<(String, bool, Option<Parasitic>)> = Vec::new();
    for derived in &reachable.modes {
        let numeric = simulator.mode(&derived.mode)?;
        let Propagator::Modal(modal) = &numeric.propagator else {
            continue;
        };
        let eigen = modal.eigen();
        let mut order: Vec<usize> = (0..eigen.values.len())
            .filter(|&k| eigen.values[k].norm() > 0.0)
            .collect();
        if order.len() < 2 {
            continue;
        }
        order.sort_by(|&a, &b| eigen.values[b].norm().total_cmp(&eigen.values[a].norm()));
        let (fast, next) = (order[0], order[1]);
        let dominant = (0..eigen.values.len())
            .max_by(|&i, &j| {
                let p = |i: usize| (eigen.vectors[(i, fast)] * eigen.inverse[(fast, i)]).norm();
                p(i).total_cmp(&p(j))
            })
            .unwrap_or(0);
        let separation = eigen.values[fast].norm() / eigen.values[next].norm();
        for (k, state) in derived.equations.states.iter().enumerate() {
            if !state.merged.is_empty() {
                continue;
            }
            let slot = match verdicts.iter().position(|(e, _, _)| e == &state.element) {
                Some(i) => i,
                None => {
                    verdicts.push((state.element.clone(), true, None));
                    verdicts.len() - 1
                }
            };
            let flagged = k == dominant && separation >= ratio;
            let verdict = &mut verdicts[slot];
            verdict.1 &= flagged;
            if flagged {
                let candidate = Parasitic {
                    element: state.element.clone(),
                    time_constant: 1.0 / eigen.values[fast].norm(),
                    next_time_constant: 1.0 / eigen.values[next].norm(),
                    ratio: separation,
                };
                if verdict.2.as_ref().is_none_or(|c| candidate.ratio < c.ratio) {
                    verdict.2 = Some(candidate);
                }
            }
        }
    }
    Ok(verdicts
        .into_iter()
        .filter_map(|(_, all, candidate)| if all { candidate } else { None })
        .collect())
}
