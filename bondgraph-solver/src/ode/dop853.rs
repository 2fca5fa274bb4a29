//! DOP853: Dormand and Prince's explicit Runge–Kutta method of order 8 with step-size
//! control, a dense output of order 7 and Hairer's stiffness detection; see the
//! [module documentation](super).
//!
//! A step takes 12 evaluations of `f` (the last, `f` at the new state, is the next step's
//! first); the dense output costs 3 more and is built only for steps that need it
//! ([`Dop853::prepare_dense`]). The error estimate combines the embedded fifth- and
//! third-order solutions as Hairer, Nørsett and Wanner do (Solving ODEs I, II.10), and the
//! step follows it with exponent 1/8.

// The kernels index stages and components as the method's formulas do.
#![allow(clippy::needless_range_loop)]

use super::dop853_coefficients::{A, BHH, C, D, E5, EXTENDED, STAGES};
use super::problem::{OdeStats, StepOutcome, System, Tolerances};

/// `h·|λ|` above which a step is taken as limited by stability rather than accuracy
/// (DOP853's stability region reaches about 6 along the negative real axis).
const STABILITY_LIMIT: f64 = 6.1;
/// Accepted steps in a row at the stability limit that make a problem stiff.
const STIFF_STEPS: usize = 15;
/// Accepted steps in a row within the limit that clear the count.
const NONSTIFF_STEPS: usize = 6;

