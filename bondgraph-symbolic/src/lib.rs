//! Exact symbolic algebra: polynomials and rational functions of model parameters.
//!
//! State equations are derived symbolically so that every matrix entry can be printed the
//! way a textbook writes it, `-(b + K_p)/M`, and compared with published models. Two
//! design decisions follow from that:
//!
//! - **Canonical form.** Every [`RatFunc`] is kept as `num/den` with the true multivariate
//!   gcd cancelled, integer coefficients with no common factor, a positive leading
//!   denominator coefficient, and terms sorted in one fixed order. Equal rational functions
//!   are then *structurally* equal: `==` is mathematical equality, hashing works, and equal
//!   expressions print identically however they were derived.
//! - **Exact arithmetic.** Coefficients are arbitrary-precision integers, and decimal
//!   literals become exact fractions (`0.5` is 1/2), so cancellations that are exact on paper
//!   are exact here; floating point only appears in [`RatFunc::eval`], which carries
//!   intermediate products in extended range so that only a value that overflows does.
//!
//! Symbols are numbered in print order by a [`SymbolTable`]; the term order is
//! lexicographic on those ids (see [`Monomial`]), so canonical order is alphabetical order.
//! Monomials are sparse, because models have thousands of symbols but a term few.
//!
//! # A tour
//!
//! The damping entry of a mass driven through a proportional controller, derived two ways:
//! as a sum over the common denominator and as the quotient of its factors. Canonical form
//! makes them one value, printed as a textbook prints it, and exact arithmetic keeps `0.5`
//! a half.
//!
//! ```
//! use bondgraph_symbolic::{RatFunc, SymbolTable};
//!
//! let symbols = SymbolTable::new(["M", "b", "K_p"]);
//! let var = |name: &str| RatFunc::symbol(symbols.get(name).unwrap());
//! let (m, b, k_p) = (var("M"), var("b"), var("K_p"));
//!
//! // -(b + K_p)/M, and -b/M - K_p/M, and (b + K_p)(b - K_p) / (M (K_p - b)).
//! let direct = -(b.clone() + k_p.clone()).checked_div(&m).unwrap();
//! let summed = -b.checked_div(&m).unwrap() - k_p.checked_div(&m).unwrap();
//! let cancelled = ((b.clone() + k_p.clone()) * (b.clone() - k_p.clone()))
//!     .checked_div(&(m.clone() * (k_p.clone() - b.clone())))
//!     .unwrap();
//! assert_eq!(direct, summed);
//! assert_eq!(direct, cancelled);
//! assert_eq!(direct.text(&symbols), "-(b + K_p)/M");
//! assert_eq!(direct.latex(&symbols), r"-\frac{b + K_{p}}{M}");
//!
//! // Exact literals: half of 2 b is b, with no rounding on the way.
//! let half = RatFunc::from_decimal("0.5").unwrap();
//! assert_eq!(half * RatFunc::integer(2) * b.clone(), b);
//!
//! // Numbers only at the end, at values indexed by symbol (print order: b, K_p, M).
//! let order: Vec<&str> = symbols.iter().map(|(_, name)| name).collect();
//! assert_eq!(order, ["b", "K_p", "M"]);
//! assert_eq!(direct.eval(&[3.0, 5.0, 2.0]), -4.0);
//! ```
//!
//! Submodules, one job each:
//!
//! - `symbol`: names and their ids ([`Symbol`], [`SymbolTable`]);
//! - `monomial`: sparse monomials and the term order ([`Monomial`]);
//! - `poly`: polynomials and exact division ([`Poly`], [`div_exact`]);
//! - `gcd`: the multivariate gcd over the integers ([`gcd`]), with its helpers `modp`
//!   (arithmetic modulo a prime, degree bounds from modular images) and `modgcd` (Brown's
//!   modular gcd);
//! - `decimal`: exact values of number literals;
//! - `ratfunc`: rational functions in canonical form ([`RatFunc`]);
//! - `scaled`: numbers with an exponent of their own, so that evaluation does not overflow
//!   on the way ([`Scaled`]);
//! - `print`: plain-text and LaTeX rendering;
//! - [`expr`]: symbolic expressions for nonlinear laws, with exact coefficients.

pub mod decimal;
pub mod expr;
pub mod function;
mod gcd;
mod modgcd;
mod modp;
mod monomial;
mod poly;
mod print;
mod ratfunc;
mod scaled;
mod symbol;

#[cfg(test)]
mod proptests;

pub use gcd::gcd;
pub use monomial::Monomial;
pub use poly::{Poly, div_exact};
pub use print::{latex_name, latex_subscript};
pub use ratfunc::RatFunc;
pub use scaled::Scaled;
pub use symbol::{Symbol, SymbolTable};

/// Implements `Add`, `Sub`, `Mul` for every owned/borrowed combination, and the matching
/// assignment operators: from `add_ref`-style methods taking two references, and
/// `add_owned`-style methods that reuse the left operand's storage.
macro_rules! forward_binops {
    ($t:ty, $add:ident, $sub:ident, $mul:ident, $add_o:ident, $sub_o:ident, $mul_o:ident) => {
        $crate::forward_binops!(@op $t, Add, add, AddAssign, add_assign, $add, $add_o);
        $crate::forward_binops!(@op $t, Sub, sub, SubAssign, sub_assign, $sub, $sub_o);
        $crate::forward_binops!(@op $t, Mul, mul, MulAssign, mul_assign, $mul, $mul_o);
    };
    (@op $t:ty, $tr:ident, $m:ident, $tra:ident, $ma:ident, $imp:ident, $imp_o:ident) => {
        impl std::ops::$tr<&$t> for &$t {
            type Output = $t;
            fn $m(self, rhs: &$t) -> $t {
                <$t>::$imp(self, rhs)
            }
        }
        impl std::ops::$tr<$t> for &$t {
            type Output = $t;
            fn $m(self, rhs: $t) -> $t {
                <$t>::$imp(self, &rhs)
            }
        }
        impl std::ops::$tr<&$t> for $t {
            type Output = $t;
            fn $m(self, rhs: &$t) -> $t {
                <$t>::$imp_o(self, rhs)
            }
        }
        impl std::ops::$tr<$t> for $t {
            type Output = $t;
            fn $m(self, rhs: $t) -> $t {
                <$t>::$imp_o(self, &rhs)
            }
        }
        impl std::ops::$tra<&$t> for $t {
            fn $ma(&mut self, rhs: &$t) {
                *self = <$t>::$imp_o(std::mem::take(self), rhs);
            }
        }
        impl std::ops::$tra<$t> for $t {
            fn $ma(&mut self, rhs: $t) {
                *self = <$t>::$imp_o(std::mem::take(self), &rhs);
            }
        }
    };
}
pub(crate) use forward_binops;
