//! The 3-stage Radau IIA method with step-size control and dense output; see the
//! [module documentation](super).

// The kernels index stages and components as the method's formulas do.
#![allow(clippy::needless_range_loop)]

use super::lu;
use super::problem::{OdeStats, StepOutcome, System, Tolerances};

/// The method's coefficients.
struct Coefficients {
    c: [f64; 3],
    a: [[f64; 3]; 3],
    /// Weights of the stage increments `Z` in the error estimate.
    e: [f64; 3],
    /// The real eigenvalue of `A`: the error estimate's filter `(I - h γ₀ J)`.
    gamma0: f64,
}

impl Coefficients {
    fn new() -> Self {
        let s6 = 6f64.sqrt();
        let c = [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0];
        let a = [
            [
                (88.0 - 7.0 * s6) / 360.0,
                (296.0 - 169.0 * s6) / 1800.0,
                (-2.0 + 3.0 * s6) / 225.0,
            ],
            [
                (296.0 + 169.0 * s6) / 1800.0,
                (88.0 + 7.0 * s6) / 360.0,
                (-2.0 - 3.0 * s6) / 225.0,
            ],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ];
        // The real eigenvalue of A⁻¹ is 3 + 3^(2/3) - 3^(1/3).
        let gamma0 = 1.0 / (3.0 + 9f64.cbrt() - 3f64.cbrt());
        // The embedded order-3 weights b̂ with b̂₀ = γ₀: Σ b̂ᵢ cᵢ^(k-1) = 1/k - γ₀[k = 1].
        let rhs = [1.0 - gamma0, 0.5, 1.0 / 3.0];
        let vandermonde = [[1.0, 1.0, 1.0], c, [c[0] * c[0], c[1] * c[1], 1.0]];
        let b_hat = solve3(vandermonde, rhs);
        let b = a[2];
        let diff = [b_hat[0] - b[0], b_hat[1] - b[1], b_hat[2] - b[2]];
        // e = A⁻ᵀ (b̂ - b): err = γ₀ h f₀ + Σ eₖ Zₖ.
        let transpose = [
            [a[0][0], a[1][0], a[2][0]],
            [a[0][1], a[1][1], a[2][1]],
            [a[0][2], a[1][2], a[2][2]],
        ];
        let e = solve3(transpose, diff);
        Self { c, a, e, gamma0 }
    }
}

/// Solves a 3 × 3 system by Cramer's rule (for the method's coefficients only).
fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    let mut out = [0.0; 3];
    for (k, slot) in out.iter_mut().enumerate() {
        let mut mk = m;
        for row in 0..3 {
            mk[row][k] = r[row];
        }
        *slot = det(mk) / d;
    }
    out
}

/// A Radau IIA integrator with its work buffers; see the [module documentation](super).
pub struct Radau {
    n: usize,
    controlled: usize,
    tolerances: Tolerances,
    coefficients: Coefficients,
    /// Newton's stopping level, in units of the tolerance.
    newton_tolerance: f64,
    f0: Vec<f64>,
    jacobian: Vec<f64>,
    /// `I - h A⊗J`, factored.
    stage_matrix: Vec<f64>,
    stage_pivots: Vec<usize>,
    /// `I - h γ₀ J`, factored.
    error_matrix: Vec<f64>,
    error_pivots: Vec<usize>,
    z: Vec<f64>,
    stage_f: Vec<f64>,
    dz: Vec<f64>,
    stage_x: Vec<f64>,
    error: Vec<f64>,
    /// The last accepted step, for dense output: its start, size and stage increments.
    last_x0: Vec<f64>,
    last_z: Vec<f64>,
    last_h: f64,
    /// The largest magnitude of each component so far.
    peak: Vec<f64>,
    /// Work counts.
    pub stats: OdeStats,
}

