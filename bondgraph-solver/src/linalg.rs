//! Small dense linear algebra for mode matrices: eigendecomposition that stays accurate on
//! stiff matrices, and a matrix exponential for the matrices it cannot diagonalise.
//!
//! Why not a library's matrix exponential: the flagship robot's modes pair an eigenvalue near
//! -2.5e17 1/s (a 5e-15 kg tip against a 1250 N·s/m damper) with ones near -1. Scaling and
//! squaring loses the slow part entirely (a relative error of 0.73 over a 1 s step was
//! measured on nalgebra's `exp`). An eigendecomposition gives each time scale its own exact
//! exponential; backward-stable eigenvalue algorithms, though, carry absolute errors of
//! order `ε‖A‖`, which on a graded matrix can swamp the small eigenvalues. So the matrix is
//! balanced first (diagonal similarity by powers of two, which grades it evenly), its
//! eigenvalues come from nalgebra's real Schur form, and every eigenpair is then refined by
//! Newton's method on the original matrix, which converges to the eigenpair to within its own
//! condition number rather than `‖A‖`.
//!
//! A matrix whose eigenvectors are (nearly) dependent is defective; there the solver falls back
//! to [`expm`], Higham's scaling and squaring with a degree-13 Padé approximant, on matrices
//! that are not stiff enough to defeat it.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Why a matrix could not be diagonalised.
#[derive(Clone, Debug, PartialEq)]
pub enum EigenError {
    /// The Schur iteration did not converge.
    NoConvergence,
    /// The matrix is (numerically) defective: its eigenvector matrix is singular or has the
    /// given condition number.
    Defective(f64),
    /// The matrix has non-finite entries.
    NonFinite,
}

/// `A = V diag(λ) V⁻¹`.
#[derive(Clone, Debug)]
pub struct Eigen {
    /// The eigenvalues.
    pub values: Vec<Complex64>,
    /// The eigenvectors, as columns.
    pub vectors: DMatrix<Complex64>,
    /// `V⁻¹`.
    pub inverse: DMatrix<Complex64>,
    /// The 1-norm condition number of the eigenvectors of the balanced matrix (`V` up to
    /// the exact diagonal scaling of the balancing).
    pub condition: f64,
}

/// Condition numbers of the eigenvector matrix above this make the decomposition unusable.
const MAX_CONDITION: f64 = 1e10;

