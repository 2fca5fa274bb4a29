//! Units: what a model file's `unit` strings mean, and whether its laws agree with them.
//!
//! Every parameter and input may carry a unit (`"N/m"`, `"Pa*s/m^3"`, `"kPa"`). A value
//! written beside a unit is in that unit, and is converted to SI units when the file is
//! read; nothing downstream computes with units (values are SI numbers). An input's values
//! come from scenarios, experiments and `--at` in SI units, so an input's unit must be an
//! SI one. A unit also says what a parameter *is*, so a mass used as a stiffness or a
//! velocity used as a force is a mistake the file itself shows. The modules, one job each:
//!
//! - `dimension`: a dimension as exponents of the SI base dimensions;
//! - `names`: the unit symbols and SI prefixes;
//! - `scale`: exact factors to SI units (`kPa` is 1000 Pa, `rpm` 2π/60 rad/s);
//! - `parse`: unit strings to dimensions and factors;
//! - `convert`: values between a file's units and SI, read once when a file is read;
//! - [`format`](mod@format): dimensions back to readable units;
//! - `infer`: the dimension of an expression, and sums of different quantities;
//! - `domain`: which effort and flow make a bond mechanical, electrical, ...;
//! - `solve`: the dimensions of every bond's effort and flow, by propagation;
//!
//! The check of a model file's units (the laws of every element against its bond, on every
//! bond graph, linear graph and extended model, so `bondgraph check` reports it) is the
//! model validator's (`model::validate`), built on these.

pub(crate) mod convert;
pub(crate) mod dimension;
pub(crate) mod domain;
pub mod format;
pub(crate) mod infer;
pub(crate) mod names;
pub(crate) mod parse;
pub(crate) mod scale;
pub(crate) mod solve;

pub use dimension::{BondDimensions, Dim, PowError};
pub use domain::Domain;
pub use parse::{Unit, UnitError, parse_scaled, parse_unit};
