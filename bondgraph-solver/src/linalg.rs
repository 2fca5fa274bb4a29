//! Small dense linear algebra for mode matrices: eigendecomposition that stays accurate on
//! stiff matrices, and a matrix exponential for the matrices it cannot diagonalise.
//!
//! Why not a library's matrix exponential: the flagship robot's modes pair an eigenvalue near
//! -2.5e17 1/s (a 5e-15 kg tip against a 1250 N·s/m damper) with ones near -1. Scaling and
//! squaring loses the slow part entirely (a relative error of 0.73 over a 1 s step was
//! measured on nalgebra's `exp`). An eigendecomposition gives each time scale its own exact
//! exponential; backward-stable eigenvalue algorithms, though, carry absolute errors of
//! order `ε‖A‖`, which on a graded matrix can swamp the small eigenvalues. So:
//!
//! - The matrix is scaled first ([`balance`], then [`symmetrize`]: a diagonal similarity
//!   that gives every coupling pair `a_ij`, `a_ji` equal magnitudes, the energy coordinates of
//!   a passive network), which grades it evenly and puts its lossless part in the skew part.
//! - Its eigenvalues come from nalgebra's real Schur form, and every eigenpair, left and
//!   right, is then refined by Newton's method on the scaled matrix until each component of
//!   the eigenvector, not only the largest, is at rounding level. Propagation turns the
//!   eigenvectors back into the model's coordinates, where a component that is 1e-150 of the
//!   largest in scaled coordinates (how a force on a 1e-300 kg mass reaches the slow mode) is
//!   of order one; a normwise-accurate eigenvector got it wrong by 1e96 there. The inverse
//!   `V⁻¹` is formed from the left eigenvectors for the same reason, not by inverting `V`.
//! - Eigenvalues that are one to rounding (a free body's zero beside a conserved
//!   quantity's, two identical oscillators) get bases of their null spaces: refined one by
//!   one they came out as two nearly parallel vectors, and two parallel springs stretched
//!   differently.
//! - An oscillation's real part comes from the symmetric part of the scaled matrix
//!   ([`oscillation_decay`]), exact to the rounding of the damping rather than of the
//!   frequency; a conjugate pair is refined once and kept exactly conjugate.
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
    /// The 1-norm condition number of the eigenvectors of the scaled matrix (`V` up to the
    /// diagonal scaling of [`symmetrize`]).
    pub condition: f64,
}

/// Condition numbers of the eigenvector matrix above this make the decomposition unusable.
const MAX_CONDITION: f64 = 1e10;

/// `V⁻¹ V` must be the identity to within this (largest entry of the difference), or the
/// decomposition is not used: the last check that the left and right eigenvectors, refined
/// one by one, belong together.
const MAX_INVERSE_DEFECT: f64 = 1e-6;

/// Newton steps allowed to refine one eigenpair. Newton converges quadratically: from an
/// inverse-iteration start it reaches rounding level in three to five steps; the budget only
/// bounds a pair that stagnates (a multiple eigenvalue), which is then judged by its residual.
const NEWTON_BUDGET: usize = 12;

/// A relative change of an eigenvector's components that no longer shrinks is taken as
/// Newton's method having reached the rounding of its own steps once it is below this.
const STAGNATION: f64 = 1e-8;