/// The eigendecomposition of `a`, accurate on graded (stiff) matrices.
///
/// # Errors
/// [`EigenError`] when the matrix is defective, non-finite, or the iteration fails.
///
/// # Complexity
/// `O(n³)`, with small constants: the matrices here have a handful of states.
pub fn eigen(a: &DMatrix<f64>) -> Result<Eigen, EigenError> {
    let n = a.nrows();
    if a.iter().any(|x| !x.is_finite()) {
        return Err(EigenError::NonFinite);
    }
    if n == 0 {
        return Ok(Eigen {
            values: Vec::new(),
            vectors: DMatrix::zeros(0, 0),
            inverse: DMatrix::zeros(0, 0),
            condition: 1.0,
        });
    }
    let (balanced, scale) = balance(a);
    let schur = nalgebra::Schur::try_new(balanced.clone(), f64::EPSILON, 10_000)
        .ok_or(EigenError::NoConvergence)?;
    // A real eigenvalue may come out with an imaginary part of rounding size (relative to the
    // eigenvalue, or to the matrix for one near zero); snap it back so propagation can use
    // real arithmetic for it.
    let norm = one_norm(&balanced).max(f64::MIN_POSITIVE);
    let snap = |v: Complex64| {
        if v.im.abs() <= 1e-13 * v.re.abs() || v.im.abs() <= 1e-14 * norm {
            Complex64::new(v.re, 0.0)
        } else {
            v
        }
    };
    let mut values: Vec<Complex64> = schur
        .complex_eigenvalues()
        .iter()
        .map(|v| snap(*v))
        .collect();
    // Deterministic order: by real part, then imaginary part.
    values.sort_by(|x, y| {
        x.re.partial_cmp(&y.re)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(x.im.partial_cmp(&y.im).unwrap_or(std::cmp::Ordering::Equal))
    });
    let complex: DMatrix<Complex64> = balanced.map(|x| Complex64::new(x, 0.0));

    let mut vectors = DMatrix::<Complex64>::zeros(n, n);
    let mut i = 0;
    while i < n {
        // A cluster of (numerically) equal eigenvalues gets a basis of its null space.
        let mut j = i + 1;
        while j < n && (values[j] - values[i]).norm() <= 1e-9 * values[i].norm().max(1e-300) {
            j += 1;
        }
        if j - i == 1 {
            let (value, vector) = refine(
                &complex,
                values[i],
                inverse_iteration(&complex, values[i], norm),
            );
            // Refinement works in complex arithmetic; keep a real eigenvalue real.
            values[i] = snap(value);
            vectors.set_column(i, &vector);
        } else {
            let basis = null_space(&complex, values[i], norm, j - i)?;
            for (k, column) in basis.into_iter().enumerate() {
                vectors.set_column(i + k, &column);
            }
        }
        i = j;
    }
    // Judge the eigenvectors in the balanced coordinates: the balancing is an exact
    // similarity by powers of two, so the grading it removes (a momentum of order 1 beside a
    // displacement of order 1e-10 in a stiff oscillator) costs no precision, and must not
    // count as near-dependence (it once sent such oscillators to the exponential, which
    // turned a rotation into growth).
    for c in 0..n {
        let column_norm = vectors
            .column(c)
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max);
        if column_norm == 0.0 || !column_norm.is_finite() {
            return Err(EigenError::Defective(f64::INFINITY));
        }
        let mut column = vectors.column_mut(c);
        column /= Complex64::new(column_norm, 0.0);
    }
    let balanced_inverse = vectors
        .clone()
        .try_inverse()
        .ok_or(EigenError::Defective(f64::INFINITY))?;
    let condition = complex_one_norm(&vectors) * complex_one_norm(&balanced_inverse);
    if condition.is_nan() || condition > MAX_CONDITION {
        return Err(EigenError::Defective(condition));
    }
    // Undo the balancing exactly: A = D B D⁻¹, so V = D W and V⁻¹ = W⁻¹ D⁻¹; then scale each
    // eigenvector to a largest component of 1 (and the matching row of V⁻¹ inversely).
    let mut inverse = balanced_inverse;
    for r in 0..n {
        for c in 0..n {
            vectors[(r, c)] *= scale[r];
            inverse[(c, r)] /= scale[r];
        }
    }
    for c in 0..n {
        let column_norm = vectors
            .column(c)
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max);
        if column_norm == 0.0 || !column_norm.is_finite() {
            return Err(EigenError::Defective(f64::INFINITY));
        }
        let mut column = vectors.column_mut(c);
        column /= Complex64::new(column_norm, 0.0);
        let mut row = inverse.row_mut(c);
        row *= Complex64::new(column_norm, 0.0);
    }
    Ok(Eigen {
        values,
        vectors,
        inverse,
        condition,
    })
}

/// Each scaling step moves a row's and a column's sums 4 times apart, and finite doubles
/// span 2^2098: more steps than this cannot be needed.
const MAX_SCALING_STEPS: usize = 1100;

/// Balances `a` by a diagonal similarity of powers of two (Parlett and Reinsch, as LAPACK's
/// `gebal` without permutations): returns `B = D⁻¹ A D` and the diagonal of `D`.
///
/// A row or column whose off-diagonal sum is not finite (an infinite or NaN entry, or finite
/// entries whose sum overflows) cannot be judged and is left unscaled; callers that need
/// finite matrices refuse them before ([`eigen`], [`expm`]). Every loop is bounded, so no
/// input keeps it from returning.
pub fn balance(a: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let n = a.nrows();
    let mut b = a.clone();
    let mut scale = vec![1.0; n];
    const RADIX: f64 = 2.0;
    let mut converged = false;
    let mut sweeps = 0;
    while !converged && sweeps < 100 {
        converged = true;
        sweeps += 1;
        for i in 0..n {
            let column: f64 = (0..n).filter(|&r| r != i).map(|r| b[(r, i)].abs()).sum();
            let row: f64 = (0..n).filter(|&c| c != i).map(|c| b[(i, c)].abs()).sum();
            let total = column + row;
            if column == 0.0 || row == 0.0 || !total.is_finite() {
                continue;
            }
            let mut f = 1.0;
            let mut c = column;
            let mut r = row;
            let mut steps = 0;
            while c < r / RADIX && steps < MAX_SCALING_STEPS {
                c *= RADIX * RADIX;
                r /= RADIX * RADIX;
                f *= RADIX;
                steps += 1;
            }
            while c >= r * RADIX && steps < MAX_SCALING_STEPS {
                c /= RADIX * RADIX;
                r *= RADIX * RADIX;
                f /= RADIX;
                steps += 1;
            }
            if (c + r) < 0.95 * total && f.is_finite() && f > 0.0 {
                converged = false;
                scale[i] *= f;
                for k in 0..n {
                    b[(i, k)] /= f;
                    b[(k, i)] *= f;
                }
            }
        }
    }
    (b, scale)
}

