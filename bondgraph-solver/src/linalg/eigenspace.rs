//! Eigenspaces of clustered eigenvalues: where close eigenvalues make single eigenvectors
//! ill-conditioned, the invariant subspace they span is refined as a block (block Newton,
//! block inverse iteration) and its basis kept orthonormal.

use super::*;

/// The right and left bases of an eigenspace of dimension `k` near `value` ([`eigenspace`])
/// that is biorthogonal to every group but `group` (the one it would replace): `(λ, X, Y)`.
pub(super) fn eigenspace_pair(
    m: &Matrices,
    pairs: &Pairs,
    groups: &[Vec<usize>],
    group: Option<usize>,
    value: Complex64,
    k: usize,
    norm: f64,
) -> Option<(Complex64, DMatrix<Complex64>, DMatrix<Complex64>)> {
    let (value, basis) = eigenspace(&m.complex, value, k, norm)?;
    let (_, cobasis) = eigenspace(&m.transposed, value, k, norm)?;
    if !is_eigenspace(&m.real, value, &basis, &cobasis)
        || !is_eigenspace(&m.real_transposed, value, &cobasis, &basis)
    {
        return None;
    }
    let separate = groups
        .iter()
        .enumerate()
        .filter(|(h, _)| Some(*h) != group)
        .flat_map(|(_, members)| members.iter().copied())
        .all(|j| {
            (0..k).all(|c| {
                pairing(&pairs.left.column(j), &basis.column(c)) <= COUPLED
                    && pairing(&cobasis.column(c), &pairs.right.column(j)) <= COUPLED
            })
        });
    separate.then_some((value, basis, cobasis))
}

/// Whether the columns of `x` span an eigenspace of `b` for `value` to rounding, with `y`
/// spanning the left one: [`is_eigenvector`] for the residual `R = B X - λ X` once its part
/// in the eigenspace, `X (YᵀX)⁻¹ YᵀR`, is taken out, and that part itself at the rounding
/// of `B X` as the left eigenvectors sum it (`|YᵀR| ≤ 16 n ε |Y|ᵀ |B| |X|`).
///
/// For an exact eigenspace `YᵀR = 0`, as `Yᵀ B = λ Yᵀ`; computed, the part is not zero but
/// rounding, and Newton's method for the eigenspace reads it as a coupling `M - λI` between
/// the columns (a free body's momentum taking up 2e-17 of a spring's rounding) rather than
/// move them: column by column, such a basis is not one to rounding, though its span is.
fn is_eigenspace(
    b: &DMatrix<f64>,
    value: Complex64,
    x: &DMatrix<Complex64>,
    y: &DMatrix<Complex64>,
) -> bool {
    let (n, k) = x.shape();
    let tolerance = ROUNDING * n as f64 * f64::EPSILON;
    let Some(inverse) = (y.transpose() * x).try_inverse() else {
        return false;
    };
    for c in 0..k {
        let largest = x.column(c).iter().map(|z| z.norm()).fold(0.0, f64::max);
        let mut residual = DVector::<Complex64>::zeros(n);
        let mut size = DVector::<f64>::zeros(n);
        for r in 0..n {
            let mut row = 0.0;
            residual[r] = -value * x[(r, c)];
            size[r] = (value * x[(r, c)]).norm();
            for l in 0..n {
                residual[r] += x[(l, c)] * b[(r, l)];
                size[r] += (x[(l, c)] * b[(r, l)]).norm();
                row += b[(r, l)].abs();
            }
            size[r] += row * largest;
        }
        let inside = y.transpose() * &residual;
        for d in 0..k {
            let allowed: f64 = (0..n).map(|r| y[(r, d)].norm() * size[r]).sum();
            if inside[d].norm() > tolerance * allowed {
                return false;
            }
        }
        let coefficients = &inverse * inside;
        for r in 0..n {
            let mut projected = residual[r];
            let mut allowed = size[r];
            for d in 0..k {
                projected -= x[(r, d)] * coefficients[d];
                allowed += (x[(r, d)] * coefficients[d]).norm();
            }
            if projected.norm() > tolerance * allowed {
                return false;
            }
        }
    }
    true
}

