//! Whether an answer's `(A', B', E')` is the model's `(A, B, E)` in other state variables:
//! an invertible `T` (the answer's states are `z = T x`) with `T A = A' T`, `T B = B'` and
//! `T E = E'`, that is `A' = T A T⁻¹`, `B' = T B`, `E' = T E`.
//!
//! The conditions are linear in `T`'s `n²` entries, so they are solved exactly by
//! Gauss–Jordan elimination over the rational functions of the parameters. When the
//! model's pair is controllable (`K = [B E, A B, A E, …, Aⁿ⁻¹B, Aⁿ⁻¹E]` has rank `n`), the
//! equations imply `T K = K'` and fix `T = K' K⁺`: the solution is unique and only its
//! invertibility is left to check. Otherwise the solutions form an affine family
//! `T₀ + Σ cᵢ Nᵢ`; an invertible `T` needs equal controllability ranks (`T K = K'` with `T`
//! invertible keeps the rank), then is looked for at a few rational points `c`, which
//! proves existence when one is invertible, and failing that decided exactly by inverting
//! `T₀ + Σ cᵢ Nᵢ` with the `cᵢ` as fresh symbols.
//!
//! Large modes are checked at two exact rational parameter points instead of symbolically
//! ([`at_point`]); the elimination is the same.

use super::Matrix;
use super::characteristic::product;
use crate::equations::matrix::inverse;
use crate::symbolic::{Poly, RatFunc, Symbol};

/// `A`, `B` and `E` of one side.
#[derive(Clone, Copy, Debug)]
pub struct System<'a> {
    /// `A` (states × states).
    pub a: &'a [Vec<RatFunc>],
    /// `B` (states × inputs).
    pub b: &'a [Vec<RatFunc>],
    /// `E` (states × inputs).
    pub e: &'a [Vec<RatFunc>],
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub enum Similarity {
    /// An invertible `T` with `z = T x`; `unique` when the equations fix it (a controllable
    /// pair), else one of a family.
    Found {
        /// `T`, rows the answer's states, columns the model's.
        t: Matrix,
        /// Whether `T` is the only solution.
        unique: bool,
    },
    /// No `T` at all, invertible or not, satisfies the equations.
    NoSolution,
    /// Solutions exist but every one is singular.
    Singular {
        /// The ranks of the model's and the answer's controllability matrices, when they
        /// differ (the reason).
        ranks: Option<(usize, usize)>,
    },
}