/// An eigenvector of `a` for the (approximate) eigenvalue `value`, by inverse iteration.
fn inverse_iteration(a: &DMatrix<Complex64>, value: Complex64, norm: f64) -> DVector<Complex64> {
    let n = a.nrows();
    // A shift a little off the eigenvalue keeps the system solvable.
    let offset = Complex64::new(norm * 1e-13 + 1e-300, norm * 1e-13);
    let shifted = a - DMatrix::<Complex64>::identity(n, n) * (value + offset);
    let lu = shifted.lu();
    let mut v = DVector::<Complex64>::from_fn(n, |i, _| {
        Complex64::new(1.0 + 0.37 * i as f64, 0.11 * i as f64)
    });
    for _ in 0..3 {
        let Some(next) = lu.solve(&v) else { break };
        let largest = next.iter().map(|z| z.norm()).fold(0.0, f64::max);
        if largest == 0.0 || !largest.is_finite() {
            break;
        }
        v = next / Complex64::new(largest, 0.0);
    }
    v
}

/// Newton refinement of a simple eigenpair: solves
/// `[A - λI, -v; e_kᵀ, 0] [δv; δλ] = -[Av - λv; 0]` with `k` the largest component of `v`.
fn refine(
    a: &DMatrix<Complex64>,
    mut value: Complex64,
    mut vector: DVector<Complex64>,
) -> (Complex64, DVector<Complex64>) {
    let n = a.nrows();
    for _ in 0..4 {
        let k = (0..n)
            .max_by(|&i, &j| vector[i].norm().total_cmp(&vector[j].norm()))
            .unwrap_or(0);
        let pivot = vector[k];
        if pivot.norm() == 0.0 {
            break;
        }
        vector /= pivot;
        let residual = a * &vector - &vector * value;
        let mut system = DMatrix::<Complex64>::zeros(n + 1, n + 1);
        system
            .view_mut((0, 0), (n, n))
            .copy_from(&(a - DMatrix::<Complex64>::identity(n, n) * value));
        for r in 0..n {
            system[(r, n)] = -vector[r];
        }
        system[(n, k)] = Complex64::new(1.0, 0.0);
        let mut rhs = DVector::<Complex64>::zeros(n + 1);
        for r in 0..n {
            rhs[r] = -residual[r];
        }
        let Some(step) = system.lu().solve(&rhs) else {
            break;
        };
        let delta_value = step[n];
        if !delta_value.re.is_finite() || !delta_value.im.is_finite() {
            break;
        }
        for r in 0..n {
            vector[r] += step[r];
        }
        value += delta_value;
        if delta_value.norm() <= 1e-15 * value.norm().max(1e-300) {
            break;
        }
    }
    (value, vector)
}

/// A basis of the null space of `a - λI` of the expected dimension, or the matrix is
/// defective.
fn null_space(
    a: &DMatrix<Complex64>,
    value: Complex64,
    norm: f64,
    dimension: usize,
) -> Result<Vec<DVector<Complex64>>, EigenError> {
    let n = a.nrows();
    let shifted = a - DMatrix::<Complex64>::identity(n, n) * value;
    let svd = nalgebra::SVD::try_new(shifted, false, true, f64::EPSILON, 10_000)
        .ok_or(EigenError::NoConvergence)?;
    let v_t = svd.v_t.ok_or(EigenError::NoConvergence)?;
    let tolerance = 1e-10 * norm.max(value.norm());
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]));
    let small = order
        .iter()
        .filter(|&&i| svd.singular_values[i] <= tolerance)
        .count();
    if small < dimension {
        return Err(EigenError::Defective(f64::INFINITY));
    }
    Ok(order
        .iter()
        .take(dimension)
        .map(|&i| v_t.row(i).transpose().map(|z| z.conj()))
        .collect())
}