/// Rounding level, in units of `ε` per term, below which a residual or a symmetric part is
/// taken as zero (see [`is_eigenvector`] and [`symmetric_part`]).
const ROUNDING: f64 = 16.0;

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
    let (scaled, scale) = symmetrize(a);
    let schur = nalgebra::Schur::try_new(scaled.clone(), f64::EPSILON, 10_000)
        .ok_or(EigenError::NoConvergence)?;
    // A real eigenvalue may come out with an imaginary part of rounding size (relative to the
    // eigenvalue, or to the matrix for one near zero); snap it back so propagation can use
    // real arithmetic for it.
    let norm = one_norm(&scaled).max(f64::MIN_POSITIVE);
    let snap = |v: Complex64| {
        if v.im.abs() <= 1e-13 * v.re.abs() || v.im.abs() <= 1e-14 * norm {
            Complex64::new(v.re, 0.0)
        } else {
            v
        }
    };
    // Each value beside the Schur form's own, unsnapped: on a graded matrix the Schur form's
    // absolute error (ε‖B‖, 55 /s for the flagship's tip) can exceed a slow oscillation's
    // frequency, and the snapped value must then be checked (below).
    let mut values: Vec<(Complex64, Complex64)> = schur
        .complex_eigenvalues()
        .iter()
        .map(|v| (snap(*v), *v))
        .collect();
    // Deterministic order: by real part, then imaginary part (so a conjugate pair is
    // adjacent, its negative imaginary part first).
    let order = |x: &Complex64, y: &Complex64| {
        x.re.partial_cmp(&y.re)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(x.im.partial_cmp(&y.im).unwrap_or(std::cmp::Ordering::Equal))
    };
    values.sort_by(|x, y| order(&x.0, &y.0).then(order(&x.1, &y.1)));
    let raw: Vec<Complex64> = values.iter().map(|v| v.1).collect();
    let mut values: Vec<Complex64> = values.iter().map(|v| v.0).collect();
    let complex: DMatrix<Complex64> = scaled.map(|x| Complex64::new(x, 0.0));
    let transposed = complex.transpose();

    // Each eigenvalue with its right and left eigenvectors, refined one by one; a conjugate
    // pair is refined once, so that it stays exactly conjugate (and propagation real).
    let mut right = DMatrix::<Complex64>::zeros(n, n);
    let mut left = DMatrix::<Complex64>::zeros(n, n);
    let mut i = 0;
    while i < n {
        let paired = raw[i].im < 0.0 && i + 1 < n && raw[i + 1] == raw[i].conj();
        if paired && values[i].im == 0.0 {
            // A pair the snapping made real: two close real eigenvalues, or an oscillation
            // slower than the Schur form's rounding. Refined as real, each must be an
            // eigenpair to rounding; if not, the pair is refined as the oscillation it is.
            let first = eigenpair(&complex, values[i], norm);
            let second = eigenpair(&complex, values[i + 1], norm);
            if first.0.im == 0.0
                && second.0.im == 0.0
                && is_eigenvector(&scaled, first.0, &first.1)
                && is_eigenvector(&scaled, second.0, &second.1)
            {
                for (k, (value, vector)) in [(i, first), (i + 1, second)] {
                    let (_, covector) = eigenpair(&transposed, value, norm);
                    values[k] = value;
                    right.set_column(k, &vector);
                    left.set_column(k, &covector);
                }
                i += 2;
                continue;
            }
            values[i] = raw[i];
            values[i + 1] = raw[i + 1];
        }
        let target = if paired { i + 1 } else { i };
        let (value, vector) = eigenpair(&complex, values[target], norm);
        // Refined, an eigenvalue is accurate to its own size: snap relative to that alone.
        let value = if value.im.abs() <= 1e-13 * value.re.abs() {
            Complex64::new(value.re, 0.0)
        } else {
            value
        };
        let (_, covector) = eigenpair(&transposed, value, norm);
        values[target] = value;
        right.set_column(target, &vector);
        left.set_column(target, &covector);
        if paired {
            values[i] = value.conj();
            right.set_column(i, &vector.map(|z| z.conj()));
            left.set_column(i, &covector.map(|z| z.conj()));
        }
        i = target + 1;
    }

    // Eigenvalues that are one to rounding (a free body's and a conserved quantity's zeros,
    // two identical oscillators) get bases of their null spaces; Newton's method has no
    // unique answer there, and the refined vectors would be (nearly) parallel.
    let clusters = clusters(&scaled, &values, &right, &left);
    let mut inverse = DMatrix::<Complex64>::zeros(n, n);
    for cluster in &clusters {
        if let [j] = cluster[..] {
            let (v, w) = (right.column(j), left.column(j));
            let pairing = w.transpose() * v;
            let pairing = pairing[(0, 0)];
            if pairing.norm() == 0.0 || !pairing.re.is_finite() || !pairing.im.is_finite() {
                return Err(EigenError::Defective(f64::INFINITY));
            }
            inverse.set_row(j, &(w.transpose() / pairing));
            continue;
        }
        let value = cluster.iter().map(|&j| values[j]).sum::<Complex64>() / cluster.len() as f64;
        let value = snap(value);
        let basis = null_space(&complex, value, norm, cluster.len())?;
        let cobasis = null_space(&transposed, value, norm, cluster.len())?;
        let k = cluster.len();
        let r = DMatrix::from_columns(&basis);
        let l = DMatrix::from_columns(&cobasis);
        let rows = (l.transpose() * &r)
            .try_inverse()
            .ok_or(EigenError::Defective(f64::INFINITY))?
            * l.transpose();
        for (slot, &j) in cluster.iter().enumerate() {
            values[j] = value;
            right.set_column(j, &r.column(slot));
            inverse.set_row(j, &rows.row(slot));
        }
        debug_assert_eq!(rows.nrows(), k);
    }

    // The real part of an oscillation from the symmetric part of the matrix (see
    // [`oscillation_decay`]): exact to the rounding of the damping rather than of the
    // frequency, which matters once the frequency times the time span exceeds 1/ε.
    let symmetric = symmetric_part(&scaled);
    for cluster in &clusters {
        if let [j] = cluster[..]
            && values[j].im != 0.0
        {
            values[j].re = oscillation_decay(&symmetric, &right.column(j).into_owned());
        }
    }

    // Judge the eigenvectors in the scaled coordinates: the scaling is an exact similarity,
    // so the grading it removes (a momentum of order 1 beside a displacement of order 1e-10
    // in a stiff oscillator) costs no precision, and must not count as near-dependence (it
    // once sent such oscillators to the exponential, which turned a rotation into growth).
    for c in 0..n {
        let column_norm = right.column(c).iter().map(|z| z.norm()).fold(0.0, f64::max);
        if column_norm == 0.0 || !column_norm.is_finite() {
            return Err(EigenError::Defective(f64::INFINITY));
        }
        let mut column = right.column_mut(c);
        column /= Complex64::new(column_norm, 0.0);
        let mut row = inverse.row_mut(c);
        row *= Complex64::new(column_norm, 0.0);
    }
    let condition = complex_one_norm(&right) * complex_one_norm(&inverse);
    if condition.is_nan() || condition > MAX_CONDITION {
        return Err(EigenError::Defective(condition));
    }
    let defect = (&inverse * &right - DMatrix::<Complex64>::identity(n, n))
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max);
    if defect.is_nan() || defect > MAX_INVERSE_DEFECT {
        return Err(EigenError::Defective(condition));
    }
    // Undo the scaling: A = D B D⁻¹, so V = D W and V⁻¹ = W⁻¹ D⁻¹; then scale each
    // eigenvector to a largest component of 1 (and the matching row of V⁻¹ inversely).
    let mut vectors = right;
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

