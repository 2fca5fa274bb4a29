//! A scenario's table of points in time: where a time falls among them, and the value and
//! rate there, for [`Signal::Table`](super::Signal::Table) and for a cursor that reads a
//! measured signal in the order a run does.

/// Where `t` is in a table: before the first point, after the last, or on a segment.
pub(super) enum Segment {
    Before,
    After,
    Between((f64, f64), (f64, f64)),
}

pub(super) fn segment(points: &[(f64, f64)], t: f64) -> Segment {
    segment_at(points, points.partition_point(|p| p.0 <= t))
}

/// The segment of a table whose first point at a later time than `t` is `after` (the count
/// of points at or before `t`).
fn segment_at(points: &[(f64, f64)], after: usize) -> Segment {
    if after == 0 {
        Segment::Before
    } else if after == points.len() {
        Segment::After
    } else {
        Segment::Between(points[after - 1], points[after])
    }
}

/// The points of a table where its rate changes: where the slope from the left (zero before
/// the first point) differs from the slope to the right (zero after the last). A point
/// between two collinear pieces, such as a sample of a recorded signal held constant, is no
/// breakpoint: the signal is one line across it, and an integrator may step over it.
pub(super) fn table_breakpoints(points: &[(f64, f64)]) -> Vec<f64> {
    let slope = |k: usize| {
        if k == 0 || k == points.len() {
            0.0
        } else {
            let ((t0, v0), (t1, v1)) = (points[k - 1], points[k]);
            (v1 - v0) / (t1 - t0)
        }
    };
    (0..points.len())
        .filter(|&k| slope(k) != slope(k + 1))
        .map(|k| points[k].0)
        .collect()
}

/// A table's value at `t` on its segment.
pub(super) fn table_value(points: &[(f64, f64)], segment: Segment, t: f64) -> f64 {
    match segment {
        Segment::Before => points.first().map_or(0.0, |p| p.1),
        Segment::After => points.last().map_or(0.0, |p| p.1),
        Segment::Between((t0, v0), (t1, v1)) => {
            if t == t0 {
                v0
            } else {
                v0 + (v1 - v0) * (t - t0) / (t1 - t0)
            }
        }
    }
}

/// A table's rate from the right on its segment.
pub(super) fn table_rate(segment: Segment) -> f64 {
    match segment {
        Segment::Before | Segment::After => 0.0,
        Segment::Between((t0, v0), (t1, v1)) => (v1 - v0) / (t1 - t0),
    }
}

/// A [`Signal::Table`](super::Signal::Table)'s points read at times that mostly increase, as a simulation reads a
/// measured signal: the segment found last, then the next, are tried before a binary search
/// (which a run through a recorded signal, reading it at every sample, otherwise spends a
/// tenth of its time on). Values and rates are exactly [`Signal::value`](super::Signal::value)'s and
/// [`Signal::rate`](super::Signal::rate)'s.
#[derive(Debug)]
pub struct TableCursor<'a> {
    points: &'a [(f64, f64)],
    /// The count of points at or before the time read last.
    after: std::cell::Cell<usize>,
}

impl<'a> TableCursor<'a> {
    /// A cursor over a table's points (in increasing time, as the reader checks them).
    pub fn new(points: &'a [(f64, f64)]) -> Self {
        Self {
            points,
            after: std::cell::Cell::new(0),
        }
    }

    /// The value at `t`, as [`Signal::value`](super::Signal::value) gives it.
    pub fn value(&self, t: f64) -> f64 {
        table_value(self.points, self.segment(t), t)
    }

    /// The rate from the right at `t`, as [`Signal::rate`](super::Signal::rate) gives it.
    pub fn rate(&self, t: f64) -> f64 {
        table_rate(self.segment(t))
    }

    /// The table's points where its rate changes, as [`Signal::breakpoints`](super::Signal::breakpoints) gives them.
    pub fn breakpoints(&self) -> Vec<f64> {
        table_breakpoints(self.points)
    }

    fn segment(&self, t: f64) -> Segment {
        let points = self.points;
        // `after` is the count of points at or before `t` where the points around it say so.
        let holds = |after: usize| {
            after <= points.len()
                && (after == 0 || points[after - 1].0 <= t)
                && (after == points.len() || points[after].0 > t)
        };
        let last = self.after.get();
        let after = if holds(last) {
            last
        } else if holds(last + 1) {
            last + 1
        } else {
            points.partition_point(|p| p.0 <= t)
        };
        self.after.set(after);
        segment_at(points, after)
    }
}
