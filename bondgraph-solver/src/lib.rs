//! Simulation of the state equations that `bondgraph-core` derives: exact, hybrid, bounded.
//!
//! A model's modes (one for a smooth model, one per combination of its switching elements'
//! states otherwise) are simulated from event to event. Within a linear mode the state is
//! propagated in closed form ([`propagate`]: eigen-coordinates and φ-functions, so a 5e-15 kg
//! mass beside a 1250 N·s/m damper costs nothing and loses nothing); a nonlinear mode is
//! integrated ([`ode`]: DOP853, switching to Radau IIA where the mode is stiff). Events are
//! the zeros of the guards ([`events`]), located to a few ulps; what happens at them (a
//! contact sticks, a string goes slack) is the modes' business ([`hybrid`]). Around that:
//! steady states read off the exact asymptote or polished by Newton's method, and continued
//! to nearby parameter values for fits ([`steady`]), equilibria ([`equilibrium`]), energy books
//! that balance to rounding ([`energy`]), poles and step responses ([`analysis`]), and
//! parasitic storage found from the eigen-structure ([`parasitic`]). Every loop has a budget
//! of work ([`Settings`]), and exhausting one is an error that says which and where.
//!
//! The usual path is a scenario file ([`scenario::run`]): a [`Simulator`] over the model's
//! modes, a [`Run`] of it under the scenario's inputs, and a [`Trajectory`] of the recorded
//! outputs.
//!
//! # Example
//!
//! A mass on a spring and a damper (`m = 2`, `k = 200`, `b = 4`: `ω_n = 10 rad/s`, `ζ = 0.1`)
//! pushed by a unit force step; the spring's force follows the textbook's step response
//! `F (1 - e^{-ζω_n t} (cos ω_d t + ζ ω_n/ω_d sin ω_d t))`:
//!
//! ```
//! use bondgraph_core::model::{Builder, ElementSpec};
//! use bondgraph_core::equations::OutputSpec;
//! use bondgraph_core::mode::Mode;
//! use bondgraph_core::scenario::Signal;
//! use bondgraph_solver::{Output, Run, Simulator};
//!
//! let model = Builder::new("mass_spring_damper")
//!     .parameter("m", 2.0, "kg")
//!     .parameter("k", 200.0, "N/m")
//!     .parameter("b", 4.0, "N*s/m")
//!     .input("F", "N")
//!     .element("force", ElementSpec::effort_source("F"))
//!     .element("v", ElementSpec::One)
//!     .element("mass", ElementSpec::inertance("m"))
//!     .element("spring", ElementSpec::stiffness("k"))
//!     .element("damper", ElementSpec::resistance("b"))
//!     .bonds([("force", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")])
//!     .build()
//!     .unwrap();
//! let spring = Output {
//!     name: "effort:spring".into(),
//!     spec: OutputSpec::parse(&model, "effort:spring").unwrap(),
//!     integral: false,
//! };
//! let mut simulator = Simulator::new(&model, vec![spring]);
//! let trajectory = simulator.run(&Run {
//!     inputs: &[&Signal::Constant(1.0)],
//!     initial_mode: Mode::initial(&model),
//!     initial_state: vec![0.0, 0.0],
//!     duration: 0.5,
//!     sample: Some(0.25),
//!     audit_energy: false,
//! }).unwrap();
//!
//! let (zeta, wn) = (0.1_f64, 10.0_f64);
//! let wd = wn * (1.0 - zeta * zeta).sqrt();
//! let t = 0.5;
//! let exact = 1.0 - (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin());
//! assert_eq!(trajectory.times, [0.0, 0.25, 0.5]);
//! let spring = trajectory.value(2, 0).unwrap();
//! assert!((spring - exact).abs() < 1e-14, "{spring} against {exact}");
//! ```
//!
//! A scenario file says the same (inputs, initial state, duration, what to record) for
//! [`scenario::run`].

pub mod analysis;
pub mod energy;
pub mod equilibrium;
pub mod events;
mod gauss;
pub mod hybrid;
pub mod linalg;
pub mod nonlinear;
pub mod numeric;
pub mod ode;
pub mod parasitic;
pub mod propagate;
pub mod scenario;
pub mod steady;

pub use hybrid::{
    Event, Output, Run, Settings, SharedForms, Signal, SimError, Simulator, Stall, Stats, Stepper,
    TimeScale, Trajectory,
};