impl Radau {
    /// An integrator for systems of `dimension` components, the first `controlled` of
    /// which set the step size.
    pub fn new(dimension: usize, controlled: usize, tolerances: Tolerances) -> Self {
        let n = dimension;
        // The estimate is of order 3 and the method of order 5: as in RADAU5, the error is
        // controlled against 0.1·rtol^(2/3), which makes the actual error about rtol.
        let relative = 0.1 * tolerances.relative.powf(2.0 / 3.0);
        let internal = Tolerances {
            relative,
            absolute: tolerances.absolute * relative / tolerances.relative,
            peak_fraction: tolerances.peak_fraction,
        };
        let newton_tolerance = (10.0 * f64::EPSILON / relative).max(0.03f64.min(relative.sqrt()));
        Self {
            n,
            controlled: controlled.min(n),
            tolerances: internal,
            coefficients: Coefficients::new(),
            newton_tolerance,
            f0: vec![0.0; n],
            jacobian: vec![0.0; n * n],
            stage_matrix: vec![0.0; 9 * n * n],
            stage_pivots: vec![0; 3 * n],
            error_matrix: vec![0.0; n * n],
            error_pivots: vec![0; n],
            z: vec![0.0; 3 * n],
            stage_f: vec![0.0; 3 * n],
            dz: vec![0.0; 3 * n],
            stage_x: vec![0.0; n],
            error: vec![0.0; n],
            last_x0: vec![0.0; n],
            last_z: vec![0.0; 3 * n],
            last_h: 0.0,
            peak: vec![0.0; n],
            stats: OdeStats::default(),
        }
    }

    /// What an error in component `r` at magnitude `value` is judged against.
    fn scale(&self, r: usize, value: f64) -> f64 {
        self.tolerances.absolute
            + self.tolerances.relative * (value + self.tolerances.peak_fraction * self.peak[r])
    }

    pub(super) fn note_peaks(&mut self, x: &[f64]) {
        for (peak, v) in self.peak.iter_mut().zip(x) {
            *peak = peak.max(v.abs());
        }
    }

    /// The tolerances the error estimate is held to (see [`Radau::new`]).
    pub fn tolerances(&self) -> Tolerances {
        self.tolerances
    }

    /// A first step size for `(tau, x)`: where an explicit Euler step would change the state
    /// by about the tolerance's square root, within `[1e-12, max]`.
    pub fn initial_step(&mut self, system: &mut dyn System, tau: f64, x: &[f64], max: f64) -> f64 {
        system.rhs(tau, x, &mut self.f0);
        self.stats.rhs += 1;
        self.note_peaks(x);
        let mut norm: f64 = 0.0;
        for i in 0..self.controlled {
            let scale = self.scale(i, x[i].abs());
            norm = norm.max((self.f0[i] / scale).abs());
        }
        let h = if norm > 0.0 {
            0.01 * (1.0 / norm).powf(0.25) * self.tolerances.relative.powf(-0.25) * 1e-2
        } else {
            max
        };
        h.clamp(1e-12_f64.min(max), max)
    }

    /// Solves the stage equations of a step of size `h` from `(tau, x)`; false when Newton's
    /// iteration does not converge. The Jacobian is evaluated at `(tau, x)` when `fresh`.
    fn solve_stages(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &[f64],
        h: f64,
        fresh: bool,
    ) -> bool {
        let n = self.n;
        if fresh {
            system.rhs(tau, x, &mut self.f0);
            system.jacobian(tau, x, &mut self.jacobian);
            self.stats.rhs += 1;
            self.stats.jacobians += 1;
        }
        let a = self.coefficients.a;
        let c = self.coefficients.c;
        let size = 3 * n;
        for i in 0..3 {
            for r in 0..n {
                let row = (i * n + r) * size;
                for j in 0..3 {
                    for col in 0..n {
                        let identity = if i == j && r == col { 1.0 } else { 0.0 };
                        self.stage_matrix[row + j * n + col] =
                            identity - h * a[i][j] * self.jacobian[r * n + col];
                    }
                }
            }
        }
        if !lu::factor(&mut self.stage_matrix, size, &mut self.stage_pivots) {
            return false;
        }
        for i in 0..3 {
            for r in 0..n {
                self.z[i * n + r] = c[i] * h * self.f0[r];
            }
        }
        let mut previous = f64::INFINITY;
        let mut eta: f64 = 1.0;
        for iteration in 0..8 {
            for i in 0..3 {
                for r in 0..n {
                    self.stage_x[r] = x[r] + self.z[i * n + r];
                }
                system.rhs(
                    tau + c[i] * h,
                    &self.stage_x,
                    &mut self.stage_f[i * n..(i + 1) * n],
                );
                self.stats.rhs += 1;
            }
            for i in 0..3 {
                for r in 0..n {
                    let mut g = self.z[i * n + r];
                    for j in 0..3 {
                        g -= h * a[i][j] * self.stage_f[j * n + r];
                    }
                    self.dz[i * n + r] = -g;
                }
            }
            lu::solve(&self.stage_matrix, size, &self.stage_pivots, &mut self.dz);
            let mut sum = 0.0;
            for i in 0..3 {
                for r in 0..n {
                    self.z[i * n + r] += self.dz[i * n + r];
                    if r < self.controlled {
                        let scale =
                            self.tolerances.absolute + self.tolerances.relative * x[r].abs();
                        sum += (self.dz[i * n + r] / scale).powi(2);
                    }
                }
            }
            let norm = (sum / (3 * self.controlled.max(1)) as f64).sqrt();
            if !norm.is_finite() {
                return false;
            }
            if iteration > 0 {
                let theta = norm / previous;
                if theta >= 0.99 {
                    return false;
                }
                eta = theta / (1.0 - theta);
            }
            if eta * norm <= self.newton_tolerance || norm <= 1e-3 * self.newton_tolerance {
                return true;
            }
            previous = norm;
        }
        false
    }