/// Balances `a` by a diagonal similarity of powers of two (Parlett and Reinsch, as LAPACK's
/// `gebal` without permutations): returns `B = D⁻¹ A D` and the diagonal of `D`.
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
            if column == 0.0 || row == 0.0 {
                continue;
            }
            let mut f = 1.0;
            let mut c = column;
            let mut r = row;
            let total = c + r;
            while c < r / RADIX {
                c *= RADIX * RADIX;
                r /= RADIX * RADIX;
                f *= RADIX;
            }
            while c >= r * RADIX {
                c /= RADIX * RADIX;
                r *= RADIX * RADIX;
                f /= RADIX;
            }
            if (c + r) < 0.95 * total {
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

/// Scales `a` by a diagonal similarity so that its couplings come in pairs of equal
/// magnitude: returns `B = D⁻¹ A D` and the diagonal of `D`.
///
/// A passive network's mode matrix is `(J - R) Q`: a skew-symmetric junction structure `J`
/// (it conserves power), a dissipation `R` and the energy's Hessian `Q`. Scaled to energy
/// coordinates (`D = Q^{-1/2}`) it is `J̃ - R̃`, whose skew part carries the frequencies and
/// whose symmetric part carries the damping, apart. That scaling is found from the matrix
/// alone: wherever `a_ij` and `a_ji` are both nonzero, `|b_ij| = |b_ji|` asks
/// `(d_j/d_i)² = |a_ji/a_ij|`, which is set along a spanning tree of such pairs (consistent
/// on cycles for a network, by the same argument). Each connected set keeps the mean level
/// that [`balance`] gives it, and [`balance`] alone scales the rest.
///
/// The diagonal is not a power of two, so `B` carries one rounding per entry, a
/// componentwise perturbation of relative size `ε` that any backward-stable step adds anyway.
fn symmetrize(a: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let (balanced, mut scale) = balance(a);
    let n = balanced.nrows();
    let mut exponent: Vec<Option<f64>> = vec![None; n];
    for root in 0..n {
        if exponent[root].is_some() {
            continue;
        }
        exponent[root] = Some(0.0);
        let mut component = vec![root];
        let mut head = 0;
        while let Some(&i) = component.get(head) {
            head += 1;
            let level = exponent[i].unwrap_or(0.0);
            for j in 0..n {
                let (forward, backward) = (balanced[(i, j)], balanced[(j, i)]);
                if j == i || exponent[j].is_some() || forward == 0.0 || backward == 0.0 {
                    continue;
                }
                exponent[j] = Some(level + 0.5 * (backward.abs().log2() - forward.abs().log2()));
                component.push(j);
            }
        }
        let mean = component
            .iter()
            .map(|&i| exponent[i].unwrap_or(0.0))
            .sum::<f64>()
            / component.len() as f64;
        for &i in &component {
            exponent[i] = exponent[i].map(|e| e - mean);
        }
    }
    let exponent: Vec<f64> = exponent.into_iter().map(|e| e.unwrap_or(0.0)).collect();
    let scaled = DMatrix::from_fn(n, n, |i, j| {
        balanced[(i, j)] * (exponent[j] - exponent[i]).exp2()
    });
    // Far outside the range of floating point (a ratio of couplings near 1e600) the factors
    // overflow; the balanced matrix is then as good as it gets.
    let representable = scaled
        .iter()
        .zip(balanced.iter())
        .all(|(s, b)| s.is_finite() && (*s != 0.0) == (*b != 0.0));
    if !representable {
        return (balanced, scale);
    }
    for (s, e) in scale.iter_mut().zip(&exponent) {
        *s *= e.exp2();
    }
    if scale.iter().any(|s| !s.is_finite() || *s == 0.0) {
        return balance(a);
    }
    (scaled, scale)
}

/// The symmetric part `(B + Bᵀ)/2` of `b`, with the entries where `b_ij` and `b_ji` cancel to
/// rounding (`|b_ij + b_ji| ≤ 16 ε (|b_ij| + |b_ji|)`) set to zero.
///
/// After [`symmetrize`], a lossless coupling (a spring between two masses, a transformer) is
/// skew to rounding: its two entries are the same product of parameters taken in different
/// orders, and the scaling's own rounding. Zeroing that remainder is a componentwise
/// perturbation of the two entries by at most `16 ε` of themselves, and it keeps a coupling of
/// `7e150 rad/s` from lending its rounding (`1e135 /s`) to the damping.
fn symmetric_part(b: &DMatrix<f64>) -> DMatrix<f64> {
    let n = b.nrows();
    DMatrix::from_fn(n, n, |i, j| {
        let (forward, backward) = (b[(i, j)], b[(j, i)]);
        let sum = forward + backward;
        if i != j && sum.abs() <= ROUNDING * f64::EPSILON * (forward.abs() + backward.abs()) {
            0.0
        } else {
            0.5 * sum
        }
    })
}

/// The real part of the eigenvalue of `B` whose eigenvector is `v`, from the symmetric part
/// `H` of `B` alone: `B v = λ v` gives `v* B v = λ v* v`, and `v* K v` is imaginary for the
/// skew part `K`, so `Re λ = v* H v / v* v`, exactly, for any real matrix.
///
/// The Schur form and Newton's method both leave an eigenvalue an absolute error of order
/// `ε |λ|`. For an oscillation that is a damping error of `ε ω`: harmless over a few periods,
/// but over the `1e150` periods a `1e-300 kg` mass on a spring makes in a second it turns
/// `e^{σt}` into zero or infinity. Here the error is of order `ε ‖H‖`: the damping's own.
fn oscillation_decay(symmetric: &DMatrix<f64>, v: &DVector<Complex64>) -> f64 {
    let n = v.len();
    let mut energy = 0.0;
    let mut decay = 0.0;
    for k in 0..n {
        energy += v[k].norm_sqr();
        for l in 0..n {
            let h = symmetric[(k, l)];
            if h != 0.0 {
                decay += h * (v[k].conj() * v[l]).re;
            }
        }
    }
    decay / energy
}

/// An eigenpair of `a` near `value`: inverse iteration for a start, then Newton's method
/// ([`refine`]). A real `value` gives a real eigenvector (in complex storage).
fn eigenpair(
    a: &DMatrix<Complex64>,
    value: Complex64,
    norm: f64,
) -> (Complex64, DVector<Complex64>) {
    refine(a, value, inverse_iteration(a, value, norm))
}

/// Groups the refined eigenvalues that are one to rounding: `i` and `j` when they agree to
/// `1e-9` of their size, or when each one's eigenvector is an eigenvector for the other's
/// value as well ([`is_eigenvector`]) and the left and right eigenvectors are not
/// biorthogonal (`|w_iᵀ v_j|` above `1e-8 ‖w_i‖ ‖v_j‖`, either way round). Distinct eigenvalues
/// have biorthogonal eigenvectors whatever the rounding; a slow mode of a graded matrix can
/// pass for a zero row by row, and must not be merged with one. Each group is a list of
/// indices; most have one.
fn clusters(
    b: &DMatrix<f64>,
    values: &[Complex64],
    right: &DMatrix<Complex64>,
    left: &DMatrix<Complex64>,
) -> Vec<Vec<usize>> {
    let n = values.len();
    let mut group: Vec<usize> = (0..n).collect();
    fn root(group: &mut [usize], mut i: usize) -> usize {
        while group[i] != i {
            group[i] = group[group[i]];
            i = group[i];
        }
        i
    }
    let norm = |m: &DMatrix<Complex64>, j: usize| m.column(j).iter().map(|z| z.norm()).sum::<f64>();
    let coupled = |i: usize, j: usize| {
        let pairing = (left.column(i).transpose() * right.column(j))[(0, 0)].norm();
        pairing > 1e-8 * norm(left, i) * norm(right, j)
    };
    for i in 0..n {
        for j in i + 1..n {
            let close =
                (values[i] - values[j]).norm() <= 1e-9 * values[i].norm().max(values[j].norm());
            let same = close
                || (is_eigenvector(b, values[j], &right.column(i).into_owned())
                    && is_eigenvector(b, values[i], &right.column(j).into_owned())
                    && (coupled(i, j) || coupled(j, i)));
            if same {
                let (ri, rj) = (root(&mut group, i), root(&mut group, j));
                group[rj] = ri;
            }
        }
    }
    let mut clusters: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; n];
    for i in 0..n {
        let r = root(&mut group, i);
        if slot[r] == usize::MAX {
            slot[r] = clusters.len();
            clusters.push(Vec::new());
        }
        clusters[slot[r]].push(i);
    }
    clusters
}