/// A basis of the eigenspace of `a` (complex storage of `real`) for the eigenvalue near
/// `value` of dimension `k`, with the eigenvalue refined; `None` if there is none to
/// rounding.
///
/// Block inverse iteration from `k` fixed start vectors gives the span of the `k`
/// eigenvectors nearest `value`; Newton's method on `A X = X M`, `Eᵀ X = I` (`E` picking `k`
/// rows of `X`) then refines it until every component is at rounding, as [`refine`] does for
/// one vector: the bordered matrix `[A - λI, -X; Eᵀ, 0]`, `λ = tr M / k`, is regular for an
/// eigenvalue with `k` independent eigenvectors, whichever basis they have. The result is an
/// eigenspace if every column is an eigenvector to rounding ([`is_eigenvector`]) and `M` is
/// `λ I` to the rounding of the rows of `A X` it is read from.
fn eigenspace(
    a: &DMatrix<Complex64>,
    value: Complex64,
    k: usize,
    norm: f64,
) -> Option<(Complex64, DMatrix<Complex64>)> {
    let n = a.nrows();
    if k > n {
        return None;
    }
    let mut basis = block_inverse_iteration(a, value, k, norm)?;
    let pivots = pivot_rows(&basis)?;
    let square = DMatrix::from_fn(k, k, |r, c| basis[(pivots[r], c)]);
    basis = &basis * square.try_inverse()?;
    let mut block = {
        let product = a * &basis;
        DMatrix::from_fn(k, k, |r, c| product[(pivots[r], c)])
    };
    block_newton(a, &mut basis, &mut block, &pivots);
    // The eigenvalue: `M`'s diagonal entry with the least rounding, the size of the terms of
    // the row of `A X` it is read from (a conserved stretch's exact zero, rather than a free
    // body's from a damper's row at 1e-20 /s).
    let size = |c: usize| {
        (0..n)
            .map(|l| (a[(pivots[c], l)] * basis[(l, c)]).norm())
            .sum::<f64>()
    };
    let best = (0..k).min_by(|&c, &d| size(c).total_cmp(&size(d)))?;
    let value = (a.row(pivots[best]) * basis.column(best))[(0, 0)];
    Some((value, basis))
}

/// Newton's method on `A X = X M`, `Eᵀ X = I` (`E` the `pivots`), in place: until every
/// component of `X` is at rounding, its changes stop shrinking, or [`NEWTON_BUDGET`] runs
/// out. Each step solves `[A - λI, -X; Eᵀ, 0] [δX; δM] = -[A X - X M; 0]` with
/// `λ = tr M / k`, exact Newton once `M = λ I`.
fn block_newton(
    a: &DMatrix<Complex64>,
    basis: &mut DMatrix<Complex64>,
    block: &mut DMatrix<Complex64>,
    pivots: &[usize],
) {
    let (n, k) = basis.shape();
    let relative = |delta: Complex64, size: Complex64| {
        if delta.norm() == 0.0 {
            0.0
        } else {
            delta.norm() / size.norm().max(f64::MIN_POSITIVE)
        }
    };
    let mut previous = f64::INFINITY;
    for iteration in 0..NEWTON_BUDGET {
        let lambda = block.trace() / k as f64;
        let residual = a * &*basis - &*basis * &*block;
        let mut system = DMatrix::<Complex64>::zeros(n + k, n + k);
        system
            .view_mut((0, 0), (n, n))
            .copy_from(&(a - DMatrix::<Complex64>::identity(n, n) * lambda));
        system.view_mut((0, n), (n, k)).copy_from(&(-&*basis));
        for (slot, &p) in pivots.iter().enumerate() {
            system[(n + slot, p)] = Complex64::new(1.0, 0.0);
        }
        let mut rhs = DMatrix::<Complex64>::zeros(n + k, k);
        rhs.view_mut((0, 0), (n, k)).copy_from(&(-residual));
        let Some(step) = system.lu().solve(&rhs) else {
            break;
        };
        if step.iter().any(|z| !z.re.is_finite() || !z.im.is_finite()) {
            break;
        }
        let mut change = 0.0f64;
        let mut normwise = 0.0f64;
        for c in 0..k {
            let largest = basis.column(c).iter().map(|z| z.norm()).fold(0.0, f64::max);
            for r in 0..n {
                change = change.max(relative(step[(r, c)], basis[(r, c)]));
                normwise = normwise.max(step[(r, c)].norm() / largest);
            }
        }
        if iteration > 0 && normwise > 1.0 {
            // Diverging: keep the last.
            break;
        }
        *basis += step.view((0, 0), (n, k));
        *block += step.view((n, 0), (k, k));
        if change <= 4.0 * f64::EPSILON || (change >= previous && change <= STAGNATION) {
            break;
        }
        previous = change;
    }
}

