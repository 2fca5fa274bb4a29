//! The characteristic polynomial `det(sI - A)` and the adjugate `adj(sI - A)` of a symbolic
//! matrix, by the Faddeev–LeVerrier recurrence.
//!
//! Why this recurrence: it needs only matrix products, traces and division by integers, all
//! exact in the field of rational functions, and it yields the adjugate's coefficient
//! matrices on the way, which is what a transfer function `C adj(sI - A) B / det(sI - A)`
//! needs. No pivoting, so no case split on whether a symbolic entry might vanish.

use crate::symbolic::RatFunc;

/// A dense square matrix of rational functions, row-major.
pub type Matrix = Vec<Vec<RatFunc>>;

/// `det(sI - A)` and `adj(sI - A)` as polynomials in `s`.
#[derive(Clone, Debug, PartialEq)]
pub struct Characteristic {
    /// The coefficients `c₀ … cₙ` of `det(sI - A) = sⁿ + cₙ₋₁ sⁿ⁻¹ + … + c₀`, lowest power
    /// first (`cₙ = 1`).
    pub coefficients: Vec<RatFunc>,
    /// `M₁ … Mₙ` with `adj(sI - A) = Σₖ Mₖ sⁿ⁻ᵏ` (`M₁ = I`).
    pub adjugate: Vec<Matrix>,
}

/// The characteristic polynomial and adjugate of the square matrix `a`.
///
/// # Arguments
/// `a`: an `n × n` matrix (rows of equal length `n`).
///
/// # Returns
/// [`Characteristic`], with `n + 1` coefficients and `n` adjugate matrices.
///
/// # Complexity
/// `n` matrix products: `O(n⁴)` rational-function operations.
///
/// # Example
/// ```
/// use bondgraph_core::analysis::characteristic;
/// use bondgraph_core::symbolic::{RatFunc, SymbolTable};
///
/// // A = [[0, 1], [-k, -b]]: det(sI - A) = s² + b s + k.
/// let t = SymbolTable::new(["b", "k"]);
/// let (b, k) = (RatFunc::symbol(t.get("b").unwrap()), RatFunc::symbol(t.get("k").unwrap()));
/// let a = vec![vec![RatFunc::zero(), RatFunc::one()], vec![-k.clone(), -b.clone()]];
/// let ch = characteristic(&a);
/// assert_eq!(ch.coefficients, [k, b, RatFunc::one()]);
/// ```
pub fn characteristic(a: &[Vec<RatFunc>]) -> Characteristic {
    let n = a.len();
    let mut coefficients = vec![RatFunc::zero(); n + 1];
    coefficients[n] = RatFunc::one();
    let mut adjugate: Vec<Matrix> = Vec::with_capacity(n);
    let mut m = identity(n);
    for k in 1..=n {
        if k > 1 {
            m = product(a, &m);
            for (i, row) in m.iter_mut().enumerate() {
                row[i] += &coefficients[n - k + 1];
            }
        }
        let am = product(a, &m);
        let trace: RatFunc = (0..n).map(|i| am[i][i].clone()).sum();
        let k_inverse = RatFunc::integer(k as i64).inv().expect("k >= 1");
        coefficients[n - k] = -(trace * k_inverse);
        adjugate.push(m.clone());
    }
    Characteristic {
        coefficients,
        adjugate,
    }
}

/// The `n × n` identity.
pub(crate) fn identity(n: usize) -> Matrix {
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    if i == j {
                        RatFunc::one()
                    } else {
                        RatFunc::zero()
                    }
                })
                .collect()
        })
        .collect()
}

/// `x · y` for conformable dense matrices, skipping zero entries of `x`.
pub(crate) fn product(x: &[Vec<RatFunc>], y: &[Vec<RatFunc>]) -> Matrix {
    let columns = y.first().map_or(0, Vec::len);
    x.iter()
        .map(|row| {
            let mut out = vec![RatFunc::zero(); columns];
            for (k, entry) in row.iter().enumerate() {
                if entry.is_zero() {
                    continue;
                }
                for (j, cell) in out.iter_mut().enumerate() {
                    if !y[k][j].is_zero() {
                        *cell += entry * &y[k][j];
                    }
                }
            }
            out
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::SymbolTable;

    fn n(k: i64) -> RatFunc {
        RatFunc::integer(k)
    }

    #[test]
    fn three_by_three_against_the_determinant_by_hand() {
        // A = [[1, 2, 0], [0, 3, 1], [1, 0, 2]]: det(sI - A) = s³ - tr(A) s² + (sum of the
        // principal 2x2 minors) s - det(A), by hand tr = 6, minors 3 + 2 + 6 = 11,
        // det = 1·(3·2 - 1·0) - 2·(0·2 - 1·1) = 8.
        let a = vec![
            vec![n(1), n(2), n(0)],
            vec![n(0), n(3), n(1)],
            vec![n(1), n(0), n(2)],
        ];
        let ch = characteristic(&a);
        assert_eq!(ch.coefficients, [n(-8), n(11), n(-6), n(1)]);
    }

    #[test]
    fn adjugate_times_matrix_is_the_determinant() {
        // adj(sI - A)(sI - A) = det(sI - A) I, coefficient by coefficient in s:
        // s^n: M1 = I; s^(n-k): M_{k+1} - M_k A = c_{n-k} I; s^0: -M_n A = c_0 I.
        let t = SymbolTable::new(["a", "b", "c"]);
        let s = |x: &str| RatFunc::symbol(t.get(x).unwrap());
        let a = vec![
            vec![s("a"), n(1), n(0)],
            vec![n(0), s("b"), n(2)],
            vec![s("c"), n(0), n(-1)],
        ];
        let ch = characteristic(&a);
        let last = product(&ch.adjugate[2], &a);
        for (i, row) in last.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                let expected = if i == j { -&ch.coefficients[0] } else { n(0) };
                assert_eq!(*x, expected);
            }
        }
    }
}
