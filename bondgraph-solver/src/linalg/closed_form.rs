//! Eigenvalues of one- and two-state matrices in closed form.
//!
//! A steady-state search of a nonlinear mode asks for the eigenvalues of its Jacobian after
//! every window it integrates (its time scales, whether a candidate equilibrium is stable),
//! and most such modes have one or two states (a contact stuck with its motor's current, a
//! carriage sliding with it). The refined eigendecomposition ([`super::eigen`]: a Schur form,
//! then left and right eigenvectors refined by Newton's method) was a fifth of a fit's time
//! on such a model, for values the quadratic formula gives exactly.
//!
//! Accuracy on graded matrices, where the refinement earns its cost, comes from the form:
//! the larger root is `m ± √d` with the sign of `m` (no cancellation), the smaller one
//! `det / λ₁`, and the determinant `ad - bc` is taken with a fused multiply-add (Kahan's
//! algorithm) to nearly full relative precision. `[[-2.5e17, 1e17], [1, -1]]` (a light tip
//! on a stiff damper) so gives `-0.6` to rounding, where `tr/2 - √(tr²/4 - det)` loses it.

use nalgebra::DMatrix;
use num_complex::Complex64;

/// The eigenvalues of a 1×1 or 2×2 matrix, a conjugate pair's negative imaginary part first;
/// `None` for a larger matrix or where the formula overflows or meets a value that is not
/// finite (the general routine answers there).
pub fn closed_form_eigenvalues(a: &DMatrix<f64>) -> Option<Vec<Complex64>> {
    let values = match (a.nrows(), a.ncols()) {
        (1, 1) => vec![Complex64::new(a[(0, 0)], 0.0)],
        (2, 2) => two_by_two(a[(0, 0)], a[(0, 1)], a[(1, 0)], a[(1, 1)]),
        _ => return None,
    };
    values
        .iter()
        .all(|v| v.re.is_finite() && v.im.is_finite())
        .then_some(values)
}

/// `[[a, b], [c, d]]`: `λ = m ± √(h² + bc)` with `m = (a + d)/2`, `h = (a - d)/2`.
fn two_by_two(a: f64, b: f64, c: f64, d: f64) -> Vec<Complex64> {
    let mean = 0.5 * a + 0.5 * d;
    let half_difference = 0.5 * a - 0.5 * d;
    let discriminant = half_difference.mul_add(half_difference, b * c);
    if discriminant < 0.0 {
        let imaginary = (-discriminant).sqrt();
        return vec![
            Complex64::new(mean, -imaginary),
            Complex64::new(mean, imaginary),
        ];
    }
    let root = discriminant.sqrt();
    let larger = if mean >= 0.0 {
        mean + root
    } else {
        mean - root
    };
    let smaller = if larger == 0.0 {
        0.0
    } else {
        determinant(a, b, c, d) / larger
    };
    let (low, high) = if smaller <= larger {
        (smaller, larger)
    } else {
        (larger, smaller)
    };
    vec![Complex64::new(low, 0.0), Complex64::new(high, 0.0)]
}

/// `ad - bc` to nearly full relative precision (Kahan): the rounding of `bc` is recovered by
/// a fused multiply-add and added back.
fn determinant(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let bc = b * c;
    let bc_rounding = (-b).mul_add(c, bc);
    a.mul_add(d, -bc) + bc_rounding
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(rows: [[f64; 2]; 2]) -> Vec<Complex64> {
        let a = DMatrix::from_row_slice(2, 2, &[rows[0][0], rows[0][1], rows[1][0], rows[1][1]]);
        closed_form_eigenvalues(&a).unwrap()
    }

    fn close(x: Complex64, expected: Complex64, relative: f64) -> bool {
        (x - expected).norm() <= relative * expected.norm()
    }

    #[test]
    fn a_damped_oscillator_and_an_overdamped_one() {
        // m = 1 kg, k = 4 N/m, b = 2 N s/m: λ = -1 ± i√3.
        let v = values([[0.0, 1.0], [-4.0, -2.0]]);
        assert!(
            close(v[0], Complex64::new(-1.0, -3f64.sqrt()), 1e-15),
            "{v:?}"
        );
        assert!(
            close(v[1], Complex64::new(-1.0, 3f64.sqrt()), 1e-15),
            "{v:?}"
        );
        // b = 5: λ = (-5 ± 3)/2 = -4, -1.
        let v = values([[0.0, 1.0], [-4.0, -5.0]]);
        assert_eq!(
            v,
            vec![Complex64::new(-4.0, 0.0), Complex64::new(-1.0, 0.0)]
        );
    }

    #[test]
    fn the_slow_root_of_a_graded_matrix_keeps_its_precision() {
        // Characteristic polynomial λ² + (2.5e17 + 1) λ + 1.5e17: the roots are
        // -1.5e17/λ₁ and λ₁ = -(2.5e17 + 1) + 1.5e17/(2.5e17 + 1) + ..., so the slow one is
        // -0.6 (1 + 2.4e-18) to first order: -0.6 to rounding.
        let v = values([[-2.5e17, 1e17], [1.0, -1.0]]);
        assert!(close(v[1], Complex64::new(-0.6, 0.0), 4e-16), "{v:?}");
        assert!(close(v[0], Complex64::new(-2.5e17, 0.0), 1e-15), "{v:?}");
        // The textbook form tr/2 - √(tr²/4 - det) loses it entirely.
        let (tr, det): (f64, f64) = (-2.5e17 - 1.0, 2.5e17 - 1e17);
        let naive: f64 = tr / 2.0 + (tr * tr / 4.0 - det).sqrt();
        assert!((naive + 0.6).abs() > 0.5);
    }

    #[test]
    fn agrees_with_the_refined_decomposition() {
        // A motor's current and speed (R/L = 3000 /s, a coupling K, a mechanical pole 40 /s)
        // and a stuck contact's single state.
        for rows in [
            [[-3000.0, -75.4], [1468.0, -40.0]],
            [[-15500.0, 0.0], [0.0, -3.1]],
            [[1e-3, 2.0], [-3.0, 4e5]],
        ] {
            let a =
                DMatrix::from_row_slice(2, 2, &[rows[0][0], rows[0][1], rows[1][0], rows[1][1]]);
            let by_parts =
                |x: &Complex64, y: &Complex64| x.re.total_cmp(&y.re).then(x.im.total_cmp(&y.im));
            let mut closed = closed_form_eigenvalues(&a).unwrap();
            let mut refined = super::super::eigen(&a).unwrap().values;
            closed.sort_by(by_parts);
            refined.sort_by(by_parts);
            for (x, y) in closed.iter().zip(&refined) {
                assert!(close(*x, *y, 1e-13), "{closed:?} against {refined:?}");
            }
        }
        let one = DMatrix::from_row_slice(1, 1, &[-7.0]);
        assert_eq!(
            closed_form_eigenvalues(&one),
            Some(vec![Complex64::new(-7.0, 0.0)])
        );
        assert_eq!(closed_form_eigenvalues(&DMatrix::zeros(3, 3)), None);
        let huge = DMatrix::from_row_slice(2, 2, &[1e300, 1e300, 1e300, -1e300]);
        assert_eq!(closed_form_eigenvalues(&huge), None);
    }
}
