//! Simulation of the state equations that `bondgraph-core` derives.

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
    Event, Output, Run, Settings, Signal, SimError, Simulator, Stall, Stats, Stepper, TimeScale,
    Trajectory,
};
