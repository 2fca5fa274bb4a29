//! Energy accounting: what the sources supplied, what resistors and friction dissipated, and
//! what was stored, so that a simulation can be checked against the first law.
//!
//! Junctions, transformers and gyrators conserve power, so over any run
//! `ΔE_stored = ∫ P_supplied - ∫ P_dissipated - E_lost`, where `E_lost` is the kinetic energy
//! lost when bodies merge at an event (two bodies sticking together are a perfectly plastic
//! collision; with Karnopp's dead band their velocities differ by at most the band, so the
//! loss is small but not zero).
//!
//! **Within a linear mode the books are exact.** Each port's effort and flow are affine in
//! the state and the inputs, and the state is a sum of modal terms `e^{λτ}` and polynomials
//! (`propagate.rs`), so a power is a sum of products of exponentials and polynomials, whose
//! integrals are closed forms (`modal`): `∫ e^{(λ_i+λ_j)s} ds = h φ₁((λ_i+λ_j)h)` (exact
//! also where `λ_i + λ_j ≈ 0`, the steady part of a lightly damped swing), and moments
//! `∫ sᵏ e^{λs} ds` by recurrences run in their stable direction. The cost of a stretch is
//! the same whether it holds one oscillation or a million, so the books are kept
//! incrementally from sample to sample at a cost linear in the run's duration, and a
//! stiff mode's 1e-17 s transient is integrated as exactly as a slow swing. Quadrature
//! (`quadrature`) is kept only for a mode whose matrix cannot be diagonalised, on panels
//! bounded by a budget, with its own error estimate; nonlinear modes integrate the powers
//! along with their states (`hybrid/integrate.rs`).
//!
//! **The books say their own error.** Beside each integral runs the same sum over the
//! terms' magnitudes; a few ulps of it bound what rounding (and the cancellation between a
//! row's terms, such as a motor's back-EMF against its supply) can have cost
//! ([`EnergyBalance::error`]).
//!
//! **A step of an input that drives dependent storage** (a force on two springs meeting at
//! a massless node) makes the state jump by `E Δu` ([`crate::numeric`]): the step is the
//! limit of a ramp, along which the carried state `x - E u` stays put while the rate terms
//! of the ports' rows carry an impulse. Its energy is that limit (`jump`): a port whose
//! effort (or flow) has a rate coefficient `r` takes `r·Δu` times the mean of its flow (or
//! effort) over the step. What the jump stores and what the ports took then balance, and
//! what rounding leaves between them goes into the error bound. Only where one port's
//! effort and flow would both be impulsive does the limit grow without bound; the books
//! then take what the jump stored, less what the other ports took, as lost at the event,
//! as a sticking loss is.

mod modal;
mod quadrature;

use bondgraph_core::model::ElementId;
use bondgraph_core::scenario::Book;

use crate::numeric::{NumericMode, dot};
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
    /// A bound on the books' own error: the rounding of their integrals, from the
    /// magnitudes of the terms summed (and a quadrature's estimate where one was used).
    pub error: f64,
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
    /// Whether it needs the books kept (an integral of the ports' powers).
    pub fn needs_books(self) -> bool {
        matches!(self, EnergyColumn::Book(Book::Supplied | Book::Dissipated))
    }
}

pub(crate) use crate::gauss::{NODES, WEIGHTS};

/// What a stretch of time adds to the books.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Increment {
    /// Delivered by the sources.
    pub supplied: f64,
    /// Absorbed by resistors and friction.
    pub dissipated: f64,
    /// A bound on the error of the two.
    pub error: f64,
}

impl std::ops::AddAssign for Increment {
    fn add_assign(&mut self, other: Self) {
        self.supplied += other.supplied;
        self.dissipated += other.dissipated;
        self.error += other.error;
    }
}

impl Increment {
    /// Books `power` integrated over a port (the power into it), with `magnitude`, the
    /// same integral over the magnitudes of its terms.
    fn book(&mut self, source: bool, power: f64, magnitude: f64) {
        if source {
            self.supplied -= power;
        } else {
            self.dissipated += power;
        }
        self.error += magnitude;
    }
}

/// The books of one segment of a linear mode, kept from sample to sample: each call adds a
/// stretch `[a, b]` of the segment's local time.
pub(crate) struct SegmentBooks {
    method: Method,
}