fn one_norm(a: &DMatrix<f64>) -> f64 {
    (0..a.ncols())
        .map(|c| a.column(c).iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

fn complex_one_norm(a: &DMatrix<Complex64>) -> f64 {
    (0..a.ncols())
        .map(|c| a.column(c).iter().map(|z| z.norm()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// The matrix exponential `e^A` by scaling and squaring with a degree-13 Padé approximant
/// (Higham, "The scaling and squaring method for the matrix exponential revisited", 2005).
///
/// Accurate to near machine precision for matrices whose eigenvalues span a few orders of
/// magnitude; not for stiff ones (see the module documentation). `None` if `A` has
/// non-finite entries or the Padé denominator is singular.
///
/// `A` is balanced first ([`balance`], an exact similarity by powers of two) and the
/// balancing undone on the result. A badly graded defective matrix needs it: the slack mode
/// of a 1e-30 kg mass, `[[0, 0], [1/m, 0]]` over 1e-10 s, has a norm of 1e20 and would take 65
/// squarings, which grow the rounding error of the Padé step's pivoting (a 1e-30 entry where
/// the exact exponential has zero, making the Jordan block's double eigenvalue 1 split into
/// `1 ± 1e-15`) by `2^65` in the exponent, to infinity. Balanced, the same matrix has a norm
/// near 1e5 and needs 15 squarings.
pub fn expm(a: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let (balanced, scale) = balance(a);
    let mut result = expm_unbalanced(&balanced)?;
    // A = D B D⁻¹, so e^A = D e^B D⁻¹.
    let n = a.nrows();
    for r in 0..n {
        for c in 0..n {
            result[(r, c)] *= scale[r] / scale[c];
        }
    }
    result.iter().all(|x| x.is_finite()).then_some(result)
}

fn expm_unbalanced(a: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    const B: [f64; 14] = [
        64764752532480000.0,
        32382376266240000.0,
        7771770303897600.0,
        1187353796428800.0,
        129060195264000.0,
        10559470521600.0,
        670442572800.0,
        33522128640.0,
        1323241920.0,
        40840800.0,
        960960.0,
        16380.0,
        182.0,
        1.0,
    ];
    const THETA_13: f64 = 5.371920351148152;
    let n = a.nrows();
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let norm = one_norm(a);
    let squarings = if norm > THETA_13 {
        (norm / THETA_13).log2().ceil().max(0.0) as i32
    } else {
        0
    };
    if squarings > 1100 {
        return None;
    }
    let a = a / 2f64.powi(squarings);
    let identity = DMatrix::<f64>::identity(n, n);
    let a2 = &a * &a;
    let a4 = &a2 * &a2;
    let a6 = &a4 * &a2;
    let u_inner = &a6 * (&a6 * B[13] + &a4 * B[11] + &a2 * B[9])
        + &a6 * B[7]
        + &a4 * B[5]
        + &a2 * B[3]
        + &identity * B[1];
    let u = &a * u_inner;
    let v = &a6 * (&a6 * B[12] + &a4 * B[10] + &a2 * B[8])
        + &a6 * B[6]
        + &a4 * B[4]
        + &a2 * B[2]
        + &identity * B[0];
    let numerator = &v + &u;
    let denominator = &v - &u;
    let mut result = denominator.lu().solve(&numerator)?;
    for _ in 0..squarings {
        result = &result * &result;
    }
    result.iter().all(|x| x.is_finite()).then_some(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, relative: f64) -> bool {
        (a - b).abs() <= relative * b.abs().max(1e-300)
    }

    /// `balance` in a thread, failing the test if it has not returned within 10 s.
    fn balance_promptly(a: DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || sender.send(balance(&a)));
        receiver
            .recv_timeout(std::time::Duration::from_secs(10))
            .expect("balance returns")
    }

    #[test]
    fn balancing_returns_on_entries_whose_sums_are_not_finite() {
        // An infinite entry (and two finite ones whose row sum overflows) once made the
        // scaling loop `while c >= r * RADIX` run for ever: inf / 4 stays inf. Such a row
        // and column are left as they are; the others are balanced as usual.
        for a in [
            DMatrix::from_row_slice(2, 2, &[0.0, f64::INFINITY, 1.0, 0.0]),
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, f64::NAN, 0.0]),
            DMatrix::from_row_slice(3, 3, &[0.0, 1e308, 1e308, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0]),
        ] {
            let (b, scale) = balance_promptly(a.clone());
            assert!(scale.iter().all(|s| s.is_finite() && *s > 0.0), "{scale:?}");
            assert_eq!(b.nrows(), a.nrows());
        }
        // A finite, badly graded matrix is still balanced: [[0, 2^40], [2^-40, 0]] becomes
        // [[0, 1], [1, 0]] with D = diag(2^20, 2^-20)... up to the power of two the sweep
        // settles on; its off-diagonal entries are then within a factor 4 of each other.
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 2f64.powi(40), 2f64.powi(-40), 0.0]);
        let (b, _) = balance_promptly(a);
        let ratio = b[(0, 1)] / b[(1, 0)];
        assert!((0.25..=4.0).contains(&ratio), "{b}");
    }

    #[test]
    fn stiff_two_by_two_keeps_its_slow_eigenvalue() {
        // The robot tip on a taut inner structure, in energy variables p, q:
        // dp/dt = -(b/m) p - 2 k q, dq/dt = 2 p/m. Eigenvalues solve
        // λ² + (b/m) λ + 4k/m = 0; the slow one is -1600.000000000010240 (50-digit arithmetic).
        let (m, b, k) = (0.5e-14, 1250.0, 5e5);
        let a = DMatrix::from_row_slice(2, 2, &[-b / m, -2.0 * k, 2.0 / m, 0.0]);
        let e = eigen(&a).unwrap();
        assert!(
            close(e.values[1].re, -1_600.000_000_000_01, 1e-13),
            "{:?}",
            e.values
        );
        assert!(
            close(e.values[0].re, -2.499999999999984e17, 1e-13),
            "{:?}",
            e.values
        );
        // Real eigenvalues stay real after refinement (propagation uses real arithmetic).
        assert!(e.values.iter().all(|v| v.im == 0.0), "{:?}", e.values);
        // A V = V Λ, column by column, relative to each eigenvalue's own scale.
        let ac = a.map(|x| Complex64::new(x, 0.0));
        for j in 0..2 {
            let v = e.vectors.column(j);
            let residual = &ac * v - v * e.values[j];
            let scale = e.values[j].norm() * v.iter().map(|z| z.norm()).fold(0.0, f64::max);
            assert!(
                residual.iter().all(|z| z.norm() <= 1e-12 * scale),
                "{residual}"
            );
        }
    }

    #[test]
    fn oscillator_has_conjugate_eigenvalues() {
        // m x'' + k x = 0 in (p, q): eigenvalues ±i sqrt(k/m) = ±10i for k = 100, m = 1.
        let a = DMatrix::from_row_slice(2, 2, &[0.0, -100.0, 1.0, 0.0]);
        let e = eigen(&a).unwrap();
        assert!(close(e.values[0].im.abs(), 10.0, 1e-14));
        assert!(e.values[0].re.abs() < 1e-12);
        assert!((e.values[0] - e.values[1].conj()).norm() < 1e-12);
    }

    #[test]
    fn repeated_but_diagonalisable_and_defective_matrices() {
        let zero = DMatrix::<f64>::zeros(2, 2);
        let e = eigen(&zero).unwrap();
        assert_eq!(e.values, vec![Complex64::new(0.0, 0.0); 2]);
        // A Jordan block: a free mass pushed by a spring with no restoring force.
        let jordan = DMatrix::from_row_slice(2, 2, &[0.0, 0.0, 1.0, 0.0]);
        assert!(matches!(eigen(&jordan), Err(EigenError::Defective(_))));
    }

    #[test]
    fn expm_of_a_rotation_and_a_jordan_block() {
        // e^{[[0, -t], [t, 0]]} is a rotation by t; e^{[[0, 0], [1, 0]]} = [[1, 0], [1, 1]].
        let t = 1.3;
        let r = expm(&DMatrix::from_row_slice(2, 2, &[0.0, -t, t, 0.0])).unwrap();
        assert!(close(r[(0, 0)], t.cos(), 1e-14) && close(r[(1, 0)], t.sin(), 1e-14));
        let j = expm(&DMatrix::from_row_slice(2, 2, &[0.0, 0.0, 1.0, 0.0])).unwrap();
        assert_eq!(j, DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 1.0, 1.0]));
        // A large norm exercises the squarings: e^{-50} for a 1x1 matrix.
        let d = expm(&DMatrix::from_row_slice(1, 1, &[-50.0])).unwrap();
        assert!(close(d[(0, 0)], (-50.0f64).exp(), 1e-12));
    }
}
