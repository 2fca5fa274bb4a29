//! Documented limits on the size of inputs, so that every input is bounded in time and
//! memory and a file beyond them gets a clear error instead of exhausting the machine.
//!
//! Exact rational algebra is what makes equal entries print equally, but it has a price:
//! `(m + k + b)^300` expands into 45 451 terms with 480-bit coefficients, and the
//! derivation's greatest common divisors over such polynomials once took 3.9 GB before the
//! allocator gave up. No physical law needs anything near these limits; the textbook
//! models and the examples with data stay below a tenth of them.
//!
//! | what | limit |
//! |---|---|
//! | total degree of a law's expanded parameter expression (numerator or denominator) | [`MAX_EXPRESSION_DEGREE`] |
//! | terms of a law's expanded parameter expression (numerator or denominator) | [`MAX_EXPRESSION_TERMS`] |
//! | samples a simulation records | [`MAX_SAMPLES`] |
//! | events (mode changes) in one simulation | [`MAX_EVENTS`] |
//! | steps in one simulation (integration steps and event-location samples) | [`MAX_STEPS`] |
//! | modes `check` and `modes` enumerate for a model | [`MAX_MODES`] |
//! | size of a model, scenario, experiment or extension file | [`MAX_FILE_BYTES`] |
//! | size of a CSV data file | [`MAX_DATA_FILE_BYTES`] |
//! | measurements (rows) in a CSV data file | [`MAX_DATA_ROWS`] |
//! | bytes in one cell or column name of a CSV data file | [`MAX_CELL_BYTES`] |
//!
//! ```
//! use bondgraph_core::{limits, model};
//! let text = r#"Model(name: "m", parameters: { "m": (value: 1.0), "k": (value: 1.0) },
//!     inputs: {}, elements: { "v": One, "mass": I(inertance: "(m + k)^1000"),
//!     "spring": C(stiffness: "k") }, bonds: [("v", "mass"), ("v", "spring")])"#;
//! let error = bondgraph_ron::model::load_str("m.ron", text).unwrap_err();
//! assert!(error.to_string().contains(&limits::MAX_EXPRESSION_DEGREE.to_string()));
//! ```

use crate::symbolic::RatFunc;

/// The largest total degree of a parameter expression's numerator or denominator, once
/// expanded.
pub const MAX_EXPRESSION_DEGREE: u32 = 32;

/// The most terms in a parameter expression's numerator or denominator, once expanded.
pub const MAX_EXPRESSION_TERMS: usize = 1000;

/// The most samples one simulation records (outputs times samples is what takes memory:
/// a million samples of a few outputs is tens of megabytes).
pub const MAX_SAMPLES: u64 = 1_000_000;

/// The most events (mode changes) one simulation may have, by default. Chattering (many
/// events in a short time) is caught long before; this bounds a run that switches at a
/// steady pace for a very long time (the belt's stick-slip, two events every 1.16 s, would
/// reach it after 58 000 s simulated; [`MAX_STEPS`] stops it first, at 50 573 s).
pub const MAX_EVENTS: usize = 100_000;

/// The most steps one simulation may take: the integrator's steps in nonlinear modes
/// (accepted or rejected, and the exact steps that land on events) plus the event
/// locator's samples in linear modes. A step costs about a microsecond on the textbook
/// models (up to ten with events or in the subnormal range), so the limit is seconds of
/// work: a pendulum released for 1e12 s, which once integrated for ever, stops at
/// t = 60 587 s; a velocity damped at 1e307 /s, whose steps were 1e-260 s, stops with that
/// time scale named, where ten million steps took 84 s. The belt's stick-slip takes about
/// seven samples an event.
pub const MAX_STEPS: u64 = 1_000_000;

/// The most modes `check` and `modes` enumerate for one model, and the most combinations
/// a simulation searches when no single switch is consistent. Each friction contact has
/// three modes and each string or flow limit two, so the modes grow as `3^N`, each derived
/// symbolically: eight contacts in a chain (6561 modes) took 3.4 s, twelve ran out of
/// patience. A model with two contacts and a string has 18.
pub const MAX_MODES: usize = 1000;

/// The largest input file read as text, in bytes (16 MiB: the largest example is 12 kB).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// The largest CSV data file read, in bytes (256 MiB: a million rows of ten columns of
/// full-precision numbers is about 250 MB; the examples' data are a few kilobytes).
pub const MAX_DATA_FILE_BYTES: u64 = 256 << 20;

/// The most measurements (rows) in one CSV data file: as many as the samples of a
/// simulation ([`MAX_SAMPLES`]), since each row of a time series is compared with one.
pub const MAX_DATA_ROWS: usize = 1_000_000;

/// The longest cell or column name in a CSV data file, in bytes. A double needs at most 24
/// characters (`-2.2250738585072014e-308`); the rest is room for padding and long names.
pub const MAX_CELL_BYTES: usize = 256;

/// Why an expanded expression is over the limits, in words; `None` when it is within them.
pub fn expression_too_large(value: &RatFunc) -> Option<String> {
    for (part, poly) in [
        ("numerator", value.numerator()),
        ("denominator", value.denominator()),
    ] {
        if poly.degree() > MAX_EXPRESSION_DEGREE {
            return Some(format!(
                "expands to a {part} of degree {}, over the limit of {MAX_EXPRESSION_DEGREE}",
                poly.degree()
            ));
        }
        if poly.term_count() > MAX_EXPRESSION_TERMS {
            return Some(format!(
                "expands to a {part} of {} terms, over the limit of {MAX_EXPRESSION_TERMS}",
                poly.term_count()
            ));
        }
    }
    None
}

/// The number of samples a run of `duration` seconds records every `interval` seconds
/// (both ends included), as a float so that `1e308 / 5e-324` is infinite rather than a
/// wrapped integer.
pub fn sample_count(duration: f64, interval: f64) -> f64 {
    (duration / interval).floor() + 1.0
}

/// A count as an integer while it is one exactly, else in exponent form (`1e308`).
pub fn count_in_words(count: f64) -> String {
    if count < 9.007_199_254_740_992e15 {
        format!("{count:.0}")
    } else {
        format!("{count:e}")
    }
}
