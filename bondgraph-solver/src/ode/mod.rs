//! ODE integration for nonlinear modes: DOP853 (explicit, order 8) while the problem is
//! not stiff, Radau IIA (implicit, order 5) once it is ([`Switching`]).
//!
//! Linear modes are propagated in closed form; a nonlinear mode `dx/dt = f(x, u)` needs a
//! numerical integrator. Most are not stiff (a pendulum, a Duffing oscillator), and for
//! them an explicit method of high order is the fastest at tight tolerances: DOP853 takes
//! large steps with no Jacobian and no linear algebra, and its dense output of order 7
//! serves sampling and event location. A nonlinear model can also have the same fast
//! parasitic dynamics as a linear one (a light tip on a stiff damper, an orifice near empty,
//! a diode's exponential); DOP853's stiffness test notices its steps being held to its
//! stability limit, and the segment goes on with Radau IIA, which is L-stable and stiffly
//! accurate, its collocation polynomial a dense output of order 3, and with the analytic
//! Jacobian (differentiated symbolically, compiled to a tape) its simplified Newton
//! iteration converges in a few steps. LSODA switches between Adams and BDF the same way.
//!
//! Radau IIA follows Hairer and Wanner (Solving ODEs II, IV.8) and their RADAU5: the stage
//! system `(I - h A⊗J) ΔZ = -G(Z)` is solved as one real `3n × 3n` system (the systems here
//! are small, so RADAU5's split into a real and a complex `n × n` one is not worth its
//! bookkeeping); the Jacobian is kept from step to step while Newton's iteration contracts
//! fast, and its factorisation too while the step size would change by less than 20 %;
//! Newton starts from the last step's collocation polynomial; the error estimate is the
//! embedded third-order formula filtered by `(I - h γ₀ J)⁻¹` (estimated again from
//! `f(x + err)` at the first step and after a rejection); and the step size follows
//! Gustafsson's predictive controller. On Van der Pol's stiff oscillator this takes no
//! more evaluations of `f` than scipy's RADAU5 at the same accuracy (`radau.rs`). Work
//! buffers are allocated once per integrator, so steps allocate nothing.
//!
//! `diffsol` (BDF and SDIRK with root finding) was considered: it builds from crates.io,
//! but brings faer and the gemm family with it (about 150 crates, 2 min 19 s of a cold
//! build on two cores, measured), and its event location works on its interpolant, while
//! the hybrid loop here refines each event by re-integrating exactly to it.

pub mod dop853;
mod dop853_coefficients;
mod lu;
mod problem;
pub mod radau;
pub mod switching;
#[cfg(test)]
mod test_systems;

pub use dop853::Dop853;
pub use problem::{OdeStats, StepOutcome, System, Tolerances};
pub use radau::Radau;
pub use switching::{Method, Switching};
