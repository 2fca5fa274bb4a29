//! Small dense linear algebra for mode matrices: eigendecomposition that stays accurate on
//! stiff matrices, and a matrix exponential for the matrices it cannot diagonalise.
//!
//! Why not a library's matrix exponential: a light tip on a stiff damper pairs an eigenvalue near
//! -2.5e17 1/s (a 5e-15 kg tip against a 1250 N·s/m damper) with ones near -1. Scaling and
//! squaring loses the slow part entirely (a relative error of 0.73 over a 1 s step was
//! measured on nalgebra's `exp`). An eigendecomposition gives each time scale its own exact
//! exponential; backward-stable eigenvalue algorithms, though, carry absolute errors of
//! order `ε‖A‖`, which on a graded matrix can swamp the small eigenvalues. So:
//!
//! - The matrix is scaled first ([`balance`], then `symmetrize`: a diagonal similarity by
//!   powers of two that gives every coupling pair `a_ij`, `a_ji` magnitudes within a factor
//!   of two, near the energy coordinates of a passive network). Powers of two make the
//!   similarity exact, so the scaled matrix keeps the model's exact relations between entries:
//!   a damper's or a spring's two rows are exact negatives, two parallel springs' rows are
//!   equal. Rounding them apart (a scaling by `√2`) costs the damping of a nearly rigid link
//!   its precision: `b (v₁ - v₂)²` from terms `b v²` `1e9` times larger.
//! - Its eigenvalues come from nalgebra's real Schur form, and every eigenpair, left and
//!   right, is then refined by Newton's method on the scaled matrix until each component of
//!   the eigenvector, not only the largest, is at rounding level. Propagation turns the
//!   eigenvectors back into the model's coordinates, where a component that is 1e-150 of the
//!   largest in scaled coordinates (how a force on a 1e-300 kg mass reaches the slow mode) is
//!   of order one; a normwise-accurate eigenvector got it wrong by 1e96 there. The inverse
//!   `V⁻¹` is formed from the left eigenvectors for the same reason, not by inverting `V`.
//! - Every refined eigenpair must be one to rounding and biorthogonal to the others. One that
//!   is not belongs to a repeated eigenvalue (a conserved quantity's zero beside a free
//!   body's, two springs side by side, two identical oscillators): refined one by one, such
//!   eigenvalues come out as nearly parallel vectors, or a zero as a creep rate `1e-5 /s`
//!   that is only `ε‖A‖` to the Schur form. It joins the eigenvalue whose eigenspace, one
//!   dimension larger, exists (`eigenspace`: block inverse iteration and Newton's method
//!   on `A X = X M`, componentwise like single pairs); an SVD's null space is accurate only
//!   to `ε‖A‖` over the gap to the next eigenvalue, `1e-7` beside a slow oscillation.
//! - An oscillation's real part comes from the energy balance `Re λ = v* W B v / v* W v`
//!   (`oscillation_decay`) when that is the more accurate: its lossless couplings cancel
//!   exactly, so a 7e150 rad/s oscillation's rounding (1e135 /s) does not reach its damping.
//!   A conjugate pair is refined once and kept exactly conjugate.
//!
//! A matrix whose eigenvectors are (nearly) dependent is defective; there the solver falls back
//! to [`expm`], Higham's scaling and squaring with a degree-13 Padé approximant, on matrices
//! that are not stiff enough to defeat it.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

mod balance;
mod closed_form;
mod eigenspace;
mod expm;

pub use balance::balance;
use balance::{Scaled, symmetrize};
pub use closed_form::closed_form_eigenvalues;
use eigenspace::eigenspace_pair;
pub use expm::expm;

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
    /// diagonal scaling of `symmetrize`).
    pub condition: f64,
}

/// Condition numbers of the eigenvector matrix above this make the decomposition unusable.
const MAX_CONDITION: f64 = 1e10;

/// `V⁻¹ V` must be the identity to within this (largest entry of the difference), or the
/// decomposition is not used: the last check that the left and right eigenvectors, refined
/// one by one, belong together.
const MAX_INVERSE_DEFECT: f64 = 1e-6;

