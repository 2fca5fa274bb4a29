//! Symbolic matrices: small dense ones, and the mass (or compliance) matrix of a merged
//! group, [`StorageMatrix`], kept as its diagonal plus one rank-one term per dependent
//! element so that a group of many states followed by few dependents is solved in time
//! linear in its states.

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

/// The storage matrix of a merged group, `M = D + Tᵀ C T`: the diagonal `D` of the group's
/// own storage (masses, compliances), and for each dependent element `j` its row `t_j` of
/// `T` (how its co-energy variable follows the group's) and its storage `c_j`.
///
/// `M` is dense as soon as one dependent follows all the group's states (a spring in series
/// with eighty parallel springs), and inverting it densely costs `O(n³)` symbolic operations.
/// With `d` dependents and `n > d` states it is solved instead through Woodbury's identity,
/// `M⁻¹ = D⁻¹ - D⁻¹ Tᵀ W⁻¹ T D⁻¹` with the `d × d` capacitance matrix `W = C⁻¹ + T D⁻¹ Tᵀ`,
/// in `O(n d + d³)`; `M` is singular exactly when `W` is (`det M = det D det C det W`).
#[derive(Clone, Debug)]
pub(crate) struct StorageMatrix {
    diagonal: Vec<RatFunc>,
    rows: Vec<Vec<RatFunc>>,
    storage: Vec<RatFunc>,
    inverse: Inverse,
}

/// How [`StorageMatrix::solve`] applies `M⁻¹`.
#[derive(Clone, Debug)]
enum Inverse {
    /// `M⁻¹` itself, when the group has no more states than dependents.
    Dense(Matrix),
    /// `D⁻¹` and `W⁻¹`, for Woodbury's identity.
    Woodbury {
        inverse_diagonal: Vec<RatFunc>,
        inverse_capacitance: Matrix,
    },
}

impl StorageMatrix {
    /// `diag(diagonal) + Σⱼ storage[j] · rows[j] rows[j]ᵀ`, or `None` if it is singular.
    pub(crate) fn new(
        diagonal: Vec<RatFunc>,
        rows: Vec<Vec<RatFunc>>,
        storage: Vec<RatFunc>,
    ) -> Option<Self> {
        debug_assert_eq!(rows.len(), storage.len());
        debug_assert!(rows.iter().all(|row| row.len() == diagonal.len()));
        let mut matrix = Self {
            diagonal,
            rows,
            storage,
            inverse: Inverse::Dense(Vec::new()),
        };
        let (n, d) = (matrix.diagonal.len(), matrix.rows.len());
        let inverse_diagonal: Option<Vec<RatFunc>> =
            matrix.diagonal.iter().map(RatFunc::inv).collect();
        let inverse_storage: Option<Vec<RatFunc>> =
            matrix.storage.iter().map(RatFunc::inv).collect();
        matrix.inverse = match (inverse_diagonal, inverse_storage) {
            (Some(inverse_diagonal), Some(inverse_storage)) if d < n => {
                // W = C⁻¹ + T D⁻¹ Tᵀ.
                let capacitance: Matrix = (0..d)
                    .map(|i| {
                        (0..d)
                            .map(|j| {
                                let mut entry = if i == j {
                                    inverse_storage[i].clone()
                                } else {
                                    RatFunc::zero()
                                };
                                for (k, over) in inverse_diagonal.iter().enumerate() {
                                    let (a, b) = (&matrix.rows[i][k], &matrix.rows[j][k]);
                                    if !a.is_zero() && !b.is_zero() {
                                        entry += &(a * b) * over;
                                    }
                                }
                                entry
                            })
                            .collect()
                    })
                    .collect();
                Inverse::Woodbury {
                    inverse_capacitance: inverse(&capacitance)?,
                    inverse_diagonal,
                }
            }
            _ => {
                let dense: Matrix = (0..n)
                    .map(|a| (0..n).map(|b| matrix.entry(a, b)).collect())
                    .collect();
                Inverse::Dense(inverse(&dense)?)
            }
        };
        Some(matrix)
    }

