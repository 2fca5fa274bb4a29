//! What an event knows about the guard it crossed, for judging the modes it may lead to.
//!
//! The event locator stops where a guard's value is zero up to the accuracy of the root, so
//! the watched quantity is left with a residue of either sign (a relative velocity of a few
//! 1e-17 m/s still on the old side, say). The mode entered often watches the same quantity
//! against the same threshold the other way round (a contact reversing through zero
//! velocity: `slip-` left when `v >= 0`, `slip+` left when `v <= 0`). Judged by its value,
//! the new guard would see the residue as "already crossed" and send the contact straight
//! back, for good: a silently wrong steady state. The quantity is at its threshold by
//! construction, so such a guard is judged by its rate instead, as at any exact zero.

use bondgraph_core::guards::Watched;
use bondgraph_core::model::ElementId;

use std::sync::Arc;

use crate::numeric::{NumericGuard, NumericMode};

/// The mode an event leaves, the element that switched and why, and the guard crossed.
pub(super) struct Trigger<'a> {
    pub mode: &'a Arc<NumericMode>,
    pub element: ElementId,
    pub why: super::Why,
    pub crossed: Crossed,
}

/// The quantity an event found at its threshold.
#[derive(Clone, Copy, Debug)]
pub(super) struct Crossed {
    /// The switching element.
    pub element: ElementId,
    /// What its crossed guard watched.
    pub watched: Watched,
    /// The crossed guard's value at the event (zero up to the root's accuracy).
    pub residue: f64,
}

impl Crossed {
    /// Whether `guard`, of value `value` and rounding tolerance `tolerance` in the mode being
    /// judged, watches the crossed quantity at the crossed threshold: same element, same
    /// quantity, and a value no larger than the crossing's residue (a guard on another
    /// threshold, such as a dead band, is further away than that).
    ///
    /// A tension-only element's two guards watch one threshold in two units: taut, its
    /// tension falls to zero; slack, its extension rises to zero. Either crossing leaves the
    /// other at its threshold by construction, whatever its residue (a string going slack at
    /// an extension of +2e-19 m, its tension's root found at -2e-16 N by the guard's own
    /// evaluation, was once taut again at once, and slack, and taut: `no mode is consistent`).
    pub fn watches_as(&self, guard: &NumericGuard, value: f64, tolerance: f64) -> bool {
        let string = |w: Watched| matches!(w, Watched::Tension | Watched::SlackLength);
        guard.element == self.element
            && ((guard.watched == self.watched && value.abs() <= 2.0 * self.residue + tolerance)
                || (guard.watched != self.watched && string(guard.watched) && string(self.watched)))
    }
}
