//! Energy accounting: what the sources supplied, what resistors and friction dissipated, and
//! what was stored, so that a simulation can be checked against the first law.
//!
//! Junctions, transformers and gyrators conserve power, so over any run
//! `ΔE_stored = ∫ P_supplied - ∫ P_dissipated - E_lost`, where `E_lost` is the kinetic energy
//! lost when bodies merge at an event (two bodies sticking together are a perfectly plastic
//! collision; with Karnopp's dead band their velocities differ by at most the band, so the
//! loss is small but not zero). Powers are products of the closed-form trajectories; they are
//! integrated by 8-point Gauss–Legendre quadrature on panels that follow the mode's time
//! scales (geometric near the start of a segment, where a stiff mode settles in 1e-17 s, and
//! fine enough for every oscillation).

use bondgraph_core::model::ElementId;
use bondgraph_core::scenario::Book;
use num_complex::Complex64;

use crate::numeric::NumericMode;
use crate::propagate::Segment;

/// The energy books of a run, in joules.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyBalance {
    /// Stored at the start.
    pub initial_stored: f64,
    /// Stored at the end.
    pub final_stored: f64,
    /// Delivered by the sources.
    pub supplied: f64,
    /// Absorbed by resistors and friction contacts.
    pub dissipated: f64,
    /// Lost when states were merged at events.
    pub lost_at_events: f64,
}

impl EnergyBalance {
    /// `ΔE_stored - (supplied - dissipated - lost)`: zero up to integration error.
    pub fn residual(&self) -> f64 {
        (self.final_stored - self.initial_stored)
            - (self.supplied - self.dissipated - self.lost_at_events)
    }

    /// The largest of the terms, to judge the residual against.
    pub fn scale(&self) -> f64 {
        [
            self.initial_stored,
            self.final_stored,
            self.supplied,
            self.dissipated,
            self.lost_at_events,
        ]
        .iter()
        .map(|x| x.abs())
        .fold(0.0, f64::max)
    }
}

/// An energy recorded beside the outputs at every sample ([`crate::hybrid::Simulator::with_energy_columns`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyColumn {
    /// The energy one storage element holds.
    Element(ElementId),
    /// A book: supplied and dissipated since time 0 (merges at events counted as
    /// dissipated), or stored now.
    Book(Book),
}

impl EnergyColumn {
    /// Whether it needs the books kept (a quadrature of the ports' powers).
    pub fn needs_books(self) -> bool {
        matches!(self, EnergyColumn::Book(Book::Supplied | Book::Dissipated))
    }
}

/// Gauss–Legendre nodes and weights on [-1, 1], 8 points.
pub(crate) const NODES: [f64; 8] = [
    -0.960_289_856_497_536_3,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
pub(crate) const WEIGHTS: [f64; 8] = [
    0.101_228_536_290_376_26,
    0.222_381_034_453_374_47,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362,
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_47,
    0.101_228_536_290_376_26,
];

/// Panel edges over `[0, length]` for a mode with these eigenvalues.
fn panels(values: &[Complex64], length: f64) -> Vec<f64> {
    let fastest = values
        .iter()
        .map(|v| v.norm())
        .filter(|r| *r > 0.0 && r.is_finite())
        .fold(0.0, f64::max);
    let mut edges = vec![0.0, length];
    if fastest > 0.0 {
        let mut t = (0.01 / fastest).min(length / 4096.0);
        while t < length {
            edges.push(t);
            t *= 1.1;
        }
    }
    for k in 1..256 {
        edges.push(length * k as f64 / 256.0);
    }
    for v in values {
        if v.im == 0.0 {
            continue;
        }
        let spacing = 2.0 * std::f64::consts::PI / v.im.abs() / 32.0;
        let horizon = if v.re < 0.0 {
            (40.0 / -v.re).min(length)
        } else {
            length
        };
        let count = ((horizon / spacing) as usize).min(200_000);
        edges.extend((1..=count).map(|k| k as f64 * spacing));
    }
    edges.retain(|t| (0.0..=length).contains(t));
    edges.sort_by(f64::total_cmp);
    edges.dedup();
    edges
}

/// `(supplied, dissipated)` over a segment of `length` from its start.
pub(crate) fn integrate_segment(
    mode: &NumericMode,
    segment: &mut Segment<'_>,
    u0: &[f64],
    u1: &[f64],
    length: f64,
) -> (f64, f64) {
    if length <= 0.0 || mode.ports.is_empty() {
        return (0.0, 0.0);
    }
    let mut x = vec![0.0; segment.dimension()];
    let mut u = vec![0.0; u0.len()];
    let (mut supplied, mut dissipated) = (0.0, 0.0);
    let edges = panels(mode.propagator.eigenvalues(), length);
    for pair in edges.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
        for (node, weight) in NODES.iter().zip(WEIGHTS) {
            let tau = mid + half * node;
            segment.state_into(tau, &mut x);
            for (k, slot) in u.iter_mut().enumerate() {
                *slot = u0[k] + u1[k] * tau;
            }
            for port in &mode.ports {
                let power = port.effort.eval(&x, &u, u1) * port.flow.eval(&x, &u, u1);
                if port.source {
                    supplied -= weight * half * power;
                } else {
                    dissipated += weight * half * power;
                }
            }
        }
    }
    (supplied, dissipated)
}