    /// Whether any dependent element is merged in (otherwise `M` is diagonal).
    pub(crate) fn has_dependents(&self) -> bool {
        !self.rows.is_empty()
    }

    /// The entry `M[a][b]`.
    pub(crate) fn entry(&self, a: usize, b: usize) -> RatFunc {
        let mut entry = if a == b {
            self.diagonal[a].clone()
        } else {
            RatFunc::zero()
        };
        for (row, storage) in self.rows.iter().zip(&self.storage) {
            if !row[a].is_zero() && !row[b].is_zero() {
                entry += &(&row[a] * &row[b]) * storage;
            }
        }
        entry
    }

    /// The size of the linear system solved to apply `M⁻¹`: the number of states for a
    /// dense inverse, of dependents for Woodbury's.
    #[cfg(test)]
    pub(crate) fn system_size(&self) -> usize {
        match &self.inverse {
            Inverse::Dense(m)
            | Inverse::Woodbury {
                inverse_capacitance: m,
                ..
            } => m.len(),
        }
    }

    /// `M⁻¹ · forms`.
    pub(crate) fn solve(&self, forms: &[LinearForm]) -> Vec<LinearForm> {
        let (inverse_diagonal, inverse_capacitance) = match &self.inverse {
            Inverse::Dense(inverse) => return apply(inverse, forms),
            Inverse::Woodbury {
                inverse_diagonal,
                inverse_capacitance,
            } => (inverse_diagonal, inverse_capacitance),
        };
        // z = D⁻¹ v, g = T z, h = W⁻¹ g, M⁻¹ v = z - D⁻¹ Tᵀ h.
        let z: Vec<LinearForm> = forms
            .iter()
            .enumerate()
            .map(|(k, form)| form.scaled(&inverse_diagonal[k]))
            .collect();
        let g: Vec<LinearForm> = self
            .rows
            .iter()
            .map(|row| {
                let mut sum = LinearForm::zero();
                for (t, z) in row.iter().zip(&z) {
                    sum.add_scaled(z, t);
                }
                sum
            })
            .collect();
        let h = apply(inverse_capacitance, &g);
        z.into_iter()
            .enumerate()
            .map(|(k, mut solved)| {
                for (row, h) in self.rows.iter().zip(&h) {
                    if !row[k].is_zero() {
                        solved.add_scaled(h, &-(&row[k] * &inverse_diagonal[k]));
                    }
                }
                solved
            })
            .collect()
    }
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

    /// Woodbury's identity (two dependents, three states) against Gauss-Jordan on the
    /// dense matrix `diag(a, b, c) + k (1, 1, 0)(1, 1, 0)ᵀ + l (0, 1, 1)(0, 1, 1)ᵀ`.
    #[test]
    fn storage_matrix_solves_as_its_dense_inverse() {
        let t = SymbolTable::new(["a", "b", "c", "k", "l"]);
        let [a, b, c, k, l] = ["a", "b", "c", "k", "l"].map(|name| sym(&t, name));
        let (one, zero) = (RatFunc::one(), RatFunc::zero());
        let storage = StorageMatrix::new(
            vec![a.clone(), b.clone(), c.clone()],
            vec![
                vec![one.clone(), one.clone(), zero.clone()],
                vec![zero.clone(), one.clone(), one.clone()],
            ],
            vec![k.clone(), l.clone()],
        )
        .unwrap();
        assert_eq!(storage.system_size(), 2);
        let dense = vec![
            vec![&a + &k, k.clone(), zero.clone()],
            vec![k.clone(), &(&b + &k) + &l, l.clone()],
            vec![zero.clone(), l.clone(), &c + &l],
        ];
        for (i, row) in dense.iter().enumerate() {
            for (j, entry) in row.iter().enumerate() {
                assert_eq!(&storage.entry(i, j), entry, "M[{i}][{j}]");
            }
        }
        let forms: Vec<LinearForm> = (0..3)
            .map(|i| LinearForm::var(crate::linear::Var::Input(i)))
            .collect();
        assert_eq!(
            storage.solve(&forms),
            apply(&inverse(&dense).unwrap(), &forms)
        );
    }
}
