//! When a run's outputs are sampled: at `k × interval`, the run's end included.
//!
//! A sample's time is `k × interval` rather than a running sum, which would drift by
//! rounding. The end of a run is meant to be sampled when the interval divides the duration
//! (0.3 s every 0.1 s), but `3 × 0.1` is `0.30000000000000004`, past 0.3, and the last
//! sample was lost. `k × interval` carries three roundings (the interval's, the duration's
//! and the product's), together at most 1.5 ε times the duration, so a sample time within
//! 2 ε of the end is the end.

/// The sample times of a run.
#[derive(Clone, Copy, Debug)]
pub(super) struct SampleTimes {
    interval: f64,
    /// The end of the run, where known.
    end: Option<f64>,
}

impl SampleTimes {
    /// Every `interval` seconds from zero.
    pub fn every(interval: f64) -> Self {
        Self {
            interval,
            end: None,
        }
    }

    /// The same samples, for a run that ends at `end`.
    pub fn ending_at(self, end: f64) -> Self {
        Self {
            end: Some(end),
            ..self
        }
    }

    /// The time of sample `k`.
    pub fn time(&self, k: u64) -> f64 {
        let time = k as f64 * self.interval;
        match self.end {
            Some(end) if (time - end).abs() <= 2.0 * f64::EPSILON * end => end,
            _ => time,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sample_a_rounding_error_past_the_end_is_the_end() {
        let times = SampleTimes::every(0.1).ending_at(0.3);
        assert_eq!(3.0 * 0.1, 0.30000000000000004);
        assert_eq!(times.time(3), 0.3);
        assert_eq!(times.time(2), 0.2);
        assert_eq!(times.time(4), 0.4);
        // Without a known end, the product as it is.
        assert_eq!(SampleTimes::every(0.1).time(3), 0.30000000000000004);
        // An interval that does not divide the duration keeps its own times.
        let uneven = SampleTimes::every(0.3).ending_at(1.0);
        assert_eq!(uneven.time(3), 0.8999999999999999);
        assert_eq!(uneven.time(4), 1.2);
    }
}
