//! The books of a mode whose matrix cannot be diagonalised, by quadrature of the propagated
//! state (each evaluation an augmented matrix exponential, so evaluations are counted).
//!
//! A stretch `[a, b]` is cut into panels: geometric ones from the segment's start, where a
//! stiff component settles within `1/|λ|`, then equal ones of about `2/|λ|_max` each, at
//! most [`PANELS`] in all. Each panel takes 8-point Gauss–Legendre; the 4-point rule on the
//! same panel estimates its error, which goes into the books' error bound, so that a
//! stretch with more oscillations than the budget follows is said, not hidden.

use crate::numeric::NumericMode;
use crate::propagate::Segment;

use super::{Increment, NODES, WEIGHTS};

/// The most panels a stretch is cut into.
pub(super) const PANELS: usize = 512;

/// 4-point Gauss–Legendre nodes and weights on [-1, 1], for the error estimate.
const NODES_4: [f64; 4] = [
    -0.861_136_311_594_052_6,
    -0.339_981_043_584_856_3,
    0.339_981_043_584_856_3,
    0.861_136_311_594_052_6,
];
const WEIGHTS_4: [f64; 4] = [
    0.347_854_845_137_453_85,
    0.652_145_154_862_546_1,
    0.652_145_154_862_546_1,
    0.347_854_845_137_453_85,
];

/// The books of one segment by quadrature ([`super::SegmentBooks`]).
pub(super) struct QuadratureBooks {
    u0: Vec<f64>,
    u1: Vec<f64>,
    /// The mode's fastest rate, `max |λ|` (0 for none).
    fastest: f64,
    x: Vec<f64>,
    u: Vec<f64>,
    edges: Vec<f64>,
}

impl QuadratureBooks {
    pub fn new(mode: &NumericMode, u0: &[f64], u1: &[f64]) -> Self {
        let fastest = mode
            .propagator
            .eigenvalues()
            .iter()
            .map(|v| v.norm())
            .filter(|r| r.is_finite())
            .fold(0.0, f64::max);
        QuadratureBooks {
            u0: u0.to_vec(),
            u1: u1.to_vec(),
            fastest,
            x: Vec::new(),
            u: vec![0.0; u0.len()],
            edges: Vec::new(),
        }
    }

    /// The books over `[a, b]` (local times, `b > a`).
    pub fn over(
        &mut self,
        mode: &NumericMode,
        segment: &mut Segment<'_>,
        a: f64,
        b: f64,
    ) -> Increment {
        self.x.resize(segment.dimension(), 0.0);
        panels(self.fastest, a, b, &mut self.edges);
        let mut increment = Increment::default();
        let edges = std::mem::take(&mut self.edges);
        for pair in edges.windows(2) {
            let (mid, half) = ((pair[0] + pair[1]) / 2.0, (pair[1] - pair[0]) / 2.0);
            let mut fine = Increment::default();
            for (node, weight) in NODES.iter().zip(WEIGHTS) {
                self.power_at(mode, segment, mid + half * node, weight * half, &mut fine);
            }
            let mut coarse = Increment::default();
            for (node, weight) in NODES_4.iter().zip(WEIGHTS_4) {
                self.power_at(mode, segment, mid + half * node, weight * half, &mut coarse);
            }
            increment.supplied += fine.supplied;
            increment.dissipated += fine.dissipated;
            increment.error += fine.error
                + (fine.supplied - coarse.supplied).abs()
                + (fine.dissipated - coarse.dissipated).abs();
        }
        self.edges = edges;
        increment
    }

    /// Adds `weight` times the ports' powers at local time `tau` to `books`.
    fn power_at(
        &mut self,
        mode: &NumericMode,
        segment: &mut Segment<'_>,
        tau: f64,
        weight: f64,
        books: &mut Increment,
    ) {
        segment.state_into(tau, &mut self.x);
        for (k, slot) in self.u.iter_mut().enumerate() {
            *slot = self.u0[k] + self.u1[k] * tau;
        }
        for port in &mode.ports {
            let (x, u, rate) = (&self.x, &self.u, &self.u1);
            let power = port.effort.eval(x, u, rate) * port.flow.eval(x, u, rate);
            let magnitude = port.effort.magnitude(x, u, rate) * port.flow.magnitude(x, u, rate);
            books.book(
                port.source,
                weight * power,
                4.0 * f64::EPSILON * weight * magnitude,
            );
        }
    }
}

/// Panel edges over `[a, b]` of a segment whose fastest rate is `fastest`: geometric from
/// the segment's start (doubling from `1/fastest`), then equal panels of about
/// `2/fastest`; at most [`PANELS`] in all, however short or long the stretch.
fn panels(fastest: f64, a: f64, b: f64, edges: &mut Vec<f64>) {
    edges.clear();
    edges.push(a);
    let length = b - a;
    let mut from = a;
    if fastest > 0.0 && a == 0.0 {
        let mut t = 1.0 / fastest;
        while t < b && t > from && edges.len() < PANELS / 2 {
            edges.push(t);
            from = t;
            t *= 2.0;
        }
    }
    let rest = b - from;
    let wanted = (rest * fastest / 2.0).ceil();
    let budget = PANELS + 1 - edges.len();
    let count = if wanted.is_finite() && wanted >= 1.0 {
        (wanted as usize).min(budget)
    } else {
        1
    };
    for k in 1..count {
        let t = from + rest * k as f64 / count as f64;
        if t > *edges.last().unwrap_or(&a) && t < b {
            edges.push(t);
        }
    }
    if length > 0.0 {
        edges.push(b);
    }
}