/// Searches for `T` with `T A = A' T`, `T B = B'`, `T E = E'`; `fresh` is a symbol index
/// past every symbol the entries use (for the exact singularity check).
///
/// # Complexity
/// Gauss–Jordan elimination on `n² + 2nm` equations in `n²` unknowns: `O(n⁶)` exact
/// operations, whose size grows with the parameters' expressions.
pub fn similarity(model: System, answer: System, fresh: u32) -> Similarity {
    let n = model.a.len();
    let m = model.b.first().map_or(0, Vec::len);
    let unknowns = n * n;
    let index = |i: usize, j: usize| i * n + j;
    let mut rows: Vec<Vec<RatFunc>> = Vec::new();
    // (T A - A' T)[i][j] = Σ_l T[i][l] A[l][j] - Σ_l A'[i][l] T[l][j] = 0.
    for i in 0..n {
        for j in 0..n {
            let mut row = vec![RatFunc::zero(); unknowns + 1];
            for l in 0..n {
                row[index(i, l)] += model.a[l][j].clone();
                row[index(l, j)] -= answer.a[i][l].clone();
            }
            rows.push(row);
        }
    }
    // (T B)[i][k] = Σ_l T[i][l] B[l][k] = B'[i][k], and E alike.
    for (given, wanted) in [(model.b, answer.b), (model.e, answer.e)] {
        for i in 0..n {
            for k in 0..m {
                let mut row = vec![RatFunc::zero(); unknowns + 1];
                for l in 0..n {
                    row[index(i, l)] = given[l][k].clone();
                }
                row[unknowns] = wanted[i][k].clone();
                rows.push(row);
            }
        }
    }
    let Some((particular, null)) = solve(rows, unknowns) else {
        return Similarity::NoSolution;
    };
    let matrix = |v: &[RatFunc]| -> Matrix { v.chunks(n.max(1)).map(<[_]>::to_vec).collect() };
    let t0 = matrix(&particular);
    if null.is_empty() && (n == 0 || inverse(&t0).is_some()) {
        return Similarity::Found {
            t: t0,
            unique: true,
        };
    }
    let (rank_model, rank_answer) = (controllability_rank(model), controllability_rank(answer));
    if rank_model != rank_answer {
        return Similarity::Singular {
            ranks: Some((rank_model, rank_answer)),
        };
    }
    if null.is_empty() {
        return Similarity::Singular { ranks: None };
    }
    let member = |c: &[RatFunc]| -> Matrix {
        let mut t = particular.clone();
        for (ci, basis) in c.iter().zip(&null) {
            if ci.is_zero() {
                continue;
            }
            for (x, y) in t.iter_mut().zip(basis) {
                if !y.is_zero() {
                    *x += ci * y;
                }
            }
        }
        matrix(&t)
    };
    let d = null.len();
    let found = |t: Matrix| Similarity::Found { t, unique: false };
    // T₀ itself, then each direction alone, then pseudo-random small integers.
    let mut trials: Vec<Vec<RatFunc>> = vec![vec![RatFunc::zero(); d]];
    for k in 0..d {
        let mut c = vec![RatFunc::zero(); d];
        c[k] = RatFunc::one();
        trials.push(c);
    }
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let k = i64::try_from((state >> 33) % 199).unwrap_or(0) - 99;
        RatFunc::integer(if k == 0 { 100 } else { k })
    };
    for _ in 0..8 {
        trials.push((0..d).map(|_| next()).collect());
    }
    for c in &trials {
        let t = member(c);
        if inverse(&t).is_some() {
            return found(t);
        }
    }
    // Exactly: is det(T₀ + Σ cᵢ Nᵢ) zero as a polynomial in the cᵢ?
    let symbolic: Vec<RatFunc> = (0..d)
        .map(|k| RatFunc::symbol(Symbol(fresh + u32::try_from(k).unwrap_or(0))))
        .collect();
    if inverse(&member(&symbolic)).is_none() {
        return Similarity::Singular { ranks: None };
    }
    // A non-zero polynomial of degree at most n vanishes at few of many random points.
    for _ in 0..200 {
        let c: Vec<RatFunc> = (0..d).map(|_| next()).collect();
        let t = member(&c);
        if inverse(&t).is_some() {
            return found(t);
        }
    }
    // An invertible member exists but 200 points missed it: too unlikely to matter, and
    // reported as none rather than as a T that was not shown to be invertible.
    Similarity::Singular { ranks: None }
}

/// The rank of `[B E, A B, A E, …]`: how many state directions the inputs reach.
pub fn controllability_rank(system: System) -> usize {
    let n = system.a.len();
    let mut block: Matrix = system
        .b
        .iter()
        .zip(system.e)
        .map(|(b, e)| b.iter().chain(e).cloned().collect())
        .collect();
    let mut columns: Matrix = vec![Vec::new(); n];
    for _ in 0..n {
        for (row, more) in columns.iter_mut().zip(&block) {
            row.extend(more.iter().cloned());
        }
        block = product(system.a, &block);
    }
    rank(&columns)
}

/// The rank of a matrix, exactly.
pub fn rank(matrix: &[Vec<RatFunc>]) -> usize {
    let columns = matrix.first().map_or(0, Vec::len);
    let rows = matrix
        .iter()
        .map(|row| {
            let mut row = row.clone();
            row.push(RatFunc::zero());
            row
        })
        .collect();
    echelon(rows, columns).1.len()
}

