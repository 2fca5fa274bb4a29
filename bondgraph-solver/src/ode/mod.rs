//! Stiff ODE integration for nonlinear modes: the 3-stage Radau IIA method (order 5).
//!
//! Linear modes are propagated in closed form; a nonlinear mode `dx/dt = f(x, u)` needs a
//! numerical integrator, and one that copes with stiffness, because a nonlinear model has
//! the same fast parasitic dynamics as a linear one (a light tip on a stiff damper, an
//! orifice near empty, a diode's exponential). Radau IIA is L-stable and stiffly accurate,
//! its collocation polynomial gives a dense output of order 3 for event location and
//! sampling, and with the analytic Jacobian (differentiated symbolically, compiled to a
//! tape) its simplified Newton iteration converges in a few steps.
//!
//! The implementation follows Hairer and Wanner (Solving ODEs II, IV.8): the stage system
//! `(I - h A⊗J) ΔZ = -G(Z)` is solved with one LU decomposition per step (the systems here
//! are small), the error estimate is the embedded third-order formula filtered by
//! `(I - h γ₀ J)⁻¹`, and the step size follows it with exponent 1/4. Work buffers are
//! allocated once per integrator, so steps allocate nothing.
//!
//! `diffsol` (BDF and SDIRK with root finding) was considered: it builds from crates.io,
//! but brings faer and the gemm family with it (about 150 crates, 2 min 19 s of a cold
//! build on two cores, measured), and its event location works on its interpolant, while
//! the hybrid loop here refines each event by re-integrating exactly to it.

mod lu;
pub mod radau;

pub use radau::{Radau, StepOutcome, System, Tolerances};
