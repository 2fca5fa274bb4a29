//! Explicit while the problem lets it, implicit once it is stiff: DOP853 with Radau IIA
//! behind it, as LSODA puts BDF behind Adams.
//!
//! Most nonlinear modes are not stiff (a pendulum, a Duffing oscillator): an explicit
//! method of order 8 takes a few large steps at the tolerance used here, with no Jacobian
//! and no linear algebra, where Radau IIA's order-3 error estimate holds it to many short
//! ones. A mode with fast parasitic dynamics (a light tip on a stiff damper, an orifice near
//! empty, a diode's exponential) is stiff: DOP853's steps are held to its stability limit,
//! its stiffness test ([`Dop853::is_stiff`]) says so after 15 such steps, and the rest of
//! the segment is integrated by Radau IIA. The caller can also switch at once
//! ([`Switching::force_implicit`]), when explicit steps collapse.

use super::dop853::Dop853;
use super::problem::{OdeStats, StepOutcome, System, Tolerances};
use super::radau::Radau;

/// Which method took the last accepted step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// DOP853, explicit.
    Explicit,
    /// Radau IIA, implicit.
    Implicit,
}

/// DOP853 until the problem proves stiff, then Radau IIA; see the
/// [module documentation](self).
pub struct Switching {
    explicit: Dop853,
    implicit: Radau,
    /// The method that takes the next step.
    current: Method,
    /// The method that took the last accepted step (its dense output is the one to use).
    last: Method,
    /// What it was made for: the components that set the step size, the tolerances.
    controlled: usize,
    tolerances: Tolerances,
}

impl Switching {
    /// An integrator for systems of `dimension` components, the first `controlled` of
    /// which set the step size, to `tolerances` (each method applies them its own way).
    pub fn new(dimension: usize, controlled: usize, tolerances: Tolerances) -> Self {
        Self {
            explicit: Dop853::new(dimension, controlled, tolerances),
            implicit: Radau::new(dimension, controlled, tolerances),
            current: Method::Explicit,
            last: Method::Explicit,
            controlled,
            tolerances,
        }
    }

    /// Whether it integrates systems of `dimension` components, the first `controlled`
    /// setting the step size, to `tolerances`: whether [`Switching::reset`] makes it what
    /// [`Switching::new`] would.
    pub fn made_for(&self, dimension: usize, controlled: usize, tolerances: Tolerances) -> bool {
        self.explicit.dimension() == dimension
            && self.controlled == controlled
            && self.tolerances == tolerances
    }

    /// Starts again as [`Switching::new`] does, explicit, keeping the buffers (and the work
    /// counts).
    pub fn reset(&mut self) {
        self.explicit.reset();
        self.implicit.reset();
        self.current = Method::Explicit;
        self.last = Method::Explicit;
    }

    /// The method that takes the next step.
    pub fn method(&self) -> Method {
        self.current
    }

    /// Work counts of both methods together.
    pub fn stats(&self) -> OdeStats {
        let (a, b) = (self.explicit.stats, self.implicit.stats);
        OdeStats {
            accepted: a.accepted + b.accepted,
            rejected: a.rejected + b.rejected,
            rhs: a.rhs + b.rhs,
            jacobians: a.jacobians + b.jacobians,
            factorizations: a.factorizations + b.factorizations,
        }
    }

    /// Switches to Radau IIA for the rest of the segment, keeping what the states' peaks
    /// were (their absolute tolerances).
    pub fn force_implicit(&mut self) {
        if self.current == Method::Implicit {
            return;
        }
        self.implicit.note_peaks(self.explicit.peaks());
        self.current = Method::Implicit;
    }

    /// A first step size for `(tau, x)`, within `[1e-12, max]`.
    pub fn initial_step(&mut self, system: &mut dyn System, tau: f64, x: &[f64], max: f64) -> f64 {
        match self.current {
            Method::Explicit => self.explicit.initial_step(system, tau, x, max),
            Method::Implicit => self.implicit.initial_step(system, tau, x, max),
        }
    }

    /// Attempts a step of size `h` from `(tau, x)`; on acceptance `x` becomes the state at
    /// `tau + h` and the dense output refers to this step.
    pub fn step(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &mut [f64],
        h: f64,
    ) -> StepOutcome {
        let outcome = match self.current {
            Method::Explicit => self.explicit.step(system, tau, x, h),
            Method::Implicit => self.implicit.step(system, tau, x, h),
        };
        if matches!(outcome, StepOutcome::Accepted { .. }) {
            self.last = self.current;
        }
        if self.current == Method::Explicit && self.explicit.is_stiff() {
            self.force_implicit();
        }
        outcome
    }

    /// Builds the dense output of the last accepted step where the method needs to (three
    /// evaluations of `f` for DOP853); call it before [`Switching::dense`].
    pub fn prepare_dense(&mut self, system: &mut dyn System) {
        if self.last == Method::Explicit {
            self.explicit.prepare_dense(system);
        }
    }