enum Method {
    /// The mode exchanges no energy with any port.
    Idle,
    /// In closed form, from the modal solution.
    Modal(Box<modal::ModalBooks>),
    /// By quadrature of the propagated state (a defective matrix).
    Quadrature(quadrature::QuadratureBooks),
}

impl SegmentBooks {
    /// The books of `segment` of `mode`, its inputs `u₀ + u₁ τ`.
    pub fn new(mode: &NumericMode, segment: &Segment<'_>, u0: &[f64], u1: &[f64]) -> Self {
        let method = if mode.ports.is_empty() {
            Method::Idle
        } else if let Some(books) = modal::ModalBooks::new(mode, segment, u0, u1) {
            Method::Modal(Box::new(books))
        } else {
            Method::Quadrature(quadrature::QuadratureBooks::new(mode, u0, u1))
        };
        SegmentBooks { method }
    }

    /// What `[a, b]` of the segment (local times) adds to the books; nothing if `b ≤ a`.
    pub fn over(
        &mut self,
        mode: &NumericMode,
        segment: &mut Segment<'_>,
        a: f64,
        b: f64,
    ) -> Increment {
        if b.partial_cmp(&a) != Some(std::cmp::Ordering::Greater) {
            return Increment::default();
        }
        match &mut self.method {
            Method::Idle => Increment::default(),
            Method::Modal(books) => books.over(mode, segment, a, b),
            Method::Quadrature(books) => books.over(mode, segment, a, b),
        }
    }
}

/// What an input's step from `before` to `after` (left and right limits) adds to the books
/// of `mode` at its carried state `x` (`x - E u`, which does not jump): the limit of a ramp
/// ever steeper. Along it a row `y = c·x + d·u + r·u̇ + k` is its rate-free part, moving
/// from `c·x + d·before + k` to `c·x + d·after + k`, plus the impulse `r·Δu/δ` over the
/// ramp's duration `δ`; a port's `∫ e f` tends to `(r_e·Δu)·mean(f) + (r_f·Δu)·mean(e)`.
/// The magnitude of every product goes into the error bound. The second value says whether
/// some port's effort and flow are both impulsive: its `(r_e·Δu)(r_f·Δu)/δ` grows without
/// bound as the ramp steepens, and no finite figure is the limit.
pub(crate) fn jump(
    mode: &NumericMode,
    x: &[f64],
    before: &[f64],
    after: &[f64],
) -> (Increment, bool) {
    let mut increment = Increment::default();
    let mut unbounded = false;
    let step: Vec<f64> = after.iter().zip(before).map(|(a, b)| a - b).collect();
    if step.iter().all(|d| *d == 0.0) {
        return (increment, unbounded);
    }
    let mean_inputs: Vec<f64> = after
        .iter()
        .zip(before)
        .map(|(a, b)| 0.5 * (a + b))
        .collect();
    let mean = |row: &crate::numeric::Row| {
        dot(&row.state, x) + dot(&row.input, &mean_inputs) + row.constant
    };
    let mean_magnitude = |row: &crate::numeric::Row| {
        let sum = |c: &[f64], v: &[f64]| c.iter().zip(v).map(|(a, b)| (a * b).abs()).sum::<f64>();
        sum(&row.state, x) + sum(&row.input, &mean_inputs) + row.constant.abs()
    };
    let impulse = |row: &crate::numeric::Row| dot(&row.rate, &step);
    let impulse_magnitude = |row: &crate::numeric::Row| {
        row.rate
            .iter()
            .zip(&step)
            .map(|(a, b)| (a * b).abs())
            .sum::<f64>()
    };
    for port in &mode.ports {
        let energy =
            impulse(&port.effort) * mean(&port.flow) + impulse(&port.flow) * mean(&port.effort);
        let magnitude = impulse_magnitude(&port.effort) * mean_magnitude(&port.flow)
            + impulse_magnitude(&port.flow) * mean_magnitude(&port.effort);
        increment.book(port.source, energy, 4.0 * f64::EPSILON * magnitude);
        unbounded |= impulse(&port.effort) != 0.0 && impulse(&port.flow) != 0.0;
    }
    (increment, unbounded)
}
