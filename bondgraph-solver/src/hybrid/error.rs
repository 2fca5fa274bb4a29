//! Why a simulation stopped, in words that name the elements, the mode and the time.

use std::fmt;

use bondgraph_core::diagnostics::Diagnostics;

use super::{Stall, TimeScale};

/// Why a simulation stopped.
#[derive(Clone, Debug)]
pub enum SimError {
    /// A mode could not be derived.
    Derivation(Diagnostics),
    /// The inputs do not match the model.
    Inputs(String),
    /// No mode is consistent at this instant.
    NoConsistentMode {
        /// When.
        t: f64,
        /// The modes tried, in order.
        tried: Vec<String>,
        /// The elements that kept switching.
        elements: Vec<String>,
    },
    /// Too many events in too short a time.
    Chattering {
        /// When it was detected.
        t: f64,
        /// How many events.
        events: usize,
        /// Over how long.
        window: f64,
        /// The elements that switched.
        elements: Vec<String>,
        /// Why the last of them switched (the quantity at its threshold).
        reason: String,
        /// The fastest time scale of the modes entered, when the events came faster than
        /// it with the inputs steady.
        time_scale: Option<f64>,
    },
    /// No single switch is consistent, and the modes of the elements that kept switching
    /// have more combinations than the search may derive.
    TooManyCombinations {
        /// When.
        t: f64,
        /// The elements that kept switching.
        elements: Vec<String>,
        /// How many combinations, in words.
        combinations: String,
        /// The limit.
        limit: usize,
    },
    /// More events than allowed.
    TooManyEvents {
        /// When.
        t: f64,
        /// The limit.
        limit: usize,
    },
    /// More steps than allowed (integration steps and event-location samples).
    TooManySteps {
        /// The time reached.
        t: f64,
        /// The limit.
        limit: u64,
        /// The last integration step's length, on the integrated path.
        step: Option<f64>,
        /// The fastest time scale of the mode there.
        time_scale: Option<TimeScale>,
    },
    /// Time stopped advancing: integration steps under the resolution of time at `t`, or
    /// segments that ended where they began.
    Stalled {
        /// When.
        t: f64,
        /// The mode.
        mode: String,
        /// What was seen.
        cause: Stall,
    },
    /// A recorded output became infinite or not a number, the states still finite (a
    /// velocity near the largest double times a gain).
    NonFiniteOutput {
        /// When.
        t: f64,
        /// The mode.
        mode: String,
        /// The outputs concerned.
        outputs: Vec<String>,
    },
    /// A state became infinite or not a number.
    NonFinite {
        /// When.
        t: f64,
        /// The mode.
        mode: String,
        /// The states concerned.
        states: Vec<String>,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Derivation(d) => write!(f, "{d}"),
            SimError::Inputs(message) => write!(f, "{message}"),
            SimError::NoConsistentMode { t, tried, elements } => write!(
                f,
                "at t = {} s no mode is consistent: switching {} cycles through {}",
                At(*t),
                quoted(elements),
                tried.join(" -> ")
            ),
            SimError::Chattering {
                t,
                events,
                window,
                elements,
                reason,
                time_scale,
            } => {
                write!(
                    f,
                    "chattering at t = {} s: {events} events in {window:e} s",
                    At(*t)
                )?;
                if let Some(scale) = time_scale {
                    write!(
                        f,
                        " with the inputs steady, faster than the modes' fastest time scale \
                         ({scale:e} s)"
                    )?;
                }
                write!(f, ", switching {} (the last: {reason})", quoted(elements))
            }
            SimError::Stalled { t, mode, cause } => write!(
                f,
                "time stopped advancing at t = {} s{}: {cause}",
                At(*t),
                in_mode(mode)
            ),
            SimError::TooManyCombinations {
                t,
                elements,
                combinations,
                limit,
            } => write!(
                f,
                "at t = {} s no single switch is consistent, and the modes of {} combine in {combinations} ways, over the limit of {limit} searched",
                At(*t),
                quoted(elements)
            ),
            SimError::TooManyEvents { t, limit } => {
                write!(f, "more than {limit} events by t = {} s", At(*t))
            }
            SimError::TooManySteps {
                t,
                limit,
                step,
                time_scale,
            } => {
                write!(
                    f,
                    "more than {limit} steps (integration steps and event-location samples) by t = {} s",
                    At(*t)
                )?;
                if let Some(step) = step {
                    write!(f, ", the last {step:e} s long")?;
                }
                write!(f, ": the duration is too long for the model's time scales")?;
                match time_scale {
                    Some(scale) => write!(f, " (the fastest there: {scale})"),
                    None => Ok(()),
                }
            }
            SimError::NonFiniteOutput { t, mode, outputs } => write!(
                f,
                "at t = {} s in mode {mode} the outputs {} are no longer finite",
                At(*t),
                quoted(outputs)
            ),
            SimError::NonFinite { t, mode, states } => write!(
                f,
                "at t = {} s in mode {mode} the states {} are no longer finite",
                At(*t),
                quoted(states)
            ),
        }
    }
}

impl std::error::Error for SimError {}

/// A time in a message: as a decimal, or in exponent form when that would run to dozens of
/// digits (a run stopped at 6e-256 s).
pub(super) struct At(pub(super) f64);

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.0;
        if t != 0.0 && (t.abs() < 1e-4 || t.abs() >= 1e16) {
            write!(f, "{t:e}")
        } else {
            write!(f, "{t}")
        }
    }
}

/// ` in mode SPEC`, or nothing for a model without switching (whose mode is empty).
pub(super) fn in_mode(mode: &str) -> String {
    if mode.is_empty() {
        String::new()
    } else {
        format!(" in mode {mode}")
    }
}

pub(super) fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}
