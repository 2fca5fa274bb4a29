//! The ODEs the integrators' unit tests share, each with its analytic Jacobian.

use super::problem::System;

/// `x'' = -x` as a first-order system, with a quadrature of `x²`: `x = cos t` from `(1, 0)`,
/// `∫ cos² = t/2 + sin 2t / 4`.
pub(super) struct Oscillator;

impl System for Oscillator {
    fn dimension(&self) -> usize {
        3
    }
    fn controlled(&self) -> usize {
        2
    }
    fn rhs(&mut self, _: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = -x[0];
        dx[2] = x[0] * x[0];
    }
    fn jacobian(&mut self, _: f64, x: &[f64], j: &mut [f64]) {
        j.fill(0.0);
        j[1] = 1.0;
        j[3] = -1.0;
        j[6] = 2.0 * x[0];
    }
}

/// The stiff test `x' = -1e6 (x - cos t)`.
pub(super) struct Stiff;

impl System for Stiff {
    fn dimension(&self) -> usize {
        1
    }
    fn controlled(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = -1e6 * (x[0] - t.cos());
    }
    fn jacobian(&mut self, _: f64, _: &[f64], j: &mut [f64]) {
        j[0] = -1e6;
    }
}

/// Van der Pol's oscillator in Hairer and Wanner's scaling (Solving ODEs II, IV.10):
/// `x₀' = x₁`, `ε x₁' = (1 - x₀²) x₁ - x₀`. Not stiff at `ε = 1`; at `ε = 1e-6` the IVP test
/// set's stiff `vdpol`.
pub(super) struct VanDerPol {
    pub(super) epsilon: f64,
}

impl System for VanDerPol {
    fn dimension(&self) -> usize {
        2
    }
    fn controlled(&self) -> usize {
        2
    }
    fn rhs(&mut self, _: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = ((1.0 - x[0] * x[0]) * x[1] - x[0]) / self.epsilon;
    }
    fn jacobian(&mut self, _: f64, x: &[f64], j: &mut [f64]) {
        j[0] = 0.0;
        j[1] = 1.0;
        j[2] = (-2.0 * x[0] * x[1] - 1.0) / self.epsilon;
        j[3] = (1.0 - x[0] * x[0]) / self.epsilon;
    }
}