/// The Euclidean norm of `values`, scaled by their largest magnitude so that neither the
/// squares of tiny components underflow nor those of huge ones overflow.
fn scaled_norm(values: impl Iterator<Item = f64> + Clone) -> f64 {
    let largest = values.clone().fold(0.0_f64, |m, v| m.max(v.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest * values.map(|v| (v / largest).powi(2)).sum::<f64>().sqrt()
}

/// A DOP853 integrator with its work buffers; see the [module documentation](self).
pub struct Dop853 {
    n: usize,
    controlled: usize,
    tolerances: Tolerances,
    /// Stage derivatives, `EXTENDED × n`: the step's 12, `f` at the new state, the dense
    /// output's 3.
    k: Vec<f64>,
    /// Stage derivatives of [`Dop853::step_exact`], kept apart so that the accepted step's
    /// dense output survives it.
    k_exact: Vec<f64>,
    stage_x: Vec<f64>,
    x_new: Vec<f64>,
    /// The argument of the last stage (at `τ + h`), for the stiffness test.
    x_last_stage: Vec<f64>,
    /// `f` at the end of the last accepted step, reused as the next step's first stage.
    fsal: Option<(f64, Vec<f64>, Vec<f64>)>,
    /// The last accepted step: start, size, start state.
    last_tau: f64,
    last_h: f64,
    last_x0: Vec<f64>,
    /// The dense output's terms `F₀ … F₆` (`7 × n`), once built for the last step.
    dense_terms: Vec<f64>,
    dense_ready: bool,
    rejected_last: bool,
    /// The largest magnitude of each component so far.
    peak: Vec<f64>,
    stiff_count: usize,
    nonstiff_count: usize,
    /// Work counts.
    pub stats: OdeStats,
}

impl Dop853 {
    /// An integrator for systems of `dimension` components, the first `controlled` of
    /// which set the step size.
    pub fn new(dimension: usize, controlled: usize, tolerances: Tolerances) -> Self {
        let n = dimension;
        Self {
            n,
            controlled: controlled.min(n),
            tolerances,
            k: vec![0.0; EXTENDED * n],
            k_exact: vec![0.0; STAGES * n],
            stage_x: vec![0.0; n],
            x_new: vec![0.0; n],
            x_last_stage: vec![0.0; n],
            fsal: None,
            last_tau: 0.0,
            last_h: 0.0,
            last_x0: vec![0.0; n],
            dense_terms: vec![0.0; 7 * n],
            dense_ready: false,
            rejected_last: false,
            peak: vec![0.0; n],
            stiff_count: 0,
            nonstiff_count: 0,
            stats: OdeStats::default(),
        }
    }

    /// Forgets everything of the steps taken (the first stage kept, the last step, the
    /// peaks, the stiffness count) but the work counts, as a new integrator for another
    /// system of the same dimension would start, keeping the buffers.
    pub fn reset(&mut self) {
        self.fsal = None;
        self.last_tau = 0.0;
        self.last_h = 0.0;
        self.dense_ready = false;
        self.rejected_last = false;
        self.peak.fill(0.0);
        self.stiff_count = 0;
        self.nonstiff_count = 0;
    }

    /// What an error in component `r` at magnitude `value` is judged against.
    fn scale(&self, r: usize, value: f64) -> f64 {
        self.tolerances.absolute
            + self.tolerances.relative * (value + self.tolerances.peak_fraction * self.peak[r])
    }

    fn note_peaks(&mut self, x: &[f64]) {
        for (peak, v) in self.peak.iter_mut().zip(x) {
            *peak = peak.max(v.abs());
        }
    }

    /// The number of components.
    pub fn dimension(&self) -> usize {
        self.n
    }

    /// The largest magnitude of each component so far.
    pub fn peaks(&self) -> &[f64] {
        &self.peak
    }

    /// Whether the last steps were held to the stability limit: 15 accepted steps in a
    /// row with `h·|λ| > 6.1`, `|λ|` estimated from the last stage as
    /// `|f(x₁) - f(x̃)| / |x₁ - x̃|` (Hairer, Nørsett and Wanner, Solving ODEs I, IV.2).
    pub fn is_stiff(&self) -> bool {
        self.stiff_count >= STIFF_STEPS
    }

    /// A first step size for `(tau, x)` by Hairer's estimate of the second derivative,
    /// within `[1e-12, max]`.
    pub fn initial_step(&mut self, system: &mut dyn System, tau: f64, x: &[f64], max: f64) -> f64 {
        let n = self.n;
        self.note_peaks(x);
        let (f0, rest) = self.k.split_at_mut(n);
        system.rhs(tau, x, f0);
        self.stats.rhs += 1;
        let (mut dnf, mut dny) = (0.0, 0.0);
        for r in 0..self.controlled {
            let sk = self.tolerances.absolute
                + self.tolerances.relative
                    * (x[r].abs() + self.tolerances.peak_fraction * self.peak[r]);
            dnf += (f0[r] / sk).powi(2);
            dny += (x[r] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
            1e-6
        } else {
            (dny / dnf).sqrt() * 0.01
        };
        h = h.min(max);
        for r in 0..n {
            self.stage_x[r] = x[r] + h * f0[r];
        }
        let f1 = &mut rest[..n];
        system.rhs(tau + h, &self.stage_x, f1);
        self.stats.rhs += 1;
        let mut der2: f64 = 0.0;
        for r in 0..self.controlled {
            let sk = self.tolerances.absolute
                + self.tolerances.relative
                    * (x[r].abs() + self.tolerances.peak_fraction * self.peak[r]);
            der2 += ((f1[r] - f0[r]) / sk).powi(2);
        }
        let der2 = der2.sqrt() / h;
        let der12 = der2.abs().max(dnf.sqrt());
        let h1 = if der12 <= 1e-15 {
            (h * 1e-3).max(1e-6)
        } else {
            (0.01 / der12).powf(1.0 / 8.0)
        };
        self.fsal = Some((tau, x.to_vec(), f0.to_vec()));
        (100.0 * h).min(h1).min(max).max(1e-12_f64.min(max))
    }

    /// The stages of a step of size `h` from `(tau, x)`, the first given: into `k`, the
    /// new state into `x_new` and the last stage's argument into `x_last_stage`; or, for
    /// an exact step, into `k_exact` and the new state into `exact`.
    fn stages(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &[f64],
        h: f64,
        exact: Option<&mut [f64]>,
    ) {
        let n = self.n;
        let is_exact = exact.is_some();
        let (k, x_new): (&mut [f64], &mut [f64]) = match exact {
            Some(out) => (&mut self.k_exact, out),
            None => (&mut self.k, &mut self.x_new),
        };
        for s in 1..STAGES {
            combine(x, h, &A[s][..s], k, n, &mut self.stage_x);
            system.rhs(tau + C[s] * h, &self.stage_x, &mut k[s * n..(s + 1) * n]);
        }
        if !is_exact {
            self.x_last_stage.copy_from_slice(&self.stage_x);
        }
        combine(x, h, &A[STAGES][..STAGES], k, n, x_new);
        self.stats.rhs += STAGES - 1;
    }

    /// Attempts a step of size `h` from `(tau, x)`; on acceptance `x` becomes the state at
    /// `tau + h` and the step is the one [`Dop853::prepare_dense`] and [`Dop853::dense`]
    /// refer to.
    pub fn step(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &mut [f64],
        h: f64,
    ) -> StepOutcome {
        let n = self.n;
        match &self.fsal {
            Some((t, at, f)) if *t == tau && at.as_slice() == &x[..] => {
                self.k[..n].copy_from_slice(f);
            }
            _ => {
                system.rhs(tau, x, &mut self.k[..n]);
                self.stats.rhs += 1;
            }
        }
        self.stages(system, tau, x, h, None);
        let error = self.error_norm(x, h);
        if error.is_nan() || error > 1.0 {
            self.stats.rejected += 1;
            self.rejected_last = true;
            let factor = if error.is_finite() {
                (0.9 / error.powf(1.0 / 8.0)).max(0.333)
            } else {
                0.25
            };
            return StepOutcome::Rejected { h_next: h * factor };
        }
        // f at the new state: the stiffness test's, and the next step's first stage.
        let (head, tail) = self.k.split_at_mut(STAGES * n);
        system.rhs(tau + h, &self.x_new, &mut tail[..n]);
        self.stats.rhs += 1;
        // |Δf| / |Δx| between the last stage and the new state estimates |λ|; each norm is
        // scaled by its largest component, as the squares of states of 1e-171 underflow (a
        // velocity damped at 1e307 /s read as no estimate at all, and the explicit steps
        // crawled at their stability limit for ever).
        let rise = scaled_norm((0..self.controlled).map(|r| tail[r] - head[(STAGES - 1) * n + r]));
        let run = scaled_norm((0..self.controlled).map(|r| self.x_new[r] - self.x_last_stage[r]));
        if run > 0.0 {
            if h * (rise / run) > STABILITY_LIMIT {
                self.nonstiff_count = 0;
                self.stiff_count += 1;
            } else {
                self.nonstiff_count += 1;
                if self.nonstiff_count >= NONSTIFF_STEPS {
                    self.stiff_count = 0;
                }
            }
        }
        self.last_tau = tau;
        self.last_h = h;
        self.last_x0.copy_from_slice(x);
        x.copy_from_slice(&self.x_new);
        self.dense_ready = false;
        match &mut self.fsal {
            Some((t, at, f)) => {
                *t = tau + h;
                at.copy_from_slice(x);
                f.copy_from_slice(&tail[..n]);
            }
            None => self.fsal = Some((tau + h, x.to_vec(), tail[..n].to_vec())),
        }
        self.note_peaks(x);
        self.stats.accepted += 1;
        let mut factor = (0.9 / error.max(1e-30).powf(1.0 / 8.0)).clamp(1.0 / 3.0, 6.0);
        if self.rejected_last {
            factor = factor.min(1.0);
        }
        self.rejected_last = false;
        StepOutcome::Accepted { h_next: h * factor }
    }

    /// The error of the step in `x_new` from `x`, in units of the tolerance: the fifth-order
    /// estimate, corrected by the third-order one where that is smaller.
    fn error_norm(&self, x: &[f64], h: f64) -> f64 {
        let n = self.n;
        let (mut err5, mut err3) = (0.0, 0.0);
        for r in 0..self.controlled {
            let scale = self.scale(r, x[r].abs().max(self.x_new[r].abs()));
            // Each stage's rate times the step, before summing: the rates alone may be near
            // the largest double where the step's changes are not (a momentum growing at
            // 1e308 N over 1e-310 s), and their sum overflowed.
            let hk = |s: usize| h * self.k[s * n + r];
            let mut e5 = 0.0;
            let mut b = 0.0;
            for s in 0..STAGES {
                e5 += E5[s] * hk(s);
                b += A[STAGES][s] * hk(s);
            }
            let e3 = b - BHH[0] * hk(0) - BHH[1] * hk(8) - BHH[2] * hk(11);
            err5 += (e5 / scale).powi(2);
            err3 += (e3 / scale).powi(2);
        }
        if err5 == 0.0 && err3 == 0.0 {
            return 0.0;
        }
        let denominator = err5 + 0.01 * err3;
        err5 / (denominator * self.controlled.max(1) as f64).sqrt()
    }

    /// The state `h` after `(tau, x)` by one step without error control (for landing
    /// exactly on an event), leaving the accepted step's dense output as it was. With
    /// `reuse`, `f(tau, x)` of the previous call is kept.
    pub fn step_exact(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &[f64],
        h: f64,
        reuse: bool,
        out: &mut [f64],
    ) {
        let n = self.n;
        if h == 0.0 {
            out.copy_from_slice(x);
            return;
        }
        if !reuse {
            system.rhs(tau, x, &mut self.k_exact[..n]);
            self.stats.rhs += 1;
        }
        self.stages(system, tau, x, h, Some(out));
    }

    /// Builds the dense output of the last accepted step (three more evaluations of `f`);
    /// call it before the next step. Nothing to do when it is built already.
    pub fn prepare_dense(&mut self, system: &mut dyn System) {
        if self.dense_ready {
            return;
        }
        let n = self.n;
        let h = self.last_h;
        for s in STAGES + 1..EXTENDED {
            combine(&self.last_x0, h, &A[s][..s], &self.k, n, &mut self.stage_x);
            system.rhs(
                self.last_tau + C[s] * h,
                &self.stage_x,
                &mut self.k[s * n..(s + 1) * n],
            );
        }
        self.stats.rhs += EXTENDED - STAGES - 1;
        let f0 = &self.k[..n];
        let f1 = &self.k[STAGES * n..(STAGES + 1) * n];
        // x_new is the accepted state still.
        for r in 0..n {
            let delta = self.x_new[r] - self.last_x0[r];
            self.dense_terms[r] = delta;
            self.dense_terms[n + r] = h * f0[r] - delta;
            self.dense_terms[2 * n + r] = 2.0 * delta - h * (f1[r] + f0[r]);
            for (i, row) in D.iter().enumerate() {
                let mut sum = 0.0;
                for s in 0..EXTENDED {
                    sum += row[s] * self.k[s * n + r];
                }
                self.dense_terms[(3 + i) * n + r] = h * sum;
            }
        }
        self.dense_ready = true;
    }

    /// The state at fraction `theta` (0 to 1) of the last accepted step, from its dense
    /// output (built by [`Dop853::prepare_dense`]).
    pub fn dense(&self, theta: f64, out: &mut [f64]) {
        debug_assert!(self.dense_ready, "prepare_dense before dense");
        let n = self.n;
        let s = 1.0 - theta;
        let f = &self.dense_terms;
        for r in 0..n {
            let mut value = f[6 * n + r] * theta;
            value = (value + f[5 * n + r]) * s;
            value = (value + f[4 * n + r]) * theta;
            value = (value + f[3 * n + r]) * s;
            value = (value + f[2 * n + r]) * theta;
            value = (value + f[n + r]) * s;
            value = (value + f[r]) * theta;
            out[r] = self.last_x0[r] + value;
        }
    }
}

/// `out = x + h Σ_j a_j k_j` over the stages `j` that `a` covers (skipping the tableau's
/// zeros).
fn combine(x: &[f64], h: f64, a: &[f64], k: &[f64], n: usize, out: &mut [f64]) {
    out[..n].copy_from_slice(&x[..n]);
    if n == 0 {
        // A mode with no states (every body held by a stuck contact): nothing to combine.
        return;
    }
    for (&weight, stage) in a.iter().zip(k.chunks_exact(n)) {
        if weight != 0.0 {
            let w = h * weight;
            for (o, &d) in out[..n].iter_mut().zip(stage) {
                *o += w * d;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ode::test_systems::Oscillator;

    /// `dx/dt = -x²` from 1: `x = 1/(1 + t)`.
    struct Riccati;

    impl System for Riccati {
        fn dimension(&self) -> usize {
            1
        }
        fn controlled(&self) -> usize {
            1
        }
        fn rhs(&mut self, _: f64, x: &[f64], dx: &mut [f64]) {
            dx[0] = -x[0] * x[0];
        }
        fn jacobian(&mut self, _: f64, x: &[f64], j: &mut [f64]) {
            j[0] = -2.0 * x[0];
        }
    }

    /// `dx/dt = 7 t⁶`: `x = t⁷`, which order 8 integrates and order 7 interpolates exactly.
    struct Septic;

    impl System for Septic {
        fn dimension(&self) -> usize {
            1
        }
        fn controlled(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, _: &[f64], dx: &mut [f64]) {
            dx[0] = 7.0 * t.powi(6);
        }
        fn jacobian(&mut self, _: f64, _: &[f64], j: &mut [f64]) {
            j[0] = 0.0;
        }
    }

    fn fixed_steps(system: &mut dyn System, x: &mut [f64], end: f64, steps: usize) {
        let n = system.dimension();
        let mut method = Dop853::new(n, system.controlled(), Tolerances::default());
        let h = end / steps as f64;
        let mut out = vec![0.0; n];
        for i in 0..steps {
            method.step_exact(system, i as f64 * h, x, h, false, &mut out);
            x.copy_from_slice(&out);
        }
    }

    #[test]
    fn the_coefficients_meet_the_order_conditions() {
        // Rows of A sum to c, and the weights b integrate polynomials of degree 7 exactly.
        for s in 1..EXTENDED {
            let sum: f64 = A[s].iter().sum();
            assert!((sum - C[s]).abs() < 1e-14, "row {s}: {}", sum - C[s]);
        }
        for power in 1..=8 {
            let sum: f64 = (0..STAGES)
                .map(|s| A[STAGES][s] * C[s].powi(power - 1))
                .sum();
            assert!((sum - 1.0 / f64::from(power)).abs() < 1e-14, "{power}");
        }
        // The error estimates vanish on constants: their weights sum to zero.
        let e5: f64 = E5.iter().sum();
        assert!(e5.abs() < 1e-14, "{e5}");
        let b: f64 = A[STAGES].iter().sum();
        assert!((b - BHH.iter().sum::<f64>()).abs() < 1e-14);
    }

    #[test]
    fn the_method_is_of_order_eight_on_a_nonlinear_problem() {
        let errors: Vec<f64> = [4, 8]
            .iter()
            .map(|&steps| {
                let mut x = [1.0];
                fixed_steps(&mut Riccati, &mut x, 1.0, steps);
                (x[0] - 0.5).abs()
            })
            .collect();
        // Halving the step divides the error by about 2⁸ = 256.
        let ratio = errors[0] / errors[1];
        assert!((180.0..360.0).contains(&ratio), "{errors:?}: {ratio}");
    }

    #[test]
    fn a_septic_is_integrated_and_interpolated_exactly() {
        // Loose tolerances, so that the one step is accepted whatever its estimate says.
        let loose = Tolerances {
            relative: 1.0,
            absolute: 1.0,
            peak_fraction: 0.0,
        };
        let mut method = Dop853::new(1, 1, loose);
        let mut x = [0.0];
        let h = 0.8;
        assert!(matches!(
            method.step(&mut Septic, 0.0, &mut x, h),
            StepOutcome::Accepted { .. }
        ));
        assert!((x[0] - h.powi(7)).abs() < 1e-15, "{}", x[0] - h.powi(7));
        method.prepare_dense(&mut Septic);
        let mut mid = [0.0];
        for theta in [0.1, 0.37, 0.5, 0.9] {
            method.dense(theta, &mut mid);
            let want = (theta * h).powi(7);
            assert!((mid[0] - want).abs() < 1e-15, "{theta}: {}", mid[0] - want);
        }
    }

    #[test]
    fn an_oscillator_and_its_quadrature_are_accurate_in_few_steps() {
        let mut system = Oscillator;
        let mut method = Dop853::new(3, 2, Tolerances::default());
        let mut x = [1.0, 0.0, 0.0];
        let end = 10.0;
        let (mut t, mut h) = (0.0, method.initial_step(&mut system, 0.0, &x, end));
        let mut dense_checked = 0;
        while t < end {
            let step = h.min(end - t);
            match method.step(&mut system, t, &mut x, step) {
                StepOutcome::Accepted { h_next } => {
                    method.prepare_dense(&mut system);
                    let mut mid = [0.0; 3];
                    method.dense(0.5, &mut mid);
                    let tm = t + 0.5 * step;
                    assert!(
                        (mid[0] - tm.cos()).abs() < 1e-9,
                        "{tm}: {}",
                        mid[0] - tm.cos()
                    );
                    dense_checked += 1;
                    t += step;
                    h = h_next;
                }
                StepOutcome::Rejected { h_next } => h = h_next,
            }
        }
        assert!((x[0] - end.cos()).abs() < 1e-9, "{}", x[0] - end.cos());
        assert!((x[1] + end.sin()).abs() < 1e-9);
        let quadrature = end / 2.0 + (2.0 * end).sin() / 4.0;
        assert!((x[2] - quadrature).abs() < 1e-9, "{}", x[2] - quadrature);
        // Ten radians at 1e-10: about a hundred steps of order 8 (Radau IIA takes several
        // hundred).
        assert!(method.stats.accepted < 150, "{:?}", method.stats);
        assert_eq!(dense_checked, method.stats.accepted);
        assert!(!method.is_stiff());
    }
}
