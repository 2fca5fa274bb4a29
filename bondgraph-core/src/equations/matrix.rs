//! Small dense symbolic matrices: the mass (or compliance) matrix of a merged group.

use crate::linear::LinearForm;
use crate::symbolic::RatFunc;

/// A dense square matrix of rational functions, row-major.
pub(crate) type Matrix = Vec<Vec<RatFunc>>;

/// The inverse of `matrix` by Gauss-Jordan elimination, or `None` if it is singular.
pub(crate) fn inverse(matrix: &Matrix) -> Option<Matrix> {
    let n = matrix.len();
    let mut left = matrix.clone();
    let mut right: Matrix = (0..n)
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
        .collect();
    for k in 0..n {
        let pivot_row = (k..n).find(|&r| !left[r][k].is_zero())?;
        left.swap(k, pivot_row);
        right.swap(k, pivot_row);
        let pivot_inverse = left[k][k].inv()?;
        for j in 0..n {
            left[k][j] = &left[k][j] * &pivot_inverse;
            right[k][j] = &right[k][j] * &pivot_inverse;
        }
        for r in 0..n {
            if r == k || left[r][k].is_zero() {
                continue;
            }
            let factor = left[r][k].clone();
            for j in 0..n {
                let l = &left[k][j] * &factor;
                left[r][j] -= l;
                let rr = &right[k][j] * &factor;
                right[r][j] -= rr;
            }
        }
    }
    Some(right)
}

/// `matrix · forms`: row `i` is `Σⱼ matrix[i][j] · forms[j]`.
pub(crate) fn apply(matrix: &Matrix, forms: &[LinearForm]) -> Vec<LinearForm> {
    matrix
        .iter()
        .map(|row| {
            let mut sum = LinearForm::zero();
            for (coefficient, form) in row.iter().zip(forms) {
                sum.add_scaled(form, coefficient);
            }
            sum
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::{Symbol, SymbolTable};

    fn sym(table: &SymbolTable, name: &str) -> RatFunc {
        let s: Symbol = table.get(name).unwrap();
        RatFunc::symbol(s)
    }

    #[test]
    fn inverse_of_a_two_by_two_mass_matrix() {
        // [[a, b], [b, c]]⁻¹ = [[c, -b], [-b, a]] / (a c - b²), by hand.
        let t = SymbolTable::new(["a", "b", "c"]);
        let (a, b, c) = (sym(&t, "a"), sym(&t, "b"), sym(&t, "c"));
        let det = &(&a * &c) - &(&b * &b);
        let m = vec![vec![a.clone(), b.clone()], vec![b.clone(), c.clone()]];
        let inv = inverse(&m).unwrap();
        assert_eq!(inv[0][0], c.checked_div(&det).unwrap());
        assert_eq!(inv[0][1], (-&b).checked_div(&det).unwrap());
        assert_eq!(inv[1][0], (-&b).checked_div(&det).unwrap());
        assert_eq!(inv[1][1], a.checked_div(&det).unwrap());
    }

    #[test]
    fn singular_matrix_has_no_inverse() {
        let t = SymbolTable::new(["a"]);
        let a = sym(&t, "a");
        assert!(inverse(&vec![vec![a.clone(), a.clone()], vec![a.clone(), a]]).is_none());
    }
}