    /// Attempts a step of size `h` from `(tau, x)`; on acceptance `x` becomes the state at
    /// `tau + h` and [`Radau::dense`] refers to this step.
    pub fn step(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &mut [f64],
        h: f64,
    ) -> StepOutcome {
        let n = self.n;
        if !self.solve_stages(system, tau, x, h, true) {
            self.stats.rejected += 1;
            return StepOutcome::Rejected { h_next: 0.5 * h };
        }
        // The embedded estimate, filtered by (I - h γ₀ J)⁻¹.
        let gamma0 = self.coefficients.gamma0;
        let e = self.coefficients.e;
        for r in 0..n {
            for col in 0..n {
                let identity = if r == col { 1.0 } else { 0.0 };
                self.error_matrix[r * n + col] = identity - h * gamma0 * self.jacobian[r * n + col];
            }
        }
        let mut error_norm = f64::INFINITY;
        if lu::factor(&mut self.error_matrix, n, &mut self.error_pivots) {
            for r in 0..n {
                self.error[r] = gamma0 * h * self.f0[r]
                    + e[0] * self.z[r]
                    + e[1] * self.z[n + r]
                    + e[2] * self.z[2 * n + r];
            }
            lu::solve(&self.error_matrix, n, &self.error_pivots, &mut self.error);
            let mut sum = 0.0;
            for r in 0..self.controlled {
                let new = x[r] + self.z[2 * n + r];
                let scale =
                    self.tolerances.absolute + self.tolerances.relative * x[r].abs().max(new.abs());
                sum += (self.error[r] / scale).powi(2);
            }
            error_norm = (sum / self.controlled.max(1) as f64).sqrt();
        }
        let factor = if error_norm.is_finite() {
            (0.9 * error_norm.max(1e-10).powf(-0.25)).clamp(0.2, 4.0)
        } else {
            0.2
        };
        if error_norm > 1.0 {
            self.stats.rejected += 1;
            return StepOutcome::Rejected {
                h_next: h * factor.min(0.9),
            };
        }
        self.last_x0.copy_from_slice(x);
        self.last_z.copy_from_slice(&self.z);
        self.last_h = h;
        for r in 0..n {
            x[r] += self.z[2 * n + r];
        }
        self.note_peaks(x);
        self.stats.accepted += 1;
        StepOutcome::Accepted { h_next: h * factor }
    }

    /// The state `h` after `(tau, x)` by one step without error control (for landing
    /// exactly on an event); false when Newton's iteration does not converge. With `reuse`,
    /// the Jacobian of the previous call at the same `(tau, x)` is kept.
    pub fn step_exact(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &[f64],
        h: f64,
        reuse: bool,
        out: &mut [f64],
    ) -> bool {
        if h == 0.0 {
            out.copy_from_slice(x);
            return true;
        }
        if !self.solve_stages(system, tau, x, h, !reuse) {
            return false;
        }
        let n = self.n;
        for r in 0..n {
            out[r] = x[r] + self.z[2 * n + r];
        }
        true
    }