/// Whether `v` is an eigenvector of `b` for `value` to rounding, row by row:
/// `|(B v - λ v)_k| ≤ 16 n ε (Σ_l |b_kl v_l| + |λ v_k|)`. That is, `(λ, v)` is an exact
/// eigenpair of a matrix within `16 n ε` of `b`, entry by entry.
fn is_eigenvector(b: &DMatrix<f64>, value: Complex64, v: &DVector<Complex64>) -> bool {
    let n = v.len();
    let tolerance = ROUNDING * n as f64 * f64::EPSILON;
    (0..n).all(|k| {
        let mut residual = -value * v[k];
        let mut size = (value * v[k]).norm();
        for l in 0..n {
            residual += v[l] * b[(k, l)];
            size += (v[l] * b[(k, l)]).norm();
        }
        residual.norm() <= tolerance * size
    })
}

/// An eigenvector of `a` for the (approximate) eigenvalue `value`, by inverse iteration.
fn inverse_iteration(a: &DMatrix<Complex64>, value: Complex64, norm: f64) -> DVector<Complex64> {
    let n = a.nrows();
    let real = value.im == 0.0;
    let start = DVector::<Complex64>::from_fn(n, |i, _| {
        Complex64::new(
            1.0 + 0.37 * i as f64,
            if real { 0.0 } else { 0.11 * i as f64 },
        )
    });
    // A shift a hair off the eigenvalue keeps the system solvable; real, so that a real
    // eigenvalue keeps a real eigenvector. Should the shift land on an eigenvalue exactly
    // (it can: the eigenvalue is off by rounding, and so is the shift), elimination meets a
    // zero pivot and the solution is not finite: then the shift moves further off.
    let mut offset = if value.norm() > 0.0 {
        4.0 * f64::EPSILON * value.norm()
    } else {
        f64::EPSILON * f64::EPSILON * norm + f64::MIN_POSITIVE
    };
    for _ in 0..4 {
        let shifted = a - DMatrix::<Complex64>::identity(n, n) * (value + offset);
        let lu = shifted.lu();
        let mut v = start.clone();
        let mut finite = true;
        for _ in 0..3 {
            let Some(next) = lu.solve(&v) else {
                finite = false;
                break;
            };
            let largest = next.iter().map(|z| z.norm()).fold(0.0, f64::max);
            if largest == 0.0 || next.iter().any(|z| !z.re.is_finite() || !z.im.is_finite()) {
                finite = false;
                break;
            }
            v = next / Complex64::new(largest, 0.0);
        }
        if finite {
            return v;
        }
        offset *= 1e4;
    }
    start
}

