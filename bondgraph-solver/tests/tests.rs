//! Whole-crate tests of the solver on real model files, against closed-form solutions.

mod analysis;
mod continuation;
mod energy;
mod energy_books;
mod energy_records;
mod event_bounds;
mod extreme_ratios;
mod flow_limit;
mod hardening;
mod hardening_events;
mod held_nonlinear;
mod input_rates;
mod multiscale_events;
mod natural_laws;
mod nonlinear;
mod nonlinear_events;
mod oracle;
mod oscillating_guards;
mod properties;
mod settling;
mod steady_polish;
mod stick_slip;
mod stribeck;
mod stribeck_zero;
mod support;
mod trouble;