    /// The state at fraction `theta` (0 to 1) of the last accepted step, from its
    /// collocation polynomial.
    pub fn dense(&self, theta: f64, out: &mut [f64]) {
        let c = self.coefficients.c;
        let n = self.n;
        // Lagrange basis on the nodes 0, c₁, c₂, c₃ for the nodes cᵢ (the value at 0 is 0).
        let basis = |i: usize| {
            let mut value = theta / c[i];
            for j in 0..3 {
                if j != i {
                    value *= (theta - c[j]) / (c[i] - c[j]);
                }
            }
            value
        };
        let l = [basis(0), basis(1), basis(2)];
        for r in 0..n {
            out[r] = self.last_x0[r]
                + l[0] * self.last_z[r]
                + l[1] * self.last_z[n + r]
                + l[2] * self.last_z[2 * n + r];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `x'' = -x` as a first-order system, with a quadrature of `x²`.
    struct Oscillator;

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
    struct Stiff;

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

    fn integrate(
        system: &mut dyn System,
        x: &mut [f64],
        end: f64,
        tolerances: Tolerances,
    ) -> Radau {
        let mut radau = Radau::new(system.dimension(), system.controlled(), tolerances);
        let mut t = 0.0;
        let mut h = radau.initial_step(system, t, x, end);
        while t < end {
            let step = h.min(end - t);
            match radau.step(system, t, x, step) {
                StepOutcome::Accepted { h_next } => {
                    t += step;
                    h = h_next;
                }
                StepOutcome::Rejected { h_next } => h = h_next,
            }
        }
        radau
    }

    #[test]
    fn the_coefficients_are_the_method_s() {
        let k = Coefficients::new();
        // Rows of A sum to c (stage order), and b = last row integrates polynomials of
        // degree 4 exactly: Σ bᵢ cᵢ^(k-1) = 1/k.
        for i in 0..3 {
            let sum: f64 = k.a[i].iter().sum();
            assert!((sum - k.c[i]).abs() < 1e-15);
        }
        for power in 1..=5 {
            let sum: f64 = (0..3).map(|i| k.a[2][i] * k.c[i].powi(power - 1)).sum();
            assert!((sum - 1.0 / power as f64).abs() < 1e-15, "{power}");
        }
        // γ₀ is an eigenvalue of A: det(A - γ₀ I) = 0.
        let mut m = k.a;
        for (i, row) in m.iter_mut().enumerate() {
            row[i] -= k.gamma0;
        }
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        assert!(det.abs() < 1e-15, "{det}");
    }

    #[test]
    fn an_oscillator_and_its_quadrature_are_accurate() {
        let mut x = [1.0, 0.0, 0.0];
        let end = 10.0;
        let radau = integrate(&mut Oscillator, &mut x, end, Tolerances::default());
        assert!((x[0] - end.cos()).abs() < 1e-8, "{}", x[0] - end.cos());
        assert!((x[1] + end.sin()).abs() < 1e-8);
        // ∫ cos² = t/2 + sin 2t / 4
        let quadrature = end / 2.0 + (2.0 * end).sin() / 4.0;
        assert!((x[2] - quadrature).abs() < 1e-8, "{}", x[2] - quadrature);
        assert!(radau.stats.accepted < 400, "{:?}", radau.stats);
    }

    #[test]
    fn a_stiff_problem_takes_few_steps() {
        let mut x = [0.0];
        let radau = integrate(
            &mut Stiff,
            &mut x,
            2.0,
            Tolerances {
                relative: 1e-8,
                absolute: 1e-10,
                peak_fraction: 0.0,
            },
        );
        // After the fast transient x follows cos t + 1e-6 sin t (to first order).
        let want = 2f64.cos() + 1e-6 * 2f64.sin();
        assert!((x[0] - want).abs() < 1e-9, "{}", x[0] - want);
        assert!(radau.stats.accepted < 200, "{:?}", radau.stats);
    }

    #[test]
    fn the_dense_output_interpolates_the_step() {
        let mut x = [1.0, 0.0, 0.0];
        let mut radau = Radau::new(
            3,
            2,
            Tolerances {
                relative: 1e-6,
                absolute: 1e-8,
                peak_fraction: 0.0,
            },
        );
        let h = 0.05;
        assert!(matches!(
            radau.step(&mut Oscillator, 0.0, &mut x, h),
            StepOutcome::Accepted { .. }
        ));
        let mut mid = [0.0; 3];
        radau.dense(0.5, &mut mid);
        assert!((mid[0] - (h / 2.0).cos()).abs() < 1e-8);
        radau.dense(1.0, &mut mid);
        assert!((mid[0] - x[0]).abs() < 1e-15);
    }
}