/// Newton steps allowed to refine one eigenpair or eigenspace. Newton converges
/// quadratically: from an inverse-iteration start it reaches rounding level in three to five
/// steps; the budget only bounds one that stagnates, which is then judged by its residual.
const NEWTON_BUDGET: usize = 12;

/// A relative change of an eigenvector's components that no longer shrinks is taken as
/// Newton's method having reached the rounding of its own steps once it is below this.
const STAGNATION: f64 = 1e-8;

/// Rounding level, in units of `ε` per term, below which a residual or a coupling's loss is
/// taken as zero (see [`is_eigenvector`] and [`oscillation_decay`]).
const ROUNDING: f64 = 16.0;

/// `|wᵢᵀ vⱼ|` above this fraction of `‖wᵢ‖₁ ‖vⱼ‖₁` couples two eigenpairs (`i ≠ j`): distinct
/// eigenvalues have biorthogonal eigenvectors whatever the rounding, to far below this.
const COUPLED: f64 = 1e-8;

/// Eigenvalues tried, nearest first, for a repeated eigenvalue an eigenpair belongs to before
/// the matrix counts as defective.
const CLUSTER_TRIALS: usize = 4;

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
    let Scaled {
        matrix: scaled,
        scale,
        weights,
    } = symmetrize(a);
    let (raw, mut values, norm) = schur_values(&scaled)?;
    let estimates = values.clone();
    let matrices = Matrices::new(&scaled);

    // Each eigenvalue with its right and left eigenvectors, refined one by one; a conjugate
    // pair is refined once, so that it stays exactly conjugate (and propagation real).
    let mut right = DMatrix::<Complex64>::zeros(n, n);
    let mut left = DMatrix::<Complex64>::zeros(n, n);
    let mut partner: Vec<Option<usize>> = vec![None; n];
    // The left eigenvectors' own eigenvalues, equal to the right ones' to rounding.
    let mut covalues = values.clone();
    let mut i = 0;
    while i < n {
        let paired = raw[i].im < 0.0 && i + 1 < n && raw[i + 1] == raw[i].conj();
        if paired && values[i].im == 0.0 {
            // A pair the snapping made real: two close real eigenvalues, or an oscillation
            // slower than the Schur form's rounding. Refined as real, each must be an
            // eigenpair to rounding; if not, the pair is refined as the oscillation it is.
            let first = eigenpair(&matrices.complex, values[i], norm);
            let second = eigenpair(&matrices.complex, values[i + 1], norm);
            if first.0.im == 0.0
                && second.0.im == 0.0
                && is_eigenvector(&scaled, first.0, &first.1)
                && is_eigenvector(&scaled, second.0, &second.1)
            {
                for (k, (value, vector)) in [(i, first), (i + 1, second)] {
                    let (covalue, covector) = eigenpair(&matrices.transposed, value, norm);
                    values[k] = value;
                    covalues[k] = covalue;
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
        let (value, vector) = eigenpair(&matrices.complex, values[target], norm);
        // Refined, an eigenvalue is accurate to its own size: snap relative to that alone.
        let value = if value.im.abs() <= 1e-13 * value.re.abs() {
            Complex64::new(value.re, 0.0)
        } else {
            value
        };
        let (covalue, covector) = eigenpair(&matrices.transposed, value, norm);
        values[target] = value;
        covalues[target] = covalue;
        right.set_column(target, &vector);
        left.set_column(target, &covector);
        if paired {
            values[i] = value.conj();
            covalues[i] = covalue.conj();
            right.set_column(i, &vector.map(|z| z.conj()));
            left.set_column(i, &covector.map(|z| z.conj()));
            if value.im != 0.0 {
                partner[i] = Some(target);
                partner[target] = Some(i);
            }
        }
        i = target + 1;
    }

    // Repeated eigenvalues: the eigenpairs that are not one to rounding, or not independent
    // of the others, join an eigenvalue whose eigenspace is larger (see [`gather`]).
    let mut pairs = Pairs {
        values,
        covalues,
        right,
        left,
        partner,
    };
    let groups = gather(&matrices, &estimates, &mut pairs, norm);
    let groups = groups?;
    let Pairs {
        mut values,
        mut right,
        left,
        ..
    } = pairs;
    let mut inverse = group_inverse(&groups, &right, &left)?;

    // The real part of an oscillation from the energy balance (see [`oscillation_decay`])
    // where that is the more accurate.
    energy_decays(&groups, &mut values, (&right, &left), (&scaled, &weights));

    // Judge the eigenvectors in the scaled coordinates: the scaling is an exact similarity,
    // so the grading it removes (a momentum of order 1 beside a displacement of order 1e-10
    // in a stiff oscillator) costs no precision, and must not count as near-dependence (it
    // once sent such oscillators to the exponential, which turned a rotation into growth).
    normalize_columns(&mut right, &mut inverse)?;
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
    normalize_columns(&mut vectors, &mut inverse)?;
    Ok(Eigen {
        values,
        vectors,
        inverse,
        condition,
    })
}

/// The eigenvalues of the Schur form of `scaled`, in a deterministic order (by real part,
/// then imaginary part: a conjugate pair adjacent, its negative imaginary part first), as
/// computed and with a real eigenvalue's rounding-size imaginary part snapped to zero; and
/// the matrix's 1-norm, which the snapping and the refinement judge against.
///
/// # Errors
/// [`EigenError::NoConvergence`] when the Schur iteration does not converge.
#[allow(clippy::type_complexity)]
fn schur_values(
    scaled: &DMatrix<f64>,
) -> Result<(Vec<Complex64>, Vec<Complex64>, f64), EigenError> {
    let schur = nalgebra::Schur::try_new(scaled.clone(), f64::EPSILON, 10_000)
        .ok_or(EigenError::NoConvergence)?;
    // A real eigenvalue may come out with an imaginary part of rounding size (relative to the
    // eigenvalue, or to the matrix for one near zero); snap it back so propagation can use
    // real arithmetic for it.
    let norm = one_norm(scaled).max(f64::MIN_POSITIVE);
    let snap = |v: Complex64| {
        if v.im.abs() <= 1e-13 * v.re.abs() || v.im.abs() <= 1e-14 * norm {
            Complex64::new(v.re, 0.0)
        } else {
            v
        }
    };
    // Each value beside the Schur form's own, unsnapped: on a graded matrix the Schur form's
    // absolute error (ε‖B‖, 55 /s for a 5e-15 kg tip on a 1250 N·s/m damper) can exceed a slow oscillation's
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
    let values: Vec<Complex64> = values.iter().map(|v| v.0).collect();
    Ok((raw, values, norm))
}

/// Scales each column of `vectors` to a largest component of 1, and the matching row of
/// `inverse` inversely.
///
/// # Errors
/// [`EigenError::Defective`] for a zero or non-finite column.
fn normalize_columns(
    vectors: &mut DMatrix<Complex64>,
    inverse: &mut DMatrix<Complex64>,
) -> Result<(), EigenError> {
    for c in 0..vectors.ncols() {
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
    Ok(())
}

/// The inverse of the right eigenvectors, group by group: within a group of a repeated
/// eigenvalue, `(Lᵀ R)⁻¹ Lᵀ`.
///
/// # Errors
/// [`EigenError::Defective`] where a group's pairing is singular or non-finite.
fn group_inverse(
    groups: &[Vec<usize>],
    right: &DMatrix<Complex64>,
    left: &DMatrix<Complex64>,
) -> Result<DMatrix<Complex64>, EigenError> {
    let n = right.nrows();
    let mut inverse = DMatrix::<Complex64>::zeros(n, n);
    for group in groups {
        let r = DMatrix::from_columns(&group.iter().map(|&j| right.column(j)).collect::<Vec<_>>());
        let l = DMatrix::from_columns(&group.iter().map(|&j| left.column(j)).collect::<Vec<_>>());
        let pairing = l.transpose() * &r;
        if pairing
            .iter()
            .any(|z| !z.re.is_finite() || !z.im.is_finite())
        {
            return Err(EigenError::Defective(f64::INFINITY));
        }
        let rows = pairing
            .try_inverse()
            .ok_or(EigenError::Defective(f64::INFINITY))?
            * l.transpose();
        for (slot, &j) in group.iter().enumerate() {
            inverse.set_row(j, &rows.row(slot));
        }
    }
    Ok(inverse)
}

/// The real part of each oscillation from the energy balance (see [`oscillation_decay`])
/// where that is the more accurate: over 1e150 periods, a damping error of ε ω turns
/// e^{σt} into zero or infinity. Applied to the group's members and the conjugate group
/// (exactly conjugate values).
fn energy_decays(
    groups: &[Vec<usize>],
    values: &mut [Complex64],
    (right, left): (&DMatrix<Complex64>, &DMatrix<Complex64>),
    (scaled, weights): (&DMatrix<f64>, &[f64]),
) {
    let mut decays = Vec::new();
    for group in groups {
        let j = group[0];
        if values[j].im <= 0.0 {
            continue;
        }
        let vector = right.column(j).into_owned();
        let (decay, bound) = oscillation_decay(scaled, weights, &vector);
        if bound < newton_bound(scaled, &vector, &left.column(j).into_owned()) {
            decays.push((values[j], decay));
        }
    }
    // The same to the group's members and the conjugate group (exactly conjugate values).
    for (value, decay) in decays {
        for v in values.iter_mut() {
            if *v == value || *v == value.conj() {
                v.re = decay;
            }
        }
    }
}

/// The scaled matrix in the forms the refinement uses.
struct Matrices {
    /// `B`.
    real: DMatrix<f64>,
    /// `Bᵀ`, whose eigenvectors are `B`'s left eigenvectors.
    real_transposed: DMatrix<f64>,
    /// `B` in complex storage.
    complex: DMatrix<Complex64>,
    /// `Bᵀ` in complex storage.
    transposed: DMatrix<Complex64>,
}

impl Matrices {
    fn new(b: &DMatrix<f64>) -> Self {
        let complex = b.map(|x| Complex64::new(x, 0.0));
        Matrices {
            real: b.clone(),
            real_transposed: b.transpose(),
            transposed: complex.transpose(),
            complex,
        }
    }
}

/// The eigenvalues with their right and left eigenvectors (columns), and each one's
/// conjugate (`partner`) for an oscillation.
struct Pairs {
    values: Vec<Complex64>,
    covalues: Vec<Complex64>,
    right: DMatrix<Complex64>,
    left: DMatrix<Complex64>,
    partner: Vec<Option<usize>>,
}

impl Pairs {
    /// Whether eigenpair `i` is one to rounding, left and right, with `wᵢᵀ vᵢ` not too small
    /// for the condition limit.
    fn is_sound(&self, m: &Matrices, i: usize) -> bool {
        let (v, w) = (self.right.column(i), self.left.column(i));
        is_eigenvector(&m.real, self.values[i], &v.into_owned())
            && is_eigenvector(&m.real_transposed, self.covalues[i], &w.into_owned())
            && pairing(&w, &v) * MAX_CONDITION > 1.0
    }

    /// Whether eigenpair `i`'s left eigenvector is not orthogonal to `j`'s right one.
    fn coupled(&self, i: usize, j: usize) -> bool {
        pairing(&self.left.column(i), &self.right.column(j)) > COUPLED
    }

    /// Gives the eigenvalue `value` the basis and cobasis (columns in the order of `members`).
    fn store(
        &mut self,
        members: &[usize],
        value: Complex64,
        basis: &DMatrix<Complex64>,
        cobasis: &DMatrix<Complex64>,
    ) {
        for (slot, &j) in members.iter().enumerate() {
            self.values[j] = value;
            self.covalues[j] = value;
            self.right.set_column(j, &basis.column(slot));
            self.left.set_column(j, &cobasis.column(slot));
        }
    }
}

/// `|wᵀ v| / (‖w‖₁ ‖v‖₁)`.
fn pairing<S1, S2>(
    w: &nalgebra::Matrix<Complex64, nalgebra::Dyn, nalgebra::U1, S1>,
    v: &nalgebra::Matrix<Complex64, nalgebra::Dyn, nalgebra::U1, S2>,
) -> f64
where
    S1: nalgebra::Storage<Complex64, nalgebra::Dyn, nalgebra::U1>,
    S2: nalgebra::Storage<Complex64, nalgebra::Dyn, nalgebra::U1>,
{
    let product: Complex64 = w.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
    let size = w.iter().map(|z| z.norm()).sum::<f64>() * v.iter().map(|z| z.norm()).sum::<f64>();
    if size == 0.0 {
        0.0
    } else {
        product.norm() / size
    }
}

/// Groups the eigenpairs into eigenvalues: returns the indices of each eigenvalue's pairs,
/// having given the repeated ones bases of their eigenspaces. `estimates` are the Schur
/// form's eigenvalues (snapped to real where they are real to rounding).
///
/// An eigenpair refined alone is kept when it is one to rounding ([`Pairs::is_sound`]) and
/// biorthogonal to those kept before it. Distinct eigenvalues have biorthogonal eigenvectors
/// whatever the rounding, so a pair that is not belongs to a repeated eigenvalue: Newton's
/// method has no unique answer there, and gives one eigenvector twice, or (from a Schur value
/// that is a zero to `ε‖A‖`, 1e-5 /s beside a creep rate of 2.4e-5 /s) no eigenpair at all.
/// Such a pair joins the nearest kept eigenvalue (of its Schur value, up to
/// [`CLUSTER_TRIALS`]) whose eigenspace, one dimension larger, exists and is biorthogonal to
/// the other eigenvalues' ([`eigenspace`]): a slow mode of a graded matrix can pass for a
/// zero row by row, but its eigenvector is not orthogonal to the creep's left one. Failing
/// that, it forms a new eigenvalue with the other such pairs whose Schur values are within
/// the Schur form's accuracy of its own (`16 n ε ‖B‖₁`), as many as have an eigenspace (a
/// free body's momentum and two conserved stretches, none of them kept). A pair that joins
/// nothing is kept alone if it is independent of the others, and the matrix is defective
/// otherwise.
fn gather(
    m: &Matrices,
    estimates: &[Complex64],
    pairs: &mut Pairs,
    norm: f64,
) -> Result<Vec<Vec<usize>>, EigenError> {
    let n = pairs.values.len();
    let radius = ROUNDING * n as f64 * f64::EPSILON * norm;
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut missing = Vec::new();
    for i in 0..n {
        let independent = groups
            .iter()
            .flatten()
            .all(|&j| !pairs.coupled(i, j) && !pairs.coupled(j, i));
        if independent && pairs.is_sound(m, i) {
            groups.push(vec![i]);
        } else {
            missing.push(i);
        }
    }
    let mut placed = vec![false; n];
    for &i in &missing {
        // The conjugate of an oscillation is placed with it.
        if placed[i]
            || (pairs.values[i].im < 0.0 && pairs.partner[i].is_some_and(|p| missing.contains(&p)))
        {
            continue;
        }
        let distance = |g: &[usize]| (estimates[i] - pairs.values[g[0]]).norm();
        let mut candidates: Vec<usize> = (0..groups.len()).collect();
        candidates.sort_by(|&g, &h| distance(&groups[g]).total_cmp(&distance(&groups[h])));
        // Joining a kept eigenvalue, or else founding one with other such pairs.
        let mut trials: Vec<(Option<usize>, Vec<usize>, Complex64)> = candidates
            .iter()
            .filter(|&&g| distance(&groups[g]) <= radius)
            .take(CLUSTER_TRIALS)
            .map(|&g| {
                let mut members = groups[g].clone();
                members.push(i);
                (Some(g), members, pairs.values[groups[g][0]])
            })
            .collect();
        let mut near: Vec<usize> = missing
            .iter()
            .copied()
            .filter(|&j| {
                !placed[j]
                    && (estimates[j] - estimates[i]).norm() <= radius
                    && (j == i || pairs.values[j].im >= 0.0 || pairs.partner[j].is_none())
            })
            .collect();
        near.sort_by(|&j, &k| {
            (estimates[j] - estimates[i])
                .norm()
                .total_cmp(&(estimates[k] - estimates[i]).norm())
        });
        for k in (2..=near.len()).rev() {
            trials.push((None, near[..k].to_vec(), estimates[i]));
        }
        let mut joined = false;
        for (group, members, value) in trials {
            let Some((value, basis, cobasis)) =
                eigenspace_pair(m, pairs, &groups, group, value, members.len(), norm)
            else {
                continue;
            };
            // An oscillation's conjugate joins the conjugate eigenvalue, with conjugate bases.
            let mirror = if value.im == 0.0 {
                None
            } else {
                let conjugates: Option<Vec<usize>> =
                    members.iter().map(|&j| pairs.partner[j]).collect();
                let Some(conjugates) = conjugates else {
                    continue;
                };
                // The kept members' conjugates are a group; the new ones' must be missing.
                let side = match group {
                    Some(_) => groups.iter().position(|g| g.contains(&conjugates[0])),
                    None => None,
                };
                let fresh = conjugates
                    .iter()
                    .zip(&members)
                    .filter(|(_, j)| !group.is_some_and(|g| groups[g].contains(j)))
                    .all(|(c, _)| missing.contains(c) && !placed[*c]);
                if !fresh || (group.is_some() && side.is_none()) {
                    continue;
                }
                Some((conjugates, side))
            };
            let g = match group {
                Some(g) => {
                    groups[g] = members.clone();
                    g
                }
                None => {
                    groups.push(members.clone());
                    groups.len() - 1
                }
            };
            pairs.store(&groups[g], value, &basis, &cobasis);
            for &j in &members {
                placed[j] = true;
            }
            if let Some((conjugates, side)) = mirror {
                let h = match side {
                    Some(h) => {
                        groups[h] = conjugates.clone();
                        h
                    }
                    None => {
                        groups.push(conjugates.clone());
                        groups.len() - 1
                    }
                };
                let conjugate = |x: &DMatrix<Complex64>| x.map(|z| z.conj());
                pairs.store(
                    &groups[h],
                    value.conj(),
                    &conjugate(&basis),
                    &conjugate(&cobasis),
                );
                for &j in &conjugates {
                    placed[j] = true;
                }
            }
            joined = true;
            break;
        }
        if joined {
            continue;
        }
        let independent = groups
            .iter()
            .flatten()
            .all(|&j| !pairs.coupled(i, j) && !pairs.coupled(j, i));
        if !independent {
            return Err(EigenError::Defective(f64::INFINITY));
        }
        groups.push(vec![i]);
        placed[i] = true;
        if let Some(p) = pairs.partner[i].filter(|p| missing.contains(p) && !placed[*p]) {
            groups.push(vec![p]);
            placed[p] = true;
        }
    }
    groups.sort_by_key(|members| members[0]);
    Ok(groups)
}

/// A sum of products carried to twice the working precision (Ogita, Rump and Oishi's
/// `Dot2`): each product and each addition split exactly into its rounded value and its
/// error, the errors summed apart.
#[derive(Clone, Copy, Default)]
struct Compensated {
    sum: f64,
    error: f64,
}

impl Compensated {
    /// Adds `a b`.
    fn add_product(&mut self, a: f64, b: f64) {
        let product = a * b;
        let product_error = a.mul_add(b, -product);
        let sum = self.sum + product;
        let z = sum - self.sum;
        self.error += (self.sum - (sum - z)) + (product - z) + product_error;
        self.sum = sum;
    }

    /// Adds `a s` for a compensated `s`.
    fn add_scaled(&mut self, a: f64, s: &Compensated) {
        self.add_product(a, s.sum);
        self.error += a * s.error;
    }

    fn value(&self) -> f64 {
        self.sum + self.error
    }
}

/// The real part of the eigenvalue of `B` whose eigenvector is `v`, from the energy
/// balance, with a bound on its rounding error: `(σ, bound)`.
///
/// `B v = λ v` gives `v* W B v = λ v* W v` for any positive diagonal `W`, so
/// `Re λ = Re(v* W B v) / v* W v` exactly. With `W` the energy weights of [`symmetrize`], a
/// lossless coupling (a spring between two masses, a transformer) contributes
/// `(w_i b_ij + w_j b_ji) Re(v̄_i v_j)`, zero but for the weights' rounding: such pairs (whose
/// two terms cancel to `16 ε` of themselves) are left out, so a coupling of `7e150 rad/s`
/// lends its rounding (`1e135 /s`) to nothing. The rest (dampers, sources of loss) is summed
/// row by row in twice the working precision: a damper between a 4.6e-8 kg and a 3.7e-5 kg
/// mass that move together to 3e-5 dissipates `b (v₁ - v₂)²`, 1e9 times less than its terms
/// `b v²`, and its rows are exact negatives in `B`, so only the sum loses anything. The bound
/// is the first-order effect of a rounding `ε` in each component of `v` and each weight:
/// `4 ε Σ w_k |v_k| |(B v)_k| / v* W v`, with the lossless pairs left out of `B v`.
fn oscillation_decay(b: &DMatrix<f64>, weights: &[f64], v: &DVector<Complex64>) -> (f64, f64) {
    let n = v.len();
    let lossless = |k: usize, l: usize| {
        let (forward, backward) = (weights[k] * b[(k, l)], weights[l] * b[(l, k)]);
        forward != 0.0
            && backward != 0.0
            && (forward + backward).abs()
                <= ROUNDING * f64::EPSILON * (forward.abs() + backward.abs())
    };
    let mut total = Compensated::default();
    let mut energy = 0.0;
    let mut spread = 0.0;
    for k in 0..n {
        let (mut re, mut im) = (Compensated::default(), Compensated::default());
        for l in 0..n {
            let x = b[(k, l)];
            if x == 0.0 || (l != k && lossless(k, l)) {
                continue;
            }
            re.add_product(x, v[l].re);
            im.add_product(x, v[l].im);
        }
        let w = weights[k];
        total.add_scaled(w * v[k].re, &re);
        total.add_scaled(w * v[k].im, &im);
        energy += w * v[k].norm_sqr();
        spread += w * v[k].norm() * re.value().hypot(im.value());
    }
    let decay = total.value() / energy;
    (
        decay,
        4.0 * f64::EPSILON * spread / energy + f64::EPSILON * decay.abs(),
    )
}

/// A bound on the rounding error of an eigenvalue refined by Newton's method from its
/// eigenvector `v` and left eigenvector `w`: `ε |w|ᵀ |B| |v| / |wᵀ v|`, the effect of a
/// rounding in each entry of `B`.
fn newton_bound(b: &DMatrix<f64>, v: &DVector<Complex64>, w: &DVector<Complex64>) -> f64 {
    let n = v.len();
    let mut size = 0.0;
    for k in 0..n {
        for l in 0..n {
            size += w[k].norm() * b[(k, l)].abs() * v[l].norm();
        }
    }
    let product: Complex64 = w.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
    f64::EPSILON * size / product.norm()
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

/// Whether `v` is an eigenvector of `b` for `value` to rounding, row by row:
/// `|(B v - λ v)_k| ≤ 16 n ε (Σ_l |b_kl v_l| + |λ v_k| + Σ_l |b_kl| ‖v‖∞)`. That is,
/// `(λ, v)` is an exact eigenpair of a matrix within `16 n ε` of `b`, entry by entry, for a
/// vector within `16 n ε` of `v`'s largest component. The last allows for components far
/// below the largest that no refinement determines to their own precision: a conserved
/// quantity's eigenvector has no momentum, and Newton's method leaves it a remainder that
/// each step shrinks but never to zero; a basis of a repeated eigenvalue carries `ε`-sized
/// parts of its other vectors. It is a bound row by row, not on `‖B‖`: a creep rate of
/// 2.4e-5 /s in a matrix of norm 6e14 still fails it for zero, in the rows of the springs
/// it stretches, whose norms are near 1e5.
fn is_eigenvector(b: &DMatrix<f64>, value: Complex64, v: &DVector<Complex64>) -> bool {
    let n = v.len();
    let tolerance = ROUNDING * n as f64 * f64::EPSILON;
    let largest = v.iter().map(|z| z.norm()).fold(0.0, f64::max);
    (0..n).all(|k| {
        let mut residual = -value * v[k];
        let mut size = (value * v[k]).norm();
        let mut row = 0.0;
        for l in 0..n {
            residual += v[l] * b[(k, l)];
            size += (v[l] * b[(k, l)]).norm();
            row += b[(k, l)].abs();
        }
        residual.norm() <= tolerance * (size + row * largest)
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

pub(super) fn one_norm(a: &DMatrix<f64>) -> f64 {
    (0..a.ncols())
        .map(|c| a.column(c).iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

fn complex_one_norm(a: &DMatrix<Complex64>) -> f64 {
    (0..a.ncols())
        .map(|c| a.column(c).iter().map(|z| z.norm()).sum::<f64>())
        .fold(0.0, f64::max)
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
        // A light tip on a taut string, in energy variables p, q:
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