/// The augmented rows (`unknowns + 1` entries, the right-hand side last) in reduced row
/// echelon form, with the pivot column of each leading row.
fn echelon(mut rows: Vec<Vec<RatFunc>>, unknowns: usize) -> (Vec<Vec<RatFunc>>, Vec<usize>) {
    rows.retain(|row| row.iter().any(|x| !x.is_zero()));
    let mut pivots = Vec::new();
    for column in 0..unknowns {
        let rank = pivots.len();
        // The simplest pivot keeps the expressions small.
        let Some(best) = (rank..rows.len())
            .filter(|&r| !rows[r][column].is_zero())
            .min_by_key(|&r| size(&rows[r][column]))
        else {
            continue;
        };
        rows.swap(rank, best);
        let Some(scale) = rows[rank][column].inv() else {
            continue;
        };
        for x in rows[rank].iter_mut().filter(|x| !x.is_zero()) {
            *x = &*x * &scale;
        }
        let pivot_row = rows[rank].clone();
        for (r, row) in rows.iter_mut().enumerate() {
            if r == rank || row[column].is_zero() {
                continue;
            }
            let factor = row[column].clone();
            for (x, p) in row.iter_mut().zip(&pivot_row).skip(column) {
                if !p.is_zero() {
                    *x -= &factor * p;
                }
            }
        }
        pivots.push(column);
    }
    (rows, pivots)
}

/// A solution of the augmented system with every free unknown zero, and a basis of the
/// homogeneous solutions; `None` if the system is inconsistent.
fn solve(rows: Vec<Vec<RatFunc>>, unknowns: usize) -> Option<(Vec<RatFunc>, Vec<Vec<RatFunc>>)> {
    let (rows, pivots) = echelon(rows, unknowns);
    if rows[pivots.len()..]
        .iter()
        .any(|row| !row[unknowns].is_zero())
    {
        return None;
    }
    let mut particular = vec![RatFunc::zero(); unknowns];
    for (row, &column) in rows.iter().zip(&pivots) {
        particular[column] = row[unknowns].clone();
    }
    let null = (0..unknowns)
        .filter(|column| !pivots.contains(column))
        .map(|free| {
            let mut v = vec![RatFunc::zero(); unknowns];
            v[free] = RatFunc::one();
            for (row, &column) in rows.iter().zip(&pivots) {
                v[column] = -row[free].clone();
            }
            v
        })
        .collect();
    Some((particular, null))
}

fn size(x: &RatFunc) -> usize {
    x.numerator().term_count() + x.denominator().term_count()
}

/// `x` with each symbol `s` replaced by the exact constant `point[s.index()]`; `None` where
/// the denominator vanishes there.
pub fn at_point(x: &RatFunc, point: &[RatFunc]) -> Option<RatFunc> {
    let eval = |p: &Poly| -> RatFunc {
        p.terms()
            .map(|(monomial, c)| {
                monomial.iter().fold(
                    RatFunc::from_poly(Poly::constant(c.clone())),
                    |acc, (s, e)| {
                        let value = point.get(s.index()).cloned().unwrap_or_default();
                        acc * value
                            .powi(i32::try_from(e).unwrap_or(i32::MAX))
                            .unwrap_or_default()
                    },
                )
            })
            .sum()
    };
    eval(x.numerator()).checked_div(&eval(x.denominator()))
}

