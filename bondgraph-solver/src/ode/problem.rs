//! What every integrator here shares: the problem ([`System`]), the tolerances, the outcome
//! of a step and the work counts.

/// An ODE `dx/dτ = f(τ, x)` with its Jacobian.
///
/// Components from [`System::controlled`] on are quadratures (energies, integrals of
/// outputs): they do not feed back into the others, do not enter the error and
/// convergence tests, and may have zero rows in the Jacobian.
pub trait System {
    /// The number of components.
    fn dimension(&self) -> usize;
    /// How many leading components the step size is controlled on.
    fn controlled(&self) -> usize;
    /// `dx/dτ` at `(tau, x)` into `dx`.
    fn rhs(&mut self, tau: f64, x: &[f64], dx: &mut [f64]);
    /// `∂f/∂x` at `(tau, x)` into `jacobian` (row-major, dimension × dimension).
    fn jacobian(&mut self, tau: f64, x: &[f64], jacobian: &mut [f64]);
}

/// Error tolerances: a component's error is judged against
/// `absolute + relative · (|x| + peak_fraction · peak)`, where `peak` is the largest
/// magnitude the component has had, so that the absolute part follows each state's own
/// scale (a charge of 1e-7 C and a volume of 1 m³ alike) and no unit is assumed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub relative: f64,
    /// Absolute floor (in the states' own units).
    pub absolute: f64,
    /// The fraction of a component's peak magnitude that acts as its absolute tolerance
    /// (times `relative`).
    pub peak_fraction: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            relative: 1e-10,
            absolute: 1e-18,
            peak_fraction: 1e-3,
        }
    }
}

/// The result of one step attempt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepOutcome {
    /// The step was taken; try `h_next` next.
    Accepted {
        /// The proposed next step size.
        h_next: f64,
    },
    /// The step was refused (error too large, or Newton did not converge); retry with
    /// `h_next`.
    Rejected {
        /// The step size to retry with.
        h_next: f64,
    },
}

/// Work counts of an integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OdeStats {
    /// Steps accepted.
    pub accepted: usize,
    /// Steps rejected.
    pub rejected: usize,
    /// Evaluations of `f`.
    pub rhs: usize,
    /// Evaluations of the Jacobian.
    pub jacobians: usize,
    /// LU factorisations of the implicit method's matrices (one per step size and
    /// Jacobian it uses).
    pub factorizations: usize,
}
