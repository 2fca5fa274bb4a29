//! The matrix exponential of the matrices the eigendecomposition cannot diagonalise.

use nalgebra::DMatrix;

use super::{balance, one_norm};

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