/// `k` orthonormal columns spanning the eigenvectors of `a` nearest `value`: block inverse
/// iteration, as [`inverse_iteration`] for one vector, from fixed start vectors.
fn block_inverse_iteration(
    a: &DMatrix<Complex64>,
    value: Complex64,
    k: usize,
    norm: f64,
) -> Option<DMatrix<Complex64>> {
    let n = a.nrows();
    let real = value.im == 0.0;
    // Fixed, generic start vectors: an affine ramp and cosines of distinct frequencies.
    let start = DMatrix::<Complex64>::from_fn(n, k, |r, c| {
        let x = r as f64;
        let re = if c == 0 {
            1.0 + 0.37 * x
        } else {
            (0.7 * (c as f64) * (x + 1.0) + 0.3).cos()
        };
        Complex64::new(
            re,
            if real {
                0.0
            } else {
                0.11 * x + 0.05 * c as f64
            },
        )
    });
    // A shift off the eigenvalue by its own rounding, and at least `ε²‖B‖`: a tinier one is
    // lost when added to `B`'s entries, and elimination meets an exact zero pivot. Nor below
    // `√MIN_POSITIVE`, which complex division squares.
    let mut offset = 4.0 * f64::EPSILON * value.norm()
        + f64::EPSILON * f64::EPSILON * norm
        + f64::MIN_POSITIVE.sqrt();
    for _ in 0..4 {
        let lu = (a - DMatrix::<Complex64>::identity(n, n) * (value + offset)).lu();
        let mut x = start.clone();
        let mut finite = true;
        for _ in 0..3 {
            let Some(mut next) = lu.solve(&x) else {
                finite = false;
                break;
            };
            if !orthonormalize(&mut next) {
                finite = false;
                break;
            }
            x = next;
        }
        if finite {
            return Some(x);
        }
        offset *= 1e4;
    }
    None
}

/// Orthonormalizes the columns of `x` in place (Gram-Schmidt, twice); false if they are not
/// finite or not independent.
fn orthonormalize(x: &mut DMatrix<Complex64>) -> bool {
    if x.iter().any(|z| !z.re.is_finite() || !z.im.is_finite()) {
        return false;
    }
    for c in 0..x.ncols() {
        // Scaled first, so that the products below cannot overflow.
        let largest = x.column(c).iter().map(|z| z.norm()).fold(0.0, f64::max);
        if largest == 0.0 || !largest.is_finite() {
            return false;
        }
        // (By a real number: a complex division would square `largest`.)
        let mut column = x.column(c).map(|z| z / largest);
        for _ in 0..2 {
            for d in 0..c {
                let projection = x.column(d).dotc(&column);
                column -= x.column(d) * projection;
            }
        }
        let size = column.norm();
        if size == 0.0 || !size.is_finite() {
            return false;
        }
        x.set_column(c, &column.map(|z| z / size));
    }
    true
}

/// `k` rows of the `n × k` matrix `x` on which it is regular, chosen as Gaussian elimination
/// with partial pivoting by columns would; `None` if it has no such rows.
fn pivot_rows(x: &DMatrix<Complex64>) -> Option<Vec<usize>> {
    let (n, k) = x.shape();
    let mut work = x.clone();
    let mut rows = Vec::with_capacity(k);
    for c in 0..k {
        let p = (0..n)
            .filter(|r| !rows.contains(r))
            .max_by(|&r, &s| work[(r, c)].norm().total_cmp(&work[(s, c)].norm()))?;
        let pivot = work[(p, c)];
        if pivot.norm() == 0.0 {
            return None;
        }
        for d in c + 1..k {
            let factor = work[(p, d)] / pivot;
            for r in 0..n {
                let delta = work[(r, c)] * factor;
                work[(r, d)] -= delta;
            }
        }
        rows.push(p);
    }
    Some(rows)
}