/// Newton refinement of a simple eigenpair: solves
/// `[A - λI, -v; e_kᵀ, 0] [δv; δλ] = -[Av - λv; 0]` with `k` the largest component of `v`,
/// until every component of the step is at rounding level relative to the component itself
/// (not to the largest: in a graded matrix the small components of an eigenvector carry the
/// coupling of the small time scales), the step stops shrinking, or [`NEWTON_BUDGET`] runs
/// out.
fn refine(
    a: &DMatrix<Complex64>,
    mut value: Complex64,
    mut vector: DVector<Complex64>,
) -> (Complex64, DVector<Complex64>) {
    let n = a.nrows();
    let mut previous = f64::INFINITY;
    for iteration in 0..NEWTON_BUDGET {
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
        if step.iter().any(|z| !z.re.is_finite() || !z.im.is_finite()) {
            break;
        }
        let relative = |delta: Complex64, size: Complex64| {
            if delta.norm() == 0.0 {
                0.0
            } else {
                delta.norm() / size.norm().max(f64::MIN_POSITIVE)
            }
        };
        // Componentwise, for convergence; normwise (the pivot is 1), for divergence.
        let change = (0..n)
            .map(|r| relative(step[r], vector[r]))
            .fold(relative(step[n], value), f64::max);
        let normwise = (0..n)
            .map(|r| step[r].norm())
            .fold(relative(step[n], value), f64::max);
        if iteration > 0 && normwise > 1.0 {
            // Diverging (a multiple eigenvalue, where the system is singular): keep the last.
            break;
        }
        for r in 0..n {
            vector[r] += step[r];
        }
        value += step[n];
        // Converged; or stuck at the level of rounding (a component's relative change no
        // longer shrinks, and is small: while a component is still far from its value, a
        // tiny one that Newton must bring down by many orders, each step changes it wholly).
        if change <= 4.0 * f64::EPSILON || (change >= previous && change <= STAGNATION) {
            break;
        }
        previous = change;
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
    fn a_vanishing_mass_keeps_its_slow_mode_and_an_undamped_oscillation() {
        // two_masses.ron with m1 = 1e-300 kg, x = (p1, q, p2). As m1 → 0 the slow eigenvalue
        // is -b/m2 = -0.8333…; the fast pair is ±i sqrt(k/m1) = ±7.0710678118654755e150 i,
        // damped at a rate of order b m1/m2² = 1e-300 /s: over any time a model has, not at
        // all. (Were: a real part of -3.4e117 for one of the pair, 1e96 in V⁻¹.)
        let (m1, m2, k, b) = (1e-300, 3.0, 50.0, 2.5);
        let a = DMatrix::from_row_slice(
            3,
            3,
            &[0.0, -k, 0.0, 1.0 / m1, 0.0, -1.0 / m2, 0.0, k, -b / m2],
        );
        let e = eigen(&a).unwrap();
        let slow = e.values.iter().find(|v| v.im == 0.0).unwrap();
        assert!(close(slow.re, -b / m2, 1e-15), "{:?}", e.values);
        let fast: Vec<_> = e.values.iter().filter(|v| v.im != 0.0).collect();
        assert_eq!(fast.len(), 2);
        assert_eq!(*fast[0], fast[1].conj());
        assert!(close(fast[0].im.abs(), 7.071_067_811_865_475e150, 1e-15));
        // The damping is known to the rounding of the damping, ε b/m2, not of ω (1e135 /s).
        assert!(
            fast[0].re.abs() <= 4.0 * f64::EPSILON * b / m2,
            "{:?}",
            e.values
        );
    }

    #[test]
    fn a_double_zero_gets_independent_eigenvectors() {
        // Two free masses (2.5e6, 2.5e-3 kg) joined by springs of 1e3 and 3e3 N/m side by
        // side, x = (p1, q1, q2, p2): the total momentum and q1 - q2 are free, a double zero
        // with two independent eigenvectors. (Were: two simple eigenvalues of -6e-148 and
        // -3e-142 with nearly parallel eigenvectors, condition 1.6e6.)
        let (m1, m2, k1, k2) = (2.5e6, 2.5e-3, 1e3, 3e3);
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0,
                -k1,
                -k2,
                0.0,
                1.0 / m1,
                0.0,
                0.0,
                -1.0 / m2,
                1.0 / m1,
                0.0,
                0.0,
                -1.0 / m2,
                0.0,
                k1,
                k2,
                0.0,
            ],
        );
        let e = eigen(&a).unwrap();
        // Zero to the rounding of the oscillation's 1265 rad/s.
        let zeros = e.values.iter().filter(|v| v.norm() <= 1e-12 * 1264.9);
        assert_eq!(zeros.count(), 2, "{:?}", e.values);
        assert!(e.condition < 100.0, "{}", e.condition);
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
