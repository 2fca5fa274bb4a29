//! The study's tests: the paper's equations, tables and Fig. 6, and every library on the
//! flagship's bundled models and data.

mod fig6_events;
mod global_fits;
mod hidden;
mod paper;
mod reproduce;
mod stability;
mod stalls;
mod steady_regimes;
mod support;
mod tables;