/// Every entry of `m` at `point` (see [`at_point`]); `None` if one is undefined there.
pub fn matrix_at_point(m: &[Vec<RatFunc>], point: &[RatFunc]) -> Option<Matrix> {
    m.iter()
        .map(|row| row.iter().map(|x| at_point(x, point)).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::SymbolTable;

    fn n(k: i64) -> RatFunc {
        RatFunc::integer(k)
    }

    fn zeros(rows: usize) -> Matrix {
        vec![vec![RatFunc::zero()]; rows]
    }

    /// The mass-spring-damper in (p, q): dp/dt = -b/m p - k q + F, dq/dt = p/m.
    fn msd(table: &SymbolTable) -> (Matrix, Matrix) {
        let s = |name: &str| RatFunc::symbol(table.get(name).unwrap());
        let (b, k, m) = (s("b"), s("k"), s("m"));
        let a = vec![
            vec![-(&b * &m.inv().unwrap()), -k.clone()],
            vec![m.inv().unwrap(), n(0)],
        ];
        (a, vec![vec![n(1)], vec![n(0)]])
    }

    #[test]
    fn a_mixed_change_of_variables_is_found_exactly() {
        // z1 = q, z2 = p + b q: dz1/dt = p/m = -b/m z1 + z2/m, dz2/dt = -k z1 + F (by hand).
        let table = SymbolTable::new(["b", "k", "m"]);
        let s = |name: &str| RatFunc::symbol(table.get(name).unwrap());
        let (a, b) = msd(&table);
        let m_inv = s("m").inv().unwrap();
        let a2 = vec![
            vec![-(&s("b") * &m_inv), m_inv.clone()],
            vec![-s("k"), n(0)],
        ];
        let b2 = vec![vec![n(0)], vec![n(1)]];
        let e = zeros(2);
        let found = similarity(
            System {
                a: &a,
                b: &b,
                e: &e,
            },
            System {
                a: &a2,
                b: &b2,
                e: &e,
            },
            3,
        );
        assert_eq!(
            found,
            Similarity::Found {
                t: vec![vec![n(0), n(1)], vec![n(1), s("b")]],
                unique: true
            }
        );
    }

    #[test]
    fn no_input_reaches_nothing_and_a_wrong_damping_has_no_t() {
        let table = SymbolTable::new(["b", "k", "m"]);
        let (a, b) = msd(&table);
        let e = zeros(2);
        let model = System {
            a: &a,
            b: &b,
            e: &e,
        };
        // B' = 0: T B = 0 needs a singular T; the ranks say why.
        let none = zeros(2);
        assert_eq!(
            similarity(
                model,
                System {
                    a: &a,
                    b: &none,
                    e: &e
                },
                3
            ),
            Similarity::Singular {
                ranks: Some((2, 0))
            }
        );
        // Doubled damping: another characteristic polynomial, so no T at all.
        let mut a2 = a.clone();
        a2[0][0] = &a[0][0] * &n(2);
        assert_eq!(
            similarity(
                model,
                System {
                    a: &a2,
                    b: &b,
                    e: &e
                },
                3
            ),
            Similarity::NoSolution
        );
    }

    #[test]
    fn an_uncontrollable_pair_has_a_family_of_t() {
        // A = diag(1, 2), B = (1, 0): the second state is unreachable, T = diag(1, c).
        let a = vec![vec![n(1), n(0)], vec![n(0), n(2)]];
        let b = vec![vec![n(1)], vec![n(0)]];
        let e = zeros(2);
        let system = System {
            a: &a,
            b: &b,
            e: &e,
        };
        let Similarity::Found { t, unique } = similarity(system, system, 0) else {
            panic!("similar to itself");
        };
        assert!(!unique);
        assert!(t[0][0].is_one() && t[0][1].is_zero() && t[1][0].is_zero());
        assert!(!t[1][1].is_zero());
        assert_eq!(controllability_rank(system), 1);
    }

    #[test]
    fn a_rational_point_is_exact() {
        let table = SymbolTable::new(["k", "m"]);
        let s = |name: &str| RatFunc::symbol(table.get(name).unwrap());
        let x = (&s("k") * &s("k")).checked_div(&(&s("m") + &n(1))).unwrap();
        let point = [n(3), RatFunc::rational(1.into(), 2.into()).unwrap()];
        // 9 / (3/2) = 6
        assert_eq!(at_point(&x, &point), Some(n(6)));
        let pole = [n(3), n(-1)];
        assert_eq!(at_point(&x, &pole), None);
    }
}