    /// The state at fraction `theta` (0 to 1) of the last accepted step.
    pub fn dense(&self, theta: f64, out: &mut [f64]) {
        match self.last {
            Method::Explicit => self.explicit.dense(theta, out),
            Method::Implicit => self.implicit.dense(theta, out),
        }
    }

    /// The state `h` after `(tau, x)` by one step of the method that took the last accepted
    /// step, without error control (for landing exactly on an event); false when Radau's
    /// Newton iteration does not converge. With `reuse`, what the previous call evaluated
    /// at the same `(tau, x)` is kept. The dense output is left as it was.
    pub fn step_exact(
        &mut self,
        system: &mut dyn System,
        tau: f64,
        x: &[f64],
        h: f64,
        reuse: bool,
        out: &mut [f64],
    ) -> bool {
        match self.last {
            Method::Explicit => {
                self.explicit.step_exact(system, tau, x, h, reuse, out);
                true
            }
            Method::Implicit => self.implicit.step_exact(system, tau, x, h, reuse, out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ode::test_systems::{Stiff, VanDerPol};

    /// The stiff test at the scale of 1e-170: `x' = -1e6 (x - 1e-170 cos t)`.
    struct TinyStiff;

    impl System for TinyStiff {
        fn dimension(&self) -> usize {
            1
        }
        fn controlled(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
            dx[0] = -1e6 * (x[0] - 1e-170 * t.cos());
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
    ) -> Switching {
        let mut method = Switching::new(system.dimension(), system.controlled(), tolerances);
        let mut t = 0.0;
        let mut h = method.initial_step(system, t, x, end);
        while t < end {
            let step = h.min(end - t);
            match method.step(system, t, x, step) {
                StepOutcome::Accepted { h_next } => {
                    t += step;
                    h = h_next;
                }
                StepOutcome::Rejected { h_next } => h = h_next,
            }
        }
        method
    }

    #[test]
    fn a_stiff_problem_is_handed_to_radau() {
        let mut x = [0.0];
        let tolerances = Tolerances {
            relative: 1e-8,
            absolute: 1e-10,
            peak_fraction: 0.0,
        };
        let method = integrate(&mut Stiff, &mut x, 2.0, tolerances);
        assert_eq!(method.method(), Method::Implicit);
        // After the fast transient x follows cos t + 1e-6 sin t (to first order).
        let want = 2f64.cos() + 1e-6 * 2f64.sin();
        // Radau IIA holds its error to about the relative tolerance (its last step here is
        // 1.5 s long).
        assert!((x[0] - want).abs() < 1e-8, "{}", x[0] - want);
        // DOP853 alone would need h < 6.1e-6 over 2 s: some 330 000 steps.
        let stats = method.stats();
        assert!(stats.accepted < 300, "{stats:?}");
    }

    /// The stiffness test estimates `|λ|` from the changes of `f` and `x` between two
    /// points, whose squares underflowed for states of 1e-170 (`(1e-171)² = 0`): a velocity
    /// damped at 1e307 /s through a transformer of ratio 1e-154 was never found stiff, and
    /// DOP853 crawled at its stability limit for ten million steps. The same problem as
    /// `a_stiff_problem_is_handed_to_radau`, scaled by 1e-170, is handed over as that one is.
    #[test]
    fn a_stiff_problem_of_tiny_states_is_handed_to_radau() {
        let mut x = [0.0];
        let tolerances = Tolerances {
            relative: 1e-8,
            absolute: 1e-180,
            peak_fraction: 0.0,
        };
        let method = integrate(&mut TinyStiff, &mut x, 2.0, tolerances);
        assert_eq!(method.method(), Method::Implicit);
        let want = 1e-170 * (2f64.cos() + 1e-6 * 2f64.sin());
        assert!((x[0] - want).abs() < 1e-178, "{}", x[0] - want);
        let stats = method.stats();
        assert!(stats.accepted < 300, "{stats:?}");
    }

    #[test]
    fn a_non_stiff_problem_stays_explicit() {
        // Van der Pol (μ = 1) started at the top of its limit cycle (x = 2.00862, x' = 0) is
        // back there after one period, 6.66329 (the cycle's published amplitude and period).
        const AMPLITUDE: f64 = 2.008_619_860_874_843;
        let mut x = [AMPLITUDE, 0.0];
        let period = 6.663_286_859_323_13;
        let method = integrate(
            &mut VanDerPol { epsilon: 1.0 },
            &mut x,
            period,
            Tolerances::default(),
        );
        assert_eq!(method.method(), Method::Explicit);
        assert!((x[0] - AMPLITUDE).abs() < 1e-8, "{x:?}");
        assert!(x[1].abs() < 1e-8, "{x:?}");
        assert_eq!(method.stats().jacobians, 0);
    }
}
