//! Time that stops advancing, and what was seen when it did.
//!
//! Two different things stop the clock, and the message must say which: an integrator
//! whose steps shrink below the spacing of doubles at `t` with no guard in reach (a state
//! blowing up in finite time), or segments that end where they began, each at a crossing
//! whose switch is declined (static friction that cannot hold, found again and again). The
//! second was once reported as the first: a belt table reversing at 0.000488 s was said to
//! take "steps shorter than the spacing of floating-point numbers" where that spacing was
//! 5e-20 s and no step was taken at all.

use std::fmt;

/// Segments in a row that may end where they began before the run is said to be stalled.
pub const STALLED_SEGMENTS: usize = 1000;

/// An integrator's step no longer than this many resolutions of time (spacings of doubles)
/// is held at the clock's resolution: it makes no progress worth the work.
pub(super) const HELD_RESOLUTIONS: f64 = 4.0;

/// The resolution of time at `t`: the spacing of doubles there (2.2e-16 s at 1 s, the
/// smallest subnormal, 4.9e-324 s, at zero).
pub(super) fn resolution_at(t: f64) -> f64 {
    let t = t.abs();
    t.next_up() - t
}

/// What was seen when time stopped advancing.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Stall {
    /// An integrator's step fell to a few resolutions of time at `t` with no guard met.
    Steps {
        /// The last step tried, in seconds.
        step: f64,
        /// The resolution of time there (the spacing of doubles), in seconds.
        resolution: f64,
    },
    /// Segments in a row ended where they began.
    Segments {
        /// How many.
        count: usize,
        /// The element whose guard the last of them found crossing, and why, if one did.
        crossing: Option<(String, String)>,
        /// Whether that crossing's switch was declined (its element could not hold).
        declined: bool,
    },
}

impl fmt::Display for Stall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stall::Steps { step, resolution } => write!(
                f,
                "the integrator's steps fell to {step:e} s, within {HELD_RESOLUTIONS} times the \
                 resolution of time there ({resolution:e} s), with no guard met"
            ),
            Stall::Segments {
                count,
                crossing: None,
                ..
            } => write!(f, "{count} segments in a row ended where they began"),
            Stall::Segments {
                count,
                crossing: Some((element, reason)),
                declined,
            } => write!(
                f,
                "{count} segments in a row ended where they began, each at a crossing of \
                 '{element}' ({reason}){}",
                if *declined {
                    " whose switch was declined"
                } else {
                    ""
                }
            ),
        }
    }
}

/// Counts the segments in a row that end where they began.
#[derive(Debug, Default)]
pub(super) struct Progress {
    count: usize,
}

impl Progress {
    /// After a segment from `before` to `after` that found `crossing` (element and reason,
    /// `declined` if its switch was refused): the stall, once more than
    /// [`STALLED_SEGMENTS`] in a row made no progress.
    /// The crossing is put into words only for a stall.
    pub fn after_segment(
        &mut self,
        before: f64,
        after: f64,
        crossing: impl FnOnce() -> Option<(String, String)>,
        declined: bool,
    ) -> Option<Stall> {
        if after > before {
            self.count = 0;
            return None;
        }
        self.count += 1;
        (self.count > STALLED_SEGMENTS).then(|| Stall::Segments {
            count: self.count,
            crossing: crossing(),
            declined,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_without_progress_are_a_stall_naming_the_crossing() {
        let mut progress = Progress::default();
        let crossing = || {
            Some((
                "friction".to_string(),
                "relative velocity reached zero".into(),
            ))
        };
        for _ in 0..STALLED_SEGMENTS {
            assert_eq!(progress.after_segment(0.5, 0.5, crossing, true), None);
        }
        let stall = progress
            .after_segment(0.5, 0.5, crossing, true)
            .expect("stalled");
        assert_eq!(
            stall.to_string(),
            "1001 segments in a row ended where they began, each at a crossing of 'friction' \
             (relative velocity reached zero) whose switch was declined"
        );
    }

    #[test]
    fn the_resolution_of_time_is_the_spacing_of_doubles() {
        assert_eq!(resolution_at(0.0), 4.9e-324);
        assert_eq!(resolution_at(1.0), f64::EPSILON);
        assert_eq!(resolution_at(-1.0), f64::EPSILON);
        assert_eq!(resolution_at(0.75), f64::EPSILON / 2.0);
        let stall = Stall::Steps {
            step: 1e-323,
            resolution: resolution_at(0.0),
        };
        assert_eq!(
            stall.to_string(),
            "the integrator's steps fell to 1e-323 s, within 4 times the resolution of time \
             there (5e-324 s), with no guard met"
        );
    }

    #[test]
    fn progress_resets_the_count() {
        let mut progress = Progress::default();
        for _ in 0..STALLED_SEGMENTS {
            assert_eq!(progress.after_segment(1.0, 1.0, || None, false), None);
        }
        assert_eq!(progress.after_segment(1.0, 1.5, || None, false), None);
        for _ in 0..STALLED_SEGMENTS {
            assert_eq!(progress.after_segment(1.5, 1.5, || None, false), None);
        }
        assert_eq!(
            progress
                .after_segment(1.5, 1.5, || None, false)
                .map(|s| s.to_string()),
            Some("1001 segments in a row ended where they began".into())
        );
    }
}
